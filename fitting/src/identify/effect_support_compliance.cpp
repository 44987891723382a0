// support_compliance: the fixed sides become Robin supports, springs per area k_n (normal) and k_t
// (tangential), and k_a for the uniform part of the normal displacement (the support's axial
// compliance; k_n acts on its rocking and the rest), fitted as log(k / (E_prior / L)). Why a
// separate axial stiffness: a support made compliant by a thin bonded layer of a nearly
// incompressible material is much stiffer axially (the layer is confined) than in rocking
// (support_spring_modes.hpp); with one k_n for both, a pull and a bending load case cannot both
// fit, and the remainder reads as a scaled load.
#include <algorithm>
#include <cmath>
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
    return Eigen::VectorXd::Constant(3, std::log(1e5));
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
    return {"log_kn", "log_kt", "log_ka"};
  }
  std::vector<std::string> parameter_units() const override {
    return {"log(k_n L / E_prior)", "log(k_t L / E_prior)", "log(k_a L / E_prior)"};
  }
  Eigen::VectorXd initial_values() const override {
    // Springs 100x stiffer than the body over its length: 1% extra displacement, close to the
    // Dirichlet support the case declares.
    return Eigen::VectorXd::Constant(3, std::log(100.0));
  }
  void add_terms(const EffectContext&, int first, ModelTerms& terms) const override {
    const double k_ref = reference_stiffness_;
    auto exponential = [k_ref](int index) -> Coefficient {
      return [k_ref, index](const Eigen::VectorXd& theta, Eigen::VectorXd* gradient) {
        const double k = k_ref * std::exp(theta[index]);
        if (gradient) {
          gradient->setZero(theta.size());
          (*gradient)[index] = k;
        }
        return k;
      };
    };
    terms.stiffness.push_back({normal_, exponential(first)});
    terms.stiffness.push_back({tangential_, exponential(first + 1)});
    terms.stiffness.push_back({axial_, exponential(first + 2)});
    terms.released_dofs.insert(terms.released_dofs.end(), released_.begin(), released_.end());
  }
  std::vector<std::pair<std::string, double>> derived(
      const Eigen::VectorXd& values) const override {
    return {{"k_n [Pa/m]", reference_stiffness_ * std::exp(values[0])},
            {"k_t [Pa/m]", reference_stiffness_ * std::exp(values[1])},
            {"k_a [Pa/m]", reference_stiffness_ * std::exp(values[2])}};
  }

 private:
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
  // ground yet, so the fitted k_n, k_t stay in the report.
  type.carry_over = [](const Eigen::VectorXd&, SpringModelChanges&) {
    return CarryOverResult{CarryOver::kNotCarried,
                           "(the spring model's supported particles stay fixed; the support "
                           "motion of the reference is part of the reported error)"};
  };
  return type;
}

}  // namespace isospring::fitting
