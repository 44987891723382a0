#pragma once
// PNG figures through gnuplot, run headless: the data and the script go to a temporary folder,
// gnuplot renders with the pngcairo terminal (png when cairo is missing) into a temporary file
// that is renamed over the target. Figures are a convenience: when gnuplot is missing or fails,
// every function prints one warning on stderr and returns false; it never throws for that, so
// a command never fails because of a figure.
#include <filesystem>
#include <string>
#include <vector>

namespace isospring::io {

struct PlotSeries {
  std::string name;
  std::vector<double> x, y;
};

struct PlotOptions {
  std::string title, xlabel, ylabel;
  int width = 900, height = 600;  // pixels
  bool log_y = false;             // histogram / scatter / bars: logarithmic y axis
};

/// True when a `gnuplot` that can write PNG is on the PATH (checked once).
bool gnuplot_available();

/// Log-log lines with markers, one per series; each legend entry ends with the slope of the
/// last segment ("p=2: slope 3.01"), the observed convergence rate.
bool plot_convergence(const std::filesystem::path& png, const std::vector<PlotSeries>& series,
                      const PlotOptions& options = {});

/// Histogram of `values` in `bins` equal bins between their minimum and maximum.
bool plot_histogram(const std::filesystem::path& png, const std::vector<double>& values, int bins,
                    const PlotOptions& options = {});

/// Scatter of y against x per series; `identity_line` adds y = x (predicted vs measured).
bool plot_xy_scatter(const std::filesystem::path& png, const std::vector<PlotSeries>& series,
                     const PlotOptions& options = {}, bool identity_line = false);

/// Small multiples: one scatter panel per series (its name as the panel title), the panels
/// stacked (two columns from four series on), sharing the x range; y from 0. The image is
/// options.width wide and kPanelHeight pixels high per row of panels (+ 60 for the title), so
/// no series hides another however many there are.
inline constexpr int kPanelHeight = 230;
bool plot_xy_panels(const std::filesystem::path& png, const std::vector<PlotSeries>& series,
                    const PlotOptions& options = {});

/// Clustered bars: for every label a "before" and an "after" bar (e.g. error per load case
/// before and after calibration).
bool plot_bars_before_after(const std::filesystem::path& png,
                            const std::vector<std::string>& labels,
                            const std::vector<double>& before, const std::vector<double>& after,
                            const PlotOptions& options = {});

/// Cost against accuracy: one series per object (x: cost, e.g. microseconds per step, on a log
/// axis; y: error, log axis when options.log_y), every point an open symbol; the points with
/// `marked[series][point]` (e.g. Pareto-optimal) filled and joined by a line in the series'
/// colour. Points with a non-positive or non-finite coordinate are left out.
bool plot_frontier(const std::filesystem::path& png, const std::vector<PlotSeries>& series,
                   const std::vector<std::vector<bool>>& marked, const PlotOptions& options = {});

/// The slope of log y against log x over the last two points with positive finite values
/// (NaN when there are fewer than two).
double last_log_slope(const PlotSeries& series);

}  // namespace isospring::io
