// The measured-data loop for Python: isospring.identify(case) calls workflows::run_identify, the
// function `isospring identify` calls (reading the case's "measurements", placing the markers, the
// loop). Not here: the recalibration of the spring model (the program writes it to model.json) and
// --drop-outside.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "bindings.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/workflows/identify_command.hpp"

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

py::dict identify(const io::Case& c, std::optional<int> max_dofs, bool discretization_check) {
  workflows::IdentifyCommandOptions options;
  if (max_dofs) options.max_dofs = *max_dofs;
  options.discretization_check = discretization_check;
  options.recalibrate = false;  // not returned here; `isospring identify` writes it to model.json
  workflows::IdentifyCommandResult result;
  {
    // The loop holds no Python object: other Python threads may run meanwhile.
    py::gil_scoped_release release;
    result = workflows::run_identify(c, options, io::Progress("identify", true));
  }
  const fitting::IdentifyResult& r = result.identify;
  const std::vector<fitting::Marker>& markers = result.markers;
  std::vector<Eigen::Vector3d> positions, measured;
  for (const auto& m : markers) {
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
    for (const auto& m : markers) out.push_back(m.load_case);
    return out;
  }();
  d["positions"] = rows(positions);
  d["measured"] = rows(measured);
  d["model_before"] = rows(r.model_before);
  d["model_after"] = rows(r.model_after);
  d["warnings"] = r.warnings;  // what the loop adapted (e.g. a widened ghost penalty)
  d["seconds"] = r.seconds;
  return d;
}

}  // namespace

void bind_identify(py::module_& m) {
  m.def("identify", &identify, py::arg("case"), py::kw_only(), py::arg("max_dofs") = py::none(),
        py::arg("discretization_check") = true,
        "The measured-data loop on the case's \"measurements\" (docs/identify.md): "
        "fits E (and nu), adds the missing effects. Returns a dict: effects_added, parameters and "
        "parameters_before (effect, name, unit, value, standard_error), youngs_modulus, "
        "poisson_ratio, rms/max before and after, noise_estimate, and per marker load_case, "
        "positions, measured, model_before and model_after (m, 3) displacements; warnings (what "
        "the loop adapted, e.g. a widened ghost penalty).");
}

}  // namespace isospring::python
