// The measured-data loop (fitting::identify) for Python: isospring.identify(case) reads the
// case's "measurements" (io::read_measurement_settings, io::read_markers_csv), places the markers
// on the model (fitting::place_markers) and runs the loop, as `isospring identify` does before it
// writes its report. Not here: the recalibration of the spring model (it needs the case's
// "calibration" object, which only the program parses) and --drop-outside.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "bindings.hpp"
#include "isospring/fitting/identify.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/case_refinement_ladder.hpp"
#include "isospring/io/markers.hpp"
#include "isospring/nurbs/error.hpp"

namespace py = pybind11;

namespace isospring::python {
namespace {

py::list parameters(const std::vector<fitting::ParameterEstimate>& estimates) {
  py::list out;
  for (const auto& p : estimates) {
    py::dict d;
    d["effect"] = p.effect;
    d["name"] = p.name;
    d["unit"] = p.unit;
    d["value"] = p.value;
    d["standard_error"] = p.standard_error;
    out.append(d);
  }
  return out;
}

// The default placement tolerance of `isospring identify`: 1e-3 of the control nets' bounding-box
// diagonal (apps/cmd_identify.cpp, README "measurements").
double default_tolerance(const std::vector<nurbs::Patch>& patches) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& p : patches) {
    const auto [a, b] = p.control_bounds();
    lo = lo.cwiseMin(a);
    hi = hi.cwiseMax(b);
  }
  return 1e-3 * (hi - lo).norm();
}

py::dict identify(const io::Case& c, std::optional<int> max_dofs, bool discretization_check) {
  if (!c.measurements)
    throw nurbs::InputError(c.file.string() +
                            ": no \"measurements\" object; add {\"file\": "
                            "\"markers.csv\"} (README.md, \"Measured data\")");
  std::vector<std::string> ids;
  for (const auto& load : c.problem.load_cases) ids.push_back(load.id);
  const io::MeasurementSettings settings =
      io::read_measurement_settings(c.measurements->raw, c.file.parent_path(), c.dimension, ids,
                                    c.file.string() + ": measurements");
  const fitting::Measurements data = io::read_markers_csv(settings.file, settings.file_options);
  const double tolerance =
      settings.placement_tolerance.value_or(default_tolerance(c.problem.patches));
  const fitting::PlacementResult placed =
      fitting::place_markers(c.problem.patches, data.markers, tolerance);
  if (!placed.outside.empty())
    throw nurbs::InputError(settings.file.string() + ": " + std::to_string(placed.outside.size()) +
                            " marker(s) lie farther than " + std::to_string(tolerance) +
                            " m from the model (measurements.placement_tolerance)");

  fitting::IdentifyOptions options = settings.identify;
  options.discretization.ladder = io::case_refinement_ladder(c);
  if (max_dofs) options.discretization.max_dofs = *max_dofs;
  options.discretization.enabled = options.discretization.enabled && discretization_check;
  fitting::IdentifyResult r;
  {
    // The loop holds no Python object: other Python threads may run meanwhile.
    py::gil_scoped_release release;
    r = fitting::identify(c.problem, data.markers, placed.placements, options);
  }
  std::vector<Eigen::Vector3d> positions, measured;
  for (const auto& m : data.markers) {
    positions.push_back(m.position);
    measured.push_back(m.displacement);
  }
  py::dict d;
  d["effects_added"] = r.effects_added;
  d["parameters"] = parameters(r.parameters);
  d["parameters_before"] = parameters(r.parameters_before);
  d["youngs_modulus"] = r.youngs_modulus;
  d["poisson_ratio"] = r.poisson_ratio;
  d["rms_before"] = r.before.rms;
  d["rms_after"] = r.after.rms;
  d["max_before"] = r.before.max;
  d["max_after"] = r.after.max;
  d["noise_estimate"] = r.noise_estimate;
  d["load_case"] = [&] {
    std::vector<std::string> out;
    for (const auto& m : data.markers) out.push_back(m.load_case);
    return out;
  }();
  d["positions"] = rows(positions);
  d["measured"] = rows(measured);
  d["model_before"] = rows(r.model_before);
  d["model_after"] = rows(r.model_after);
  d["seconds"] = r.seconds;
  return d;
}

}  // namespace

void bind_identify(py::module_& m) {
  m.def("identify", &identify, py::arg("case"), py::kw_only(), py::arg("max_dofs") = py::none(),
        py::arg("discretization_check") = true,
        "The measured-data loop on the case's \"measurements\" (README.md, \"Measured data\"): "
        "fits E (and nu), adds the missing effects. Returns a dict: effects_added, parameters and "
        "parameters_before (effect, name, unit, value, standard_error), youngs_modulus, "
        "poisson_ratio, rms/max before and after, noise_estimate, and per marker load_case, "
        "positions, measured, model_before and model_after (m, 3) displacements.");
}

}  // namespace isospring::python
