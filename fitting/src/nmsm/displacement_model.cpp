// Prepared displacement objective: pattern, scatter map and symbolic factorisation built once.
#include "displacement_model.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "isospring/analysis/spring_volume.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting::detail {

namespace {

void check_data(const DisplacementFitData& data, const Grouping& grouping) {
  const int dim = data.network.dimension;
  const auto particle_dofs = static_cast<Eigen::Index>(data.network.positions.size()) * dim;
  const auto nodes = static_cast<Eigen::Index>(data.particle_of_node.size());
  if (data.loads.empty() || data.loads.size() != data.references.size())
    throw nurbs::InputError("calibration: give at least one load case with a reference");
  if (grouping.group_of_spring.size() != data.network.springs.size() || grouping.num_groups() == 0)
    throw nurbs::InputError("calibration: the stiffness grouping does not cover every spring");
  for (int g : grouping.group_of_spring)
    if (g < 0 || g >= grouping.num_groups())
      throw nurbs::InputError("calibration: a spring's stiffness group is out of range");
  for (size_t c = 0; c < data.loads.size(); ++c) {
    if (data.loads[c].size() != particle_dofs || data.references[c].size() != nodes * dim)
      throw nurbs::InputError("calibration: load case " + std::to_string(c) +
                              " has loads or reference displacements of the wrong size");
    if (!(data.references[c].cwiseAbs().maxCoeff() > 0.0) || !data.references[c].allFinite())
      throw nurbs::InputError("calibration: load case " + std::to_string(c) +
                              " has a zero or non-finite reference displacement; every fitted "
                              "load case must load the part");
  }
}

}  // namespace

DisplacementModel::DisplacementModel(const DisplacementFitData& data, const Grouping& grouping)
    : dim_(data.network.dimension),
      groups_(grouping.num_groups()),
      rows_per_case_(static_cast<int>(data.particle_of_node.size()) * data.network.dimension),
      dofs_(static_cast<int>(data.network.positions.size()) * data.network.dimension,
            analysis::constrained_dofs(data.network, data.constrained_dofs)) {
  check_data(data, grouping);
  const auto& net = data.network;
  const int nodes = static_cast<int>(data.particle_of_node.size());
  for (int a = 0; a < nodes; ++a)
    for (int d = 0; d < dim_; ++d)
      row_free_.push_back(dofs_.free_index(data.particle_of_node[a] * dim_ + d));
  for (size_t c = 0; c < data.loads.size(); ++c) {
    double o_max = 0.0;
    for (int a = 0; a < nodes; ++a)
      o_max = std::max(o_max, data.references[c].segment(a * dim_, dim_).norm());
    scale_.push_back(1.0 / (o_max * std::sqrt(static_cast<double>(nodes))));
    load_.push_back(dofs_.restrict(data.loads[c]));
  }
  scaled_reference_.resize(num_residuals());
  for (size_t c = 0; c < data.loads.size(); ++c)
    scaled_reference_.segment(static_cast<Eigen::Index>(c) * rows_per_case_, rows_per_case_) =
        scale_[c] * data.references[c];

  // Every stiffness element is rank one, K_e = k_e g_e g_e^T: a spring has g = (n on i, -n on j),
  // a volume term g = b / sqrt(|V0|) with b = dV/dx over its cell's corners (spring_volume.hpp).
  // Only free DOFs are kept; a DOF that appears twice (merged corners) is summed into one entry.
  auto add_element = [&](const std::vector<int>& particle_dofs, const Eigen::VectorXd& values,
                         int group) {
    std::vector<std::pair<int, double>> entries;
    for (size_t a = 0; a < particle_dofs.size(); ++a) {
      const int f = dofs_.free_index(particle_dofs[a]);
      if (f < 0) continue;
      auto it =
          std::find_if(entries.begin(), entries.end(), [f](const auto& e) { return e.first == f; });
      if (it == entries.end())
        entries.emplace_back(f, values[static_cast<Eigen::Index>(a)]);
      else
        it->second += values[static_cast<Eigen::Index>(a)];
    }
    for (const auto& [f, v] : entries) {
      entry_free_.push_back(f);
      entry_value_.push_back(v);
    }
    entry_begin_.push_back(static_cast<int>(entry_free_.size()));
    group_of_element_.push_back(group);
  };
  entry_begin_.push_back(0);
  for (size_t s = 0; s < net.springs.size(); ++s) {
    const analysis::Spring& spring = net.springs[s];
    Eigen::Vector3d l = net.positions[spring.i] - net.positions[spring.j];
    if (dim_ == 2) l.z() = 0.0;
    const double length = l.norm();
    const Eigen::Vector3d n = length > 0.0 ? Eigen::Vector3d(l / length) : Eigen::Vector3d::Zero();
    // Entries interleaved (i_x, j_x, i_y, j_y, ...) and the stretch below summed per component
    // as n_d (u_i,d - u_j,d): the same floating-point operations, in the same order, as before
    // volume terms existed, so plain spring fits are bit-for-bit unchanged.
    SpringData data_s;
    data_s.n = n;
    std::vector<int> particle_dofs;
    Eigen::VectorXd values(2 * dim_);
    for (int d = 0; d < 3; ++d) {
      data_s.free_i[d] = d < dim_ ? dofs_.free_index(spring.i * dim_ + d) : -1;
      data_s.free_j[d] = d < dim_ ? dofs_.free_index(spring.j * dim_ + d) : -1;
    }
    for (int d = 0; d < dim_; ++d) {
      particle_dofs.push_back(spring.i * dim_ + d);
      values[2 * d] = n[d];
      particle_dofs.push_back(spring.j * dim_ + d);
      values[2 * d + 1] = -n[d];
    }
    springs_.push_back(data_s);
    add_element(particle_dofs, values, grouping.group_of_spring[s]);
  }
  merged_begin_ = num_elements();
  if (!net.volumes.empty() && grouping.group_of_volume.size() != net.volumes.size())
    throw nurbs::InputError("calibration: the stiffness grouping does not cover every volume term");
  for (size_t v = 0; v < net.volumes.size(); ++v) {
    const analysis::VolumeTerm& term = net.volumes[v];
    const int g = grouping.group_of_volume[v];
    if (g < 0 || g >= groups_)
      throw nurbs::InputError("calibration: a volume term's group is out of range");
    // A volume term is one rank-one element; a shear term one per deviatoric strain mode, all
    // sharing its parameter.
    for (const Eigen::VectorXd& column : analysis::rest_stiffness_columns(net, term))
      add_element(analysis::volume_dofs(term, dim_), column, g);
    if (term.points.empty()) merged_begin_ = num_elements();  // strain points only after it
  }

  build_scatter();
  std::vector<int> springs_in_group(static_cast<size_t>(groups_), 0);
  for (int g : group_of_element_) ++springs_in_group[g];
  one_spring_per_group_ =
      std::all_of(springs_in_group.begin(), springs_in_group.end(), [](int n) { return n == 1; });
  merged_jacobian_ = merged_jacobian_ && !one_spring_per_group_;
  solver_.cholmod().print = 0;  // a non-positive-definite trial is reported by info(), not printed
  solver_.analyzePattern(k_);
}

bool DisplacementModel::same_dofs(int e, int f) const {
  return std::equal(
      entry_free_.begin() + entry_begin_[e], entry_free_.begin() + entry_begin_[e + 1],
      entry_free_.begin() + entry_begin_[f], entry_free_.begin() + entry_begin_[f + 1]);
}

void DisplacementModel::build_scatter() {
  const int scattered = merged_begin_;
  // K's pattern: every element's upper-triangle entries g_a g_b at (f_a, f_b), f_a <= f_b. Entries
  // with g_a g_b = 0 (a spring along an axis) stay in it, so that the pattern (and the symbolic
  // factorisation) does not depend on the stiffness values. Consecutive elements on the same
  // DOFs (a shear term's columns, a strain point's volume and shear terms) add their clique once.
  std::vector<Eigen::Triplet<double>> pattern;
  for (int e = 0; e < num_elements(); ++e) {
    if (e > 0 && same_dofs(e, e - 1)) continue;
    for (int a = entry_begin_[e]; a < entry_begin_[e + 1]; ++a)
      for (int b = entry_begin_[e]; b < entry_begin_[e + 1]; ++b)
        if (entry_free_[a] <= entry_free_[b])
          pattern.emplace_back(entry_free_[a], entry_free_[b], 1.0);
  }
  const int n = dofs_.num_free();
  k_.resize(n, n);
  k_.setFromTriplets(pattern.begin(), pattern.end());
  k_.makeCompressed();
  pattern = {};
  auto slot_of = [&](int r, int c) {
    const int* first = k_.innerIndexPtr() + k_.outerIndexPtr()[c];
    const int* last = k_.innerIndexPtr() + k_.outerIndexPtr()[c + 1];
    return static_cast<int>(std::lower_bound(first, last, r) - k_.innerIndexPtr());
  };
  // Springs and cell terms: one scatter per element, k_e g_a g_b in element order (models
  // without strain points add the same numbers in the same order as ever, bit for bit).
  begin_.push_back(0);
  for (int s = 0; s < scattered; ++s) {
    for (int a = entry_begin_[s]; a < entry_begin_[s + 1]; ++a)
      for (int b = entry_begin_[s]; b < entry_begin_[s + 1]; ++b) {
        const int r = entry_free_[a], c = entry_free_[b];
        if (r > c) continue;
        slot_.push_back(slot_of(r, c));
        coefficient_.push_back(entry_value_[a] * entry_value_[b]);
      }
    begin_.push_back(static_cast<int>(coefficient_.size()));
  }
  // Strain-point elements: K depends linearly on the parameters, K = sum_g k_g K_g, so their
  // g g^T are summed per group and K entry once here. A strain point's 6 columns of 27 x 3 DOFs
  // scatter 6 x 3,321 entries; 1,728 points (the cube at 3 per direction) made 34 million
  // multiply-adds per evaluation, now the entries of the summed K_g.
  std::vector<std::vector<int>> members(static_cast<size_t>(groups_));
  for (int e = scattered; e < num_elements(); ++e) members[group_of_element_[e]].push_back(e);
  std::vector<int> where(static_cast<size_t>(k_.nonZeros()), -1);
  std::vector<int> slots;  // the element's upper-triangle slots, kept while its DOFs repeat
  for (int g = 0; g < groups_; ++g) {
    const size_t first = term_slot_.size();
    int slots_of = -1;
    for (int e : members[g]) {
      if (slots_of < 0 || !same_dofs(e, slots_of)) {
        slots.clear();
        for (int a = entry_begin_[e]; a < entry_begin_[e + 1]; ++a)
          for (int b = entry_begin_[e]; b < entry_begin_[e + 1]; ++b)
            if (entry_free_[a] <= entry_free_[b])
              slots.push_back(slot_of(entry_free_[a], entry_free_[b]));
        slots_of = e;
      }
      size_t next = 0;
      for (int a = entry_begin_[e]; a < entry_begin_[e + 1]; ++a)
        for (int b = entry_begin_[e]; b < entry_begin_[e + 1]; ++b) {
          if (entry_free_[a] > entry_free_[b]) continue;
          const int slot = slots[next++];
          const double coefficient = entry_value_[a] * entry_value_[b];
          if (where[slot] < 0) {
            where[slot] = static_cast<int>(term_slot_.size());
            term_slot_.push_back(slot);
            term_row_.push_back(entry_free_[a]);
            term_col_.push_back(entry_free_[b]);
            term_group_.push_back(g);
            term_coefficient_.push_back(coefficient);
          } else {
            term_coefficient_[where[slot]] += coefficient;
          }
        }
    }
    for (size_t i = first; i < term_slot_.size(); ++i) where[term_slot_[i]] = -1;
  }
  // du/dtheta through the summed K_g when that visits fewer entries than the elements do. Strain
  // points grouped by rest volume may not: a group holds the points of one Gauss weight in every
  // knot span, so its K_g covers much of K. With one element per parameter, gram() and
  // dual_k_form() read every element's force: never.
  size_t element_entries = 0;
  for (int e = scattered; e < num_elements(); ++e)
    element_entries += static_cast<size_t>(entry_begin_[e + 1] - entry_begin_[e]);
  merged_jacobian_ = !term_slot_.empty() && 2 * term_slot_.size() < element_entries;
}

bool DisplacementModel::evaluate(const Eigen::VectorXd& theta, Eigen::VectorXd& residuals,
                                 Eigen::MatrixXd* jacobian) {
  const int free = dofs_.num_free();
  const auto cases = static_cast<int>(load_.size());
  const Eigen::VectorXd k_group = theta.array().exp().matrix();
  // exp overflows to inf beyond theta ~ 709 and underflows to 0 below ~ -745: both make K
  // meaningless, so the trial fails (Ceres then shortens the step).
  if (!k_group.allFinite() || !(k_group.minCoeff() > 0.0)) return false;

  // Both solvers evaluate a trial point without the Jacobian and, once it is accepted, again
  // with it: the factorisation and displacements of an unchanged theta are reused.
  if (!(factored_ && theta.size() == factored_theta_.size() && theta == factored_theta_)) {
    factored_ = false;
    factor_at_inverse_ = false;
    double* values = k_.valuePtr();
    std::fill(values, values + k_.nonZeros(), 0.0);
    for (size_t s = 0; s + 1 < begin_.size(); ++s) {
      const double k = k_group[group_of_element_[s]];
      for (int e = begin_[s]; e < begin_[s + 1]; ++e) values[slot_[e]] += k * coefficient_[e];
    }
    for (size_t i = 0; i < term_slot_.size(); ++i)
      values[term_slot_[i]] += k_group[term_group_[i]] * term_coefficient_[i];
    solver_.factorize(k_);
    // A network the spring solves would refuse as singular (groups at the stiffness floor left
    // holding a near-mechanism) is no trial point: the fit must not end where the calibrated
    // model cannot be solved. Which side of the line such a fit ended on was decided by
    // round-off (the torus of ThesisExperiments with OpenBLAS on two threads).
    constexpr double kSingularPivotRatio = 1e-13;
    if (solver_.info() != Eigen::Success || !(solver_.pivot_ratio() > kSingularPivotRatio))
      return false;
    u_.resize(static_cast<size_t>(cases));
    for (int c = 0; c < cases; ++c) {
      u_[c] = solver_.solve(load_[c]);
      if (!u_[c].allFinite()) return false;
    }
    factored_ = true;
    factored_theta_ = theta;
  }
  const std::vector<Eigen::VectorXd>& u = u_;

  residuals.resize(static_cast<Eigen::Index>(cases) * rows_per_case_);
  for (int c = 0; c < cases; ++c) {
    const Eigen::Index offset = static_cast<Eigen::Index>(c) * rows_per_case_;
    for (int row = 0; row < rows_per_case_; ++row) {
      const int f = row_free_[row];
      residuals[offset + row] =
          scale_[c] * (f >= 0 ? u[c][f] : 0.0) - scaled_reference_[offset + row];
    }
  }
  if (!jacobian) return true;

  // dK/dtheta_g u = sum_{s in g} k_s g_s (g_s^T u): column g of the right-hand side B_c.
  // du/dtheta = -K^-1 B_c. Few parameters: solve for B_c's columns. Many (per spring): the
  // residual rows of K^-1 (K is symmetric, so its columns) times the sparse B_c, which costs one
  // solve per free DOF instead of one per parameter.
  jacobian->setZero(residuals.size(), groups_);
  const bool use_inverse = groups_ * cases > free;
  Eigen::MatrixXd& inverse = inverse_;
  if (use_inverse) {
    if (identity_.rows() != free) identity_ = Eigen::MatrixXd::Identity(free, free);
    inverse = solver_.solve(identity_);
  } else
    inverse.resize(0, 0);  // gram() is only valid for the adjoint form
  factor_at_inverse_ = use_inverse;
  spring_force_.assign(static_cast<size_t>(cases), Eigen::VectorXd(num_elements()));
  // K^-1's residual rows (zero for held DOFs), gathered once: the adjoint columns are axpys.
  Eigen::MatrixXd& rows = inverse_rows_;
  if (use_inverse) {
    rows.setZero(rows_per_case_, free);
    for (int f = 0; f < free; ++f)
      for (int row = 0; row < rows_per_case_; ++row)
        if (row_free_[row] >= 0) rows(row, f) = inverse(row_free_[row], f);
  }
  for (int c = 0; c < cases; ++c) {
    const Eigen::Index offset = static_cast<Eigen::Index>(c) * rows_per_case_;
    // The element's strain g_e . u (a spring's stretch along its rest direction, a cell's
    // volume change over sqrt(|V0|)), times k, spread as g_e onto its free DOFs.
    // Each element is visited, or (merged_jacobian_) those before merged_begin_, and the strain
    // points' columns come from the summed K_g: sum_{e in g} k_g g_e (g_e^T u) = k_g K_g u.
    const int visited = merged_jacobian_ ? merged_begin_ : num_elements();
    auto for_each_entry = [&](auto&& emit) {
      for (int s = 0; s < visited; ++s) {
        double stretch = 0.0;
        if (s < static_cast<int>(springs_.size())) {
          const SpringData& sp = springs_[static_cast<size_t>(s)];
          for (int d = 0; d < dim_; ++d)
            stretch += sp.n[d] * ((sp.free_i[d] >= 0 ? u[c][sp.free_i[d]] : 0.0) -
                                  (sp.free_j[d] >= 0 ? u[c][sp.free_j[d]] : 0.0));
        } else {
          for (int a = entry_begin_[s]; a < entry_begin_[s + 1]; ++a)
            stretch += entry_value_[a] * u[c][entry_free_[a]];
        }
        const int g = group_of_element_[s];
        const double factor = k_group[g] * stretch;
        spring_force_[c][s] = factor;
        for (int a = entry_begin_[s]; a < entry_begin_[s + 1]; ++a)
          emit(entry_free_[a], g, factor * entry_value_[a]);
      }
      if (visited == num_elements()) return;
      for (size_t i = 0; i < term_slot_.size(); ++i) {
        const int g = term_group_[i], r = term_row_[i], col = term_col_[i];
        const double k = k_group[g] * term_coefficient_[i];
        emit(r, g, k * u[c][col]);
        if (r != col) emit(col, g, k * u[c][r]);
      }
    };
    if (use_inverse) {
      // J(:, g) -= scale b K^-1(residual rows, f) for every entry (f, g, b) of B_c. The entries
      // are summed per (DOF, group) first: the elements of one group share DOFs (a knot span's
      // strain points all couple its (p+1)^d control points), so the sparse B_c has far fewer
      // entries than the element loop emits, and each costs one column axpy of K^-1's rows.
      b_triplets_.clear();
      for_each_entry([&](int f, int g, double b) { b_triplets_.emplace_back(f, g, b); });
      b_sparse_.resize(free, groups_);
      b_sparse_.setFromTriplets(b_triplets_.begin(), b_triplets_.end());
      jacobian->middleRows(offset, rows_per_case_).noalias() -= scale_[c] * (rows * b_sparse_);
    } else {
      Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(free, groups_);
      for_each_entry([&](int f, int g, double b) { rhs(f, g) += b; });
      const Eigen::MatrixXd du = solver_.solve(rhs);
      for (int row = 0; row < rows_per_case_; ++row)
        if (row_free_[row] >= 0) jacobian->row(offset + row) = -scale_[c] * du.row(row_free_[row]);
    }
  }
  return jacobian->allFinite();
}

bool DisplacementModel::gram(const Eigen::VectorXd& weight, Eigen::MatrixXd& result) {
  const int free = dofs_.num_free();
  const auto cases = static_cast<int>(spring_force_.size());
  if (!one_spring_per_group_ || inverse_.rows() != free || cases == 0) return false;
  // J_c = -s_c E K^-1 B_c (E: residual rows), so J_c W J_d^T = s_c s_d E K^-1 G_cd K^-1 E^T with
  // G_cd = B_c W B_d^T = sum_s w_s (k_s stretch_s,c)(k_s stretch_s,d) g_s g_s^T: a spring matrix
  // with K's pattern. Cost: one free^3 product instead of the dense rows^2 x springs one.
  result.setZero(num_residuals(), num_residuals());
  // K^-1 G = sum_s w_s (K^-1 g_s) g_s^T, built column by column: K^-1 g_s combines <= 6 columns
  // of K^-1 and lands in <= 6 columns, all contiguous axpys (half the flops of G K^-1 through a
  // sparse G, and no index chasing).
  Eigen::MatrixXd inverse_g(free, free);
  Eigen::VectorXd column(free);
  for (int c = 0; c < cases; ++c)
    for (int d = 0; d <= c; ++d) {
      inverse_g.setZero();
      for (int s = 0; s < num_elements(); ++s) {
        const double w = weight[group_of_element_[s]] * spring_force_[c][s] * spring_force_[d][s];
        if (w == 0.0) continue;
        column.setZero();
        for (int a = entry_begin_[s]; a < entry_begin_[s + 1]; ++a)
          column += entry_value_[a] * inverse_.col(entry_free_[a]);
        for (int a = entry_begin_[s]; a < entry_begin_[s + 1]; ++a)
          inverse_g.col(entry_free_[a]) += (w * entry_value_[a]) * column;
      }
      const Eigen::MatrixXd g_inverse = inverse_g.transpose();  // G K^-1 (both symmetric)
      // K^-1 (G K^-1): through the factorisation when it is still the one of inverse_ (CHOLMOD's
      // supernodal multi-right-hand-side solve, BLAS 3), else a dense product.
      const Eigen::MatrixXd m = factor_at_inverse_ ? Eigen::MatrixXd(solver_.solve(g_inverse))
                                                   : Eigen::MatrixXd(inverse_ * g_inverse);
      const double scale = scale_[c] * scale_[d];
      // Column-major: b outer, a inner; case block (c, d), mirrored onto (d, c).
      for (int b = 0; b < rows_per_case_; ++b) {
        if (row_free_[b] < 0) continue;
        for (int a = 0; a < rows_per_case_; ++a)
          if (row_free_[a] >= 0)
            result(c * rows_per_case_ + a, d * rows_per_case_ + b) =
                scale * m(row_free_[a], row_free_[b]);
      }
      if (c != d)
        result.block(d * rows_per_case_, c * rows_per_case_, rows_per_case_, rows_per_case_) =
            result.block(c * rows_per_case_, d * rows_per_case_, rows_per_case_, rows_per_case_)
                .transpose();
    }
  return true;
}

bool DisplacementModel::dual_k_form(const Eigen::VectorXd& weight,
                                    const std::vector<Eigen::Index>& rows, Eigen::MatrixXd& k,
                                    Eigen::MatrixXd& k_squared, Eigen::MatrixXd& g) const {
  const int free = dofs_.num_free();
  if (!one_spring_per_group_ || !factor_at_inverse_ || spring_force_.size() != 1 ||
      static_cast<int>(rows.size()) != free)
    return false;
  // The row -> free DOF map must be a permutation.
  std::vector<int> dof_of_row(rows.size());
  std::vector<bool> seen(static_cast<size_t>(free), false);
  for (size_t a = 0; a < rows.size(); ++a) {
    if (rows[a] < 0 || rows[a] >= rows_per_case_) return false;
    const int f = row_free_[static_cast<size_t>(rows[a])];
    if (f < 0 || seen[static_cast<size_t>(f)]) return false;
    seen[static_cast<size_t>(f)] = true;
    dof_of_row[a] = f;
  }
  // Everything in row order: the row of free DOF f is position_of_dof[f].
  std::vector<int> position_of_dof(static_cast<size_t>(free));
  for (int a = 0; a < free; ++a) position_of_dof[static_cast<size_t>(dof_of_row[a])] = a;
  // k_ holds K at the Jacobian's point while factor_at_inverse_ (the solver's factorisation).
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> permutation(free);
  for (int f = 0; f < free; ++f) permutation.indices()[f] = position_of_dof[static_cast<size_t>(f)];
  Eigen::SparseMatrix<double> k_rows;
  k_rows = k_.selfadjointView<Eigen::Upper>().twistedBy(permutation);  // P K P^T, both triangles
  k = k_rows;
  k_squared = Eigen::SparseMatrix<double>(k_rows * k_rows);
  // s^2 P B W B^T P^T: per spring s^2 w_s (k_s g_s^T u)^2 g_s g_s^T.
  const double scale = scale_[0] * scale_[0];
  g.setZero(free, free);
  for (int s = 0; s < num_elements(); ++s) {
    const double force = spring_force_[0][s];
    const double w = scale * weight[group_of_element_[s]] * force * force;
    if (w == 0.0) continue;
    for (int b = entry_begin_[s]; b < entry_begin_[s + 1]; ++b)
      for (int a = entry_begin_[s]; a < entry_begin_[s + 1]; ++a)
        g(position_of_dof[entry_free_[a]], position_of_dof[entry_free_[b]]) +=
            w * entry_value_[a] * entry_value_[b];
  }
  return true;
}

std::vector<double> DisplacementModel::percent_e_max(const Eigen::VectorXd& residuals) const {
  // r = (u - u_ref) / (o_max sqrt(n)), so 100 |r_a| sqrt(n) = 100 |u_a - u_ref,a| / o_max.
  const int nodes = rows_per_case_ / dim_;
  std::vector<double> result;
  for (size_t c = 0; c < scale_.size(); ++c) {
    double worst = 0.0;
    for (int a = 0; a < nodes; ++a)
      worst = std::max(
          worst,
          residuals.segment(static_cast<Eigen::Index>(c) * rows_per_case_ + a * dim_, dim_).norm());
    result.push_back(100.0 * worst * std::sqrt(static_cast<double>(nodes)));
  }
  return result;
}

}  // namespace isospring::fitting::detail
