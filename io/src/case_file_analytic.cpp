// Closed-form elasticity solutions a case can name in "analytic" (formulas as in
// /work/shared/reference/benchmarks.md and Timoshenko & Goodier, Theory of Elasticity):
//   kirsch         infinite plate with a circular hole, far-field traction along x (2D)
//   lame_cylinder  thick-walled cylinder under internal pressure (2D ring section)
//   timoshenko     cantilever with a parabolic end shear load (plane stress)
//   hollow_sphere  thick sphere under internal pressure (3D)
#include <cmath>

#include "case_file_json.hpp"
#include "isospring/io/case_file.hpp"

namespace isospring::io {
using case_json::Field;
using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

/// E and nu of the equivalent plane-stress problem: plane strain uses E/(1-nu^2), nu/(1-nu).
std::pair<double, double> plane_stress_equivalent(const analysis::Material& m,
                                                  analysis::Formulation formulation) {
  const double E = m.youngs_modulus, nu = m.poisson_ratio;
  if (formulation == analysis::Formulation::kPlaneStrain) return {E / (1 - nu * nu), nu / (1 - nu)};
  return {E, nu};
}

/// Out-of-plane stress: zero in plane stress, nu (sxx + syy) in plane strain.
void add_szz(Matrix3d& s, const analysis::Material& m, analysis::Formulation formulation) {
  if (formulation == analysis::Formulation::kPlaneStrain)
    s(2, 2) = m.poisson_ratio * (s(0, 0) + s(1, 1));
}

Vector3d read_center(const Field& field, const char* key) {
  return field.has(key) ? field.at(key).vector(2, 3) : Vector3d::Zero();
}

void require_2d(const Field& field, analysis::Formulation formulation, const std::string& type) {
  if (formulation == analysis::Formulation::kSolid)
    field.fail(": '" + type + "' is a 2D solution; the case is a 3D (solid) analysis");
}

AnalyticSolution kirsch(const Field& field, const analysis::Material& m,
                        analysis::Formulation formulation) {
  field.expect_object({"type", "traction", "radius", "center"});
  require_2d(field, formulation, "kirsch");
  const double T = field.at("traction").number();
  const double a = field.at("radius").positive();
  const Vector3d c = read_center(field, "center");
  const double mu = m.youngs_modulus / (2 * (1 + m.poisson_ratio));
  const double nu = m.poisson_ratio;
  const double kappa =
      formulation == analysis::Formulation::kPlaneStrain ? 3 - 4 * nu : (3 - nu) / (1 + nu);
  AnalyticSolution s;
  s.displacement = [=](const Vector3d& x) {
    const double r = std::hypot(x.x() - c.x(), x.y() - c.y());
    const double t = std::atan2(x.y() - c.y(), x.x() - c.x());
    const double f = T * a / (8 * mu);
    const double ux = f * (r / a * (kappa + 1) * std::cos(t) +
                           2 * a / r * ((1 + kappa) * std::cos(t) + std::cos(3 * t)) -
                           2 * std::pow(a / r, 3) * std::cos(3 * t));
    const double uy = f * (r / a * (kappa - 3) * std::sin(t) +
                           2 * a / r * ((1 - kappa) * std::sin(t) + std::sin(3 * t)) -
                           2 * std::pow(a / r, 3) * std::sin(3 * t));
    return Vector3d(ux, uy, 0);
  };
  s.stress = [=](const Vector3d& x) {
    const double r = std::hypot(x.x() - c.x(), x.y() - c.y());
    const double t = std::atan2(x.y() - c.y(), x.x() - c.x());
    const double q2 = (a / r) * (a / r), q4 = q2 * q2;
    Matrix3d sigma = Matrix3d::Zero();
    sigma(0, 0) =
        T * (1 - q2 * (1.5 * std::cos(2 * t) + std::cos(4 * t)) + 1.5 * q4 * std::cos(4 * t));
    sigma(1, 1) =
        T * (-q2 * (0.5 * std::cos(2 * t) - std::cos(4 * t)) - 1.5 * q4 * std::cos(4 * t));
    sigma(0, 1) = sigma(1, 0) =
        T * (-q2 * (0.5 * std::sin(2 * t) + std::sin(4 * t)) + 1.5 * q4 * std::sin(4 * t));
    add_szz(sigma, m, formulation);
    return sigma;
  };
  return s;
}

/// Radial/hoop stresses to Cartesian: s_rr e_r e_r^T + s_tt e_t e_t^T (+ s_zz).
Matrix3d polar_stress(const Vector3d& e_r, double s_rr, double s_tt) {
  const Vector3d e_t(-e_r.y(), e_r.x(), 0);
  return s_rr * e_r * e_r.transpose() + s_tt * e_t * e_t.transpose();
}

AnalyticSolution lame_cylinder(const Field& field, const analysis::Material& m,
                               analysis::Formulation formulation) {
  field.expect_object({"type", "inner_radius", "outer_radius", "pressure", "center"});
  require_2d(field, formulation, "lame_cylinder");
  const double ri = field.at("inner_radius").positive();
  const double ro = field.at("outer_radius").positive();
  if (ro <= ri) field.at("outer_radius").fail(" must be larger than inner_radius");
  const double P = field.at("pressure").number();
  const Vector3d c = read_center(field, "center");
  // Plain variables, not a structured binding: the lambdas below capture them, which clang
  // before 16 does not allow for structured bindings (the sanitizer and fuzz builds use clang).
  const std::pair<double, double> equivalent = plane_stress_equivalent(m, formulation);
  const double E = equivalent.first, nu = equivalent.second;
  const double A = P * ri * ri / (ro * ro - ri * ri);
  AnalyticSolution s;
  s.displacement = [=](const Vector3d& x) {
    const Vector3d d(x.x() - c.x(), x.y() - c.y(), 0);
    const double r = d.norm();
    const double ur = A / E * ((1 - nu) * r + (1 + nu) * ro * ro / r);
    return Vector3d(ur * d / r);
  };
  s.stress = [=](const Vector3d& x) {
    const Vector3d d(x.x() - c.x(), x.y() - c.y(), 0);
    const double q = ro * ro / d.squaredNorm();
    Matrix3d sigma = polar_stress(d.normalized(), A * (1 - q), A * (1 + q));
    add_szz(sigma, m, formulation);
    return sigma;
  };
  return s;
}

AnalyticSolution timoshenko(const Field& field, const analysis::Material& m,
                            analysis::Formulation formulation) {
  field.expect_object({"type", "length", "depth", "load", "origin"});
  if (formulation != analysis::Formulation::kPlaneStress)
    field.fail(": 'timoshenko' is a plane-stress solution; set analysis.type to plane_stress");
  const double L = field.at("length").positive();
  const double D = field.at("depth").positive();
  const double P = field.at("load").number();       // end shear force per unit thickness [N/m]
  const Vector3d o = read_center(field, "origin");  // clamped end, mid-depth
  const double E = m.youngs_modulus, nu = m.poisson_ratio, I = D * D * D / 12;
  AnalyticSolution s;
  s.displacement = [=](const Vector3d& p) {
    const double x = p.x() - o.x(), y = p.y() - o.y();
    const double ux = P * y / (6 * E * I) * ((6 * L - 3 * x) * x + (2 + nu) * (y * y - D * D / 4));
    const double uy =
        -P / (6 * E * I) *
        (3 * nu * y * y * (L - x) + (4 + 5 * nu) * D * D * x / 4 + (3 * L - x) * x * x);
    return Vector3d(ux, uy, 0);
  };
  s.stress = [=](const Vector3d& p) {
    const double x = p.x() - o.x(), y = p.y() - o.y();
    Matrix3d sigma = Matrix3d::Zero();
    sigma(0, 0) = P * (L - x) * y / I;
    sigma(0, 1) = sigma(1, 0) = -P / (2 * I) * (D * D / 4 - y * y);
    return sigma;
  };
  return s;
}

AnalyticSolution hollow_sphere(const Field& field, const analysis::Material& m,
                               analysis::Formulation formulation) {
  field.expect_object({"type", "inner_radius", "outer_radius", "pressure", "center"});
  if (formulation != analysis::Formulation::kSolid)
    field.fail(": 'hollow_sphere' is a 3D solution; the case is a 2D analysis");
  const double ri = field.at("inner_radius").positive();
  const double ro = field.at("outer_radius").positive();
  if (ro <= ri) field.at("outer_radius").fail(" must be larger than inner_radius");
  const double P = field.at("pressure").number();
  const Vector3d c = read_center(field, "center");
  const double E = m.youngs_modulus, nu = m.poisson_ratio;
  const double A = P * ri * ri * ri / (ro * ro * ro - ri * ri * ri);
  AnalyticSolution s;
  s.displacement = [=](const Vector3d& x) {
    const Vector3d d = x - c;
    const double r = d.norm();
    const double ur = A / E * ((1 - 2 * nu) * r + (1 + nu) * ro * ro * ro / (2 * r * r));
    return Vector3d(ur * d / r);
  };
  s.stress = [=](const Vector3d& x) {
    const Vector3d d = x - c;
    const double q = std::pow(ro / d.norm(), 3);
    const double s_rr = A * (1 - q), s_tt = A * (1 + q / 2);
    const Vector3d e = d.normalized();
    return Matrix3d(s_tt * Matrix3d::Identity() + (s_rr - s_tt) * e * e.transpose());
  };
  return s;
}

}  // namespace

AnalyticSolution make_analytic_solution(const nlohmann::json& analytic,
                                        const analysis::Material& material,
                                        analysis::Formulation formulation,
                                        const std::string& where) {
  // `where` is "file: path"; split it back so nested fields are named the same way.
  const Field field = where.find(": ") == std::string::npos ? Field(analytic, where, "analytic")
                                                            : Field::at_where(analytic, where);
  if (!analytic.is_object()) field.fail(" must be an object {\"type\": ..., parameters}");
  const Field type_field = field.at("type");
  const std::string type = type_field.string();
  AnalyticSolution solution;
  if (type == "kirsch") {
    solution = kirsch(field, material, formulation);
  } else if (type == "lame_cylinder") {
    solution = lame_cylinder(field, material, formulation);
  } else if (type == "timoshenko") {
    solution = timoshenko(field, material, formulation);
  } else if (type == "hollow_sphere") {
    solution = hollow_sphere(field, material, formulation);
  } else {
    const std::string suggestion =
        case_json::closest_word(type, {"kirsch", "lame_cylinder", "timoshenko", "hollow_sphere"});
    type_field.fail(": unknown analytic solution '" + type + "'" +
                    (suggestion.empty() ? "" : "; did you mean '" + suggestion + "'?") +
                    " Known: kirsch, lame_cylinder, timoshenko, hollow_sphere");
  }
  solution.type = type;
  solution.fields = analytic;
  return solution;
}

}  // namespace isospring::io
