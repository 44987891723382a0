// run_identify: the measured-data loop of `isospring identify` (see identify_command.hpp).
#include <algorithm>

#include "isospring/io/calibration_settings.hpp"
#include "isospring/io/case_refinement_ladder.hpp"
#include "isospring/io/report_case.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/identify_command.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;

double default_placement_tolerance(const std::vector<nurbs::Patch>& patches) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& p : patches) {
    const auto [a, b] = p.control_bounds();
    lo = lo.cwiseMin(a);
    hi = hi.cwiseMax(b);
  }
  return 1e-3 * (hi - lo).norm();
}

std::vector<std::string> identify_output_files(const std::vector<std::string>& load_case_ids) {
  std::vector<std::string> names{"report.json",   "report.md",    "residuals.svg",
                                 "residuals.csv", "residuals.gp", "errors_before_after.png",
                                 "model.json"};
  for (const auto& id : load_case_ids)
    for (const char* stage : {"before", "after"})
      names.push_back("markers_" + id + "_" + stage + ".vtp");
  return names;
}

IdentifyCommandResult run_identify(const Case& c, const IdentifyCommandOptions& options,
                                   const Progress& progress) {
  const std::string case_file = c.file.string();
  if (!c.measurements)
    throw nurbs::InputError(case_file +
                            ": no \"measurements\" object; add {\"file\": \"markers.csv\"} "
                            "(see io/markers.hpp for the fields)");
  IdentifyCommandResult r;
  r.input = c.file;
  r.case_name = c.name;
  r.case_summary = case_summary(c, c.problem);
  for (const auto& load : c.problem.load_cases) r.load_case_ids.push_back(load.id);
  r.settings = read_measurement_settings(c.measurements->raw, c.file.parent_path(), c.dimension,
                                         r.load_case_ids, case_file + ": measurements");
  const fitting::Measurements data = read_markers_csv(r.settings.file, r.settings.file_options);
  progress("read " + std::to_string(data.markers.size()) + " markers from " +
           r.settings.file.string());

  r.placement_tolerance =
      r.settings.placement_tolerance.value_or(default_placement_tolerance(c.problem.patches));
  const fitting::PlacementResult placed =
      fitting::place_markers(c.problem.patches, data.markers, r.placement_tolerance);
  std::vector<fitting::MarkerPlacement> placements;
  {
    size_t next = 0;  // placed.outside is sorted
    for (size_t m = 0; m < data.markers.size(); ++m) {
      if (next < placed.outside.size() && placed.outside[next] == static_cast<int>(m)) {
        ++next;
        r.dropped.push_back(
            {data.markers[m].row, data.markers[m].load_case, placed.placements[m].distance});
        continue;
      }
      r.markers.push_back(data.markers[m]);
      placements.push_back(placed.placements[m]);
    }
  }
  if (!placed.outside.empty() && !options.drop_outside) {
    std::string list;
    for (size_t k = 0; k < std::min<size_t>(10, placed.outside.size()); ++k) {
      const auto m = static_cast<size_t>(placed.outside[k]);
      list += "\n  row " + std::to_string(data.markers[m].row) + ": " +
              format_number(placed.placements[m].distance, 3) + " m off the model";
    }
    throw nurbs::InputError(
        r.settings.file.string() + ": " + std::to_string(placed.outside.size()) +
        " marker(s) lie farther than " + format_number(r.placement_tolerance, 3) +
        " m from the model (measurements.placement_tolerance):" + list +
        (placed.outside.size() > 10 ? "\n  ..." : "") +
        "\nfix the data or its units/columns, or pass --drop-outside to leave them out");
  }
  if (!placed.outside.empty())
    progress.warn("dropped " + std::to_string(placed.outside.size()) +
                  " marker(s) off the model (listed in report.json)");

  fitting::IdentifyOptions identify_options = r.settings.identify;
  identify_options.progress = [&progress](const std::string& s) { progress(s); };
  identify_options.discretization.ladder = case_refinement_ladder(c);
  identify_options.discretization.intermediate = case_refinement_intermediate(c);
  identify_options.discretization.ratio_from_level = case_ladder_ratio_from_level(c);
  if (options.max_dofs) identify_options.discretization.max_dofs = *options.max_dofs;
  if (!options.discretization_check) identify_options.discretization.enabled = false;
  r.identify = fitting::identify(c.problem, r.markers, placements, identify_options);
  r.identify_options = identify_options;
  r.identify_options.progress = nullptr;  // it refers to `progress`, which the result outlives

  if (!options.recalibrate) return r;
  // Carry it through: recalibrate the spring model against the corrected reference. A failed
  // recalibration is reported, not fatal: the identification itself stands. That includes input
  // errors of the calibration (no density for the masses, prescribed non-zero supports): the case
  // is fine for identification; only the "calibration" object itself is checked strictly here.
  progress("recalibrating the spring model against the corrected reference");
  const fitting::CalibrationSettings calibration_settings =
      read_calibration_settings(c.calibration, case_file).settings;
  try {
    r.recalibration = fitting::recalibrate_identified(c.problem, r.identify, calibration_settings);
  } catch (const std::exception& e) {
    r.recalibration_error = e.what();
    progress.warn("recalibration failed: " + r.recalibration_error + "; model.json not written");
  }
  return r;
}

SpringModel identify_spring_model(const IdentifyCommandResult& r) {
  const fitting::Recalibration& rc = r.recalibration.value();
  SpringModel model;
  model.network = rc.calibration.mesh.network;
  model.units = default_model_units();
  model.gravity = rc.gravity;
  const int dim = model.network.dimension;
  for (size_t l = 0; l < rc.corrected.load_cases.size(); ++l) {
    ModelLoadCase load;
    load.id = rc.corrected.load_cases[l].id;
    const Eigen::VectorXd& f = rc.particle_loads[l];
    for (Eigen::Index p = 0; p < f.size() / dim; ++p)
      if (!f.segment(p * dim, dim).isZero(0.0)) {
        Eigen::Vector3d force = Eigen::Vector3d::Zero();
        force.head(dim) = f.segment(p * dim, dim);
        load.forces.emplace_back(static_cast<int>(p), force);
      }
    model.load_cases.push_back(std::move(load));
  }
  model.provenance = {{"case", r.case_name},
                      {"isospring_version", isospring_version()},
                      {"identify",
                       {{"effects_added", r.identify.effects_added},
                        {"reference", "the identified model (corrected reference)"},
                        {"percent_e_rms", rc.percent_e_rms},
                        {"percent_e_max", rc.percent_e_max},
                        {"gamma", rc.calibration.gamma}}}};
  return model;
}

}  // namespace isospring::workflows
