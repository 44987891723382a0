// The NMSM calibration (fitting module) for Python: isospring.calibrate(case, ...) is
// fitting::calibrate with its settings as keyword arguments. The case file's own "calibration"
// object (io::read_calibration_settings, what `isospring calibrate` applies through
// io::run_calibrate) is not read here: pass the same values to reproduce the program.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "bindings.hpp"
#include "isospring/fitting/calibration.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/nurbs/error.hpp"

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

fitting::MassModel mass_model(const std::string& name) {
  if (name == "lumped") return fitting::MassModel::kLumpedIga;
  if (name == "net_cells") return fitting::MassModel::kNetCells;
  throw nurbs::InputError("calibrate: mass must be \"lumped\" or \"net_cells\"");
}

}  // namespace

void bind_fitting(py::module_& m) {
  m.def(
      "calibrate",
      [](const io::Case& c, double gamma, const std::vector<double>& gamma_sweep, bool per_spring,
         double regularization, const std::vector<std::string>& fit_load_cases,
         const std::vector<std::string>& holdout_load_cases, const std::string& mass,
         bool merge_coincident, double damping_alpha, double damping_ratio, bool upper_bounds,
         int max_iterations, int field_samples, bool matrix_approach) {
        fitting::CalibrationSettings s;
        s.gamma = gamma;
        s.gamma_sweep = gamma_sweep;
        s.per_spring = per_spring;
        s.regularization = regularization;
        s.fit_cases = fit_load_cases;
        s.holdout_cases = holdout_load_cases;
        s.mass_model = mass_model(mass);
        s.mesh.merge_coincident = merge_coincident;
        s.damping_alpha = damping_alpha;
        s.damping_ratio = damping_ratio;
        s.upper_bounds = upper_bounds;
        s.max_iterations = max_iterations;
        s.field_samples = field_samples;
        s.matrix_approach = matrix_approach;
        fitting::CalibrationResult r;
        {
          // The fit holds no Python object: other Python threads may run meanwhile.
          py::gil_scoped_release release;
          r = fitting::calibrate(c.problem, s);
        }
        return calibration_result(r);
      },
      py::arg("case"), py::kw_only(), py::arg("gamma") = 0.01,
      py::arg("gamma_sweep") = std::vector<double>{}, py::arg("per_spring") = false,
      py::arg("regularization") = 0.0, py::arg("fit_load_cases") = std::vector<std::string>{},
      py::arg("holdout_load_cases") = std::vector<std::string>{}, py::arg("mass") = "lumped",
      py::arg("merge_coincident") = false, py::arg("damping_alpha") = 0.0,
      py::arg("damping_ratio") = 0.0, py::arg("upper_bounds") = false,
      py::arg("max_iterations") = 200, py::arg("field_samples") = 11,
      py::arg("matrix_approach") = false,
      "NMSM calibration of a case against its IGA reference (docs/calibration.md; the keyword "
      "arguments are the case file's \"calibration\" fields). Returns a dict: springs (s, 2), "
      "stiffness, damping, rest_length, group, positions (n, 3), masses, fixed, gamma, "
      "parameters, fit and holdout (per load case: id, control/field/surface %e metrics, "
      "node_error), warnings, fit_seconds.");
}

}  // namespace isospring::python
