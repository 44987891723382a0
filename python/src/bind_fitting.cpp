// The NMSM calibration for Python: isospring.calibrate(case, **settings) is
// workflows::run_calibrate, the call `isospring calibrate` makes, on the case's own "calibration"
// object with the keyword arguments laid over it. The settings are read by
// io::read_calibration_settings, so they have the case file's names, defaults, checks and error
// messages (as exceptions). isospring.calibrate_immersed(case_file, **settings) is the same for an
// immersed case (workflows::run_calibrate_immersed).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "bindings.hpp"
#include "isospring/fitting/calibration.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/immersed_case.hpp"
#include "isospring/io/json_text.hpp"
#include "isospring/io/report.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/calibrate_command.hpp"
#include "isospring/workflows/calibrate_immersed.hpp"

namespace py = pybind11;

namespace isospring::python {
namespace {

using IndexMatrix = Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor>;

py::dict metrics(const fitting::ErrorMetrics& e) {
  py::dict d;
  d["percent_e_rms"] = e.percent_e_rms;
  d["percent_e_max"] = e.percent_e_max;
  d["o_max"] = e.o_max;
  d["points"] = e.points;
  return d;
}

// Per load case: the control-point, field and surface metrics, keyed as in the report.json of
// `isospring calibrate`, and the node errors u_nmsm - u_ref as an (n, 3) array.
py::dict case_errors(const fitting::CaseErrors& e) {
  py::dict d;
  d["id"] = e.id;
  d["control"] = metrics(e.control);
  d["field"] = metrics(e.field);
  d["surface"] = metrics(e.surface);
  d["node_error"] = rows(e.node_error);
  return d;
}

py::dict calibration_result(const fitting::CalibrationResult& r) {
  const analysis::SpringNetwork& net = r.mesh.network;
  const auto n = static_cast<Eigen::Index>(net.springs.size());
  IndexMatrix pairs(n, 2);
  Eigen::VectorXd stiffness(n), damping(n), rest_length(n);
  Eigen::VectorXi group(n);
  for (Eigen::Index s = 0; s < n; ++s) {
    const analysis::Spring& spring = net.springs[static_cast<size_t>(s)];
    pairs(s, 0) = spring.i;
    pairs(s, 1) = spring.j;
    stiffness[s] = spring.stiffness;
    damping[s] = spring.damping;
    rest_length[s] = spring.rest_length;
    group[s] = spring.group;
  }
  py::dict d;
  d["springs"] = pairs;
  d["stiffness"] = stiffness;
  d["damping"] = damping;
  d["rest_length"] = rest_length;
  d["group"] = group;
  d["positions"] = rows(net.positions);
  d["masses"] = net.masses;
  d["fixed"] = net.fixed;
  d["gamma"] = r.gamma;
  d["parameters"] = r.parameters;
  py::list fit, holdout;
  for (const auto& e : r.fit) fit.append(case_errors(e));
  for (const auto& e : r.holdout) holdout.append(case_errors(e));
  d["fit"] = fit;
  d["holdout"] = holdout;
  d["warnings"] = r.warnings;
  d["fit_seconds"] = r.fit_seconds;
  return d;
}

// A Python value (numbers, strings, booleans, lists, dicts) as JSON, through Python's own json
// module: exactly what the same value written in a case file would be.
nlohmann::json to_json(const py::handle& value) {
  const std::string text = py::str(py::module_::import("json").attr("dumps")(value));
  return nlohmann::json::parse(text);
}

// The keyword arguments laid over a case's "calibration" object (made an object when absent).
void overlay_settings(nlohmann::json& calibration, const py::kwargs& settings) {
  if (!calibration.is_object()) calibration = nlohmann::json::object();
  for (const auto& [key, value] : settings) {
    const std::string name = py::str(key);
    // The grouping's fields may be given flat (gamma=0.1), as in earlier versions.
    if (name == "gamma" || name == "gamma_sweep" || name == "per_spring") {
      nlohmann::json& grouping = calibration["grouping"];
      if (!grouping.is_object())
        grouping = grouping == "per_spring" ? nlohmann::json{{"per_spring", true}}
                                            : nlohmann::json::object();
      grouping[name] = to_json(value);
    } else {
      calibration[name] = to_json(value);
    }
  }
}

py::dict calibrate_immersed(const std::string& case_file, const py::kwargs& settings) {
  nlohmann::json document =
      io::parse_json_text(io::read_text_file(case_file, "case file"), case_file, "case file");
  if (!io::is_immersed_case(document))
    throw nurbs::InputError(case_file +
                            ": geometry is not {\"type\": \"immersed\", ...}; a body-fitted case "
                            "calibrates with isospring.calibrate(isospring.read_case(file))");
  overlay_settings(document["calibration"], settings);
  workflows::ImmersedCalibrateResult r;
  {
    // The immersion and the fit hold no Python object: other Python threads may run meanwhile.
    py::gil_scoped_release release;
    r = workflows::run_calibrate_immersed(io::build_immersed_case(document, case_file),
                                          io::Progress("calibrate", true));
  }
  py::dict result = calibration_result(r.calibration.calibration);
  result["control_point_of_particle"] = r.calibration.control_point_of_particle;
  result["held_particles"] = r.calibration.held_particles;
  result["worst_fitted_percent_e_rms"] = r.worst_fitted;
  result["worst_holdout_percent_e_rms"] = r.worst_holdout;
  return result;
}

}  // namespace

void bind_fitting(py::module_& m) {
  m.def(
      "calibrate",
      [](const io::Case& c, const py::kwargs& settings) {
        io::Case with = c;
        overlay_settings(with.calibration, settings);
        workflows::CalibrateCommandResult r;
        {
          // The fit holds no Python object: other Python threads may run meanwhile.
          py::gil_scoped_release release;
          r = workflows::run_calibrate(std::move(with), io::Progress("calibrate", true));
        }
        py::dict result = calibration_result(r.calibration);
        result["worst_fitted_percent_e_rms"] = r.worst_fitted;
        result["worst_holdout_percent_e_rms"] = r.worst_holdout;
        return result;
      },
      py::arg("case"),
      "NMSM calibration of a case against its IGA reference, as `isospring calibrate` does it "
      "(docs/calibration.md): the case's own \"calibration\" object, with keyword arguments "
      "laid over it under the same names (gamma, gamma_sweep and per_spring may also be given "
      "flat; e.g. calibrate(case, fit_load_cases=[\"L1\"], grouping={\"gamma\": 0.1})). Bad "
      "settings raise the program's error. Returns a dict: springs (s, 2), stiffness, damping, "
      "rest_length, group, positions (n, 3), masses, fixed, gamma, parameters, fit and holdout "
      "(per load case: id, control/field/surface %e metrics, node_error), warnings, "
      "fit_seconds, worst_fitted_percent_e_rms, worst_holdout_percent_e_rms.");
  m.def("calibrate_immersed", &calibrate_immersed, py::arg("case_file"),
        "NMSM calibration of an immersed case file ({\"geometry\": {\"type\": \"immersed\"}}), as "
        "`isospring calibrate` does it (docs/immersed.md, calibration): settings as for "
        "calibrate(). Returns calibrate()'s dict (particles on the grid's active control points) "
        "with control_point_of_particle and held_particles.");
}

}  // namespace isospring::python
