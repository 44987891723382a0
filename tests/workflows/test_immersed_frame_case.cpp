// The case file's "geometry": {"frame": ...} (docs/case-files.md): the grid along user axes or the
// part's principal axes, the report saying which, and the refusals. On the CAx-IF nut
// (tests/data/parts/caxif_nut.stp), clamped on face 4 under its weight: a frame turned by 90
// degrees about z (entries 0 and +-1, so exact) gives the file-axes grid turned, and so the same
// DOFs, strain energy and largest surface displacement to the cut-cell quadrature's tolerance:
// in the frame the grid's x is the world's y, and the cut-cell rules, which pick their line
// directions and nesting by axis, integrate the same cells differently within their tolerance
// (1e-7 of a cell's volume); measured 1.8e-7 (energy) and 1.9e-7 (displacement), checked to 1e-6.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <string>

#include "immersed_test_parts.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/io/immersed_case.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/workflows/analyze_immersed.hpp"

namespace isospring::workflows {
namespace {

namespace fs = std::filesystem;

const fs::path kNut = fs::path(ISOSPRING_SOURCE_DIR) / "tests/data/parts/caxif_nut.stp";

nlohmann::json nut_case(const nlohmann::json& frame) {
  nlohmann::json geometry = {
      {"type", "immersed"}, {"file", kNut.string()}, {"cell_size", 0.002}, {"degree", 2}};
  if (!frame.is_null()) geometry["frame"] = frame;
  return {{"schema_version", 1},
          {"name", "nut"},
          {"geometry", geometry},
          {"material", {{"E", 2.1e11}, {"nu", 0.3}, {"density", 7850.0}}},
          {"boundary", {{{"face", 4}, {"fix", {"x", "y", "z"}}}}},
          {"load_cases", {{{"id", "gravity"}, {"gravity", {0.0, 0.0, -9.81}}}}}};
}

io::ImmersedCase read(const testing::ScratchFolder& dir, const nlohmann::json& frame) {
  return io::read_immersed_case(testing::write_json(dir.path / "nut.json", nut_case(frame)));
}

std::string refusal(const testing::ScratchFolder& dir, const nlohmann::json& frame) {
  try {
    read(dir, frame);
  } catch (const nurbs::InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ImmersedFrameCase, TurnedFrameGivesTheSameSolutionAndTheReportSaysSo) {
  if (!fs::exists(kNut)) GTEST_SKIP() << kNut << " (a third-party part) is absent";
  const testing::ScratchFolder dir("immersed-frame-case");
  const io::ImmersedCase plain = read(dir, nullptr);
  const io::ImmersedCase turned = read(dir, {{"x", {0, 1, 0}}, {"y", {-1, 0, 0}}});
  EXPECT_EQ(plain.frame, "file");
  EXPECT_EQ(turned.frame, "user");
  Eigen::Matrix3d expected;
  expected << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_EQ(turned.immersion.frame, expected);
  const io::Progress quiet("analyze", true);
  const auto method = analysis::SolverOptions::Method::kCholesky;
  const ImmersedAnalysis a = run_analyze_immersed(plain, method, quiet);
  const ImmersedAnalysis b = run_analyze_immersed(turned, method, quiet);
  ASSERT_EQ(a.load_cases.size(), 1u);
  ASSERT_EQ(b.load_cases.size(), 1u);
  const analysis::ImmersedResult &ra = a.load_cases[0].result, &rb = b.load_cases[0].result;
  EXPECT_EQ(rb.dofs, ra.dofs);
  EXPECT_NEAR(rb.strain_energy, ra.strain_energy, 1e-6 * ra.strain_energy);
  EXPECT_NEAR(b.load_cases[0].max_displacement, a.load_cases[0].max_displacement,
              1e-6 * a.load_cases[0].max_displacement);
  const nlohmann::json report =
      write_immersed_outputs(b, dir.path / "out", quiet, std::chrono::steady_clock::now());
  EXPECT_EQ(report.at("immersion").at("frame"), "user");
  EXPECT_EQ(report.at("immersion").at("frame_axes").at(0), nlohmann::json({0.0, 1.0, 0.0}));

  const io::ImmersedCase principal = read(dir, "principal");
  EXPECT_EQ(principal.frame, "principal");
  EXPECT_TRUE(principal.frame_note.empty()) << principal.frame_note;
  EXPECT_LT((principal.immersion.frame - geometry::principal_frame(*principal.cad).axes).norm(),
            1e-15);
}

TEST(ImmersedFrameCase, RefusesFramesThatAreNotOnes) {
  if (!fs::exists(kNut)) GTEST_SKIP() << kNut << " (a third-party part) is absent";
  const testing::ScratchFolder dir("immersed-frame-refusals");
  EXPECT_NE(refusal(dir, "diagonal").find("\"principal\""), std::string::npos)
      << refusal(dir, "diagonal");
  const std::string skew = refusal(dir, {{"x", {1, 0, 0}}, {"y", {1, 1, 0}}});
  EXPECT_NE(skew.find("right angles"), std::string::npos) << skew;
  const std::string zero = refusal(dir, {{"x", {0, 0, 0}}, {"y", {0, 1, 0}}});
  EXPECT_NE(zero.find("nonzero"), std::string::npos) << zero;
  const std::string other = refusal(dir, {{"x", {1, 0, 0}}, {"z", {0, 0, 1}}});
  EXPECT_NE(other.find("frame"), std::string::npos) << other;
}

}  // namespace
}  // namespace isospring::workflows
