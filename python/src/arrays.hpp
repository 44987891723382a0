#pragma once
// numpy <-> Eigen conversions shared by the bindings.
#include <pybind11/numpy.h>

#include <Eigen/Core>
#include <vector>

namespace isospring::python {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Parameters as an (m, param_dim) matrix. A 1D input is m parameters of a curve
/// (param_dim == 1) and otherwise one point; the width must be param_dim, so that a (u, v) pair
/// is never silently read as two curve parameters. InputError otherwise, and for NaN or inf.
RowMatrix parameter_rows(const pybind11::array_t<double>& input, int param_dim);

/// Vectors as the rows of an (n, 3) matrix.
RowMatrix rows(const std::vector<Eigen::Vector3d>& vectors);

}  // namespace isospring::python
