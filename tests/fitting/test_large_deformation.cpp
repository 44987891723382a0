// Large-deformation calibration: references are neo-Hookean IGA solutions (never the spring
// model), the spring model's response its nonlinear equilibrium. The fit's implicit-function
// Jacobian against finite differences; the small-amplitude limit equals the linear calibration;
// on its fitted loads at %eps_G 10 and on held-out end loads (stretch, bending, twist) at the
// same amplitude the large-deformation calibration beats the linear one on a 3^3 cube; bad
// input names the field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

#include "isospring/analysis/spring_network.hpp"
#include "isospring/fitting/large_deformation_calibration.hpp"
#include "isospring/fitting/load_suite.hpp"
#include "isospring/fitting/nonlinear_displacement_fit.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/refine.hpp"
#include "nmsm_test_models.hpp"

namespace isospring::fitting {
namespace {

using analysis::HyperelasticMaterial;

// A 10 cm cube (3 x 3 x 3 control net, degree 2) clamped on x = 0.
analysis::Problem cube() {
  return testing::grid_problem({3, 3, 3}, {0.1, 0.1, 0.1});
}

// The load suite; `held_out` gets the loaded end's stretch, bending and twist (side u1), which
// are left out of training.
analysis::Problem cube_with_suite(std::vector<std::string>& training,
                                  std::vector<std::string>& held_out) {
  analysis::Problem problem = cube();
  LoadSuiteOptions options;
  options.validation = false;
  const LoadSuite suite = generate_load_suite(problem, options);
  problem.load_cases = suite.cases;
  for (const auto& id : suite.training)
    (id.rfind("p0_u1_", 0) == 0 && id != "p0_u1_y" ? held_out : training).push_back(id);
  return problem;
}

// The implicit-function Jacobian of the nonlinear fit against central differences, the model
// with volume and shear terms, on the neo-Hookean references of `ids` (suite cases) at
// %eps_G = 15.
void check_jacobian(analysis::Problem problem, const std::vector<std::string>& ids) {
  LoadSuiteOptions suite_options;
  suite_options.validation = false;
  suite_options.self_weight = false;
  for (const auto& lc : generate_load_suite(problem, suite_options).cases)
    if (std::find(ids.begin(), ids.end(), lc.id) != ids.end()) problem.load_cases.push_back(lc);
  ASSERT_EQ(problem.load_cases.size(), ids.size());
  SpringMeshOptions mesh;
  mesh.volume_terms = true;
  mesh.shear_terms = true;
  const auto factors = load_factors_for_eps_g(problem, mesh, 15.0);
  for (size_t c = 0; c < factors.size(); ++c)
    problem.load_cases[c] =
        scaled_load_case(problem.load_cases[c], factors[c], "c" + std::to_string(c));
  CalibrationSettings settings;
  settings.mesh = mesh;
  settings.gamma = 0.2;
  settings.field_metrics = false;
  settings.reference_displacements =
      finite_strain_references(problem, HyperelasticMaterial::kNeoHookean);
  const CalibrationResult start = calibrate(problem, settings);
  const SpringModelOnProblem model = spring_model_of(problem, start);
  DisplacementFitData data;
  data.network = model.network;
  data.constrained_dofs = model.extra_constrained;
  data.particle_of_node = model.particle_of_node;
  data.loads = start.particle_loads;
  data.references = settings.reference_displacements;

  const int groups = start.grouping.num_groups();
  ASSERT_GE(groups, 3);
  Eigen::VectorXd theta(groups);
  for (int g = 0; g < groups; ++g)
    theta[g] = std::log(start.fit_result.group_stiffness[g]) + 0.1 * std::sin(g + 1.0);
  Eigen::VectorXd r;
  Eigen::MatrixXd jacobian;
  ASSERT_TRUE(nonlinear_displacement_residuals(data, start.grouping, theta, r, &jacobian));
  // The springs move far from rest: the linear response would be another function.
  const double h = 1e-5;
  double worst = 0.0;
  for (int g = 0; g < groups; ++g) {
    Eigen::VectorXd plus = theta, minus = theta, r_plus, r_minus;
    plus[g] += h;
    minus[g] -= h;
    ASSERT_TRUE(nonlinear_displacement_residuals(data, start.grouping, plus, r_plus, nullptr));
    ASSERT_TRUE(nonlinear_displacement_residuals(data, start.grouping, minus, r_minus, nullptr));
    const Eigen::VectorXd fd = (r_plus - r_minus) / (2 * h);
    worst = std::max(worst, (fd - jacobian.col(g)).cwiseAbs().maxCoeff());
  }
  // Central differences: O(h^2) ~ 1e-10 truncation plus the equilibria's 1e-13 relative residual
  // over h (~1e-8 of a column); the Jacobian's entries are O(1e-2..1e-1).
  const double scale = jacobian.cwiseAbs().maxCoeff();
  EXPECT_GT(scale, 1e-3);
  EXPECT_LT(worst, 1e-6 * scale) << "worst |J - FD| " << worst << " of max |J| " << scale;
}

TEST(LargeDeformation, JacobianOfTheNonlinearFitMatchesFiniteDifferences) {
  // An oblique end load and a twist of the cube.
  check_jacobian(cube(), {"p0_u1_z", "p0_u1_twist"});
}

TEST(LargeDeformation, JacobianOfTheNonlinearFitMatchesFiniteDifferencesInPlaneStrain) {
  // The 5^2 square in plane strain: a load across the top side and an in-plane moment on it.
  check_jacobian(testing::grid_problem({5, 5}, {0.1, 0.1}), {"p0_v1_y", "p0_v1_twist"});
}

TEST(LargeDeformation, SmallAmplitudeRecoversTheLinearCalibration) {
  std::vector<std::string> training, held_out;
  const analysis::Problem problem = cube_with_suite(training, held_out);
  CalibrationSettings settings;
  settings.gamma = 0.2;
  settings.field_metrics = false;
  settings.fit_cases = training;
  const CalibrationResult linear = calibrate(problem, settings);
  LargeDeformationSettings large;
  large.amplitudes = {0.01};  // %eps_G = 1e-4
  const LargeDeformationResult nonlinear = calibrate_large_deformation(problem, settings, large);
  ASSERT_EQ(nonlinear.fit.group_stiffness.size(), linear.fit_result.group_stiffness.size());
  // Both the neo-Hookean reference and the spring equilibrium differ from their linearisations
  // by O(strain) = 1e-4 relative; the fitted stiffnesses (a well-posed grouped fit) move by the
  // same order times the fit's conditioning, so 2e-3 leaves a margin of ~20x over 1e-4.
  double worst = 0.0;
  for (size_t g = 0; g < linear.fit_result.group_stiffness.size(); ++g)
    worst = std::max(
        worst,
        std::abs(nonlinear.fit.group_stiffness[g] / linear.fit_result.group_stiffness[g] - 1.0));
  EXPECT_LT(worst, 2e-3);
  for (size_t c = 0; c < linear.fit.size(); ++c)
    EXPECT_NEAR(nonlinear.fit.percent_e_rms[c], linear.fit[c].control.percent_e_rms,
                1e-3 * linear.fit[c].control.percent_e_rms + 1e-3)
        << linear.fit[c].id;
}

TEST(LargeDeformation, FitsLargeLoadsBetterAndMeasuresHeldOutEndLoads) {
  std::vector<std::string> training, held_out;
  const analysis::Problem suite = cube_with_suite(training, held_out);
  ASSERT_EQ(held_out.size(), 3u);  // p0_u1_x (stretch), p0_u1_z (bending), p0_u1_twist
  // Training: the top and side faces' loads and the end's other shear (9 cases), springs with
  // volume and shear terms.
  std::vector<std::string> fit;
  for (const auto& id : training)
    if (id.rfind("p0_v1_", 0) == 0 || id.rfind("p0_w1_", 0) == 0 || id == "p0_u1_y")
      fit.push_back(id);
  ASSERT_EQ(fit.size(), 9u);
  CalibrationSettings settings;
  settings.gamma = 0.2;
  settings.field_metrics = false;
  settings.fit_cases = fit;
  settings.mesh.volume_terms = true;
  settings.mesh.shear_terms = true;
  const CalibrationResult linear = calibrate(suite, settings);
  const SpringModelOnProblem linear_model = spring_model_of(suite, linear);
  LargeDeformationSettings large;
  large.amplitudes = {10.0};
  const LargeDeformationResult nonlinear = calibrate_large_deformation(suite, settings, large);

  // Worst %e_rms of a model's nonlinear equilibrium over `cases` of `suite` at %eps_G = 10.
  auto worst = [&](const std::vector<std::string>& ids, const SpringModelOnProblem& model) {
    analysis::Problem test = suite;
    test.load_cases.clear();
    for (const auto& lc : suite.load_cases)
      if (std::find(ids.begin(), ids.end(), lc.id) != ids.end()) test.load_cases.push_back(lc);
    const auto factors = load_factors_for_eps_g(test, settings.mesh, 10.0);
    for (size_t c = 0; c < factors.size(); ++c)
      test.load_cases[c] = scaled_load_case(test.load_cases[c], factors[c], test.load_cases[c].id);
    const auto references = finite_strain_references(test, HyperelasticMaterial::kNeoHookean);
    double w = 0.0;
    for (const auto& c : evaluate_large_deformation(test, model, references)) {
      EXPECT_TRUE(c.solved) << c.id;
      w = std::max(w, c.control.percent_e_rms);
    }
    return w;
  };
  const double fitted_linear = worst(fit, linear_model);
  const double fitted_large = worst(fit, nonlinear.model);
  const double held_linear = worst(held_out, linear_model);
  const double held_large = worst(held_out, nonlinear.model);
  std::cout << "worst %e_rms at %eps_G 10: fitted loads " << fitted_linear
            << " (linear calibration) " << fitted_large
            << " (large-deformation calibration); held-out end loads " << held_linear << " / "
            << held_large << "\n";
  // Measured (x86-64, Release): fitted 17.53 -> 16.33, held out 19.71 -> 15.03. The margins
  // (0.6 and 3 points, about half of each gap) leave room for other BLAS/compilers but fail if
  // the large-deformation fit stops paying off.
  EXPECT_LT(fitted_large, fitted_linear - 0.6);
  EXPECT_LT(held_large, held_linear - 3.0);
}

// The 5^2 square in plane strain of bench_large_deformation (10 cm, degree 2, three elements
// per direction, the control net at the Greville points; clamped on x = 0) with the load suite;
// `training` gets every training case but the free end's stretch, bending and in-plane moment.
analysis::Problem square_with_suite(std::vector<std::string>& training) {
  analysis::Problem problem = testing::grid_problem({5, 5}, {0.1, 0.1});
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  nurbs::Patch patch({linear, linear}, {{0, 0, 0}, {0.1, 0, 0}, {0, 0.1, 0}, {0.1, 0.1, 0}});
  patch = nurbs::elevate_degree(patch, 1);
  for (int d = 0; d < 2; ++d) patch = nurbs::refine_uniform(patch, d, 3);
  problem.patches = {patch};
  LoadSuiteOptions options;
  options.validation = false;
  const LoadSuite suite = generate_load_suite(problem, options);
  problem.load_cases = suite.cases;
  for (const auto& id : suite.training)
    if (id.rfind("p0_u1_", 0) != 0) training.push_back(id);
  return problem;
}

TEST(LargeDeformation, ContinuationStopsBeforeACaseOnAnotherBranchDragsTheFit) {
  // The square with volume and shear terms fitted at %eps_G 5, 10, 20 (8 cases each). The fit
  // up to 10 explains its 16 cases within 10.4 %e_rms, but its equilibrium from rest under
  // self-weight along x at 20 inverts a net cell (V/V0 = -0.03; 443 %e_rms from the fit up to
  // 5). Fitting that amplitude anyway traded every other case for that one: it ended at 63-70
  // %e_rms and so passed the after-the-fit rule (<= 100), with every fitted case, 5 included,
  // at 40-70 %e_rms and stiffnesses spread over 0.016 .. 7.6e7. The continuation must stop
  // before such a fit and keep the fit up to 10.
  std::vector<std::string> training;
  const analysis::Problem square = square_with_suite(training);
  ASSERT_EQ(training.size(), 8u);
  CalibrationSettings settings;
  settings.gamma = 0.2;
  settings.field_metrics = false;
  settings.fit_cases = training;
  settings.mesh.volume_terms = true;
  settings.mesh.shear_terms = true;
  LargeDeformationSettings large;
  large.amplitudes = {5.0, 10.0, 20.0};
  const LargeDeformationResult result = calibrate_large_deformation(square, settings, large);
  EXPECT_EQ(result.reached_amplitude, 10.0);
  EXPECT_NE(result.stopped.find("gravity_x@20"), std::string::npos) << result.stopped;
  EXPECT_NE(result.stopped.find("before the fit"), std::string::npos) << result.stopped;
  ASSERT_EQ(result.fitted.size(), 16u);
  double worst = 0.0;
  for (const auto& c : result.fitted) {
    ASSERT_TRUE(c.solved) << c.id;
    worst = std::max(worst, c.control.percent_e_rms);
  }
  // Measured 10.4 (gravity_x@10; the other 15 cases <= 6.3); the dragged fit was >= 41.7 on
  // every case. 12 leaves room for another BLAS's last digits in the fit's path.
  EXPECT_LT(worst, 12.0);
}

TEST(LargeDeformation, NonlinearFitEndsBelowItsStartFromRestAndDoesNotStall) {
  // Plain springs on the square at %eps_G 5, started from the linear calibration: the fit's
  // cost with every equilibrium from rest (as the model is used) must not exceed its start's,
  // and the fit must not stall where its trial steps land on other branches of equilibria.
  std::vector<std::string> training;
  analysis::Problem square = square_with_suite(training);
  std::vector<analysis::LoadCase> cases;
  for (const auto& lc : square.load_cases)
    if (std::find(training.begin(), training.end(), lc.id) != training.end()) cases.push_back(lc);
  square.load_cases = cases;
  const SpringMeshOptions mesh;
  const auto factors = load_factors_for_eps_g(square, mesh, 5.0);
  for (size_t c = 0; c < factors.size(); ++c)
    square.load_cases[c] = scaled_load_case(square.load_cases[c], factors[c], cases[c].id);
  CalibrationSettings settings;
  settings.gamma = 0.2;
  settings.field_metrics = false;
  const CalibrationResult start = calibrate(square, settings);
  const SpringModelOnProblem model = spring_model_of(square, start);
  DisplacementFitData data;
  data.network = model.network;
  data.constrained_dofs = model.extra_constrained;
  data.particle_of_node = model.particle_of_node;
  data.loads = start.particle_loads;
  data.references = finite_strain_references(square, HyperelasticMaterial::kNeoHookean);
  DisplacementFitOptions options;
  options.grouping = start.grouping;
  options.initial = start.fit_result.group_stiffness;
  const DisplacementFitResult fit = fit_displacements_nonlinear(data, options);
  auto cost_from_rest = [&](const std::vector<double>& k) {
    Eigen::VectorXd theta(static_cast<Eigen::Index>(k.size())), r;
    for (size_t g = 0; g < k.size(); ++g) theta[static_cast<Eigen::Index>(g)] = std::log(k[g]);
    return nonlinear_displacement_residuals(data, start.grouping, theta, r, nullptr)
               ? 0.5 * r.squaredNorm()
               : std::numeric_limits<double>::infinity();
  };
  const double at_start = cost_from_rest(options.initial);
  const double at_end = cost_from_rest(fit.group_stiffness);
  std::cout << "cost from rest: start " << at_start << ", fit " << at_end << " (" << fit.message
            << ")\n";
  ASSERT_TRUE(std::isfinite(at_start));
  EXPECT_LE(at_end, at_start);
  // Measured: start 5.51 (a case on another branch), fit 0.0973. With each equilibrium warm-
  // started from the LAST evaluation (a rejected trial's, possibly on another branch) instead of
  // the best point's, the objective depended on the optimiser's history and the fit stalled at
  // 1.69 ("parameter tolerance": its trust region shrank around steps that evaluated on other
  // branches). 0.2 separates the two with a factor of 2 to spare on either side.
  EXPECT_LT(at_end, 0.2);
  // The reported cost and per-case errors are those from rest.
  EXPECT_NEAR(fit.cost, at_end, 1e-12 * at_end);
}

TEST(LargeDeformation, EquilibriumPastTheLimitPointIsTheSnappedThroughOne) {
  // Von Mises truss: supports at (-1, 0) and (1, 0), apex at (0, h), two springs k = 1. Its
  // limit load is about 0.043; under P = 0.2 downwards the only equilibrium is snapped through,
  // y* < -h with (l - L0) y / l = -P / 2 (k = 1), l = sqrt(1 + y^2): a scalar root found here
  // by bisection. The load path from rest crosses the limit point (singular tangent) and an
  // unstable branch (indefinite tangent) on its way there.
  const double h = 0.5, load = 0.2;
  analysis::SpringNetwork net;
  net.dimension = 2;
  net.positions = {{-1, 0, 0}, {1, 0, 0}, {0, h, 0}};
  net.masses = {1, 1, 1};
  net.fixed = {true, true, false};
  const double rest = std::sqrt(1 + h * h);
  for (int i : {0, 1}) {
    analysis::Spring spring;
    spring.i = i;
    spring.j = 2;
    spring.stiffness = 1.0;
    spring.rest_length = rest;
    net.springs.push_back(spring);
  }
  auto balance = [&](double y) {
    const double l = std::sqrt(1 + y * y);
    return (l - rest) * y / l + load / 2;
  };
  double lo = -100.0, hi = -h;  // balance(lo) < 0 < balance(hi) = P / 2
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (balance(mid) < 0 ? lo : hi) = mid;
  }
  const double y_star = 0.5 * (lo + hi);
  Eigen::VectorXd force = Eigen::VectorXd::Zero(6), u;
  force[5] = -load;
  ASSERT_TRUE(spring_equilibrium(net, force, {}, u));
  EXPECT_NEAR(u[4], 0.0, 1e-9);
  EXPECT_NEAR(u[5], y_star - h, 1e-9 * std::abs(y_star)) << "y* = " << y_star;
}

TEST(LargeDeformation, BadInputNamesTheField) {
  analysis::Problem problem = cube();
  LoadSuiteOptions suite_options;
  suite_options.validation = false;
  problem.load_cases = generate_load_suite(problem, suite_options).cases;
  CalibrationSettings settings;
  auto message = [&](const analysis::Problem& p, const LargeDeformationSettings& large) {
    try {
      calibrate_large_deformation(p, settings, large);
    } catch (const nurbs::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  LargeDeformationSettings large;
  large.amplitudes = {5.0, 0.0};
  EXPECT_EQ(message(problem, large).rfind("calibration.amplitudes[1] must be > 0", 0), 0u)
      << message(problem, large);
  large.amplitudes = {-1.0};
  EXPECT_EQ(message(problem, large).rfind("calibration.amplitudes[0] must be > 0", 0), 0u);
  large.amplitudes = {10.0, 5.0};
  EXPECT_EQ(message(problem, large).rfind("calibration.amplitudes[1] must be larger", 0), 0u);
  large.amplitudes = {};
  EXPECT_EQ(message(problem, large).rfind("calibration.amplitudes: give at least one", 0), 0u);
  large.amplitudes = {5.0};
  analysis::Problem plate = testing::grid_problem({3, 3}, {0.1, 0.1});
  plate.formulation = analysis::Formulation::kPlaneStress;
  plate.load_cases = generate_load_suite(plate, suite_options).cases;
  EXPECT_EQ(
      message(plate, large).rfind("material.model: a finite-strain law needs plane strain", 0), 0u)
      << message(plate, large);
}

}  // namespace
}  // namespace isospring::fitting
