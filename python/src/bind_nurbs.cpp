// isospring.Patch and the exact refinement operations (nurbs module) for Python.
//
// Parameters come in as an (m, d) array (or one point as a length-d sequence; for a curve, a 1D
// array of m parameters), points go out as (m, 3) arrays; control points are an (n, 3) array, first
// parametric direction fastest, as in patch files.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "bindings.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/patch.hpp"
#include "isospring/nurbs/refine.hpp"

namespace py = pybind11;

namespace isospring::python {
namespace {

using nurbs::KnotVector;
using nurbs::Patch;

nurbs::Param param_row(const RowMatrix& u, Eigen::Index row) {
  nurbs::Param p{0, 0, 0};
  for (Eigen::Index a = 0; a < u.cols(); ++a) p[static_cast<size_t>(a)] = u(row, a);
  return p;
}

Patch make_patch(const std::vector<std::vector<double>>& knots, const std::vector<int>& degrees,
                 const RowMatrix& control_points, const std::vector<double>& weights) {
  if (knots.size() != degrees.size() || knots.empty() || knots.size() > 3)
    throw nurbs::InputError(
        "Patch: give one degree and one knot vector per parametric direction "
        "(1 to 3)");
  if (control_points.cols() != 3)
    throw nurbs::InputError("Patch: control_points must have shape (n, 3)");
  std::vector<KnotVector> kv;
  for (size_t d = 0; d < knots.size(); ++d)
    kv.emplace_back(degrees[d], knots[d], "Patch: knots[" + std::to_string(d) + "]");
  std::vector<Eigen::Vector3d> points;
  for (Eigen::Index i = 0; i < control_points.rows(); ++i)
    points.emplace_back(control_points.row(i).transpose());
  return Patch(std::move(kv), std::move(points), weights);
}

RowMatrix control_point_array(const Patch& patch) {
  return rows(patch.control_points());
}

// (m, 3) points, and with derivatives (m, 3, d) first derivatives: [i, :, a] = dX/du_a.
py::object evaluate(const Patch& patch, const py::array_t<double>& input, bool derivs) {
  const RowMatrix u = parameter_rows(input, patch.param_dim());
  const int d = patch.param_dim();
  py::array_t<double> points({u.rows(), Eigen::Index{3}});
  py::array_t<double> first({u.rows(), Eigen::Index{3}, Eigen::Index{d}});
  auto p = points.mutable_unchecked<2>();
  auto f = first.mutable_unchecked<3>();
  for (Eigen::Index i = 0; i < u.rows(); ++i) {
    if (!derivs) {
      const Eigen::Vector3d x = patch.point(param_row(u, i));
      for (int c = 0; c < 3; ++c) p(i, c) = x[c];
      continue;
    }
    const nurbs::PatchDerivatives der = patch.derivatives(param_row(u, i), 1);
    for (int c = 0; c < 3; ++c) {
      p(i, c) = der.point[c];
      for (int a = 0; a < d; ++a) f(i, c, a) = der.first(c, a);
    }
  }
  if (derivs) return py::make_tuple(points, first);
  return points;
}

}  // namespace

void bind_nurbs(py::module_& m) {
  py::class_<Patch>(m, "Patch",
                    "A tensor-product NURBS patch (curve, surface or volume) embedded in 3D.")
      .def(py::init([](const std::vector<int>& degrees,
                       const std::vector<std::vector<double>>& knots,
                       const RowMatrix& control_points, const std::vector<double>& weights) {
             return make_patch(knots, degrees, control_points, weights);
           }),
           py::arg("degrees"), py::arg("knots"), py::arg("control_points"),
           py::arg("weights") = std::vector<double>{},
           "Full clamped knot vectors, (n, 3) control points (first direction fastest), "
           "optional weights (all 1 when empty). Raises InputError when they disagree.")
      .def_property_readonly("param_dim", &Patch::param_dim)
      .def_property_readonly("degrees",
                             [](const Patch& p) {
                               std::vector<int> out;
                               for (int d = 0; d < p.param_dim(); ++d) out.push_back(p.degree(d));
                               return out;
                             })
      .def_property_readonly("knots",
                             [](const Patch& p) {
                               std::vector<std::vector<double>> out;
                               for (const KnotVector& k : p.all_knots()) out.push_back(k.values());
                               return out;
                             })
      .def_property_readonly(
          "shape",
          [](const Patch& p) {
            std::vector<int> out;
            for (int d = 0; d < p.param_dim(); ++d) out.push_back(p.num_points(d));
            return out;
          },
          "Control points per direction.")
      .def_property_readonly("control_points", &control_point_array, "(n, 3) array.")
      .def_property_readonly("weights", [](const Patch& p) { return p.weights(); })
      .def_property_readonly("num_elements", &Patch::num_elements)
      .def_property_readonly("is_rational", &Patch::is_rational)
      .def(
          "evaluate",
          [](const Patch& p, const py::array_t<double>& u) { return evaluate(p, u, false); },
          py::arg("params"), "Physical points (m, 3) at parameters (m, param_dim).")
      .def(
          "derivatives",
          [](const Patch& p, const py::array_t<double>& u) { return evaluate(p, u, true); },
          py::arg("params"),
          "(points (m, 3), first (m, 3, param_dim)) with first[i, :, a] = dX/du_a.")
      .def(
          "basis",
          [](const Patch& p, const std::vector<double>& u) {
            if (static_cast<int>(u.size()) != p.param_dim())
              throw nurbs::InputError("basis: give one coordinate per parametric direction");
            nurbs::Param param{0, 0, 0};
            for (size_t a = 0; a < u.size(); ++a) param[a] = u[a];
            const nurbs::RationalBasis b = p.basis(param, 1);
            return py::make_tuple(b.indices, b.values, b.first);
          },
          py::arg("u"),
          "Non-zero rational basis functions at one parameter: (control-point indices, values, "
          "first derivatives (n, param_dim)).")
      .def("__repr__", [](const Patch& p) {
        return "<isospring.Patch param_dim=" + std::to_string(p.param_dim()) +
               " control_points=" + std::to_string(p.num_points()) +
               " elements=" + std::to_string(p.num_elements()) + ">";
      });

  m.def("insert_knot", &nurbs::insert_knot, py::arg("patch"), py::arg("dir"), py::arg("u"),
        py::arg("times") = 1, "Insert the knot u `times` times in direction dir (exact).");
  m.def("refine_knots", &nurbs::refine_knots, py::arg("patch"), py::arg("dir"), py::arg("knots"),
        "Insert many knots in direction dir (exact).");
  m.def(
      "refine_uniform",
      [](const Patch& p, int splits, std::optional<int> dir) {
        return dir ? nurbs::refine_uniform(p, *dir, splits) : nurbs::refine_uniform(p, splits);
      },
      py::arg("patch"), py::arg("splits"), py::arg("dir") = py::none(),
      "Split every span (of direction dir, or of every direction) into `splits` equal spans.");
  m.def(
      "elevate_degree",
      [](const Patch& p, int times, std::optional<int> dir) {
        return dir ? nurbs::elevate_degree(p, *dir, times) : nurbs::elevate_degree(p, times);
      },
      py::arg("patch"), py::arg("times"), py::arg("dir") = py::none(),
      "Raise the degree (of direction dir, or of every direction) by `times` (exact).");
}

}  // namespace isospring::python
