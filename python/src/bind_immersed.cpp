// The immersed analysis for Python: isospring.analyze_immersed(case_file) calls
// workflows::run_analyze_immersed, the function `isospring analyze` calls for a case whose
// geometry is {"type": "immersed"}, and returns its numbers and the fields on the part's surface.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "bindings.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/immersed_case.hpp"
#include "isospring/io/json_text.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/analyze_immersed.hpp"

namespace py = pybind11;

namespace isospring::python {
namespace {

py::dict measures(const geometry::SolidMeasures& m) {
  py::dict d;
  d["volume"] = m.volume;
  d["area"] = m.area;
  d["centroid"] = Eigen::Vector3d(m.centroid);
  return d;
}

py::dict load_case(const workflows::ImmersedLoadCaseResult& lc) {
  py::dict d;
  d["id"] = lc.id;
  d["dofs"] = lc.result.dofs;
  d["strain_energy"] = lc.result.strain_energy;
  d["max_displacement"] = lc.max_displacement;
  d["max_von_mises"] = lc.max_von_mises;
  d["reaction_sum"] = Eigen::Vector3d(lc.reaction);
  d["applied_load"] = Eigen::Vector3d(lc.applied_load);
  d["iterations"] = lc.result.iterations;
  // The stabilisation the solve needed, and why it was widened (empty when it was not).
  d["ghost_fraction"] = lc.result.ghost_fraction;
  d["warnings"] = lc.result.warnings;
  d["displacement"] = rows(lc.surface_displacement);
  d["von_mises"] = Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(
      lc.surface_von_mises.data(), static_cast<Eigen::Index>(lc.surface_von_mises.size())));
  return d;
}

py::dict analyze_immersed(const std::string& case_file, const std::string& solver,
                          const std::string& volumetric) {
  using Method = analysis::SolverOptions::Method;
  if (solver != "cholesky" && solver != "cg" && solver != "auto")
    throw nurbs::InputError("analyze_immersed: solver must be \"cholesky\", \"cg\" or \"auto\"");
  const Method method = solver == "cg"     ? Method::kConjugateGradient
                        : solver == "auto" ? Method::kAuto
                                           : Method::kCholesky;
  workflows::ImmersedAnalysis a;
  {
    // The immersion and solves hold no Python object: other Python threads may run meanwhile.
    py::gil_scoped_release release;
    nlohmann::json document =
        io::parse_json_text(io::read_text_file(case_file, "case file"), case_file, "case file");
    // The argument stands for the case file's "analysis": {"volumetric": ...} and is checked by
    // the same reader, so its errors are the case file's.
    if (!volumetric.empty() && document.is_object())
      document["analysis"]["volumetric"] = volumetric;
    if (!io::is_immersed_case(document))
      throw nurbs::InputError(case_file +
                              ": geometry is not {\"type\": \"immersed\", ...}; a body-fitted "
                              "case runs with isospring.analyze(isospring.read_case(file))");
    const io::ImmersedCase c = io::build_immersed_case(document, case_file);
    a = workflows::run_analyze_immersed(c, method, io::Progress("analyze", true));
  }
  py::dict out;
  out["name"] = a.c.name;
  out["volumetric"] = io::volumetric_key(a.c.volumetric);
  out["inside_cells"] = a.stats.inside_cells;
  out["cut_cells"] = a.stats.cut_cells;
  out["opencascade"] = measures(a.occ);
  out["quadrature"] = measures(a.quadrature);
  out["points"] = rows(a.surface.points);
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> triangles(
      static_cast<Eigen::Index>(a.surface.triangles.size()), 3);
  for (size_t t = 0; t < a.surface.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      triangles(static_cast<Eigen::Index>(t), k) = a.surface.triangles[t][static_cast<size_t>(k)];
  out["triangles"] = triangles;
  out["triangle_face"] = a.surface.triangle_face;
  py::list cases;
  for (const workflows::ImmersedLoadCaseResult& lc : a.load_cases) cases.append(load_case(lc));
  out["load_cases"] = cases;
  return out;
}

}  // namespace

void bind_immersed(py::module_& m) {
  m.def("analyze_immersed", &analyze_immersed, py::arg("case_file"), py::arg("solver") = "cholesky",
        py::arg("volumetric") = "",
        "Immersed linear elasticity of a case file whose geometry is {\"type\": \"immersed\"}, as "
        "`isospring analyze` runs it: dict of the grid's inside and cut cells, the part's "
        "measures from OpenCascade and from the quadrature, the surface triangulation (points "
        "(n, 3), triangles (m, 3), triangle_face) and per load case strain_energy, "
        "max_displacement, max_von_mises, reaction_sum, applied_load, and displacement (n, 3) "
        "and von_mises (n,) at the surface points; volumetric says which formulation ran. "
        "volumetric=\"bbar\" or \"displacement\" overrides the case file's "
        "\"analysis\": {\"volumetric\"} (empty: as the case file says).");
}

}  // namespace isospring::python
