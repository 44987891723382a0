// The effect registry: every registered effect builds under its own name, and the note it writes
// for the spring model says what its carry-over does (a "NOT carried" effect changes nothing in
// the recalibration's inputs, a "carried" one changes them).
#include <gtest/gtest.h>

#include <set>

#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/dof_map.hpp"
#include "isospring/fitting/effect.hpp"
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
