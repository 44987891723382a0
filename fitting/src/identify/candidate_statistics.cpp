// The statistics of a candidate effect in the measured-data loop: the projection of the
// residual on its new Jacobian columns, the score test and the check of its expected values
// (loop_state.hpp).
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <exception>

#include "identify/loop_state.hpp"

namespace isospring::fitting::identify_loop {

namespace {

Eigen::Index setup_rows(const std::vector<Eigen::VectorXd>& weights) {
  Eigen::Index rows = 0;
  for (const auto& w : weights) rows += w.size();
  return rows;
}

}  // namespace

NewColumnProjection project_on_new_columns(const Setup& setup, const Model& model,
                                           const Eigen::VectorXd& theta, Eigen::Index first_new,
                                           const std::vector<Eigen::VectorXd>& weights,
                                           const std::vector<Eigen::VectorXd>* model_error) {
  NewColumnProjection out;
  const Eigen::Index total = theta.size();
  ModelEvaluation eval;
  try {
    eval = model.forward->evaluate(theta, true);
  } catch (const std::exception&) {
    return out;
  }
  const Eigen::Index rows = setup_rows(weights);
  Eigen::MatrixXd jacobian(rows, total);
  Eigen::VectorXd residual(rows);
  Eigen::VectorXd error = Eigen::VectorXd::Zero(rows);
  Eigen::Index row = 0;
  for (size_t l = 0; l < weights.size(); ++l)
    for (Eigen::Index k = 0; k < weights[l].size(); ++k, ++row) {
      jacobian.row(row) = weights[l][k] * eval.jacobians[l].row(k);
      residual[row] = weights[l][k] * (setup.measured[l][k] - eval.predictions[l][k]);
      if (model_error) error[row] = weights[l][k] * (*model_error)[l][k];
    }
  // Column scaling keeps the projection's conditioning independent of the parameters' units.
  Eigen::VectorXd scale = jacobian.colwise().norm().transpose();
  for (Eigen::Index c = 0; c < total; ++c)
    if (scale[c] > 0.0) jacobian.col(c) /= scale[c];
  const Eigen::MatrixXd earlier = jacobian.leftCols(first_new);
  Eigen::MatrixXd added = jacobian.rightCols(total - first_new);
  added -= earlier * earlier.colPivHouseholderQr().solve(added);
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(added);
  out.rank = static_cast<int>(qr.rank());
  if (out.rank == 0) return out;
  out.rss = residual.squaredNorm();
  const Eigen::VectorXd step = qr.solve(residual);
  out.residual = std::min((added * step).squaredNorm(), out.rss);
  if (model_error) out.model_error = (added * qr.solve(error)).squaredNorm();
  const Eigen::Index dof = rows - total;
  if (out.rank == added.cols() && dof > 0) {
    // The step and covariance of the new parameters are those of the regression on the
    // orthogonalised columns (Frisch-Waugh-Lovell), undone column scaling.
    const double variance = (out.rss - out.residual) / static_cast<double>(dof);
    const Eigen::MatrixXd inverse_normal =
        (added.transpose() * added)
            .ldlt()
            .solve(Eigen::MatrixXd::Identity(added.cols(), added.cols()));
    out.step.resize(added.cols());
    out.step_error.resize(added.cols());
    for (Eigen::Index c = 0; c < added.cols(); ++c) {
      const double s = scale[first_new + c] > 0.0 ? scale[first_new + c] : 1.0;
      out.step[c] = step[c] / s;
      out.step_error[c] = std::sqrt(std::max(0.0, variance * inverse_normal(c, c))) / s;
    }
  }
  out.done = true;
  return out;
}

void ScoreTest::widen(double allowance) {
  if (!done) return;
  f_statistic = std::max(0.0, (reduction - allowance) / q) / ((rss - reduction) / d2);
  p_value = f_test_p_value(f_statistic, q, d2);
}

ScoreTest score_test(const Setup& setup, const Model& candidate, const Fit& current,
                     const Eigen::VectorXd& neutral, const std::vector<Eigen::VectorXd>& weights,
                     double allowance) {
  ScoreTest out;
  const Eigen::Index p = current.theta.size();
  if (neutral.size() != candidate.forward->num_parameters() - p) return out;
  Eigen::VectorXd theta(candidate.forward->num_parameters());
  theta << current.theta, neutral;
  const NewColumnProjection projection =
      project_on_new_columns(setup, candidate, theta, p, weights, nullptr);
  if (!projection.done) return out;
  const int q = projection.rank;
  const int d2 = current.rows - static_cast<int>(p) - q;
  out.reduction = projection.residual;
  if (d2 <= 0 || !(projection.rss - out.reduction > 0.0)) return out;
  out.q = q, out.d2 = d2, out.rss = projection.rss;
  if (projection.step.size() == neutral.size()) {
    out.estimate = neutral + projection.step;
    out.estimate_error = projection.step_error;
  }
  out.done = true;
  out.widen(allowance);
  return out;
}

// The first expected value of `effect` (Effect::expected_values) that its estimated parameters
// contradict, as a note for the report; empty when every one is consistent or not estimable.
// Records the estimate in the candidate's test.
std::string contradicted_expectation(const Effect& effect, const Eigen::VectorXd& values,
                                     const Eigen::VectorXd& errors, const std::string& how,
                                     CandidateTest& test) {
  for (const ExpectedValue& expected : effect.expected_values()) {
    if (expected.index >= values.size() || expected.index >= errors.size()) continue;
    const double estimate = values[expected.index], error = errors[expected.index];
    if (!std::isfinite(estimate) || !std::isfinite(error)) continue;
    test.expected_parameter = effect.parameter_names()[static_cast<size_t>(expected.index)];
    test.expected_estimate = estimate;
    test.expected_error = error;
    if (std::abs(estimate - expected.value) <= expected.tolerance + 3.0 * error) continue;
    return "not added: " + how + " " + test.expected_parameter + " = " + std::to_string(estimate) +
           " +- " + std::to_string(error) + ", inconsistent with " +
           std::to_string(expected.value) + " (tolerance " + std::to_string(expected.tolerance) +
           " + 3 standard errors): " + expected.meaning;
  }
  return {};
}

}  // namespace isospring::fitting::identify_loop
