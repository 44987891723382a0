#pragma once
// Effects: physics the nominal model may miss (self-weight, compliant supports, a stiffness
// gradient, rigid motion of the measuring frame, wrong load factors). Each effect adds parameters
// and terms to the identification's forward model (identify_model.hpp) and carries its fitted
// values over into the spring model's recalibration (identify_recalibration.hpp).
//
// The library is a registry (effect_types()): one EffectType per effect, defined in the effect's
// own file fitting/src/identify/effect_<name>.cpp, listed once in
// fitting/src/identify/effect_registry.cpp. Library, in registry order:
//   gravity             self-weight rho * g of the declared density; g (2 or 3 components) fitted
//   support_compliance  the fixed sides become Robin supports: springs per area k_n (normal) and
//                       k_t (tangential), fitted as log(k / (E_prior / L)), and k_a >= k_n on the
//                       uniform part of the normal displacement (a confined layer's axial
//                       stiffness), fitted as log(k_a / k_n) in [0, log 10]
//   stiffness_gradient  E(x) = E (1 + a . (x - x_c) / L), a fitted (2 or 3 components)
//   rigid_offset        rigid motion of the specimen in the measuring frame, one for all load
//                       cases (a frame offset does not depend on the load): translations and
//                       small rotations about x_c (2D: 2 + 1, 3D: 3 + 3)
//   load_scale          actual load factor (1 + s_l) of every load case but the first (the first
//                       one's is not separable from E)
//   geometric_nonlinearity  large deformation: total Lagrangian St. Venant-Kirchhoff solved by
//                       Newton; the prediction blends the linear and SVK solutions with a fitted
//                       weight w (0 linear, 1 SVK) so the linear model is nested and the F-test
//                       applies (effect_geometric_nonlinearity.cpp says why)
//   rigid_offset_per_load  a rigid motion per load case (the specimen moved between them); a
//                       compliant clamp also moves per load case, in proportion to the load,
//                       so a moved frame is told apart by the shared rigid_offset fitting as
//                       well, and a clamp by support_compliance fitting better
// x_c is the centre and L the diagonal of the model's bounding box.
#include <Eigen/Core>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/problem.hpp"
#include "isospring/fitting/identify_assembly.hpp"
#include "isospring/fitting/identify_model.hpp"

namespace isospring::fitting {

/// A value one of an effect's parameters must take for the effect to mean what it says (the
/// blend weight of geometric_nonlinearity is 1: SVK has no free parameter). A candidate whose
/// estimate is inconsistent with it, |estimate - value| > tolerance + 3 standard errors, fits the
/// data for another reason and is not added.
struct ExpectedValue {
  int index = 0;           // within the effect's parameters
  double value = 0.0;      // what the physics fixes
  double tolerance = 0.0;  // modelling allowance beyond the statistical error (absolute)
  std::string meaning;     // for the report: what a departure says
};

/// The loads of a model that is not a body-fitted analysis::Problem (an immersed part,
/// identify_immersed.hpp): what the load effects read through the functions below instead of
/// `problem`, and which effects have no form for such a model.
struct ModelLoads {
  std::vector<std::string> case_ids;
  std::vector<Eigen::VectorXd> case_forces;   // per load case, nominal force over all DOFs
  std::vector<Eigen::VectorXd> unit_gravity;  // per axis: the self-weight of g = e_c
  double density = 0.0;
  /// Why the named effect has no form for this model; empty when it has one.
  std::function<std::string(const std::string& effect)> unavailable;
};

/// What effects see of the problem and the data.
struct EffectContext {
  const analysis::Problem* problem = nullptr;  // null for a model given by `loads`
  const ModelLoads* loads = nullptr;           // set exactly when `problem` is null
  const analysis::DofMap* dofs = nullptr;
  const analysis::Constraints* constraints = nullptr;
  const LameMatrices* stiffness = nullptr;  // homogeneous Lame parts
  int dimension = 3;
  /// Per load case: the positions of its markers (observation row = marker * dimension + c).
  std::vector<std::vector<Eigen::Vector3d>> marker_positions;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // bounding-box centre of the model
  double length = 1.0;                               // bounding-box diagonal of the model
  double youngs_modulus_prior = 0.0;
  Coefficient lambda;  // Lame parameters as functions of theta (material parameters)
  Coefficient mu;
  /// Threads for an effect's element loops (>= 1; IdentifyOptions::threads).
  int threads = 1;
};

/// The model's load case ids, nominal force of load case l, self-weight of a unit gravity along
/// axis c and density: from `problem` (assembled) or from `loads` (effect_context.cpp).
std::vector<std::string> load_case_ids(const EffectContext& context);
Eigen::VectorXd load_case_force(const EffectContext& context, size_t l);
Eigen::VectorXd unit_gravity_force(const EffectContext& context, int c);
double model_density(const EffectContext& context);

class Effect {
 public:
  virtual ~Effect() = default;
  virtual std::string name() const = 0;
  virtual std::vector<std::string> parameter_names() const = 0;
  /// Units of the parameters as printed in reports ("m/s^2", "1", ...).
  virtual std::vector<std::string> parameter_units() const = 0;
  int num_parameters() const { return static_cast<int>(parameter_names().size()); }
  /// Starting values: the effect switched off (or, for compliance, nearly rigid).
  virtual Eigen::VectorXd initial_values() const { return Eigen::VectorXd::Zero(num_parameters()); }
  /// Values at which the effect vanishes (the model equals the one without it), for the score
  /// screening of expensive candidates; empty when there are none (a compliance is rigid only
  /// in the limit).
  virtual Eigen::VectorXd neutral_values() const { return Eigen::VectorXd::Zero(num_parameters()); }
  /// Where the score screening of the selection tests the candidate: its neutral values, or,
  /// for an effect that vanishes only in a limit, values where it is negligible against any
  /// noise (support springs 1e5 x stiffer than the body: 1e-5 of its displacement). Empty: the
  /// candidate is always fitted.
  virtual Eigen::VectorXd screening_values() const { return neutral_values(); }
  /// The name of a nested special case with fewer parameters (rigid_offset_per_load ->
  /// rigid_offset), or empty: the backward step of the selection tries the simpler one in its
  /// place.
  virtual std::string simpler() const { return {}; }
  /// True for an effect whose model needs Newton solves (geometric_nonlinearity): the selection
  /// tries it after the linear candidates and only when a score test says it may matter.
  virtual bool expensive() const { return false; }
  /// Box bounds of the parameters, each of size num_parameters() (+-infinity: free); the fits
  /// stay inside. For a parameter whose physics has a side (a stiffness ratio >= 1).
  virtual Eigen::VectorXd lower_bounds() const {
    return Eigen::VectorXd::Constant(num_parameters(), -std::numeric_limits<double>::infinity());
  }
  virtual Eigen::VectorXd upper_bounds() const {
    return Eigen::VectorXd::Constant(num_parameters(), std::numeric_limits<double>::infinity());
  }
  /// Parameters the physics fixes (see ExpectedValue); empty for effects whose parameters are
  /// all free (a gravity vector, a modulus gradient).
  virtual std::vector<ExpectedValue> expected_values() const { return {}; }
  /// Adds the effect's terms; its parameters are theta[first .. first + num_parameters()).
  virtual void add_terms(const EffectContext& context, int first, ModelTerms& terms) const = 0;
  /// Reportable values from the fitted parameters (e.g. k = k_ref exp(p)): name -> value.
  virtual std::vector<std::pair<std::string, double>> derived(const Eigen::VectorXd& values) const {
    (void)values;
    return {};
  }
};

/// What carrying effects over may change in the recalibration of the spring model
/// (recalibrate_identified): the corrected problem's loads and the calibration's mass model.
struct SpringModelChanges {
  /// Added to every load case; the spring model's particles get m_i g.
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  /// Per load case: every declared load of the case is scaled by it. Shorter than the load cases
  /// (or empty): the rest are 1.
  std::vector<double> load_factors;
  /// The calibration uses row-sum lumped masses (MassModel::kLumpedIga): m_i g is then exactly the
  /// consistent self-weight the springs were fitted under.
  bool lumped_masses = false;
};

/// How an effect reached the spring model.
enum class CarryOver {
  kModel,       // it changed SpringModelChanges (the corrected problem the springs are fitted to)
  kReference,   // only through the corrected reference displacements the springs are fitted to
  kNotCarried,  // the spring model has no counterpart; what it moves shows up in %e_rms
};

struct CarryOverResult {
  CarryOver how = CarryOver::kNotCarried;
  std::string detail;  // what was done, for people (no name, no "carried" prefix)
};

/// One effect of the library: everything identify and the recalibration need of it.
struct EffectType {
  std::string name;
  /// Builds the effect for this context, or returns nullptr with `why` set when it cannot apply
  /// here (e.g. gravity without a density, load_scale with one load case).
  std::function<std::unique_ptr<Effect>(const EffectContext& context, std::string* why)> make;
  /// Carries the fitted values into `changes` and says what it did. It is the only source of the
  /// spring-model notes (identify's and the recalibration's), so a note cannot claim a carry-over
  /// that is not done. Needs no context: the recalibration has only names and values.
  std::function<CarryOverResult(const Eigen::VectorXd& values, SpringModelChanges& changes)>
      carry_over;
};

/// The effect library, in the order identify tries the candidates.
const std::vector<EffectType>& effect_types();

/// The registered type of that name; throws nurbs::InputError for an unknown name, listing the
/// library.
const EffectType& effect_type(const std::string& name);

/// Names of the effect library, in registry order.
std::vector<std::string> effect_names();

/// The named effect for this context (effect_type(name).make). Throws nurbs::InputError for an
/// unknown name.
std::unique_ptr<Effect> make_effect(const std::string& name, const EffectContext& context,
                                    std::string* why);

/// Carries one effect's fitted values into `changes`; returns the note "name: carried ..." that
/// says what was done (the "how" decides the words: "carried into the model", "carried by the
/// reference", "NOT carried").
std::string carry_over(const std::string& name, const Eigen::VectorXd& values,
                       SpringModelChanges& changes);

}  // namespace isospring::fitting
