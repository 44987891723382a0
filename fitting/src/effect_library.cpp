// The effect library: gravity, support_compliance, stiffness_gradient, rigid_offset, load_scale
// (geometric_nonlinearity lives in effect_geometric_nonlinearity.cpp). All are linear in their
// parameters except support_compliance (log-stiffness parameters), so the forward model's
// derivatives stay exact.
#include <Eigen/Geometry>
#include <cmath>
#include <set>

#include "effect_geometric_nonlinearity.hpp"
#include "isospring/analysis/assembly.hpp"
#include "isospring/analysis/sides.hpp"
#include "isospring/fitting/effect.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

namespace {

const char* kAxes = "xyz";

class Gravity : public Effect {
 public:
  explicit Gravity(const EffectContext& context) : dimension_(context.dimension) {
    for (int c = 0; c < dimension_; ++c) {
      analysis::LoadCase unit;
      unit.gravity[c] = 1.0;
      forces_.push_back(analysis::assemble_load(*context.problem, *context.dofs, unit));
    }
  }
  std::string name() const override { return "gravity"; }
  std::vector<std::string> parameter_names() const override {
    std::vector<std::string> names;
    for (int c = 0; c < dimension_; ++c) names.push_back(std::string("g") + kAxes[c]);
    return names;
  }
  std::vector<std::string> parameter_units() const override {
    return std::vector<std::string>(static_cast<size_t>(dimension_), "m/s^2");
  }
  void add_terms(const EffectContext&, int first, ModelTerms& terms) const override {
    for (int c = 0; c < dimension_; ++c)
      terms.loads.push_back({-1, forces_[static_cast<size_t>(c)], linear_coefficient(first + c)});
  }
  std::vector<std::pair<std::string, double>> derived(
      const Eigen::VectorXd& values) const override {
    return {{"|g| [m/s^2]", values.norm()}};
  }
  std::string spring_model_note() const override {
    return "apply the fitted g to every particle (force m_i g; the lumped masses sum to rho V)";
  }

 private:
  int dimension_;
  std::vector<Eigen::VectorXd> forces_;  // load of a unit gravity along each axis
};

class SupportCompliance : public Effect {
 public:
  Eigen::VectorXd neutral_values() const override { return {}; }
  SupportCompliance(const EffectContext& context, const std::vector<size_t>& compliant)
      : reference_stiffness_(context.youngs_modulus_prior / context.length) {
    const analysis::Problem& problem = *context.problem;
    const int n = context.dofs->num_dofs();
    normal_.resize(n, n);
    tangential_.resize(n, n);
    analysis::Problem others = problem;  // the supports that stay Dirichlet
    others.supports.clear();
    for (size_t s = 0; s < problem.supports.size(); ++s) {
      if (std::find(compliant.begin(), compliant.end(), s) == compliant.end()) {
        others.supports.push_back(problem.supports[s]);
        continue;
      }
      const SideSpringMatrices springs =
          assemble_side_springs(problem, *context.dofs, problem.supports[s].side);
      normal_ += springs.normal;
      tangential_ += springs.tangential;
    }
    const analysis::Constraints kept = analysis::build_constraints(others, *context.dofs);
    const std::set<int> kept_dofs(kept.dofs.begin(), kept.dofs.end());
    for (int d : context.constraints->dofs)
      if (!kept_dofs.count(d)) released_.push_back(d);
  }
  std::string name() const override { return "support_compliance"; }
  std::vector<std::string> parameter_names() const override { return {"log_kn", "log_kt"}; }
  std::vector<std::string> parameter_units() const override {
    return {"log(k_n L / E_prior)", "log(k_t L / E_prior)"};
  }
  Eigen::VectorXd initial_values() const override {
    // Springs 100x stiffer than the body over its length: 1% extra displacement, close to the
    // Dirichlet support the case declares.
    return Eigen::VectorXd::Constant(2, std::log(100.0));
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
    terms.released_dofs.insert(terms.released_dofs.end(), released_.begin(), released_.end());
  }
  std::vector<std::pair<std::string, double>> derived(
      const Eigen::VectorXd& values) const override {
    return {{"k_n [Pa/m]", reference_stiffness_ * std::exp(values[0])},
            {"k_t [Pa/m]", reference_stiffness_ * std::exp(values[1])}};
  }
  std::string spring_model_note() const override {
    return "replace the fixed particles of the supported sides by springs to the ground with "
           "stiffness k_n A_i (normal) and k_t A_i (tangential), A_i the particle's share of the "
           "side area";
  }

 private:
  double reference_stiffness_;
  Eigen::SparseMatrix<double> normal_, tangential_;
  std::vector<int> released_;
};

class StiffnessGradient : public Effect {
 public:
  explicit StiffnessGradient(const EffectContext& context) : dimension_(context.dimension) {
    for (int c = 0; c < dimension_; ++c) {
      const Eigen::Vector3d centre = context.centre;
      const double length = context.length;
      parts_.push_back(assemble_lame_stiffness(
          *context.problem, *context.dofs,
          [c, centre, length](const Eigen::Vector3d& x) { return (x[c] - centre[c]) / length; }));
    }
  }
  std::string name() const override { return "stiffness_gradient"; }
  std::vector<std::string> parameter_names() const override {
    std::vector<std::string> names;
    for (int c = 0; c < dimension_; ++c) names.push_back(std::string("a") + kAxes[c]);
    return names;
  }
  std::vector<std::string> parameter_units() const override {
    return std::vector<std::string>(static_cast<size_t>(dimension_), "1");
  }
  void add_terms(const EffectContext& context, int first, ModelTerms& terms) const override {
    for (int c = 0; c < dimension_; ++c) {
      const LameMatrices& part = parts_[static_cast<size_t>(c)];
      terms.stiffness.push_back(
          {part.lambda_part, product(context.lambda, linear_coefficient(first + c))});
      terms.stiffness.push_back({part.mu_part, product(context.mu, linear_coefficient(first + c))});
    }
  }
  std::string spring_model_note() const override {
    return "scale every spring stiffness by 1 + a . (x_mid - x_c) / L (x_mid its midpoint), or "
           "recalibrate the springs against the corrected reference";
  }

 private:
  int dimension_;
  std::vector<LameMatrices> parts_;  // weight (x_c - centre_c) / L per axis
};

// A measuring frame's offset does not depend on the load: `shared` is one rigid motion for every
// load case; per load case (shared false) only when the specimen may have moved between them
// (re-clamped, re-seated). The F-test between the two tells a moved frame (shared) from motions
// that change with the load case (a compliant clamp moves in proportion to its load, which a
// shared motion cannot follow).
class RigidOffset : public Effect {
 public:
  RigidOffset(const EffectContext& context, bool shared)
      : dimension_(context.dimension), shared_(shared) {
    const int dim = dimension_;
    const int motions = dim == 2 ? 3 : 6;
    for (size_t l = 0; l < context.marker_positions.size(); ++l) {
      const auto& positions = context.marker_positions[l];
      const Eigen::Index rows = static_cast<Eigen::Index>(positions.size()) * dim;
      std::vector<Eigen::VectorXd> modes(static_cast<size_t>(motions), Eigen::VectorXd::Zero(rows));
      for (size_t m = 0; m < positions.size(); ++m) {
        const Eigen::Vector3d r = positions[m] - context.centre;
        const Eigen::Index row = static_cast<Eigen::Index>(m) * dim;
        for (int c = 0; c < dim; ++c) modes[static_cast<size_t>(c)][row + c] = 1.0;
        // Small rotations omega about the axes through the centre: u = omega x r.
        const int first_rotation = dim;
        for (int a = (dim == 2 ? 2 : 0); a < 3; ++a) {
          const Eigen::Vector3d u = Eigen::Vector3d::Unit(a).cross(r);
          auto& mode = modes[static_cast<size_t>(first_rotation + (dim == 2 ? 0 : a))];
          for (int c = 0; c < dim; ++c) mode[row + c] = u[c];
        }
      }
      modes_.push_back(modes);
      load_case_ids_.push_back(context.problem->load_cases[l].id);
    }
  }
  std::string name() const override { return shared_ ? "rigid_offset" : "rigid_offset_per_load"; }
  std::string simpler() const override { return shared_ ? "" : "rigid_offset"; }
  std::vector<std::string> parameter_names() const override {
    std::vector<std::string> names;
    for (size_t l = 0; l < (shared_ ? 1 : load_case_ids_.size()); ++l) {
      const std::string prefix = shared_ ? "" : load_case_ids_[l] + ".";
      for (int c = 0; c < dimension_; ++c) names.push_back(prefix + "t" + kAxes[c]);
      for (int a = (dimension_ == 2 ? 2 : 0); a < 3; ++a) names.push_back(prefix + "r" + kAxes[a]);
    }
    return names;
  }
  std::vector<std::string> parameter_units() const override {
    std::vector<std::string> units;
    for (size_t l = 0; l < (shared_ ? 1 : load_case_ids_.size()); ++l) {
      for (int c = 0; c < dimension_; ++c) units.push_back("m");
      for (int a = (dimension_ == 2 ? 2 : 0); a < 3; ++a) units.push_back("rad");
    }
    return units;
  }
  void add_terms(const EffectContext&, int first, ModelTerms& terms) const override {
    const int motions = dimension_ == 2 ? 3 : 6;
    for (size_t l = 0; l < modes_.size(); ++l) {
      int index = first + (shared_ ? 0 : static_cast<int>(l) * motions);
      for (const Eigen::VectorXd& mode : modes_[l])
        terms.offsets.push_back({static_cast<int>(l), mode, linear_coefficient(index++)});
    }
  }
  std::string spring_model_note() const override {
    return "a measurement artefact (the specimen moved in the measuring frame): nothing carries "
           "over to the spring model";
  }

 private:
  int dimension_;
  bool shared_;
  std::vector<std::vector<Eigen::VectorXd>> modes_;  // per load case: observation-space motions
  std::vector<std::string> load_case_ids_;
};

class LoadScale : public Effect {
 public:
  explicit LoadScale(const EffectContext& context) {
    const auto& cases = context.problem->load_cases;
    for (size_t l = 1; l < cases.size(); ++l) {
      ids_.push_back(cases[l].id);
      forces_.push_back(analysis::assemble_load(*context.problem, *context.dofs, cases[l]));
    }
  }
  std::string name() const override { return "load_scale"; }
  std::vector<std::string> parameter_names() const override {
    std::vector<std::string> names;
    for (const std::string& id : ids_) names.push_back(id + ".s");
    return names;
  }
  std::vector<std::string> parameter_units() const override {
    return std::vector<std::string>(ids_.size(), "1");
  }
  void add_terms(const EffectContext&, int first, ModelTerms& terms) const override {
    for (size_t k = 0; k < ids_.size(); ++k)
      terms.loads.push_back(
          {static_cast<int>(k + 1), forces_[k], linear_coefficient(first + static_cast<int>(k))});
  }
  std::string spring_model_note() const override {
    return "a measurement artefact: the load case's actual load is (1 + s) times the nominal one; "
           "apply that load to the spring model when comparing with the data";
  }

 private:
  std::vector<std::string> ids_;
  std::vector<Eigen::VectorXd> forces_;  // nominal load of load cases 2..L
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

std::vector<std::string> effect_names() {
  return {"gravity",    "support_compliance",     "stiffness_gradient",   "rigid_offset",
          "load_scale", "geometric_nonlinearity", "rigid_offset_per_load"};
}

std::unique_ptr<Effect> make_effect(const std::string& name, const EffectContext& context,
                                    std::string* why) {
  auto unavailable = [why](const std::string& reason) -> std::unique_ptr<Effect> {
    if (why) *why = reason;
    return nullptr;
  };
  if (name == "gravity") {
    if (!(context.problem->material.density > 0.0))
      return unavailable("the material has no density (set material.density)");
    return std::make_unique<Gravity>(context);
  }
  if (name == "support_compliance") {
    const std::vector<size_t> compliant = compliant_supports(context);
    if (compliant.empty())
      return unavailable("no support fixes a whole side in every direction at zero");
    return std::make_unique<SupportCompliance>(context, compliant);
  }
  if (name == "stiffness_gradient") return std::make_unique<StiffnessGradient>(context);
  if (name == "rigid_offset") return std::make_unique<RigidOffset>(context, true);
  if (name == "rigid_offset_per_load") {
    if (context.problem->load_cases.size() < 2)
      return unavailable("one load case: the same as rigid_offset");
    return std::make_unique<RigidOffset>(context, false);
  }
  if (name == "load_scale") {
    if (context.problem->load_cases.size() < 2)
      return unavailable("one load case: its load factor cannot be told apart from E");
    return std::make_unique<LoadScale>(context);
  }
  if (name == "geometric_nonlinearity") return make_geometric_nonlinearity(context);
  std::string list;
  for (const std::string& n : effect_names()) list += (list.empty() ? "" : ", ") + n;
  throw nurbs::InputError("unknown effect \"" + name + "\"; the library has: " + list);
}

}  // namespace isospring::fitting
