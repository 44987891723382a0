// End-to-end: `isospring simulate` writes a ParaView time series (series.pvd + one .vtp per
// frame), read back with VTK's XML parser and poly-data reader. Independent checks: the step
// response of one mass on one spring, u(t) = u_s (1 - cos(omega t)) (velocity Verlet), and the
// hanging chain's static equilibrium in closed form, which a damped implicit run approaches.
#include <gtest/gtest.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "isospring/analysis/spring_static.hpp"
#include "isospring/io/model_file.hpp"
#include "run_program.hpp"
#include "vtk_read.hpp"

using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;
using nlohmann::json;
namespace its = isospring::testing;

namespace {
// A vertical chain: particle 0 fixed at the origin, particles 1..n-1 hanging below it every
// `length` metres, joined by springs k with damping c.
json chain_model(int n, double mass, double k, double c, double length) {
  json model = {{"format", "isospring-spring-model"}, {"version", 1}, {"dimension", 3}};
  for (int i = 0; i < n; ++i)
    model["particles"].push_back(
        {{"x", {0.0, 0.0, -length * i}}, {"mass", mass}, {"fixed", i == 0}});
  for (int i = 0; i + 1 < n; ++i)
    model["springs"].push_back({{"i", i}, {"j", i + 1}, {"k", k}, {"c", c}, {"L0", length}});
  return model;
}

struct Frame {
  double time;
  std::string file;
};

// The .pvd collection through VTK's XML parser.
std::vector<Frame> read_pvd(const std::filesystem::path& path) {
  auto parser = vtkSmartPointer<vtkXMLDataParser>::New();
  parser->SetFileName(path.c_str());
  std::vector<Frame> frames;
  if (!parser->Parse()) return frames;
  vtkXMLDataElement* collection = parser->GetRootElement()->FindNestedElementWithName("Collection");
  if (!collection) return frames;
  for (int e = 0; e < collection->GetNumberOfNestedElements(); ++e) {
    vtkXMLDataElement* data = collection->GetNestedElement(e);
    double t = NAN;
    data->GetScalarAttribute("timestep", t);
    frames.push_back({t, data->GetAttribute("file")});
  }
  return frames;
}
}  // namespace

TEST(Simulate, VerletStepResponseOfOneSpringFollowsTheCosine) {
  TemporaryFolder out;
  const double m = 0.1, k = 10.0, g = 9.81, dt = 1e-3;  // omega = 10 rad/s, period 0.63 s
  std::ofstream(out / "model.json") << chain_model(2, m, k, 0.0, 1.0).dump();
  const auto run = run_isospring("simulate " + (out / "model.json") + " -o " + (out / "sim") +
                                 " --integrator verlet --dt 0.001 --steps 1000 --every 50 " +
                                 "--gravity 0,0,-9.81 --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto frames = read_pvd(out.path() / "sim" / "series.pvd");
  ASSERT_EQ(frames.size(), 21u);  // rest + every 50th of 1000 steps
  const double omega = std::sqrt(k / m), u_static = m * g / k;
  for (size_t f = 0; f < frames.size(); ++f) {
    const double t = 50 * dt * static_cast<double>(f);
    EXPECT_NEAR(frames[f].time, t, 1e-15);
    auto frame = its::read_vtp(out.path() / "sim" / frames[f].file);
    ASSERT_EQ(frame->GetNumberOfPoints(), 2) << frames[f].file;
    vtkDataArray* u = frame->GetPointData()->GetArray("displacement");
    ASSERT_NE(u, nullptr);
    EXPECT_EQ(its::tuple(u, 0).norm(), 0.0);  // fixed
    // Verlet's phase error after time t is about t omega^3 dt^2 / 24 (<= 4.2e-5 rad here), so
    // 1e-4 of u_s bounds the difference at every frame.
    EXPECT_NEAR(its::tuple(u, 1)(2), -u_static * (1 - std::cos(omega * t)), 1e-4 * u_static) << t;
    // The points are the deformed positions.
    EXPECT_NEAR(its::point(frame, 1).z(), -1.0 + its::tuple(u, 1)(2), 1e-15);
  }
}

// A 2D ladder of `rows` rows hanging under gravity: top row fixed, rungs, rails and both
// diagonals (not a mechanism); particle masses m, springs k with damping c.
json ladder_model(int rows, double m, double k, double c) {
  const double h = 0.2, w = 0.3;
  json model = {{"format", "isospring-spring-model"}, {"version", 1}, {"dimension", 2}};
  auto id = [](int r, int side) { return 2 * r + side; };
  for (int r = 0; r < rows; ++r)
    for (int side = 0; side < 2; ++side)
      model["particles"].push_back(
          {{"x", {w * side, -h * r, 0.0}}, {"mass", m}, {"fixed", r == 0}});
  auto spring = [&](int i, int j) {
    const double L = std::hypot(
        model["particles"][i]["x"][0].get<double>() - model["particles"][j]["x"][0].get<double>(),
        model["particles"][i]["x"][1].get<double>() - model["particles"][j]["x"][1].get<double>());
    model["springs"].push_back({{"i", i}, {"j", j}, {"k", k}, {"c", c}, {"L0", L}});
  };
  for (int r = 1; r < rows; ++r) {
    spring(id(r, 0), id(r, 1));
    for (int side = 0; side < 2; ++side) spring(id(r - 1, side), id(r, side));
    spring(id(r - 1, 0), id(r, 1));
    spring(id(r - 1, 1), id(r, 0));
  }
  return model;
}

// The 5-row ladder (masses 0.1 kg, springs 500 N/m damped 0.5 N s/m) under gravity -y, run by
// `simulate` with `flags` for 300 steps of 0.02 s: its network, the gravity forces, the last
// frame's displacement (flat, 2D) and report.json.
struct LadderRun {
  isospring::analysis::SpringNetwork net;
  Eigen::VectorXd gravity, last;
  json report;
};
LadderRun run_ladder(const std::string& flags) {
  const int rows = 5;
  const double m = 0.1;
  const json model = ladder_model(rows, m, 500.0, 0.5);
  TemporaryFolder out;
  std::ofstream(out / "model.json") << model.dump();
  const auto run =
      run_isospring("simulate " + (out / "model.json") + " -o " + (out / "sim") +
                    " --dt 0.02 --steps 300 --every 100 --gravity 0,-9.81,0 -q " + flags);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  LadderRun r;
  r.net = isospring::io::model_from_json(model, "model.json").network;
  r.gravity = Eigen::VectorXd::Zero(2 * 2 * rows);
  for (int i = 2; i < 2 * rows; ++i) r.gravity(2 * i + 1) = -m * 9.81;
  const auto frames = read_pvd(out.path() / "sim" / "series.pvd");
  EXPECT_EQ(frames.size(), 4u);
  if (frames.empty()) return r;
  EXPECT_NEAR(frames.back().time, 6.0, 1e-14);
  auto last = its::read_vtp(out.path() / "sim" / frames.back().file);
  vtkDataArray* u = last->GetPointData()->GetArray("displacement");
  EXPECT_NE(u, nullptr);
  if (!u) return r;
  r.last.resize(2 * 2 * rows);
  for (int i = 0; i < 2 * rows; ++i) r.last.segment(2 * i, 2) = its::tuple(u, i).head(2);
  std::ifstream report_file(out / "sim/report.json");
  r.report = json::parse(report_file);
  return r;
}

// Largest particle difference relative to the largest particle displacement of `expected`.
double relative_particle_difference(const Eigen::VectorXd& a, const Eigen::VectorXd& expected,
                                    double* scale) {
  double worst = 0.0;
  *scale = 0.0;
  for (Eigen::Index i = 0; i < a.size() / 2; ++i) {
    worst = std::max(worst, (a.segment(2 * i, 2) - expected.segment(2 * i, 2)).norm());
    *scale = std::max(*scale, expected.segment(2 * i, 2).norm());
  }
  return worst / *scale;
}

TEST(Simulate, DampedImplicitRunEndsAtTheStaticEquilibrium) {
  // The ladder's static equilibrium comes from Newton's method on the same network
  // (analysis::solve_spring_newton), a different code path from the time integration.
  const LadderRun run = run_ladder("");
  ASSERT_EQ(run.last.size(), run.gravity.size());
  using namespace isospring::analysis;
  SpringSolveOptions options;
  options.tolerance = 1e-13;
  const SpringSolveResult eq = solve_spring_newton(run.net, run.gravity, options);
  ASSERT_TRUE(eq.converged);
  double scale = 0.0;
  const double difference = relative_particle_difference(run.last, eq.displacement, &scale);
  ASSERT_GT(scale, 0.01);  // the load does deform the ladder (1.7 cm)
  // Backward Euler dissipates every mode by 1 / sqrt(1 + (omega dt)^2) a step or more, on top of
  // the springs' damping (slowest mode omega ~ 20 rad/s: >= 7% a step); after 300 steps the
  // transient is at round-off (measured 2.9e-14 of the deflection); 1e-9 leaves a wide margin.
  EXPECT_LT(difference, 1e-9);
  const json& report = run.report;
  EXPECT_EQ(report["frames"], 4);
  ASSERT_FALSE(report["static"].is_null());
  EXPECT_TRUE(report["static"]["converged"].get<bool>());
  EXPECT_NEAR(report["static"]["max_displacement"].get<double>(), scale, 1e-9 * scale);
  EXPECT_LT(report["static"]["final_minus_static_relative"].get<double>(), 1e-9);
}

TEST(Simulate, ReducedModelSettlesAtTheLinearStaticSolution) {
  // The reduced model (4 modes + the load's static shape) of the ladder under gravity: its
  // damped run must end at the full network's LINEAR static solution (a sparse solve of K_rest,
  // analysis::solve_spring_linear), which the load shape makes exact in the subspace.
  const LadderRun run = run_ladder("--integrator reduced --modes 4");
  ASSERT_EQ(run.last.size(), run.gravity.size());
  const Eigen::VectorXd linear =
      isospring::analysis::solve_spring_linear(run.net, run.gravity).displacement;
  double scale = 0.0;
  const double difference = relative_particle_difference(run.last, linear, &scale);
  ASSERT_GT(scale, 0.01);
  // As the full implicit run above: the transient is damped to round-off after 300 steps.
  EXPECT_LT(difference, 1e-9);
  const json& report = run.report;
  EXPECT_EQ(report["integrator"], "reduced");
  EXPECT_EQ(report["reduced"]["basis_size"], 5);
  EXPECT_LT(report["reduced"]["static_relative"].get<double>(), 1e-10);
  // 5 of 16 DOFs: the higher modes' share of the motion (measured 1.1e-4, reported).
  EXPECT_LT(report["reduced"]["projection_relative"].get<double>(), 1e-3);
  // Against the exact (nonlinear) network: 1.7 cm sag on 0.8 m, measured 0.70 %.
  EXPECT_LT(report["reduced"]["dynamic_relative"].get<double>(), 0.02);
  EXPECT_FALSE(report["reduced"]["full_network_diverged"].get<bool>());
}

TEST(Simulate, BadInputExitsWithOne) {
  TemporaryFolder out;
  std::ofstream(out / "model.json") << chain_model(2, 0.1, 10, 0, 1).dump();
  auto run =
      run_isospring("simulate " + (out / "model.json") + " -o " + (out / "a") + " --dt 0.01");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find("no load"), std::string::npos) << run.output;
  run = run_isospring("simulate " + (out / "model.json") + " -o " + (out / "a") +
                      " --dt 0.01 --load-case L1");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find("has no load cases"), std::string::npos) << run.output;
  run = run_isospring("simulate " + (out / "model.json") + " -o " + (out / "a") +
                      " --dt -1 --gravity 0,0,-1");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find("--dt"), std::string::npos) << run.output;
  // An explicit step far above the stability limit (2 / omega = 0.2 s) diverges: exit 3.
  run = run_isospring("simulate " + (out / "model.json") + " -o " + (out / "a") +
                      " --dt 5 --steps 400 --integrator verlet --gravity 0,0,-1");
  EXPECT_EQ(run.exit_code, 3) << run.output;
  EXPECT_NE(run.output.find("diverged"), std::string::npos) << run.output;
}

TEST(Simulate, VolumeTermsOfACalibratedModelRunToTheirStaticEquilibrium) {
  // The hanging 2D ladder with an area term per cell (model.json "volumes"): the
  // damped implicit run ends at the Newton equilibrium of springs AND area terms, which differs
  // measurably from the springs' alone.
  const int rows = 4;
  const double m = 0.1, k = 500.0, c = 0.5, h = 0.2, w = 0.3, kappa = 3000.0;
  json model = {{"format", "isospring-spring-model"}, {"version", 1}, {"dimension", 2}};
  auto id = [](int r, int side) { return 2 * r + side; };
  for (int r = 0; r < rows; ++r)
    for (int side = 0; side < 2; ++side)
      model["particles"].push_back(
          {{"x", {w * side, -h * r, 0.0}}, {"mass", m}, {"fixed", r == 0}});
  for (int r = 1; r < rows; ++r) {
    model["springs"].push_back({{"i", id(r, 0)}, {"j", id(r, 1)}, {"k", k}, {"c", c}, {"L0", w}});
    for (int side = 0; side < 2; ++side)
      model["springs"].push_back(
          {{"i", id(r - 1, side)}, {"j", id(r, side)}, {"k", k}, {"c", c}, {"L0", h}});
    for (int side = 0; side < 2; ++side)
      model["springs"].push_back({{"i", id(r - 1, side)},
                                  {"j", id(r, 1 - side)},
                                  {"k", k},
                                  {"c", c},
                                  {"L0", std::hypot(w, h)}});
    // Corners in tensor order (side, then row): the cell's parametric second axis points down,
    // so its signed rest area is -w h.
    model["volumes"].push_back({{"particles", {id(r - 1, 0), id(r - 1, 1), id(r, 0), id(r, 1)}},
                                {"kappa", kappa},
                                {"V0", -w * h}});
  }
  TemporaryFolder out;
  std::ofstream(out / "model.json") << model.dump();
  const auto run = run_isospring("simulate " + (out / "model.json") + " -o " + (out / "sim") +
                                 " --dt 0.02 --steps 400 --every 400 --gravity 0,-9.81,0 -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream report_file(out / "sim/report.json");
  const json report = json::parse(report_file);
  ASSERT_FALSE(report["static"].is_null()) << run.output;
  EXPECT_TRUE(report["static"]["converged"].get<bool>());
  EXPECT_LT(report["static"]["final_minus_static_relative"].get<double>(), 1e-9);

  using namespace isospring::analysis;
  SpringNetwork net = isospring::io::model_from_json(model, "model.json").network;
  ASSERT_EQ(net.volumes.size(), 3u);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(2 * 2 * rows);
  for (int i = 2; i < 2 * rows; ++i) f(2 * i + 1) = -m * 9.81;
  auto largest = [](const Eigen::VectorXd& u) {
    double m = 0.0;
    for (Eigen::Index i = 0; i < u.size() / 2; ++i) m = std::max(m, u.segment(2 * i, 2).norm());
    return m;
  };
  const SpringSolveResult with_volumes = solve_spring_newton(net, f);
  ASSERT_TRUE(with_volumes.converged);
  EXPECT_NEAR(report["static"]["max_displacement"].get<double>(),
              largest(with_volumes.displacement), 1e-6 * largest(with_volumes.displacement));
  // The area terms resist the rails' stretch (a cell that lengthens grows), so the ladder
  // hangs measurably less far than with its springs alone.
  net.volumes.clear();
  const SpringSolveResult springs_only = solve_spring_newton(net, f);
  ASSERT_TRUE(springs_only.converged);
  EXPECT_LT(largest(with_volumes.displacement), 0.95 * largest(springs_only.displacement));
}

namespace {
// Control-point table of `analyze` (i,x,y,z,ux,uy,uz) or error table of `calibrate`
// (node,x,y,z,ex,ey,ez,error): the three vector columns after the position, per row.
std::vector<Eigen::Vector3d> vector_columns(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  std::vector<Eigen::Vector3d> rows;
  while (std::getline(in, line)) {
    std::stringstream cells(line);
    std::vector<double> v;
    std::string cell;
    while (std::getline(cells, cell, ',')) v.push_back(std::stod(cell));
    if (v.size() >= 7) rows.emplace_back(v[4], v[5], v[6]);
  }
  return rows;
}
}  // namespace

// `calibrate` stores the loads it fitted under in model.json and `simulate` runs from
// that model with no load options. Checked independently of the calibration code: every stored
// load case's resultant is its traction times the loaded side's length (2 m, thickness 1), and
// the linear static response of the WRITTEN model (its springs, its stored forces) is the IGA
// reference (`analyze`'s table) plus the error `calibrate` reported (its <id>_errors.csv) at
// every control point. The damped run then ends on its static equilibrium (the README example).
TEST(Simulate, RunsACalibratedModelFromItsStoredLoadCases) {
  TemporaryFolder out;
  const std::string square = isospring::testing::example("calibrate_square.json");
  auto run = run_isospring("calibrate " + square + " -o " + (out / "cal") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  run = run_isospring("analyze " + square + " -o " + (out / "ref") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const isospring::io::SpringModel model = isospring::io::read_model_json(out / "cal/model.json");
  ASSERT_EQ(model.load_cases.size(), 4u);
  const std::map<std::string, Eigen::Vector2d> resultant{{"u1_x", {3000.0, 0.0}},
                                                         {"u1_y", {0.0, -600.0}},
                                                         {"v1_y", {0.0, -600.0}},
                                                         {"v1_x", {600.0, 0.0}}};
  for (size_t l = 0; l < model.load_cases.size(); ++l) {
    const auto& load = model.load_cases[l];
    ASSERT_TRUE(resultant.count(load.id)) << load.id;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& [particle, force] : load.forces) sum += force;
    EXPECT_NEAR((sum.head<2>() - resultant.at(load.id)).norm(), 0.0, 1e-9) << load.id;

    const Eigen::VectorXd f = isospring::io::model_force_vector(model, l, true);
    const Eigen::VectorXd u =
        isospring::analysis::solve_spring_linear(model.network, f).displacement;
    const auto reference = vector_columns(out / ("ref/" + load.id + "_control_displacements.csv"));
    const auto error = vector_columns(out / ("cal/" + load.id + "_errors.csv"));
    ASSERT_EQ(reference.size(), model.network.positions.size()) << load.id;
    ASSERT_EQ(error.size(), reference.size()) << load.id;
    double largest = 0.0, worst = 0.0;
    for (size_t p = 0; p < reference.size(); ++p) {
      const Eigen::Vector2d spring(u(static_cast<Eigen::Index>(2 * p)),
                                   u(static_cast<Eigen::Index>(2 * p + 1)));
      largest = std::max(largest, reference[p].norm());
      worst = std::max(worst, (spring - (reference[p] + error[p]).head<2>()).norm());
    }
    EXPECT_LT(worst, 1e-9 * largest) << load.id;
  }

  run = run_isospring("simulate " + (out / "cal/model.json") + " -o " + (out / "sim") +
                      " --dt 0.1 --steps 300");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("load case u1_x"), std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("warning"), std::string::npos) << run.output;
  std::ifstream report_file(out / "sim/report.json");
  const json report = json::parse(report_file);
  EXPECT_EQ(report["load_case"], "u1_x");
  ASSERT_FALSE(report["static"].is_null());
  EXPECT_TRUE(report["static"]["converged"].get<bool>());
  EXPECT_LT(report["static"]["final_minus_static_relative"].get<double>(), 1e-4);
  // Too short a run says so (and still writes its series).
  run = run_isospring("simulate " + (out / "cal/model.json") + " -o " + (out / "short") +
                      " --dt 0.02 --steps 20");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("has not settled"), std::string::npos) << run.output;
}
