// Calibration of the machine, not of isospring: the same two workloads every time, built only on
// the libraries isospring uses (Eigen's dense kernels and CHOLMOD through Eigen). Timings of the
// project's own benchmarks change when its code changes; these do not, so a run printed beside
// them says whether the machine (its load, its clock, its BLAS) was the one of an earlier report.
//
//   BM_CalibrationDenseProduct: C = A B for dense 512 x 512 matrices (Eigen's GEMM kernel, the
//     kernel of the element routines' dense products).
//   BM_CalibrationSparseCholesky: CHOLMOD's supernodal factorisation and one solve of the
//     7-point Laplacian on a 32 x 32 x 32 grid plus the identity (32,768 unknowns, a 3D stiffness
//     matrix's pattern and fill), the kernel of every static solve.
#include <benchmark/benchmark.h>
#include <Eigen/CholmodSupport>
#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <vector>

namespace {

void BM_CalibrationDenseProduct(benchmark::State& state) {
  const Eigen::Index n = 512;
  // Fixed, well-scaled entries (no random state: every run multiplies the same numbers).
  const Eigen::MatrixXd a = Eigen::MatrixXd::NullaryExpr(n, n, [](Eigen::Index i, Eigen::Index j) {
    return 1.0 / double(1 + ((i * 7 + j * 13) % 97));
  });
  const Eigen::MatrixXd b = a.transpose();
  Eigen::MatrixXd c(n, n);
  for (auto _ : state) {
    c.noalias() = a * b;
    benchmark::DoNotOptimize(c.data());
    benchmark::ClobberMemory();
  }
  state.counters["GFLOPs"] = benchmark::Counter(2.0 * double(n) * double(n) * double(n),
                                                benchmark::Counter::kIsIterationInvariantRate,
                                                benchmark::Counter::kIs1000);
}
BENCHMARK(BM_CalibrationDenseProduct)->Unit(benchmark::kMillisecond);

Eigen::SparseMatrix<double> shifted_laplacian(int m) {
  const auto index = [m](int i, int j, int k) { return (i * m + j) * m + k; };
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(std::size_t(7) * std::size_t(m * m * m));
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      for (int k = 0; k < m; ++k) {
        const int row = index(i, j, k);
        entries.emplace_back(row, row, 7.0);
        if (i + 1 < m) entries.emplace_back(row, index(i + 1, j, k), -1.0);
        if (j + 1 < m) entries.emplace_back(row, index(i, j + 1, k), -1.0);
        if (k + 1 < m) entries.emplace_back(row, index(i, j, k + 1), -1.0);
      }
  Eigen::SparseMatrix<double> upper(m * m * m, m * m * m);
  upper.setFromTriplets(entries.begin(), entries.end());
  return upper;
}

void BM_CalibrationSparseCholesky(benchmark::State& state) {
  const Eigen::SparseMatrix<double> upper = shifted_laplacian(32);
  const Eigen::VectorXd rhs = Eigen::VectorXd::Ones(upper.rows());
  for (auto _ : state) {
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> cholesky(upper);
    if (cholesky.info() != Eigen::Success) {
      state.SkipWithError("CHOLMOD could not factorise the calibration matrix");
      return;
    }
    Eigen::VectorXd x = cholesky.solve(rhs);
    benchmark::DoNotOptimize(x.data());
  }
}
BENCHMARK(BM_CalibrationSparseCholesky)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
