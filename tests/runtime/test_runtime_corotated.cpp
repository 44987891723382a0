// The runtime's corotated reduced model against analysis::CorotatedReducedModel: a document
// written by io::export_reduced_model (corotated) steps, and its forces evaluate, as the library's
// model does, to 1e-12, at a load that rotates the beam by tens of degrees.
#include <gtest/gtest.h>

#include "../analysis/beam_lattice.hpp"
#include "isospring/analysis/spring_reduced_corotated.hpp"
#include "isospring/io/export_reduced.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/runtime/runtime.h"
#include "runtime_test_support.hpp"

namespace isospring::runtime {
namespace {

TEST(RuntimeCorotated, StepsAndForcesAsTheAnalysisModel) {
  io::SpringModel model;
  model.network = analysis::beam_lattice(8, 3, 3, 1e3, 1e-3);
  const analysis::SpringNetwork& n = model.network;
  io::ReducedExportOptions options;
  options.modes = 12;
  options.load_shapes = false;
  options.error_steps = 1;
  options.corotated = true;
  options.derivative_modes = 4;
  const io::ReducedExport exported = io::export_reduced_model(model, options);
  const std::string text = exported.document.dump();
  char error[500] = "";
  ModelHandle m(isospring_model_parse(text.data(), text.size(), "corotated.json", error, 500),
                ModelDeleter());
  ASSERT_NE(m, nullptr) << error;

  const analysis::CorotatedReducedModel reference_model(
      n, options.timestep, {{options.modes, {}}, options.derivative_modes});
  analysis::CorotatedReducedModel reference = reference_model;
  analysis::ReducedSpringModel linear = reference.linear();
  const auto r = static_cast<size_t>(reference.size());
  ASSERT_EQ(isospring_model_state_size(m.get()), r);

  // A bending and twisting tip load (~30 degrees of rotation within the run).
  const Eigen::VectorXd force = analysis::beam_tip_load(n, 20.0, 60.0);
  Eigen::VectorXd g(static_cast<Eigen::Index>(r)), q = Eigen::VectorXd::Zero(g.size()), qdot = q;
  isospring_model_reduce_force(m.get(), force.data(), g.data());
  for (int step = 0; step < 100; ++step) {
    isospring_model_reduced_step(m.get(), g.data(), q.data(), qdot.data());
    reference.step(g);
    linear.step(g);
  }
  EXPECT_LE((q - reference.coordinates()).norm(), 1e-12 * reference.coordinates().norm());
  EXPECT_LE((qdot - reference.velocities()).norm(), 1e-12 * reference.velocities().norm());
  // The corotated path was taken: the linear model is far away at this rotation.
  EXPECT_GT((q - linear.coordinates()).norm(), 1e-2 * q.norm());

  Eigen::VectorXd f(g.size()), df(g.size()), f0(g.size());
  isospring_model_forces(m.get(), q.data(), qdot.data(), f.data());
  const Eigen::VectorXd expected = reference.elastic_force(q, qdot);
  EXPECT_LE((f - expected).norm(), 1e-12 * expected.norm());
  // The force is linear in the rates at fixed positions: the product along (0, qdot) is the
  // damping part exactly (f - f0 cancels the elastic part: round-off relative to |f|).
  isospring_model_forces(m.get(), q.data(), nullptr, f0.data());
  isospring_model_force_jvp(m.get(), q.data(), qdot.data(), nullptr, qdot.data(), df.data());
  EXPECT_LE((df - (f - f0)).norm(), 1e-12 * f.norm());
  // At rest every rotation is the identity: the product is the linear model's, -Lambda dq - C dv.
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(g.size());
  isospring_model_force_jvp(m.get(), zero.data(), zero.data(), q.data(), qdot.data(), df.data());
  const Eigen::VectorXd linear_product =
      -(linear.eigenvalues().cwiseProduct(q)) - linear.damping() * qdot;
  EXPECT_LE((df - linear_product).norm(), 1e-10 * linear_product.norm());
  // No call allocates (operator new counted around a step, forces and a product).
  const long before = allocation_count();
  isospring_model_reduced_step(m.get(), g.data(), q.data(), qdot.data());
  isospring_model_forces(m.get(), q.data(), qdot.data(), f.data());
  isospring_model_force_jvp(m.get(), q.data(), qdot.data(), q.data(), qdot.data(), df.data());
  EXPECT_EQ(allocation_count(), before);
  // At rest the corotated energy is zero.
  EXPECT_LE(std::abs(isospring_model_forces(m.get(), zero.data(), nullptr, f0.data())), 1e-20);
}

TEST(RuntimeCorotated, ABadCorotationObjectIsNamed) {
  io::SpringModel model;
  model.network = analysis::beam_lattice(4, 2, 2, 1e3, 1e-3);
  io::ReducedExportOptions options;
  options.modes = 4;
  options.load_shapes = false;
  options.error_steps = 1;
  options.corotated = true;
  options.derivative_modes = 2;
  nlohmann::json document = io::export_reduced_model(model, options).document;
  document["corotation"]["stiffness"][3] = nlohmann::json::array({1.0});
  const std::string text = document.dump();
  char error[500] = "";
  EXPECT_EQ(isospring_model_parse(text.data(), text.size(), "bad.json", error, 500), nullptr);
  EXPECT_NE(std::string(error).find("bad.json: corotation.stiffness[3]: must be an array of"),
            std::string::npos)
      << error;
}

}  // namespace
}  // namespace isospring::runtime
