#pragma once
// Dense kernels shared by the element loops.
#include <Eigen/Core>
#include <algorithm>

namespace isospring::analysis::detail {

// out = a b^T with Eigen's blocked matrix product, in column chunks of at most 50000 multiply-adds
// each: below that work Eigen never starts its own OpenMP team (Parallelizer.h, kMinTaskSize),
// which would oversubscribe the cores when the element loop runs serially (lazyProduct avoids the
// team too but is several times slower at these sizes).
inline void product_transpose(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b,
                              Eigen::MatrixXd& out) {
  out.setZero(a.rows(), b.rows());
  const Eigen::Index chunk =
      std::max<Eigen::Index>(1, 49999 / std::max<Eigen::Index>(1, a.rows() * b.rows()));
  for (Eigen::Index j = 0; j < a.cols(); j += chunk) {
    const Eigen::Index width = std::min(chunk, a.cols() - j);
    out.noalias() += a.middleCols(j, width) * b.middleCols(j, width).transpose();
  }
}

}  // namespace isospring::analysis::detail
