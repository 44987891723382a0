// run_identify_immersed (see identify_immersed_command.hpp).
#include "isospring/workflows/identify_immersed_command.hpp"

#include <algorithm>

#include "isospring/fitting/identify_immersed.hpp"
#include "isospring/fitting/identify_immersed_check.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/immersed_grid_ladder.hpp"

namespace isospring::workflows {
using namespace isospring::io;

namespace {

// The case summary of the reports (io::case_summary's fields): the background grid is the
// discretisation.
nlohmann::json immersed_summary(const ImmersedCase& c, const geometry::ImmersedDomain& domain) {
  nlohmann::json s;
  s["name"] = c.name;
  s["file"] = c.file.string();
  s["dimension"] = domain.dimension;
  s["formulation"] = "solid";
  s["volumetric"] = volumetric_key(c.volumetric);
  s["geometry"] = "immersed";
  s["part"] = c.part.string();
  s["material"] = {{"E", c.material.youngs_modulus},
                   {"nu", c.material.poisson_ratio},
                   {"density", c.material.density}};
  const nurbs::Patch& patch = domain.background;
  nlohmann::json p;
  for (int d = 0; d < patch.param_dim(); ++d) {
    p["degree"].push_back(patch.degree(d));
    p["elements"].push_back(patch.knots(d).num_elements());
    p["control_points"].push_back(patch.num_points(d));
  }
  s["patches"] = nlohmann::json::array({p});
  s["control_points"] = patch.num_points();
  s["elements"] = patch.num_elements();
  s["part_cells"] = domain.cells.size();
  s["supports"] = c.supports.size();
  for (const ImmersedLoadCase& lc : c.load_cases) s["load_cases"].push_back(lc.id);
  return s;
}

// The markers in a cell the part meets; the others dropped (listed) or refused.
void keep_markers_on_part(const fitting::Measurements& data, const geometry::ImmersedDomain& domain,
                          const IdentifyCommandOptions& options, const Progress& progress,
                          IdentifyCommandResult& r) {
  const std::vector<int> outside = fitting::immersed_markers_outside(domain, data.markers);
  size_t next = 0;
  for (size_t m = 0; m < data.markers.size(); ++m) {
    if (next < outside.size() && outside[next] == static_cast<int>(m)) {
      ++next;
      r.dropped.push_back({data.markers[m].row, data.markers[m].load_case,
                           std::numeric_limits<double>::quiet_NaN()});
      continue;
    }
    r.markers.push_back(data.markers[m]);
  }
  if (outside.empty()) return;
  if (!options.drop_outside) {
    std::string list;
    for (size_t k = 0; k < std::min<size_t>(10, outside.size()); ++k)
      list += "\n  row " + std::to_string(data.markers[static_cast<size_t>(outside[k])].row);
    throw nurbs::InputError(
        r.settings.file.string() + ": " + std::to_string(outside.size()) +
        " marker(s) do not lie in a background cell the immersed part meets:" + list +
        (outside.size() > 10 ? "\n  ..." : "") +
        "\nfix the data or its units/columns, or pass --drop-outside to leave them out");
  }
  progress.warn("dropped " + std::to_string(outside.size()) +
                " marker(s) off the part (listed in report.json)");
}

}  // namespace

IdentifyCommandResult run_identify_immersed(const ImmersedCase& c,
                                            const IdentifyCommandOptions& options,
                                            const Progress& progress) {
  const std::string case_file = c.file.string();
  if (!c.raw.contains("measurements"))
    throw nurbs::InputError(case_file +
                            ": no \"measurements\" object; add {\"file\": \"markers.csv\"} "
                            "(see io/markers.hpp for the fields)");
  IdentifyCommandResult r;
  r.input = c.file;
  r.case_name = c.name;
  for (const ImmersedLoadCase& load : c.load_cases) r.load_case_ids.push_back(load.id);
  r.settings = read_measurement_settings(c.raw.at("measurements"), c.file.parent_path(), 3,
                                         r.load_case_ids, case_file + ": measurements");
  const fitting::Measurements data = read_markers_csv(r.settings.file, r.settings.file_options);
  progress("read " + std::to_string(data.markers.size()) + " markers from " +
           r.settings.file.string());

  progress("immersing " + c.part.filename().string() + " (degree " +
           std::to_string(c.immersion.degree) + ")");
  const geometry::ImmersedDomain domain = geometry::immerse_solid(*c.cad, c.immersion);
  for (const std::string& w : domain.warnings) progress.warn(w);
  r.case_summary = immersed_summary(c, domain);
  keep_markers_on_part(data, domain, options, progress, r);

  fitting::IdentifyOptions identify_options = r.settings.identify;
  identify_options.progress = [&progress](const std::string& s) { progress(s); };
  if (!options.discretization_check) identify_options.discretization.enabled = false;
  if (options.max_dofs) identify_options.discretization.max_dofs = *options.max_dofs;
  std::vector<fitting::ImmersedCalibrationCase> cases;
  for (const ImmersedLoadCase& load : c.load_cases)
    cases.push_back({load.id, immersed_options(c, load)});
  r.identify = fitting::identify_immersed(domain, cases, r.markers, identify_options,
                                          immersed_grid_ladder(*c.cad, c.immersion, domain));
  for (const std::string& w : r.identify.warnings) progress.warn(w);
  r.identify_options = identify_options;
  r.identify_options.progress = nullptr;  // it refers to `progress`, which the result outlives
  r.recalibration_error =
      "not available for immersed models: the recalibration fits the spring model to the "
      "corrected reference on a body-fitted model's DOFs; calibrate the immersed part's spring "
      "model with `isospring calibrate` (with the identified E and effects declared in the case)";
  return r;
}

}  // namespace isospring::workflows
