// gnuplot figures: each function produces a real PNG (signature and IHDR size as requested)
// when gnuplot is installed; bad inputs give false, never an exception.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: CTest runs tests in parallel processes

#include <cmath>
#include <fstream>
#include <iterator>

#include "isospring/io/plot.hpp"

namespace isospring::io {
namespace {
namespace fs = std::filesystem;

fs::path plot_dir() {
  const fs::path dir = fs::temp_directory_path() /
                       (std::string("isospring_test_plot-") + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

/// Checks the PNG signature and returns (width, height) from the IHDR chunk.
std::pair<int, int> png_size(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                         std::istreambuf_iterator<char>());
  const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < 24 || !std::equal(signature, signature + 8, bytes.begin())) return {0, 0};
  if (std::string(bytes.begin() + 12, bytes.begin() + 16) != "IHDR") return {0, 0};
  auto be32 = [&](size_t at) {
    return (bytes[at] << 24) | (bytes[at + 1] << 16) | (bytes[at + 2] << 8) | bytes[at + 3];
  };
  return {be32(16), be32(20)};
}

TEST(Plot, LastLogSlopeIsTheObservedRate) {
  PlotSeries s{"p=2", {0.5, 0.25, 0.125, 0.0625}, {}};
  for (double h : s.x) s.y.push_back(7 * std::pow(h, 3));
  EXPECT_NEAR(last_log_slope(s), 3.0, 1e-12);
  EXPECT_TRUE(std::isnan(last_log_slope(PlotSeries{"one", {1.0}, {1.0}})));
}

TEST(Plot, FiguresArePngsOfTheRequestedSize) {
  if (!gnuplot_available()) GTEST_SKIP() << "gnuplot with PNG output is not installed";
  const fs::path dir = plot_dir();
  PlotOptions o{"Displacement error", "element size h [m]", "relative L2 error", 640, 480, false};
  std::vector<PlotSeries> rates;
  for (int p = 1; p <= 3; ++p) {
    PlotSeries s{"degree " + std::to_string(p), {}, {}};
    for (double h = 0.2; h > 0.01; h /= 2) {
      s.x.push_back(h);
      s.y.push_back(std::pow(h, p + 1));
    }
    rates.push_back(s);
  }
  EXPECT_TRUE(plot_convergence(dir / "convergence.png", rates, o));
  EXPECT_EQ(png_size(dir / "convergence.png"), std::make_pair(640, 480));

  std::vector<double> residuals;
  for (int i = 0; i < 500; ++i) residuals.push_back(std::sin(i * 0.37) + 0.1 * std::cos(i * 1.3));
  EXPECT_TRUE(plot_histogram(dir / "histogram.png", residuals, 20,
                             {"Residuals", "residual [mm]", "count", 500, 400, false}));
  EXPECT_EQ(png_size(dir / "histogram.png"), std::make_pair(500, 400));

  PlotSeries scatter{"L1", {1, 2, 3, 4}, {1.1, 1.9, 3.2, 3.9}};
  EXPECT_TRUE(plot_xy_scatter(dir / "scatter.png", {scatter},
                              {"Model vs measured", "measured", "model", 500, 500, false}, true));
  EXPECT_EQ(png_size(dir / "scatter.png"), std::make_pair(500, 500));

  // Small multiples: one panel per series, stacked (two columns from four on); the image grows
  // with the rows of panels instead of drawing the series over each other.
  std::vector<PlotSeries> cases;
  for (const char* id : {"L1", "L2", "L3", "L4", "L5"})
    cases.push_back({id, {0, 1, 2, 3}, {0.1, 0.2, 0.4, 0.3}});
  EXPECT_TRUE(plot_xy_panels(dir / "panels3.png", {cases[0], cases[1], cases[2]},
                             {"Errors", "x [m]", "error [%]", 700, 0, false}));
  EXPECT_EQ(png_size(dir / "panels3.png"), std::make_pair(700, 60 + 3 * kPanelHeight));
  EXPECT_TRUE(
      plot_xy_panels(dir / "panels5.png", cases, {"Errors", "x [m]", "error [%]", 700, 0, false}));
  EXPECT_EQ(png_size(dir / "panels5.png"), std::make_pair(700, 60 + 3 * kPanelHeight));
  EXPECT_FALSE(plot_xy_panels(dir / "none.png", {}, {}));

  EXPECT_TRUE(plot_bars_before_after(dir / "bars.png", {"L1", "L2", "L3 \"side\""}, {0.3, 0.5, 0.2},
                                     {0.02, 0.04, 0.01},
                                     {"RMS error", "load case", "RMS error [mm]", 600, 400, true}));
  EXPECT_EQ(png_size(dir / "bars.png"), std::make_pair(600, 400));
  // No temporary or scratch files left beside the figures.
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().extension(), ".png") << entry.path();
}

TEST(Plot, BadInputReturnsFalse) {
  EXPECT_FALSE(plot_bars_before_after(plot_dir() / "bad.png", {"a"}, {1, 2}, {1}));
  EXPECT_FALSE(plot_histogram(plot_dir() / "bad.png", {}, 10));
  EXPECT_FALSE(fs::exists(plot_dir() / "bad.png"));
}

}  // namespace
}  // namespace isospring::io
