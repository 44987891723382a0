#pragma once
// The objects and held-out large loads of the large-deformation benches: a 10 cm cube (3^3
// control net, degree 2) or a 10 cm square in plane strain (5^2), E = 15 kPa, nu = 1/3, clamped
// on x = 0; the free end's stretch, bending and twist (2D: in-plane moment) scaled by the linear
// solution to an end strain or rotation and solved by the neo-Hookean IGA.
#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "isospring/analysis/sides.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/fitting/large_deformation_calibration.hpp"
#include "isospring/fitting/load_suite.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::bench_large {

using Eigen::Vector3d;

inline analysis::Problem block(int dims, int elements) {
  std::vector<Vector3d> corners;
  for (int k = 0; k < (dims == 3 ? 2 : 1); ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) corners.emplace_back(0.1 * i, 0.1 * j, 0.1 * k);
  const nurbs::KnotVector linear(1, {0, 0, 1, 1});
  nurbs::Patch patch(std::vector<nurbs::KnotVector>(static_cast<size_t>(dims), linear), corners);
  patch = nurbs::elevate_degree(patch, 1);
  for (int d = 0; d < dims; ++d) patch = nurbs::refine_uniform(patch, d, elements);
  analysis::Problem problem;
  problem.formulation =
      dims == 3 ? analysis::Formulation::kSolid : analysis::Formulation::kPlaneStrain;
  problem.material.youngs_modulus = 15000.0;
  problem.material.poisson_ratio = 1.0 / 3.0;
  problem.material.density = 1143.0;
  problem.patches.push_back(patch);
  analysis::Support clamp;
  clamp.side = {0, 0, 0};
  clamp.fixed = {true, true, dims == 3};
  problem.supports.push_back(clamp);
  return problem;
}

// Control points of the free end (side u1) and their rest positions.
inline std::vector<Vector3d> end_points(const analysis::Problem& problem,
                                        std::vector<int>& indices) {
  indices = analysis::side_control_points(problem.patches[0], 0, 1);
  std::vector<Vector3d> x;
  for (int i : indices) x.push_back(problem.patches[0].control_point(i));
  return x;
}

// Mean end strain along x, and the best-fit rotation (degrees) of the end's points about `axis`
// (Procrustes in the plane normal to the axis), from control displacements u.
struct EndMotion {
  double strain = 0, rotation = 0;
};
inline EndMotion end_motion(const analysis::Problem& problem, const std::vector<Vector3d>& u_end,
                            const Vector3d& axis) {
  std::vector<int> indices;
  const std::vector<Vector3d> x = end_points(problem, indices);
  Vector3d c = Vector3d::Zero(), cd = Vector3d::Zero();
  for (size_t a = 0; a < x.size(); ++a) {
    c += x[a] / x.size();
    cd += (x[a] + u_end[a]) / x.size();
  }
  double s = 0, k = 0, strain = 0;
  for (size_t a = 0; a < x.size(); ++a) {
    Vector3d r = x[a] - c, rd = x[a] + u_end[a] - cd;
    r -= r.dot(axis) * axis;
    rd -= rd.dot(axis) * axis;
    s += r.cross(rd).dot(axis);
    k += r.dot(rd);
    strain += u_end[a].x() / 0.1 / x.size();
  }
  return {strain, std::atan2(s, k) * 180.0 / M_PI};
}

inline std::vector<Vector3d> end_displacements(const analysis::Problem& problem,
                                               const std::vector<std::vector<Vector3d>>& control) {
  std::vector<int> indices;
  end_points(problem, indices);
  std::vector<Vector3d> u;
  for (int i : indices) u.push_back(control[0][static_cast<size_t>(i)]);
  return u;
}

struct HeldOut {
  analysis::Problem problem;  // the held-out cases at one amplitude
  std::vector<Eigen::VectorXd> references;
  std::string measured;  // the references' end strain / rotations
};

// The end's stretch (x traction), bending (traction along the last axis) and twist (in 2D the
// in-plane moment) scaled by the linear solution to `strain` and `degrees`.
inline HeldOut held_out(const analysis::Problem& suite, const std::vector<std::string>& ids,
                        double strain, double degrees) {
  const bool solid = suite.formulation == analysis::Formulation::kSolid;
  HeldOut out;
  out.problem = suite;
  out.problem.load_cases.clear();
  for (const auto& lc : suite.load_cases)
    if (std::find(ids.begin(), ids.end(), lc.id) != ids.end()) out.problem.load_cases.push_back(lc);
  const analysis::StaticResult linear = analysis::solve_static(out.problem);
  auto axis_of = [&](const std::string& id) {
    if (id.find("twist") != std::string::npos)
      return Vector3d(solid ? Vector3d::UnitX() : Vector3d::UnitZ());
    return Vector3d(solid ? Vector3d::UnitY() : Vector3d::UnitZ());
  };
  for (size_t c = 0; c < out.problem.load_cases.size(); ++c) {
    const std::string id = out.problem.load_cases[c].id;
    const bool stretch = id == "p0_u1_x";
    const EndMotion m = end_motion(
        out.problem, end_displacements(out.problem, linear.load_cases[c].control_displacements),
        axis_of(id));
    // Linear motions are proportional to the load (the Procrustes angle is to first order).
    const double factor = stretch ? strain / m.strain : degrees / std::abs(m.rotation);
    out.problem.load_cases[c] = fitting::scaled_load_case(out.problem.load_cases[c], factor, id);
  }
  analysis::NonlinearOptions options;
  options.material = analysis::HyperelasticMaterial::kNeoHookean;
  const auto results = analysis::solve_static_nonlinear(out.problem, options);
  for (size_t c = 0; c < results.size(); ++c) {
    const std::string& id = results[c].id;
    const EndMotion m = end_motion(
        out.problem, end_displacements(out.problem, results[c].control_displacements), axis_of(id));
    char text[96];
    if (id == "p0_u1_x")
      std::snprintf(text, sizeof text, "stretch %.0f %%", 100 * m.strain);
    else
      std::snprintf(text, sizeof text, "%s %.0f deg",
                    id.find("twist") != std::string::npos ? "twist" : "bend", std::abs(m.rotation));
    out.measured += (c ? ", " : "") + std::string(text);
    out.references.push_back(results[c].displacement);
  }
  return out;
}

// The object with its load suite; `test` gets the free end's stretch, bending and twist (held
// out), `training` the other suite cases.
inline analysis::Problem suite_problem(int dims, int elements, std::vector<std::string>& training,
                                       std::vector<std::string>& test) {
  analysis::Problem suite = block(dims, elements);
  fitting::LoadSuiteOptions suite_options;
  suite_options.validation = false;
  const fitting::LoadSuite generated = fitting::generate_load_suite(suite, suite_options);
  suite.load_cases = generated.cases;
  const std::string bend = dims == 3 ? "p0_u1_z" : "p0_u1_y";
  for (const auto& id : generated.training)
    (id == "p0_u1_x" || id == bend || id == "p0_u1_twist" ? test : training).push_back(id);
  return suite;
}

}  // namespace isospring::bench_large
