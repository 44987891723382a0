// Square and cube of [S15] Table 5.1 with the published errors of Tables 5.3/5.4 attached.
#include "isospring/fitting/thesis_experiments.hpp"

#include <algorithm>

namespace isospring::fitting {

namespace {

analysis::Problem block_problem(int n, int degree, int dims) {
  analysis::Problem problem;
  const nurbs::KnotVector knots = nurbs::KnotVector::uniform(degree, n - degree);
  auto spacing = [&](int i) { return static_cast<double>(i) / (n - 1); };
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < (dims == 3 ? n : 1); ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        points.emplace_back(2.0 * spacing(i), 2.0 * spacing(j), dims == 3 ? 2.0 * spacing(k) : 0.0);
  problem.patches.emplace_back(std::vector<nurbs::KnotVector>(static_cast<size_t>(dims), knots),
                               points);
  problem.formulation =
      dims == 3 ? analysis::Formulation::kSolid : analysis::Formulation::kPlaneStress;
  problem.material = {15000.0, 1.0 / 3.0, 1143.0, 1.0};
  analysis::Support support;
  support.side = analysis::Side{0, 0, 0};
  support.fixed = {true, true, dims == 3};
  problem.supports.push_back(support);
  auto traction_case = [](const std::string& id, analysis::Side side, Eigen::Vector3d value) {
    analysis::LoadCase lc;
    lc.id = id;
    analysis::Traction t;
    t.side = side;
    t.value = value;
    lc.tractions.push_back(t);
    return lc;
  };
  const Eigen::Vector3d fit_direction =
      dims == 3 ? Eigen::Vector3d(2, -1, 1) / 3.0 : Eigen::Vector3d(1, -1, 0) / 2.0;
  problem.load_cases.push_back(traction_case("fit", {0, 0, 1}, 1500.0 * fit_direction));
  problem.load_cases.push_back(
      traction_case("holdout_x", {0, 0, 1}, Eigen::Vector3d(1500.0, 0, 0)));
  problem.load_cases.push_back(
      traction_case("holdout_v1", {0, 1, 1}, Eigen::Vector3d(0, -300.0, 0)));
  // [S15 Table 5.2] f_ext as a force on every control point of the free side u1.
  analysis::LoadCase point_case;
  point_case.id = "fit_points";
  const Eigen::Vector3d force =
      dims == 3 ? Eigen::Vector3d(80, -40, 40) : Eigen::Vector3d(200, -200, 0);
  const nurbs::Patch& patch = problem.patches[0];
  for (int cp = 0; cp < patch.num_points(); ++cp)
    if (patch.net_position(cp)[0] == n - 1) {
      analysis::PointLoad load;
      load.patch = 0;
      load.control_point = cp;
      load.force = force;
      point_case.point_loads.push_back(load);
    }
  problem.load_cases.push_back(point_case);
  return problem;
}

}  // namespace

ThesisObject thesis_square(int n, int degree) {
  ThesisObject object{"square", block_problem(n, degree, 2)};
  // Table 5.4 (net resolution, degree 2) and 5.7 (linear basis, 6x6).
  if (degree == 2 && n == 3) object.published_e_rms = 14.37, object.published_e_max = 22.69;
  if (degree == 2 && n == 4) object.published_e_rms = 2.35, object.published_e_max = 5.25;
  if (degree == 2 && n == 6) object.published_e_rms = 1.14, object.published_e_max = 2.79;
  if (degree == 2 && n == 9) object.published_e_rms = 0.50, object.published_e_max = 1.41;
  if (degree == 1 && n == 6) object.published_e_rms = 1.19, object.published_e_max = 2.55;
  return object;
}

ThesisObject thesis_cube(int n, int degree) {
  ThesisObject object{"cube", block_problem(n, degree, 3)};
  if (degree == 2 && n == 3) object.published_e_rms = 14.03, object.published_e_max = 27.27;
  if (degree == 2 && n == 4) object.published_e_rms = 2.94, object.published_e_max = 6.25;
  if (degree == 2 && n == 6) object.published_e_rms = 1.73, object.published_e_max = 7.44;
  if (degree == 2 && n == 9) object.published_e_rms = 1.70, object.published_e_max = 4.60;
  if (degree == 1 && n == 6) object.published_e_rms = 2.34, object.published_e_max = 11.33;
  return object;
}

}  // namespace isospring::fitting
