// support_compliance: the fixed sides become Robin supports, springs per area k_n (normal) and k_t
// (tangential), and k_a >= k_n for the uniform part of the normal displacement (the support's
// axial compliance; k_n acts on its rocking and the rest), fitted as log(k_n / (E_prior / L)),
// log(k_t / (E_prior / L)) and log(k_a / k_n) in [0, log 10]. Why a separate axial stiffness: a
// support made compliant by a thin bonded layer of a nearly incompressible material is stiffer
// axially (the layer is confined) than in rocking (support_spring_modes.hpp); with one k_n for
// both, a pull and a bending load case cannot both fit, and the remainder reads as a scaled load.
// Why k_a >= k_n: confinement only stiffens, and a fit step towards k_a -> 0 would free the
// body's axial translation (the stiffness was then not positive definite); at k_a = k_n the
// model is the one-stiffness support, where the fit starts.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <string>

#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/sides.hpp"
#include "isospring/fitting/effect.hpp"
#include "isospring/fitting/support_spring_modes.hpp"

namespace isospring::fitting {

namespace {

class SupportCompliance : public Effect {
 public:
  Eigen::VectorXd neutral_values() const override { return {}; }
  // Springs k = 1e5 E_prior / L: the support moves by about 1e-5 of the body's displacement,
  // far below any measurement's noise, so the model is the clamped one for the score test.
  Eigen::VectorXd screening_values() const override {
    return Eigen::Vector3d(std::log(1e5), std::log(1e5), 0.0);
  }
  SupportCompliance(const EffectContext& context, const std::vector<size_t>& compliant)
      : reference_stiffness_(context.youngs_modulus_prior / context.length) {
    const analysis::Problem& problem = *context.problem;
    const int n = context.dofs->num_dofs();
    normal_.resize(n, n);
    tangential_.resize(n, n);
    axial_.resize(n, n);
    analysis::Problem others = problem;  // the supports that stay Dirichlet
    others.supports.clear();
    for (size_t s = 0; s < problem.supports.size(); ++s) {
      if (std::find(compliant.begin(), compliant.end(), s) == compliant.end()) {
        others.supports.push_back(problem.supports[s]);
        continue;
      }
      const SideSpringMatrices springs =
          assemble_side_springs(problem, *context.dofs, problem.supports[s].side);
      const NormalSpringSplit split =
          split_normal_springs(problem, *context.dofs, problem.supports[s].side, springs.normal);
      normal_ += split.rocking + split.rest;
      axial_ += split.axial;
      tangential_ += springs.tangential;
    }
    const analysis::Constraints kept = analysis::build_constraints(others, *context.dofs);
    const std::set<int> kept_dofs(kept.dofs.begin(), kept.dofs.end());
    for (int d : context.constraints->dofs)
      if (!kept_dofs.count(d)) released_.push_back(d);
  }
  std::string name() const override { return "support_compliance"; }
  std::vector<std::string> parameter_names() const override {
    return {"log_kn", "log_kt", "log_ka_kn"};
  }
  std::vector<std::string> parameter_units() const override {
    return {"log(k_n L / E_prior)", "log(k_t L / E_prior)", "log(k_a / k_n)"};
  }
  Eigen::VectorXd initial_values() const override {
    // Springs 100x stiffer than the body over its length: 1% extra displacement, close to the
    // Dirichlet support the case declares. The axial springs start equal to the rest (k_a = k_n,
    // the one-stiffness support): on the bound, where the derivative in log(k_a / k_n) is that
    // of k_a itself, so the data pull it off the bound only once they see a confined clamp.
    return Eigen::Vector3d(std::log(100.0), std::log(100.0), 0.0);
  }
  // 0 <= log(k_a / k_n) <= log(kMaxConfinement).
  Eigen::VectorXd lower_bounds() const override {
    return Eigen::Vector3d(-kInfinity, -kInfinity, 0.0);
  }
  Eigen::VectorXd upper_bounds() const override {
    return Eigen::Vector3d(kInfinity, kInfinity, std::log(kMaxConfinement));
  }
  void add_terms(const EffectContext&, int first, ModelTerms& terms) const override {
    const double k_ref = reference_stiffness_;
    // k = k_ref exp(sum of the listed parameters): k_n = exp(log_kn), k_a = exp(log_kn +
    // log_ka_kn).
    auto exponential = [k_ref](std::vector<int> indices) -> Coefficient {
      return [k_ref, indices](const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) {
        double exponent = 0.0;
        for (int i : indices) exponent += theta[i];
        const double k = k_ref * std::exp(exponent);
        if (gradient) {
          gradient->setZero(theta.size());
          for (int i : indices) (*gradient)[i] = k;
        }
        return k;
      };
    };
    terms.stiffness.push_back({normal_, exponential({first})});
    terms.stiffness.push_back({tangential_, exponential({first + 1})});
    terms.stiffness.push_back({axial_, exponential({first, first + 2})});
    terms.released_dofs.insert(terms.released_dofs.end(), released_.begin(), released_.end());
  }
  std::vector<std::pair<std::string, double>> derived(
      const Eigen::VectorXd& values) const override {
    return {{"k_n [Pa/m]", reference_stiffness_ * std::exp(values[0])},
            {"k_t [Pa/m]", reference_stiffness_ * std::exp(values[1])},
            {"k_a [Pa/m]", reference_stiffness_ * std::exp(values[0] + values[2])}};
  }

 private:
  static constexpr double kInfinity = std::numeric_limits<double>::infinity();
  // The largest axial-to-rocking stiffness ratio the fit may reach: twice the lubrication limit
  // of an incompressible bonded strip (5, Gent and Meinecke; a disc's is 3), a guard against a
  // long first step to a rigid axial support, where the data's derivative vanishes.
  static constexpr double kMaxConfinement = 10.0;
  double reference_stiffness_;
  Eigen::SparseMatrix<double> normal_, tangential_, axial_;  // normal_: rocking and the rest
  std::vector<int> released_;
};

// Supports that can become compliant: a whole side, every in-plane component fixed at zero.
std::vector<size_t> compliant_supports(const EffectContext& context) {
  std::vector<size_t> result;
  const auto& supports = context.problem->supports;
  for (size_t s = 0; s < supports.size(); ++s) {
    const analysis::Support& support = supports[s];
    bool all_fixed = true;
    for (int c = 0; c < context.dimension; ++c) all_fixed = all_fixed && support.fixed[c];
    if (!support.control_point && !support.symmetry && all_fixed && !support.value_function &&
        support.value.isZero())
      result.push_back(s);
  }
  return result;
}

}  // namespace

EffectType support_compliance_effect_type() {
  EffectType type;
  type.name = "support_compliance";
  type.make = [](const EffectContext& context, std::string* why) -> std::unique_ptr<Effect> {
    const std::vector<size_t> compliant = compliant_supports(context);
    if (compliant.empty()) {
      if (why) *why = "no support fixes a whole side in every direction at zero";
      return nullptr;
    }
    return std::make_unique<SupportCompliance>(context, compliant);
  };
  // The spring model's supports are fixed particles (calibration.hpp); it has no springs to the
  // ground yet, so the fitted k_n, k_t, k_a stay in the report.
  type.carry_over = [](const Eigen::VectorXd&, SpringModelChanges&) {
    return CarryOverResult{CarryOver::kNotCarried,
                           "(the spring model's supported particles stay fixed; the support "
                           "motion of the reference is part of the reported error)"};
  };
  return type;
}

}  // namespace isospring::fitting
