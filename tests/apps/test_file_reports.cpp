// End-to-end: the commands that write one file (import, refine, export, export-calculix,
// export-step) leave <name>.report.json and <name>.report.md beside it (the output's whole name),
// and the report's numbers agree with the written file read back and with independent values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "isospring/io/model_file.hpp"
#include "isospring/io/patch_file.hpp"
#include "run_program.hpp"

using isospring::testing::example;
using isospring::testing::file_contents;
using isospring::testing::run_isospring;
using isospring::testing::TemporaryFolder;

namespace {
nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  return nlohmann::json::parse(in);
}
}  // namespace

// The block is 0.1 x 0.02 x 0.02 m: OpenCascade's own volume (BRepGProp) and the volume of our
// trilinear patch (Gauss quadrature, exact for it) must agree to round-off.
TEST(FileReports, ImportReportsPatchesAndFacesOfTheBlock) {
  TemporaryFolder out;
  const auto run =
      run_isospring("import " + example("cad/block.step") + " -o " + (out / "block.json") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json r = read_json(out / "block.json.report.json");
  EXPECT_EQ(r["command"], "import");
  EXPECT_EQ(r["patch_count"], 1);
  EXPECT_EQ(r["counts"]["faces"], 6);
  EXPECT_EQ(r["faces"].size(), 6u);
  for (const auto& f : r["faces"]) EXPECT_EQ(f["conversion"], "natural");
  EXPECT_NEAR(r["patches_measure"].get<double>(), r["cad_volume"].get<double>(),
              1e-12 * r["cad_volume"].get<double>());
  EXPECT_NEAR(r["cad_volume"].get<double>(), 0.1 * 0.02 * 0.02, 1e-15);
  EXPECT_EQ(isospring::io::read_patch_file(out / "block.json").size(), 1u);
  EXPECT_NE(file_contents(out / "block.json.report.md").find("| 0 | 3 | 1, 1, 1 | 2 x 2 x 2"),
            std::string::npos);
}

// Refinement is exact: the report's deviation between old and new geometry is round-off
// (1e-14 of the net size allows a few ulps of the de Boor / knot-insertion arithmetic), and its
// counts are those of the written file.
TEST(FileReports, RefineReportsCountsAndAnExactGeometry) {
  TemporaryFolder out;
  const auto run = run_isospring("refine " + example("patches/quarter_annulus.json") +
                                 " --elevate 1 --h 4 -o " + (out / "fine.json") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json r = read_json(out / "fine.json.report.json");
  const auto fine = isospring::io::read_patch_file(out / "fine.json");
  const auto coarse = isospring::io::read_patch_file(example("patches/quarter_annulus.json"));
  ASSERT_EQ(r["patches"].size(), fine.size());
  const auto& p = r["patches"][0];
  EXPECT_EQ(p["before"]["degrees"], nlohmann::json({coarse[0].degree(0), coarse[0].degree(1)}));
  EXPECT_EQ(p["after"]["degrees"], nlohmann::json({fine[0].degree(0), fine[0].degree(1)}));
  EXPECT_EQ(p["after"]["control_points"],
            nlohmann::json({fine[0].num_points(0), fine[0].num_points(1)}));
  EXPECT_EQ(p["after"]["elements"], nlohmann::json({4, 4}));
  EXPECT_LT(p["geometry_deviation_relative"].get<double>(), 1e-14);
  // Area of the quarter annulus is preserved: pi/4 (R^2 - r^2) for radii 1 and 2 = 3 pi / 4.
  EXPECT_NEAR(p["after"]["measure"].get<double>(), 3.0 * M_PI / 4.0, 1e-12);
  EXPECT_NE(file_contents(out / "fine.json.report.md").find("6 -> 42"), std::string::npos);
}

// export: counts and total mass against the model file read back; export-calculix: node count
// against the deck's *NODE block; export-step: the file size, and silence with -q (OpenCascade's
// writer statistics used to go to stdout).
TEST(FileReports, ExportsReportWhatTheyWrote) {
  TemporaryFolder out;
  auto run = run_isospring("calibrate " + example("calibrate_square.json") + " -o " +
                           (out / "cal") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  run = run_isospring("export " + (out / "cal/model.json") + " -o " + (out / "model.scn") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json e = read_json(out / "model.scn.report.json");
  const auto model = isospring::io::read_model_json(out / "cal/model.json");
  EXPECT_EQ(e["format"], "sofa");
  EXPECT_EQ(e["particles"], model.network.positions.size());
  EXPECT_EQ(e["springs"], model.network.springs.size());
  double mass = 0.0;
  for (double m : model.network.masses) mass += m;
  EXPECT_NEAR(e["total_mass"].get<double>(), mass, 1e-12 * mass);
  // Lumped IGA masses sum to rho * area * thickness = 1143 * 4 * 1.
  EXPECT_NEAR(mass, 1143.0 * 4.0, 1e-9 * mass);
  // Stiffness range and fixed count against the springs and particles read back.
  double k_min = INFINITY, k_max = 0.0;
  for (const auto& spring : model.network.springs)
    k_min = std::min(k_min, spring.stiffness), k_max = std::max(k_max, spring.stiffness);
  EXPECT_EQ(e["stiffness_range"], nlohmann::json({k_min, k_max}));
  EXPECT_EQ(e["fixed_particles"],
            std::count(model.network.fixed.begin(), model.network.fixed.end(), true));
  EXPECT_EQ(e["gravity"].size(), 3u);  // sofa and mjcf scenes carry gravity

  run = run_isospring("export-calculix " + example("cantilever_box.json") + " -o " +
                      (out / "box.inp") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json c = read_json(out / "box.inp.report.json");
  std::istringstream deck(file_contents(out / "box.inp"));
  std::string line;
  int nodes = 0;
  bool in_nodes = false;
  while (std::getline(deck, line)) {
    if (!line.empty() && line[0] == '*') {
      in_nodes = line == "*NODE" || line.rfind("*NODE,", 0) == 0;  // not *NODE PRINT / FILE
      continue;
    }
    if (in_nodes && !line.empty()) ++nodes;
  }
  EXPECT_EQ(c["nodes"], nodes);
  // 20 x 4 x 4 knot spans, one C3D20R per span; serendipity nodes = the (2n+1)^3 quadratic grid
  // without element centres (320) and face centres (20*4*5 + 20*5*4 + 21*4*4 = 1136).
  EXPECT_EQ(c["elements"], 20 * 4 * 4);
  EXPECT_EQ(c["nodes"], 41 * 9 * 9 - 320 - 1136);
  EXPECT_EQ(c["element_type"], "C3D20R");
  EXPECT_EQ(c["node_sets"], nlohmann::json({"Nall"}));
  EXPECT_EQ(c["element_sets"], nlohmann::json({"Eall"}));
  EXPECT_EQ(c["load_cases"], nlohmann::json({"tip_down", "tip_side", "gravity"}));
  EXPECT_NE(file_contents(out / "box.inp.report.md").find("1865 nodes, 320 C3D20R elements"),
            std::string::npos);

  for (const std::string name : {"annulus.step", "annulus.igs"}) {
    run = run_isospring("export-step " + example("patches/quarter_annulus.json") + " -o " +
                        (out / name) + " -q");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(run.output, "") << name;
    const nlohmann::json s = read_json(out / (name + ".report.json"));
    EXPECT_EQ(s["patches"], 1);
    EXPECT_EQ(s["file_bytes"], std::filesystem::file_size(out / name));
    EXPECT_EQ(s["format"], name.ends_with(".igs") ? "iges" : "step");
  }
}

// refine -> fine.json, then export-step -> fine.step and fine.igs in the same folder.
// Every output keeps its own report (named after the output's whole name), so the refine report
// with its geometry check survives the exports.
TEST(FileReports, OutputsWithOneStemKeepTheirOwnReports) {
  TemporaryFolder out;
  auto run = run_isospring("refine " + example("patches/quarter_annulus.json") + " --h 2 -o " +
                           (out / "fine.json") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const std::string name : {"fine.step", "fine.igs"}) {
    run = run_isospring("export-step " + (out / "fine.json") + " -o " + (out / name) + " -q");
    ASSERT_EQ(run.exit_code, 0) << run.output;
  }
  const std::vector<std::pair<std::string, std::string>> expected{
      {"fine.json", "refine"}, {"fine.step", "export-step"}, {"fine.igs", "export-step"}};
  for (const auto& [name, command] : expected) {
    const nlohmann::json r = read_json(out / (name + ".report.json"));
    EXPECT_EQ(r["command"], command) << name;
    EXPECT_EQ(std::filesystem::path(r["output"].get<std::string>()).filename(), name);
    EXPECT_TRUE(std::filesystem::exists(out / (name + ".report.md"))) << name;
  }
  EXPECT_TRUE(read_json(out / "fine.json.report.json").contains("largest_geometry_deviation"));
  EXPECT_FALSE(std::filesystem::exists(out / "fine.report.json"));
}

// a refined part exported to STEP or IGES comes back as a solid. import -> refine ->
// export-step -> import --solids 0 gives one volume patch with the refined part's volume (read
// with `info --json`, our Gauss quadrature of each file) to 1e-9, and the export report counts
// one closed solid.
TEST(FileReports, RefinedPartRoundTripsThroughStepAndIgesAsASolid) {
  TemporaryFolder out;
  auto run =
      run_isospring("import " + example("cad/block.step") + " -o " + (out / "block.json") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  run = run_isospring("refine " + (out / "block.json") + " -o " + (out / "fine.json") +
                      " --elevate 1 --h 2 -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  auto volume_of = [&](const std::string& file) {
    const auto info = run_isospring("info " + file + " --json");
    EXPECT_EQ(info.exit_code, 0) << info.output;
    const nlohmann::json j = nlohmann::json::parse(info.output);
    double volume = 0.0;
    for (const auto& p : j["patches"]) {
      EXPECT_EQ(p["parametric_dimension"], 3) << file;
      volume += p["measure"].get<double>();
    }
    return volume;
  };
  const double refined = volume_of(out / "fine.json");
  EXPECT_NEAR(refined, 0.1 * 0.02 * 0.02, 1e-15);
  for (const std::string name : {"fine.step", "fine.igs"}) {
    run = run_isospring("export-step " + (out / "fine.json") + " -o " + (out / name) + " -q");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const nlohmann::json r = read_json(out / (name + ".report.json"));
    EXPECT_EQ(r["solids"], 1) << name;
    EXPECT_TRUE(r["warnings"].empty()) << name;
    const std::string back = out / (name + ".back.json");
    run = run_isospring("import " + (out / name) + " -o " + back + " --solids 0 -q");
    ASSERT_EQ(run.exit_code, 0) << name << ": " << run.output;
    EXPECT_NEAR(volume_of(back) / refined, 1.0, 1e-9) << name;
  }
}
