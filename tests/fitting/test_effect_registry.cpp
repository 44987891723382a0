// The effect registry: every registered effect builds under its own name, and the note it writes
// for the spring model says what its carry-over does (a "NOT carried" effect changes nothing in
// the recalibration's inputs, a "carried" one changes them).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <set>

#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/elasticity.hpp"
#include "isospring/fitting/effect.hpp"
#include "isospring/fitting/identify_assembly.hpp"
#include "isospring/fitting/identify_model.hpp"
#include "isospring/nurbs/error.hpp"
#include "test_identify_plate.hpp"

namespace isospring::fitting {
namespace {

bool unchanged(const SpringModelChanges& c) {
  bool factors_one = true;
  for (const double f : c.load_factors) factors_one = factors_one && f == 1.0;
  return c.gravity.isZero(0.0) && factors_one && !c.lumped_masses;
}

// The plate of the identify tests (density, two load cases, a fully clamped side): every effect
// of the library applies to it.
struct PlateContext {
  analysis::Problem problem = testing::plate_problem();
  analysis::DofMap dofs{problem};
  analysis::Constraints constraints = analysis::build_constraints(problem, dofs);
  LameMatrices lame = assemble_lame_stiffness(problem, dofs);
  EffectContext context;
  PlateContext() {
    context.problem = &problem;
    context.dofs = &dofs;
    context.constraints = &constraints;
    context.stiffness = &lame;
    context.dimension = 2;
    std::vector<Eigen::Vector3d> positions;
    for (const Marker& m : testing::grid_markers(problem, 3, 2))
      if (m.load_case == problem.load_cases[0].id) positions.push_back(m.position);
    context.marker_positions.assign(problem.load_cases.size(), positions);
    context.centre = Eigen::Vector3d(0.05, 0.02, 0.0);
    context.length = std::hypot(0.1, 0.04);
    context.youngs_modulus_prior = problem.material.youngs_modulus;
    context.lambda = linear_coefficient(0);
    context.mu = linear_coefficient(0);
  }
};

TEST(EffectRegistry, NamesAreTheRegistryInOrderAndUnique) {
  const std::vector<std::string> names = effect_names();
  ASSERT_EQ(names.size(), effect_types().size());
  for (size_t k = 0; k < names.size(); ++k) EXPECT_EQ(names[k], effect_types()[k].name);
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  // identify's candidate order: appending keeps the selection of existing cases.
  const std::vector<std::string> first{
      "gravity",    "support_compliance",     "stiffness_gradient",   "rigid_offset",
      "load_scale", "geometric_nonlinearity", "rigid_offset_per_load"};
  ASSERT_GE(names.size(), first.size());
  EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + first.size()), first);
}

TEST(EffectRegistry, UnknownNameListsTheLibrary) {
  try {
    effect_type("magic");
    FAIL() << "expected an InputError";
  } catch (const nurbs::InputError& e) {
    const std::string what = e.what();
    for (const std::string& name : effect_names())
      EXPECT_NE(what.find(name), std::string::npos) << what;
  }
  SpringModelChanges changes;
  EXPECT_THROW(carry_over("magic", Eigen::VectorXd(), changes), nurbs::InputError);
}

TEST(EffectRegistry, EveryEffectBuildsUnderItsNameAndItsNoteMatchesItsCarryOver) {
  const PlateContext plate;
  for (const EffectType& type : effect_types()) {
    SCOPED_TRACE(type.name);
    ASSERT_TRUE(type.make) << "no factory";
    ASSERT_TRUE(type.carry_over) << "no carry-over";
    std::string why;
    const std::unique_ptr<Effect> effect = type.make(plate.context, &why);
    ASSERT_NE(effect, nullptr) << why;
    EXPECT_EQ(effect->name(), type.name);
    EXPECT_EQ(effect->parameter_units().size(), effect->parameter_names().size());

    // Fitted values away from the neutral ones: an effect that carries anything changes it here.
    const Eigen::VectorXd values = Eigen::VectorXd::Constant(effect->num_parameters(), 0.25);
    SpringModelChanges changes;
    const CarryOverResult result = type.carry_over(values, changes);
    SpringModelChanges again;
    const std::string note = carry_over(type.name, values, again);
    EXPECT_EQ(note.rfind(type.name + ": ", 0), 0u) << note;
    EXPECT_NE(note.find(result.detail), std::string::npos) << note;
    switch (result.how) {
      case CarryOver::kModel:
        EXPECT_FALSE(unchanged(changes)) << "says carried into the model, changed nothing";
        EXPECT_EQ(note.find("NOT carried"), std::string::npos) << note;
        break;
      case CarryOver::kReference:
        EXPECT_TRUE(unchanged(changes)) << "says carried by the reference, changed the model";
        EXPECT_NE(note.find("carried by the reference"), std::string::npos) << note;
        break;
      case CarryOver::kNotCarried:
        EXPECT_TRUE(unchanged(changes)) << "says not carried, changed the model";
        EXPECT_NE(note.find("NOT carried"), std::string::npos) << note;
        break;
    }
  }
}

// Every effect's bounds have one entry per parameter and hold its initial and screening values
// (a fit cannot start outside its box).
TEST(EffectRegistry, BoundsHoldTheStartingValues) {
  const PlateContext plate;
  for (const EffectType& type : effect_types()) {
    SCOPED_TRACE(type.name);
    const std::unique_ptr<Effect> effect = type.make(plate.context, nullptr);
    ASSERT_NE(effect, nullptr);
    const Eigen::VectorXd lower = effect->lower_bounds(), upper = effect->upper_bounds();
    ASSERT_EQ(lower.size(), effect->num_parameters());
    ASSERT_EQ(upper.size(), effect->num_parameters());
    EXPECT_TRUE((lower.array() < upper.array()).all());
    for (const Eigen::VectorXd& start : {effect->initial_values(), effect->screening_values()}) {
      if (start.size() == 0) continue;
      EXPECT_TRUE((start.array() >= lower.array()).all()) << start.transpose();
      EXPECT_TRUE((start.array() <= upper.array()).all()) << start.transpose();
    }
  }
}

// support_compliance's axial springs: k_a = k_n exp(r) with 0 <= r <= log 10 on the uniform part
// of the normal displacement. At r = 0 (where the fit starts) the springs are exactly the
// one-stiffness support k_n N + k_t T; for every r in the box they exceed it by a positive
// semi-definite term, so the clamped body's stiffness stays positive definite however soft
// the springs (a free k_a -> 0 freed the axial translation).
TEST(EffectRegistry, SupportComplianceAxialStiffnessIsBoundedBelowByTheNormalOne) {
  const PlateContext plate;
  const std::unique_ptr<Effect> effect = make_effect("support_compliance", plate.context, nullptr);
  ASSERT_NE(effect, nullptr);
  ASSERT_EQ(effect->num_parameters(), 3);
  EXPECT_EQ(effect->lower_bounds()[2], 0.0);
  EXPECT_NEAR(effect->upper_bounds()[2], std::log(10.0), 1e-15);
  EXPECT_EQ(effect->initial_values()[2], 0.0);
  ModelTerms terms;
  terms.num_parameters = 4;  // E, then the effect's three
  effect->add_terms(plate.context, 1, terms);
  ASSERT_EQ(terms.stiffness.size(), 3u);
  const auto springs_at = [&](const Eigen::VectorXd& theta) {
    Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(plate.dofs.num_dofs(), plate.dofs.num_dofs());
    for (const MatrixTerm& term : terms.stiffness)
      sum += term.coefficient(theta, nullptr) * Eigen::MatrixXd(term.matrix);
    return sum;
  };
  const SideSpringMatrices side =
      assemble_side_springs(plate.problem, plate.dofs, plate.problem.supports[0].side);
  const double k_ref = plate.context.youngs_modulus_prior / plate.context.length;
  // The body with its clamp released: free to move rigidly (3 zero modes) without springs.
  const auto lame = analysis::lame_parameters(plate.problem.material, plate.problem.formulation);
  const Eigen::MatrixXd body = lame.lambda * Eigen::MatrixXd(plate.lame.lambda_part) +
                               lame.mu * Eigen::MatrixXd(plate.lame.mu_part);
  const auto eigenvalues = [](const Eigen::MatrixXd& m) {
    return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(m, Eigen::EigenvaluesOnly).eigenvalues();
  };
  const Eigen::VectorXd free_body = eigenvalues(body);
  EXPECT_LT(std::abs(free_body[2]), 1e-12 * free_body.maxCoeff());
  for (const double log_kn : {-8.0, 0.0, 5.0}) {
    const Eigen::MatrixXd one_stiffness =
        k_ref * std::exp(log_kn) * Eigen::MatrixXd(side.normal) +
        k_ref * std::exp(log_kn - 1.0) * Eigen::MatrixXd(side.tangential);
    const double scale = one_stiffness.norm();
    const Eigen::MatrixXd at_bound = springs_at(Eigen::Vector4d(1.0, log_kn, log_kn - 1.0, 0.0));
    EXPECT_LT((at_bound - one_stiffness).norm(), 1e-13 * scale) << log_kn;
    for (const double r : {0.5, std::log(10.0)}) {
      const Eigen::MatrixXd extra =
          springs_at(Eigen::Vector4d(1.0, log_kn, log_kn - 1.0, r)) - one_stiffness;
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(extra);
      EXPECT_GT(eig.eigenvalues().minCoeff(), -1e-13 * scale) << log_kn << " " << r;
      EXPECT_GT(eig.eigenvalues().maxCoeff(), 1e-3 * (std::exp(r) - 1.0) * scale) << r;
    }
    // Springs 3e-4 x E / L (log_kn = -8) at r = 0 already hold the body: positive definite, and
    // every r > 0 only adds to it.
    const Eigen::VectorXd held = eigenvalues(body + at_bound);
    EXPECT_GT(held.minCoeff(), 1e-9 * held.maxCoeff()) << log_kn;
  }
}

// The wart: support_compliance's note said "springs to the ground" while the
// recalibration kept the supports fixed. The spring model has no ground springs, so it must say
// NOT carried; gravity and load_scale change what they say they change.
TEST(EffectRegistry, CarryOversDoWhatTheySay) {
  SpringModelChanges changes;
  EXPECT_EQ(
      effect_type("support_compliance").carry_over(Eigen::Vector3d(1.0, 2.0, 1.5), changes).how,
      CarryOver::kNotCarried);
  EXPECT_NE(
      carry_over("support_compliance", Eigen::Vector3d(1.0, 2.0, 1.5), changes).find("NOT carried"),
      std::string::npos);
  EXPECT_TRUE(unchanged(changes));

  carry_over("gravity", Eigen::Vector2d(0.5, -9.81), changes);
  EXPECT_EQ(changes.gravity, Eigen::Vector3d(0.5, -9.81, 0.0));
  EXPECT_TRUE(changes.lumped_masses);
  const std::string scaled = carry_over("load_scale", Eigen::Vector2d(0.1, -0.2), changes);
  ASSERT_EQ(changes.load_factors.size(), 3u);
  EXPECT_EQ(changes.load_factors[0], 1.0);
  EXPECT_DOUBLE_EQ(changes.load_factors[1], 1.1);
  EXPECT_DOUBLE_EQ(changes.load_factors[2], 0.8);
  EXPECT_NE(scaled.find("load_scale: carried as scaled loads"), std::string::npos) << scaled;
}

}  // namespace
}  // namespace isospring::fitting
