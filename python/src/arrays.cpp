// numpy <-> Eigen conversions shared by the bindings; see arrays.hpp.
#include "arrays.hpp"

#include <string>

#include "isospring/nurbs/error.hpp"

namespace py = pybind11;

namespace isospring::python {

RowMatrix parameter_rows(const py::array_t<double>& input, int param_dim) {
  const py::buffer_info info = input.request();
  if (info.ndim != 1 && info.ndim != 2)
    throw nurbs::InputError("parameters: expected an array of shape (m, " +
                            std::to_string(param_dim) + ") or one point");
  const py::array_t<double, py::array::c_style | py::array::forcecast> c(input);
  const bool curve_list = info.ndim == 1 && param_dim == 1;
  const auto points = info.ndim == 2 ? info.shape[0] : curve_list ? info.shape[0] : 1;
  const auto width = info.ndim == 2 ? info.shape[1] : curve_list ? 1 : info.shape[0];
  if (width != param_dim)
    throw nurbs::InputError("parameters: " + std::to_string(width) +
                            " coordinates per point, but the patch has parametric dimension " +
                            std::to_string(param_dim));
  RowMatrix u = Eigen::Map<const RowMatrix>(c.data(), points, width);
  // The library clamps parameters into the knot range but cannot place NaN or inf anywhere.
  if (!u.allFinite()) throw nurbs::InputError("parameters: NaN or inf");
  return u;
}

RowMatrix rows(const std::vector<Eigen::Vector3d>& vectors) {
  RowMatrix out(static_cast<Eigen::Index>(vectors.size()), 3);
  for (size_t i = 0; i < vectors.size(); ++i)
    out.row(static_cast<Eigen::Index>(i)) = vectors[i].transpose();
  return out;
}

}  // namespace isospring::python
