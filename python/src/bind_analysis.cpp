// The linear-elastic analysis (analysis module) for Python: isospring.analyze(case) solves every
// load case as `isospring analyze` does (the same library call), and isospring.field evaluates
// displacement and stress anywhere in a patch.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "bindings.hpp"
#include "isospring/analysis/post_processing.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace py = pybind11;

namespace isospring::python {
namespace {

// One (n, 3) array per patch.
std::vector<RowMatrix> per_patch(const analysis::ControlDisplacements& displacements) {
  std::vector<RowMatrix> out;
  for (const auto& patch : displacements) out.push_back(rows(patch));
  return out;
}

// Displacement, stress and von Mises stress at parameters (m, d) of one patch, for a load case
// solved on this case (the sizes are checked: a result of another case would read garbage).
py::dict field(const io::Case& c, const analysis::LoadCaseResult& result, int patch,
               const py::array_t<double>& params) {
  const auto& patches = c.problem.patches;
  if (patch < 0 || patch >= static_cast<int>(patches.size()))
    throw nurbs::InputError("field: patch " + std::to_string(patch) +
                            " out of range (the case has " + std::to_string(patches.size()) + ")");
  bool same_sizes = result.control_displacements.size() == patches.size();
  for (size_t p = 0; same_sizes && p < patches.size(); ++p)
    same_sizes =
        static_cast<int>(result.control_displacements[p].size()) == patches[p].num_points();
  if (!same_sizes)
    throw nurbs::InputError("field: the load case result was not solved on this case");
  const int d = patches[static_cast<size_t>(patch)].param_dim();
  const RowMatrix u = parameter_rows(params, d);
  RowMatrix points(u.rows(), 3), displacement(u.rows(), 3);
  py::array_t<double> stress({u.rows(), Eigen::Index{3}, Eigen::Index{3}});
  Eigen::VectorXd von_mises(u.rows());
  auto s = stress.mutable_unchecked<3>();
  for (Eigen::Index i = 0; i < u.rows(); ++i) {
    nurbs::Param param{0, 0, 0};
    for (int a = 0; a < d; ++a) param[static_cast<size_t>(a)] = u(i, a);
    const analysis::FieldPoint f =
        analysis::evaluate_field(c.problem, result.control_displacements, patch, param);
    points.row(i) = f.point.transpose();
    displacement.row(i) = f.displacement.transpose();
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) s(i, r, k) = f.stress(r, k);
    von_mises[i] = f.von_mises;
  }
  py::dict out;
  out["points"] = points;
  out["displacement"] = displacement;
  out["stress"] = stress;
  out["von_mises"] = von_mises;
  return out;
}

}  // namespace

void bind_analysis(py::module_& m) {
  py::class_<analysis::LoadCaseResult>(m, "LoadCaseResult")
      .def_readonly("id", &analysis::LoadCaseResult::id)
      .def_readonly("displacement", &analysis::LoadCaseResult::displacement,
                    "Every DOF, supported ones included (the analysis' DOF numbering).")
      .def_property_readonly(
          "control_displacements",
          [](const analysis::LoadCaseResult& r) { return per_patch(r.control_displacements); },
          "One (n, 3) array per patch: the displacement of every control point [m].")
      .def_readonly("strain_energy", &analysis::LoadCaseResult::strain_energy)
      .def_readonly("reaction_sum", &analysis::LoadCaseResult::reaction_sum)
      .def_readonly("max_displacement", &analysis::LoadCaseResult::max_displacement)
      .def_readonly("solve_seconds", &analysis::LoadCaseResult::solve_seconds);

  py::class_<analysis::StaticResult>(m, "AnalysisResult")
      .def_readonly("load_cases", &analysis::StaticResult::load_cases)
      .def_readonly("dofs", &analysis::StaticResult::dofs)
      .def_readonly("assembly_seconds", &analysis::StaticResult::assembly_seconds)
      .def_readonly("factorization_seconds", &analysis::StaticResult::factorization_seconds)
      .def(
          "__getitem__",
          [](const analysis::StaticResult& r, const std::string& id) {
            for (const auto& lc : r.load_cases)
              if (lc.id == id) return lc;
            throw py::key_error("no load case '" + id + "'");
          },
          py::arg("id"), "The result of the load case with this id.");

  m.def(
      "analyze",
      [](const io::Case& c, const std::string& solver, int threads) {
        if (solver != "cholesky" && solver != "cg" && solver != "auto")
          throw nurbs::InputError("analyze: solver must be \"cholesky\", \"cg\" or \"auto\"");
        analysis::SolverOptions options;
        options.method = solver == "cg"     ? analysis::SolverOptions::Method::kConjugateGradient
                         : solver == "auto" ? analysis::SolverOptions::Method::kAuto
                                            : analysis::SolverOptions::Method::kCholesky;
        options.threads = threads;
        // The solve holds no Python object: other Python threads may run meanwhile.
        py::gil_scoped_release release;
        return analysis::solve_static(c.problem, options);
      },
      py::arg("case"), py::arg("solver") = "cholesky", py::arg("threads") = 0,
      "Isogeometric linear elasticity of every load case of a case (one factorisation), as "
      "`isospring analyze`.");

  m.def("field", &field, py::arg("case"), py::arg("load_case"), py::arg("patch"), py::arg("params"),
        "Dict of points (m, 3), displacement (m, 3), stress (m, 3, 3) and von_mises (m,) at "
        "parameters (m, param_dim) of a patch of the case, for a LoadCaseResult of it.");
}

}  // namespace isospring::python
