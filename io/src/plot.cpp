#include "isospring/io/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>

#include "isospring/io/atomic_file.hpp"

namespace isospring::io {
namespace fs = std::filesystem;

namespace {
/// "pngcairo", "png" or "" (no usable gnuplot).
const std::string& png_terminal() {
  static const std::string terminal = [] {
    for (const char* candidate : {"pngcairo", "png"}) {
      const std::string command =
          std::string("gnuplot -e \"set terminal ") + candidate + "\" >/dev/null 2>&1";
      if (std::system(command.c_str()) == 0) return std::string(candidate);
    }
    return std::string();
  }();
  return terminal;
}

/// A gnuplot string literal: single quotes, doubled inside.
std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  return buffer;
}

/// A scratch folder removed when the plot is done.
class ScratchFolder {
 public:
  ScratchFolder() {
    std::random_device random;
    path_ = fs::temp_directory_path() / ("isospring_plot_" + std::to_string(random()));
    fs::create_directories(path_);
  }
  ~ScratchFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string header(const PlotOptions& o, const std::string& terminal, const fs::path& output) {
  std::ostringstream s;
  s << "set terminal " << terminal << " size " << o.width << "," << o.height
    << (terminal == "pngcairo" ? " enhanced font 'sans,11'" : "") << "\n"
    << "set output " << quoted(output.string()) << "\n"
    << "set title " << quoted(o.title) << " noenhanced\n"
    << "set xlabel " << quoted(o.xlabel) << " noenhanced\n"
    << "set ylabel " << quoted(o.ylabel) << " noenhanced\n"
    << "set grid\nset key top left box opaque noenhanced\n";
  if (o.log_y) s << "set logscale y\nset format y '10^{%L}'\n";
  return s.str();
}

/// Writes the data files given as (name, content), runs the script, renames the PNG.
bool render(
    const fs::path& png, const std::string& what,
    const std::vector<std::pair<std::string, std::string>>& data,
    const std::function<std::string(const fs::path& folder, const fs::path& output)>& script) {
  const std::string& terminal = png_terminal();
  if (terminal.empty()) {
    std::cerr << "warning: gnuplot with PNG output not found; figure '" << png.string()
              << "' not written (install gnuplot-nox)\n";
    return false;
  }
  try {
    ScratchFolder scratch;
    for (const auto& [name, content] : data) std::ofstream(scratch.path() / name) << content;
    write_via_temporary(png, [&](const fs::path& temporary) {
      const fs::path script_file = scratch.path() / "plot.gp";
      std::ofstream(script_file) << script(scratch.path(), temporary);
      const std::string command = "gnuplot " + quoted(script_file.string()) + " >" +
                                  quoted((scratch.path() / "log.txt").string()) + " 2>&1";
      if (std::system(command.c_str()) != 0 || !fs::exists(temporary) ||
          fs::file_size(temporary) == 0) {
        std::ifstream log(scratch.path() / "log.txt");
        std::stringstream text;
        text << log.rdbuf();
        throw std::runtime_error("gnuplot failed for the " + what + ": " + text.str());
      }
    });
    return true;
  } catch (const std::exception& e) {
    std::cerr << "warning: figure '" << png.string() << "' not written: " << e.what() << "\n";
    return false;
  }
}

std::string series_file(const PlotSeries& s, bool positive_only) {
  std::ostringstream out;
  const size_t n = std::min(s.x.size(), s.y.size());
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
    if (positive_only && (s.x[i] <= 0 || s.y[i] <= 0)) continue;
    out << number(s.x[i]) << " " << number(s.y[i]) << "\n";
  }
  return out.str();
}

/// Bars start at 0 on a linear axis; on a log axis the range is padded so the smallest positive
/// bar is visible and not drawn on the frame.
std::string y_range(const std::vector<double>& a, const std::vector<double>& b, bool log_y) {
  if (!log_y) return "set yrange [0:*]\n";
  double lo = std::numeric_limits<double>::infinity(), hi = 0;
  for (const auto* values : {&a, &b})
    for (double v : *values)
      if (std::isfinite(v) && v > 0) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!(hi > 0)) return "";
  return "set yrange [" + number(lo / 3) + ":" + number(hi * 3) + "]\n";
}
}  // namespace

bool gnuplot_available() {
  return !png_terminal().empty();
}

double last_log_slope(const PlotSeries& s) {
  std::vector<std::pair<double, double>> points;
  for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
    if (std::isfinite(s.x[i]) && std::isfinite(s.y[i]) && s.x[i] > 0 && s.y[i] > 0)
      points.emplace_back(std::log(s.x[i]), std::log(s.y[i]));
  if (points.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  const auto& a = points[points.size() - 2];
  const auto& b = points.back();
  return (b.second - a.second) / (b.first - a.first);
}

bool plot_convergence(const fs::path& png, const std::vector<PlotSeries>& series,
                      const PlotOptions& options) {
  std::vector<std::pair<std::string, std::string>> data;
  for (size_t s = 0; s < series.size(); ++s)
    data.emplace_back("series" + std::to_string(s) + ".dat", series_file(series[s], true));
  return render(png, "convergence plot", data, [&](const fs::path& folder, const fs::path& out) {
    std::ostringstream g;
    g << header(options, png_terminal(), out) << "set logscale xy\nset format x '10^{%L}'\n"
      << "set format y '10^{%L}'\nset key bottom right\nplot ";
    for (size_t s = 0; s < series.size(); ++s) {
      std::string title = series[s].name;
      const double slope = last_log_slope(series[s]);
      if (std::isfinite(slope)) {
        char text[32];
        std::snprintf(text, sizeof(text), ": slope %.2f", slope);
        title += text;
      }
      g << (s ? ", " : "") << quoted((folder / ("series" + std::to_string(s) + ".dat")).string())
        << " using 1:2 with linespoints lw 2 pt " << 5 + 2 * static_cast<int>(s % 4)
        << " ps 1.3 title " << quoted(title);
    }
    return g.str() + "\n";
  });
}

bool plot_histogram(const fs::path& png, const std::vector<double>& values, int bins,
                    const PlotOptions& options) {
  std::vector<double> finite;
  for (double v : values)
    if (std::isfinite(v)) finite.push_back(v);
  if (finite.empty() || bins < 1) {
    std::cerr << "warning: figure '" << png.string() << "' not written: no finite values\n";
    return false;
  }
  const auto [lo, hi] = std::minmax_element(finite.begin(), finite.end());
  const double low = *lo, width = *hi > *lo ? (*hi - *lo) / bins : 1.0;
  std::vector<int> counts(static_cast<size_t>(bins), 0);
  for (double v : finite)
    ++counts[static_cast<size_t>(std::clamp(static_cast<int>((v - low) / width), 0, bins - 1))];
  std::ostringstream table;
  for (int b = 0; b < bins; ++b)
    table << number(low + (b + 0.5) * width) << " " << counts[static_cast<size_t>(b)] << "\n";
  return render(png, "histogram", {{"histogram.dat", table.str()}},
                [&](const fs::path& folder, const fs::path& out) {
                  std::ostringstream g;
                  g << header(options, png_terminal(), out)
                    << "unset key\n"  // one unnamed series: no empty legend box
                    << "set style fill solid 0.6 border -1\n"
                    << "set boxwidth " << number(0.9 * width) << "\nset yrange [0:*]\n"
                    << "plot " << quoted((folder / "histogram.dat").string())
                    << " using 1:2 with boxes lc rgb '#3070b0' notitle\n";
                  return g.str();
                });
}

bool plot_xy_scatter(const fs::path& png, const std::vector<PlotSeries>& series,
                     const PlotOptions& options, bool identity_line) {
  std::vector<std::pair<std::string, std::string>> data;
  for (size_t s = 0; s < series.size(); ++s)
    data.emplace_back("series" + std::to_string(s) + ".dat", series_file(series[s], false));
  return render(png, "scatter plot", data, [&](const fs::path& folder, const fs::path& out) {
    std::ostringstream g;
    g << header(options, png_terminal(), out) << "plot ";
    for (size_t s = 0; s < series.size(); ++s)
      g << (s ? ", " : "") << quoted((folder / ("series" + std::to_string(s) + ".dat")).string())
        << " using 1:2 with points pt " << 7 + 2 * static_cast<int>(s % 3) << " ps 1.2 title "
        << quoted(series[s].name);
    if (identity_line)
      g << (series.empty() ? "" : ", ") << "x with lines dt 2 lc rgb 'black' title 'y = x'";
    return g.str() + "\n";
  });
}

bool plot_xy_panels(const fs::path& png, const std::vector<PlotSeries>& series,
                    const PlotOptions& options) {
  if (series.empty()) {
    std::cerr << "warning: figure '" << png.string() << "' not written: no series\n";
    return false;
  }
  std::vector<std::pair<std::string, std::string>> data;
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
  for (size_t s = 0; s < series.size(); ++s) {
    data.emplace_back("series" + std::to_string(s) + ".dat", series_file(series[s], false));
    for (const double x : series[s].x)
      if (std::isfinite(x)) x_lo = std::min(x_lo, x), x_hi = std::max(x_hi, x);
  }
  const size_t count = series.size(), columns = count <= 3 ? 1 : 2;
  const size_t rows = (count + columns - 1) / columns;
  const int width = options.width, height = 60 + static_cast<int>(rows) * kPanelHeight;
  return render(png, "panel plot", data, [&](const fs::path& folder, const fs::path& out) {
    std::ostringstream g;
    const std::string& terminal = png_terminal();
    g << "set terminal " << terminal << " size " << width << "," << height
      << (terminal == "pngcairo" ? " enhanced font 'sans,10'" : "") << "\n"
      << "set output " << quoted(out.string()) << "\n"
      << "set multiplot layout " << rows << "," << columns << " title " << quoted(options.title)
      << " noenhanced\n"
      << "set xlabel " << quoted(options.xlabel) << " noenhanced\n"
      << "set ylabel " << quoted(options.ylabel) << " noenhanced\n"
      << "set grid\nunset key\nset yrange [0:*]\n";
    if (x_lo < x_hi) {
      const double pad = 0.03 * (x_hi - x_lo);
      g << "set xrange [" << number(x_lo - pad) << ":" << number(x_hi + pad) << "]\n";
    }
    for (size_t s = 0; s < count; ++s)
      g << "set title " << quoted(series[s].name) << " noenhanced\nplot "
        << quoted((folder / ("series" + std::to_string(s) + ".dat")).string())
        << " using 1:2 with points pt 7 ps 0.9 lc rgb '#3070b0' notitle\n";
    g << "unset multiplot\n";
    return g.str();
  });
}

bool plot_bars_before_after(const fs::path& png, const std::vector<std::string>& labels,
                            const std::vector<double>& before, const std::vector<double>& after,
                            const PlotOptions& options) {
  if (labels.size() != before.size() || labels.size() != after.size() || labels.empty()) {
    std::cerr << "warning: figure '" << png.string()
              << "' not written: labels, before and after differ in length\n";
    return false;
  }
  std::ostringstream table;
  for (size_t i = 0; i < labels.size(); ++i) {
    std::string label = labels[i];
    std::replace(label.begin(), label.end(), '"', '\'');
    table << '"' << label << "\" " << number(before[i]) << " " << number(after[i]) << "\n";
  }
  return render(png, "bar chart", {{"bars.dat", table.str()}},
                [&](const fs::path& folder, const fs::path& out) {
                  const std::string file = quoted((folder / "bars.dat").string());
                  std::ostringstream g;
                  g << header(options, png_terminal(), out)
                    << "set style data histograms\nset style histogram clustered gap 1\n"
                    << "set style fill solid 0.8 border -1\nset key top right\n"
                    << y_range(before, after, options.log_y) << "set xtics noenhanced\n"
                    << "plot " << file << " using 2:xtic(1) lc rgb '#c04040' title 'before', "
                    << file << " using 3 lc rgb '#3070b0' title 'after'\n";
                  return g.str();
                });
}

bool plot_frontier(const fs::path& png, const std::vector<PlotSeries>& series,
                   const std::vector<std::vector<bool>>& marked, const PlotOptions& options) {
  std::vector<std::pair<std::string, std::string>> data;
  for (size_t s = 0; s < series.size(); ++s) {
    PlotSeries front;
    for (size_t i = 0; i < std::min(series[s].x.size(), series[s].y.size()); ++i)
      if (s < marked.size() && i < marked[s].size() && marked[s][i]) {
        front.x.push_back(series[s].x[i]);
        front.y.push_back(series[s].y[i]);
      }
    // The front joined from cheap to costly.
    std::vector<size_t> order(front.x.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return front.x[a] < front.x[b]; });
    PlotSeries sorted;
    for (size_t i : order) sorted.x.push_back(front.x[i]), sorted.y.push_back(front.y[i]);
    data.emplace_back("all" + std::to_string(s) + ".dat", series_file(series[s], true));
    data.emplace_back("front" + std::to_string(s) + ".dat", series_file(sorted, true));
  }
  return render(png, "frontier plot", data, [&](const fs::path& folder, const fs::path& out) {
    std::ostringstream g;
    g << header(options, png_terminal(), out) << "set logscale x\nset format x '10^{%L}'\n"
      << "set key top right\nplot ";
    for (size_t s = 0; s < series.size(); ++s) {
      // Six colours and symbols told apart also in grey (open symbol n, filled n + 1).
      static const char* const kColours[] = {"#7b2d9e", "#009e73", "#0072b2",
                                             "#e69f00", "#d55e00", "#555555"};
      const std::string colour = std::string("rgb '") + kColours[s % 6] + "'";
      const int open_symbol = 4 + 2 * static_cast<int>(s % 6);  // 4 6 8 10 12 14
      g << (s ? ", " : "") << quoted((folder / ("all" + std::to_string(s) + ".dat")).string())
        << " using 1:2 with points lc " << colour << " pt " << open_symbol << " ps 1.4 notitle, "
        << quoted((folder / ("front" + std::to_string(s) + ".dat")).string())
        << " using 1:2 with linespoints lc " << colour << " lw 2 pt " << open_symbol + 1
        << " ps 1.6 title " << quoted(series[s].name);
    }
    return g.str() + "\n";
  });
}

}  // namespace isospring::io
