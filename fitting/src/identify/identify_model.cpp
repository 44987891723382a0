// ForwardModel: at most one sparse Cholesky factorisation per theta (none when only E, loads or
// offsets changed since the last one), all load cases and all parameter derivatives solved
// against it.
#include "isospring/fitting/identify_model.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "factorization_cache.hpp"
#include "free_block.hpp"

namespace isospring::fitting {

Coefficient linear_coefficient(int index, double scale) {
  return [index, scale](const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) {
    if (gradient) {
      gradient->setZero(theta.size());
      (*gradient)[index] = scale;
    }
    return scale * theta[index];
  };
}

Coefficient constant_coefficient(double value) {
  return [value](const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) {
    if (gradient) gradient->setZero(theta.size());
    return value;
  };
}

Coefficient product(Coefficient a, Coefficient b) {
  return [a, b](const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) {
    Eigen::VectorXd ga, gb;
    const double va = a(theta, gradient ? &ga : nullptr);
    const double vb = b(theta, gradient ? &gb : nullptr);
    if (gradient) *gradient = va * gb + vb * ga;
    return va * vb;
  };
}

std::shared_ptr<FactorizationCache> make_factorization_cache() {
  return std::make_shared<FactorizationCache>();
}

std::shared_ptr<FactorizationCache> copy_factorization_cache(FactorizationCache& cache) {
  auto copy = make_factorization_cache();
  const std::lock_guard<std::mutex> lock(cache.mutex);
  copy->copy_factorization(cache);
  return copy;
}

FactorizationStats factorization_stats(const FactorizationCache& cache) {
  return cache.stats;
}

FactorizationStats ForwardModel::factorization_stats() const {
  std::lock_guard<std::mutex> lock(linear_cache_->mutex);
  return linear_cache_->stats;
}

ForwardModel::ForwardModel(ModelTerms terms, std::vector<Observation> observations,
                           const std::vector<int>& constrained_dofs,
                           const std::vector<double>& constrained_values, int num_dofs,
                           int num_load_cases, std::shared_ptr<FactorizationCache> cache)
    : linear_cache_(cache ? std::move(cache) : make_factorization_cache()),
      terms_(std::move(terms)),
      observations_(std::move(observations)),
      num_dofs_(num_dofs),
      num_load_cases_(num_load_cases) {
  prescribed_.setZero(num_dofs);
  std::vector<bool> constrained(static_cast<size_t>(num_dofs), false);
  for (size_t k = 0; k < constrained_dofs.size(); ++k) {
    constrained[static_cast<size_t>(constrained_dofs[k])] = true;
    prescribed_[constrained_dofs[k]] = constrained_values[k];
  }
  for (int d : terms_.released_dofs) {
    constrained[static_cast<size_t>(d)] = false;
    prescribed_[d] = 0.0;
  }
  free_index_.assign(static_cast<size_t>(num_dofs), -1);
  for (int d = 0; d < num_dofs; ++d)
    if (!constrained[static_cast<size_t>(d)]) {
      free_index_[static_cast<size_t>(d)] = static_cast<int>(free_dofs_.size());
      free_dofs_.push_back(d);
    }
  for (const MatrixTerm& term : terms_.stiffness)
    free_blocks_.push_back(
        detail::free_upper_block(term.matrix, free_index_, static_cast<int>(free_dofs_.size())));
  if (!terms_.nonlinear.empty()) nonlinear_cache_ = make_nonlinear_cache();
  // Local terms: each touches at most 1/4 of the free DOFs, and together at most 1500 of them
  // (the dense |B| x |B| algebra of a low-rank solve then costs less than a factorisation).
  const int nf = static_cast<int>(free_dofs_.size());
  std::vector<bool> touched(static_cast<size_t>(nf), false);
  local_term_.assign(free_blocks_.size(), false);
  for (size_t j = 0; j < free_blocks_.size(); ++j) {
    std::vector<bool> rows(static_cast<size_t>(nf), false);
    int count = 0;
    for (int k = 0; k < free_blocks_[j].outerSize(); ++k)
      for (Eigen::SparseMatrix<double>::InnerIterator it(free_blocks_[j], k); it; ++it)
        for (const Eigen::Index d : {it.row(), it.col()})
          if (!rows[static_cast<size_t>(d)]) rows[static_cast<size_t>(d)] = true, ++count;
    if (count == 0 || 4 * count > nf) continue;
    local_term_[j] = true;
    for (int d = 0; d < nf; ++d)
      if (rows[static_cast<size_t>(d)]) touched[static_cast<size_t>(d)] = true;
  }
  for (int d = 0; d < nf; ++d)
    if (touched[static_cast<size_t>(d)]) local_dofs_.push_back(d);
  const bool any_global = std::count(local_term_.begin(), local_term_.end(), false) > 0;
  if (local_dofs_.size() > 1500 || 4 * static_cast<int>(local_dofs_.size()) > nf || !any_global) {
    local_term_.assign(free_blocks_.size(), false);
    local_dofs_.clear();
  }
  std::vector<int> local_index(static_cast<size_t>(nf), -1);
  for (size_t b = 0; b < local_dofs_.size(); ++b)
    local_index[static_cast<size_t>(local_dofs_[b])] = static_cast<int>(b);
  local_blocks_.resize(free_blocks_.size());
  for (size_t j = 0; j < free_blocks_.size(); ++j) {
    if (!local_term_[j]) continue;
    const auto nb = static_cast<Eigen::Index>(local_dofs_.size());
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(nb, nb);
    for (int k = 0; k < free_blocks_[j].outerSize(); ++k)
      for (Eigen::SparseMatrix<double>::InnerIterator it(free_blocks_[j], k); it; ++it) {
        const int r = local_index[static_cast<size_t>(it.row())];
        const int q = local_index[static_cast<size_t>(it.col())];
        block(r, q) = it.value();
        block(q, r) = it.value();  // the stored upper triangle, mirrored
      }
    local_blocks_[j] = std::move(block);
  }
  // Fingerprint: the free DOFs and each term's size and entries (sums of values and of their
  // position-weighted values), so that two models share a factorisation only for the same K_j.
  fingerprint_ = {static_cast<double>(num_dofs), static_cast<double>(free_dofs_.size())};
  double free_sum = 0.0;
  for (int d : free_dofs_) free_sum += static_cast<double>(d) * 1e-3;
  fingerprint_.push_back(free_sum);
  for (const auto& block : free_blocks_) {
    double sum = 0.0, weighted = 0.0;
    for (int k = 0; k < block.outerSize(); ++k)
      for (Eigen::SparseMatrix<double>::InnerIterator it(block, k); it; ++it) {
        sum += it.value();
        weighted += it.value() * (1.0 + 1e-3 * it.row() + 1e-6 * it.col());
      }
    fingerprint_.insert(fingerprint_.end(), {static_cast<double>(block.nonZeros()), sum, weighted});
  }
}

void ForwardModel::make_pattern() const {
  if (pattern_ready_) return;
  pattern_.resize(static_cast<Eigen::Index>(free_dofs_.size()),
                  static_cast<Eigen::Index>(free_dofs_.size()));
  for (const auto& block : free_blocks_) pattern_ += block;  // the union of the patterns
  pattern_.makeCompressed();
  for (const auto& block : free_blocks_) {
    std::vector<int> at(static_cast<size_t>(block.nonZeros()));
    for (Eigen::Index k = 0; k < block.outerSize(); ++k) {
      int p = pattern_.outerIndexPtr()[k];
      for (int i = block.outerIndexPtr()[k]; i < block.outerIndexPtr()[k + 1]; ++i) {
        while (pattern_.innerIndexPtr()[p] != block.innerIndexPtr()[i]) ++p;  // both sorted
        at[static_cast<size_t>(i)] = p;
      }
    }
    positions_.push_back(std::move(at));
  }
  pattern_ready_ = true;
}

void ForwardModel::load_vector(int l, const Eigen::VectorXd& theta, bool with_jacobian,
                               Eigen::VectorXd& force, Eigen::MatrixXd& dforce) const {
  force = Eigen::VectorXd::Zero(num_dofs_);
  dforce = Eigen::MatrixXd::Zero(num_dofs_, with_jacobian ? num_parameters() : 0);
  for (const VectorTerm& term : terms_.loads) {
    if (term.load_case >= 0 && term.load_case != l) continue;
    Eigen::VectorXd g;
    force += term.coefficient(theta, with_jacobian ? &g : nullptr) * term.vector;
    if (with_jacobian) dforce += term.vector * g.transpose();
  }
}

void ForwardModel::add_offsets(int l, const Eigen::VectorXd& theta, bool with_jacobian,
                               Eigen::VectorXd& y, Eigen::MatrixXd& jac) const {
  for (const VectorTerm& term : terms_.offsets) {
    if (term.load_case >= 0 && term.load_case != l) continue;
    Eigen::VectorXd g;
    y += term.coefficient(theta, with_jacobian ? &g : nullptr) * term.vector;
    if (with_jacobian) jac += term.vector * g.transpose();
  }
}

ModelEvaluation ForwardModel::evaluate(const Eigen::VectorXd& theta, bool with_jacobian) const {
  if (!terms_.nonlinear.empty()) return evaluate_nonlinear(theta, with_jacobian);
  const int p = num_parameters();
  const int nf = static_cast<int>(free_dofs_.size());
  const size_t nt = terms_.stiffness.size();
  std::vector<double> c(nt);
  std::vector<Eigen::VectorXd> dc(nt);
  for (size_t j = 0; j < nt; ++j) c[j] = terms_.stiffness[j].coefficient(theta, &dc[j]);
  FactorizationCache& cache = *linear_cache_;
  std::lock_guard<std::mutex> lock(cache.mutex);
  // K_ff = scale * (the factorised matrix): solutions are the cached factor's divided by scale.
  double scale = cache.scale_to(fingerprint_, c, {});
  // Or K_ff = scale * (K_c + U C U^T) when only local terms changed: a low-rank solve.
  // (I + C G)^-1 C, applied to the few right-hand sides of a solve (|B| x |B| LU of I + C G, and
  // C): forming the |B| x |B| product itself took 16 % of a soft-clamp run's CPU time.
  Eigen::PartialPivLU<Eigen::MatrixXd> update;
  Eigen::MatrixXd change;
  bool low_rank = false;
  if (scale == 0.0 && !local_dofs_.empty()) {
    const double s = cache.scale_to(fingerprint_, c, local_term_);
    bool same_signs = s > 0.0;
    for (size_t j = 0; j < nt && same_signs; ++j)
      if (local_term_[j] && c[j] * cache.coefficients[j] < 0.0) same_signs = false;
    if (same_signs) {
      if (!cache.low_rank_ready) {
        const auto nb = static_cast<Eigen::Index>(local_dofs_.size());
        Eigen::MatrixXd u = Eigen::MatrixXd::Zero(nf, nb);
        for (Eigen::Index b = 0; b < nb; ++b) u(local_dofs_[static_cast<size_t>(b)], b) = 1.0;
        cache.w = cache.cholesky->solve(u);
        cache.g.resize(nb, nb);
        for (Eigen::Index b = 0; b < nb; ++b)
          cache.g.row(b) = cache.w.row(local_dofs_[static_cast<size_t>(b)]);
        cache.low_rank_ready = true;
      }
      change = Eigen::MatrixXd::Zero(cache.g.rows(), cache.g.cols());
      for (size_t j = 0; j < nt; ++j)
        if (local_term_[j]) change += (c[j] / s - cache.coefficients[j]) * local_blocks_[j];
      // C (I + G C)^-1 = (I + C G)^-1 C (push-through identity).
      const Eigen::MatrixXd capacitance =
          Eigen::MatrixXd::Identity(change.rows(), change.cols()) + change * cache.g;
      update.compute(capacitance);
      // A nearly singular capacitance (springs driven towards zero: K itself nearly singular)
      // would amplify round-off: factorise anew instead, which also tests definiteness.
      if (update.rcond() > 1e-10) {
        low_rank = true;
        scale = s;
        ++cache.stats.low_rank_updates;
      }
    }
  }
  if (scale == 0.0) {
    // sum_j c_j K_j,ff on the union pattern, summed in the order of the terms (as the sparse
    // sum kff += c_j K_j,ff would: the same values on the same pattern).
    make_pattern();
    Eigen::SparseMatrix<double> kff = pattern_;
    std::fill(kff.valuePtr(), kff.valuePtr() + kff.nonZeros(), 0.0);
    for (size_t j = 0; j < nt; ++j) {
      const double* v = free_blocks_[j].valuePtr();
      const std::vector<int>& at = positions_[j];
      for (size_t i = 0; i < at.size(); ++i) kff.valuePtr()[at[i]] += c[j] * v[i];
    }
    if (!cache.factorize(kff)) {
      throw std::runtime_error(
          "the stiffness at the current parameters is not positive definite (a parameter left "
          "its physical range, e.g. a negative Young's modulus or nu >= 0.5)");
    }
    cache.fingerprint = fingerprint_;
    cache.coefficients = c;
    cache.low_rank_ready = false;
    scale = 1.0;
  } else if (!low_rank) {
    ++cache.stats.reuses;
  }
  auto solve = [&](const auto& rhs) {
    Eigen::MatrixXd x = cache.cholesky->solve(rhs);
    if (low_rank) {
      Eigen::MatrixXd at_local(static_cast<Eigen::Index>(local_dofs_.size()), x.cols());
      for (size_t b = 0; b < local_dofs_.size(); ++b)
        at_local.row(static_cast<Eigen::Index>(b)) = x.row(local_dofs_[b]);
      x -= cache.w * update.solve(change * at_local);
    }
    return (x / scale).eval();
  };

  auto to_free = [&](const Eigen::VectorXd& global) {
    Eigen::VectorXd f(nf);
    for (int k = 0; k < nf; ++k) f[k] = global[free_dofs_[static_cast<size_t>(k)]];
    return f;
  };

  // All load cases at once: one solve with a column per load case, one product of each K_j
  // with all displacements and one solve with p columns per load case for the Jacobian. A
  // supernodal solve and a sparse product stream the factor or K_j once whatever the number of
  // columns (bench_identify_model, BM_ForwardModelJacobianSolves, 3 load cases, 8 stiffness
  // terms: 61 -> 54 ms per evaluation with its Jacobian, load case by load case before).
  const int nl = num_load_cases_;
  // u = prescribed + free solution of K_ff u_f = f_f - (K u_c)_f.
  Eigen::VectorXd ku_c = Eigen::VectorXd::Zero(num_dofs_);
  if (prescribed_.squaredNorm() > 0.0)
    for (size_t j = 0; j < nt; ++j) ku_c += c[j] * (terms_.stiffness[j].matrix * prescribed_);
  std::vector<Eigen::MatrixXd> dforces(static_cast<size_t>(nl));
  Eigen::MatrixXd forces_free(nf, nl);
  for (int l = 0; l < nl; ++l) {
    Eigen::VectorXd force;
    load_vector(l, theta, with_jacobian, force, dforces[static_cast<size_t>(l)]);
    forces_free.col(l) = to_free(force - ku_c);
  }
  const Eigen::MatrixXd solutions_free = solve(forces_free);
  Eigen::MatrixXd displacements = prescribed_.replicate(1, nl);
  for (int k = 0; k < nf; ++k)
    displacements.row(free_dofs_[static_cast<size_t>(k)]) = solutions_free.row(k);

  Eigen::MatrixXd derivatives_free;  // nf x (nl p): load case l in columns l p .. l p + p - 1
  if (with_jacobian) {
    // Right-hand sides df/dtheta - dK/dtheta u (prescribed DOFs do not depend on theta).
    std::vector<Eigen::MatrixXd>& rhs = dforces;
    for (size_t j = 0; j < nt; ++j) {
      if (!(dc[j].cwiseAbs().maxCoeff() > 0.0)) continue;
      const Eigen::MatrixXd ku = terms_.stiffness[j].matrix * displacements;
      for (int l = 0; l < nl; ++l)
        for (int k = 0; k < p; ++k)
          if (dc[j][k] != 0.0) rhs[static_cast<size_t>(l)].col(k) -= dc[j][k] * ku.col(l);
    }
    Eigen::MatrixXd rhs_free(nf, static_cast<Eigen::Index>(nl) * p);
    for (int l = 0; l < nl; ++l)
      for (int k = 0; k < nf; ++k)
        rhs_free.block(k, static_cast<Eigen::Index>(l) * p, 1, p) =
            rhs[static_cast<size_t>(l)].row(free_dofs_[static_cast<size_t>(k)]);
    // Only the non-zero columns are solved (K^-1 0 = 0): parameters that act on the
    // observations alone (rigid offsets, 6 per load case) would otherwise be most of them.
    std::vector<Eigen::Index> nonzero;
    for (Eigen::Index k = 0; k < rhs_free.cols(); ++k)
      if (rhs_free.col(k).squaredNorm() > 0.0) nonzero.push_back(k);
    derivatives_free = Eigen::MatrixXd::Zero(nf, rhs_free.cols());
    if (!nonzero.empty())
      derivatives_free(Eigen::all, nonzero) = solve(Eigen::MatrixXd(rhs_free(Eigen::all, nonzero)));
  }

  return observe(displacements, derivatives_free, theta, with_jacobian);
}

// The predictions at the markers (and their Jacobians) from the displacements of every load case
// and the free DOFs' derivatives (load case l in columns l p .. l p + p - 1), offsets added.
ModelEvaluation ForwardModel::observe(const Eigen::MatrixXd& displacements,
                                      const Eigen::MatrixXd& derivatives_free,
                                      const Eigen::VectorXd& theta, bool with_jacobian) const {
  const int p = num_parameters();
  const int nf = static_cast<int>(free_dofs_.size());
  const int nl = num_load_cases_;
  ModelEvaluation out;
  for (int l = 0; l < nl; ++l) {
    Eigen::VectorXd u = displacements.col(l);
    const Eigen::SparseMatrix<double, Eigen::RowMajor>& h =
        observations_[static_cast<size_t>(l)].operator_;
    Eigen::VectorXd y = h * u;
    Eigen::MatrixXd jac;
    if (with_jacobian) {
      Eigen::MatrixXd du = Eigen::MatrixXd::Zero(num_dofs_, p);
      for (int k = 0; k < nf; ++k)
        du.row(free_dofs_[static_cast<size_t>(k)]) =
            derivatives_free.block(k, static_cast<Eigen::Index>(l) * p, 1, p);
      jac = h * du;
    }
    add_offsets(l, theta, with_jacobian, y, jac);
    out.predictions.push_back(std::move(y));
    out.jacobians.push_back(std::move(jac));
    out.displacements.push_back(std::move(u));
  }
  return out;
}

}  // namespace isospring::fitting
