// The reduced-model export (io/export_reduced.hpp): an engine that reads only the document and
// runs the documented step (docs/reduced_model.md) moves like the full network, to the error the
// document reports; the model's load cases are exact statically; bad options are named.
#include <gtest/gtest.h>

#include <cmath>

#include "isospring/analysis/spring_dynamics.hpp"
#include "isospring/analysis/spring_linear_implicit.hpp"
#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/io/export_reduced.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {

// A 5 x 3 x 3 lattice of 1 cm spacing (edges, face and body diagonals to forward neighbours),
// face x = 0 fixed, 2 g particles, damping 2 % of critical per spring; a tip load case and
// gravity.
SpringModel lattice_model() {
  SpringModel model;
  analysis::SpringNetwork& net = model.network;
  const int nx = 5, ny = 3, nz = 3;
  auto index = [&](int i, int j, int k) { return (k * ny + j) * nx + i; };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        net.positions.emplace_back(0.01 * i, 0.01 * j, 0.01 * k);
        net.masses.push_back(0.002);
        net.fixed.push_back(i == 0);
      }
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (int dk = 0; dk <= 1; ++dk)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const bool forward = dk > 0 || dj > 0 || (dj == 0 && di > 0);
              const int a = i + di, b = j + dj, c = k + dk;
              if (!forward || a < 0 || b < 0 || a >= nx || b >= ny || c >= nz) continue;
              analysis::Spring s;
              s.i = index(i, j, k);
              s.j = index(a, b, c);
              s.rest_length = (net.positions[s.i] - net.positions[s.j]).norm();
              s.stiffness = 50.0 / s.rest_length;
              net.springs.push_back(s);
            }
  analysis::assign_damping_ratio(net, 0.02);
  ModelLoadCase tip{"tip", {}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      tip.forces.emplace_back(index(nx - 1, j, k), Eigen::Vector3d(0, 0, -0.02));
  model.load_cases = {tip};
  model.gravity = {0, -9.81, 0};
  model.units = default_model_units();
  return model;
}

Eigen::MatrixXd matrix_of(const nlohmann::json& rows) {
  Eigen::MatrixXd m(static_cast<Eigen::Index>(rows.size()),
                    static_cast<Eigen::Index>(rows.at(0).size()));
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) m(i, j) = rows[i][j].get<double>();
  return m;
}

TEST(ExportReduced, AnEngineReadingTheDocumentMovesLikeTheFullNetwork) {
  const SpringModel model = lattice_model();
  ReducedExportOptions options;
  options.modes = 10;
  options.error_steps = 400;
  const ReducedExport exported = export_reduced_model(model, options, {{"case", "lattice"}});
  const nlohmann::json& d = exported.document;
  ASSERT_EQ(d.at("format"), "isospring.reduced_spring_model");
  ASSERT_EQ(d.at("version"), 1);
  ASSERT_EQ(exported.basis_size, 12);  // 10 modes + the tip case (with gravity) + gravity
  ASSERT_EQ(exported.errors.size(), 2u);
  EXPECT_EQ(exported.errors[0].load, "tip");
  EXPECT_EQ(exported.errors[1].load, "gravity");
  for (const ReducedLoadError& e : exported.errors) {
    std::printf("%s: static %.3g, projection %.3g, dynamic %.3g (max %.3g m) over %d steps\n",
                e.load.c_str(), e.error.static_relative, e.error.projection_relative,
                e.error.dynamic_relative, e.error.dynamic_max, e.error.steps);
    EXPECT_FALSE(e.error.exact_diverged);
    EXPECT_LT(e.error.static_relative, 1e-10);  // load shapes: exact statically
    EXPECT_LT(e.error.dynamic_relative, 0.05);
  }

  // The engine's side: only the document and the force vector.
  const Eigen::MatrixXd basis = matrix_of(d.at("basis"));
  const Eigen::MatrixXd damping = matrix_of(d.at("damping"));
  const Eigen::MatrixXd step_inverse = matrix_of(d.at("step_inverse"));
  const std::vector<double> ev = d.at("eigenvalues").get<std::vector<double>>();
  const Eigen::VectorXd lambda = Eigen::Map<const Eigen::VectorXd>(ev.data(), ev.size());
  const double dt = d.at("timestep").get<double>();
  ASSERT_EQ(basis.rows(), 45 * 3);
  const Eigen::VectorXd force = model_force_vector(model, 0, true);
  const Eigen::VectorXd g = basis.transpose() * force;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(lambda.size()), v = q;

  analysis::LinearImplicitIntegrator full(model.network, dt);
  analysis::SpringState state = analysis::rest_state(model.network);
  const Eigen::VectorXd rest = state.x;
  double difference = 0.0, motion = 0.0;
  for (int step = 0; step < options.error_steps; ++step) {
    const Eigen::VectorXd rhs =
        dt * (g - lambda.cwiseProduct(q) - damping * v - dt * lambda.cwiseProduct(v));
    v += step_inverse * rhs;
    q += dt * v;
    full.step(state, force);
    difference += (basis * q - (state.x - rest)).squaredNorm();
    motion += (state.x - rest).squaredNorm();
  }
  // The document's step is the library's: the same error to round-off.
  EXPECT_NEAR(std::sqrt(difference / motion), exported.errors[0].error.dynamic_relative,
              1e-9 * exported.errors[0].error.dynamic_relative);
}

TEST(ExportReduced, BadOptionsAreNamed) {
  const SpringModel model = lattice_model();
  ReducedExportOptions options;
  options.modes = 500;
  try {
    export_reduced_model(model, options);
    FAIL() << "no error";
  } catch (const nurbs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("modes = 500"), std::string::npos) << e.what();
  }
  options.modes = 4;
  options.timestep = -1.0;
  EXPECT_THROW(export_reduced_model(model, options), nurbs::InputError);
  options.timestep = 1e-3;
  options.error_steps = 0;
  EXPECT_THROW(export_reduced_model(model, options), nurbs::InputError);
}

}  // namespace
}  // namespace isospring::io
