// Small multiples of coloured scatter maps as SVG (svg_scatter.hpp).
#include "isospring/io/svg_scatter.hpp"
#include "export_xml.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "isospring/io/atomic_file.hpp"

namespace isospring::io {
namespace {

// Layout constants [px].
constexpr double kLeft = 64.0;       // room for y tick labels and the y label
constexpr double kBottom = 44.0;     // x tick labels and the x label
constexpr double kTop = 30.0;        // panel title
constexpr double kGap = 26.0;        // between panels
constexpr double kBarGap = 18.0;     // panel -> colour bar
constexpr double kBarWidth = 14.0;   // colour bar
constexpr double kBarLabels = 92.0;  // tick labels and the rotated label of the colour bar
constexpr double kHeader = 34.0;     // the document title
constexpr double kFont = 11.0;       // tick labels and axis labels
constexpr double kTitleFont = 12.0;  // panel titles

using detail::xml_escape;  // text and attribute values: & < > " escaped

std::string num(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2f", v);
  return buffer;
}

std::string label(double v) {
  if (std::abs(v) < 1e-300) return "0";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", v);
  return buffer;
}

// 1, 2 or 5 times a power of ten, about range / 4; ticks inside [lo, hi].
std::vector<double> ticks(double lo, double hi) {
  const double raw = (hi - lo) / 4.0;
  if (!(raw > 0.0) || !std::isfinite(raw)) return {lo};
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = power;
  for (const double m : {1.0, 2.0, 5.0, 10.0})
    if (m * power >= raw) {
      step = m * power;
      break;
    }
  std::vector<double> out;
  for (double t = std::ceil(lo / step - 1e-9) * step; t <= hi + 1e-9 * step; t += step)
    out.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  return out;
}

// Viridis, linearly interpolated between five stops; t in [0, 1].
std::string colour(double t) {
  static const std::array<std::array<double, 3>, 5> stops{
      {{68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}}};
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * 4.0;
  const auto k = std::min<size_t>(3, static_cast<size_t>(t));
  const double f = t - static_cast<double>(k);
  char buffer[16];
  std::snprintf(buffer, sizeof buffer, "#%02x%02x%02x",
                static_cast<int>(std::lround(stops[k][0] + f * (stops[k + 1][0] - stops[k][0]))),
                static_cast<int>(std::lround(stops[k][1] + f * (stops[k + 1][1] - stops[k][1]))),
                static_cast<int>(std::lround(stops[k][2] + f * (stops[k + 1][2] - stops[k][2]))));
  return buffer;
}

struct Range {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
  // Padded by 5 % (a point on the edge stays inside the frame); a single value gets +-0.5 or
  // +-5 % of itself.
  void pad() {
    if (!(lo <= hi)) lo = 0.0, hi = 1.0;
    double span = hi - lo;
    if (span <= 0.0) span = std::abs(lo) > 0.0 ? 0.1 * std::abs(lo) : 1.0;
    lo -= 0.05 * span;
    hi += 0.05 * span;
  }
};

}  // namespace

std::string scatter_grid_svg(const std::vector<ScatterRow>& rows,
                             const ScatterGridOptions& options) {
  Range xr, yr;
  size_t columns = 1;
  for (const auto& row : rows) {
    columns = std::max(columns, row.panels.size());
    for (const auto& panel : row.panels) {
      if (panel.x.size() != panel.y.size() || panel.x.size() != panel.value.size())
        throw std::invalid_argument("scatter_grid_svg: x, y and value sizes differ in a panel");
      for (size_t i = 0; i < panel.x.size(); ++i) xr.add(panel.x[i]), yr.add(panel.y[i]);
    }
  }
  xr.pad();
  yr.pad();
  // Equal scales when the shape allows it; a very flat or tall region is kept readable.
  const double aspect = (yr.hi - yr.lo) / (xr.hi - xr.lo);
  double pw = options.panel_size, ph = options.panel_size;
  if (aspect <= 1.0)
    ph = std::max(0.3 * options.panel_size, options.panel_size * aspect);
  else
    pw = std::max(0.3 * options.panel_size, options.panel_size / aspect);
  const double cell_w = kLeft + pw + kGap, cell_h = kTop + ph + kBottom;
  const double header = options.title.empty() ? 8.0 : kHeader;
  const double width = static_cast<double>(columns) * cell_w + kBarGap + kBarWidth + kBarLabels;
  const double height = header + static_cast<double>(rows.size()) * cell_h + 8.0;

  std::ostringstream svg;
  svg << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(width) << "\" height=\""
      << num(height) << "\" viewBox=\"0 0 " << num(width) << " " << num(height)
      << "\" font-family=\"sans-serif\" font-size=\"" << num(kFont) << "\">\n"
      << "<rect class=\"background\" x=\"0\" y=\"0\" width=\"" << num(width) << "\" height=\""
      << num(height) << "\" fill=\"white\"/>\n";
  if (!options.title.empty())
    svg << "<text class=\"title\" x=\"" << num(width / 2) << "\" y=\"22\" text-anchor=\"middle\" "
        << "font-size=\"14\" font-weight=\"bold\">" << xml_escape(options.title) << "</text>\n";

  for (size_t r = 0; r < rows.size(); ++r) {
    const ScatterRow& row = rows[r];
    double row_max = 0.0;
    for (const auto& panel : row.panels)
      for (const double v : panel.value)
        if (std::isfinite(v)) row_max = std::max(row_max, v);
    const double scale = row_max > 0.0 ? row_max : 1.0;
    const double top = header + static_cast<double>(r) * cell_h;
    for (size_t c = 0; c < row.panels.size(); ++c) {
      const ScatterPanel& panel = row.panels[c];
      const double x0 = static_cast<double>(c) * cell_w + kLeft, y0 = top + kTop;
      auto px = [&](double x) { return x0 + (x - xr.lo) / (xr.hi - xr.lo) * pw; };
      auto py = [&](double y) { return y0 + ph - (y - yr.lo) / (yr.hi - yr.lo) * ph; };
      svg << "<g class=\"panel\" data-row=\"" << xml_escape(row.name) << "\" data-column=\""
          << xml_escape(panel.column) << "\" data-points=\"" << panel.x.size() << "\">\n"
          << "<text class=\"panel-title\" x=\"" << num(x0 + pw / 2) << "\" y=\"" << num(y0 - 10)
          << "\" text-anchor=\"middle\" font-size=\"" << num(kTitleFont) << "\">"
          << xml_escape(panel.title) << "</text>\n"
          << "<rect class=\"frame\" x=\"" << num(x0) << "\" y=\"" << num(y0) << "\" width=\""
          << num(pw) << "\" height=\"" << num(ph) << "\" fill=\"#f4f4f4\" stroke=\"#444\"/>\n";
      for (const double t : ticks(xr.lo, xr.hi))
        svg << "<line x1=\"" << num(px(t)) << "\" y1=\"" << num(y0 + ph) << "\" x2=\"" << num(px(t))
            << "\" y2=\"" << num(y0 + ph + 4) << "\" stroke=\"#444\"/>"
            << "<text class=\"tick\" x=\"" << num(px(t)) << "\" y=\"" << num(y0 + ph + 16)
            << "\" text-anchor=\"middle\">" << label(t) << "</text>\n";
      for (const double t : ticks(yr.lo, yr.hi))
        svg << "<line x1=\"" << num(x0 - 4) << "\" y1=\"" << num(py(t)) << "\" x2=\"" << num(x0)
            << "\" y2=\"" << num(py(t)) << "\" stroke=\"#444\"/>"
            << "<text class=\"tick\" x=\"" << num(x0 - 6) << "\" y=\"" << num(py(t) + 4)
            << "\" text-anchor=\"end\">" << label(t) << "</text>\n";
      svg << "<text class=\"axis-label\" x=\"" << num(x0 + pw / 2) << "\" y=\"" << num(y0 + ph + 34)
          << "\" text-anchor=\"middle\">" << xml_escape(options.xlabel) << "</text>\n"
          << "<text class=\"axis-label\" x=\"" << num(x0 - 48) << "\" y=\"" << num(y0 + ph / 2)
          << "\" text-anchor=\"middle\" transform=\"rotate(-90 " << num(x0 - 48) << " "
          << num(y0 + ph / 2) << ")\">" << xml_escape(options.ylabel) << "</text>\n";
      for (size_t i = 0; i < panel.x.size(); ++i) {
        if (!std::isfinite(panel.x[i]) || !std::isfinite(panel.y[i])) continue;
        svg << "<circle cx=\"" << num(px(panel.x[i])) << "\" cy=\"" << num(py(panel.y[i]))
            << "\" r=\"3.5\" fill=\"" << colour(panel.value[i] / scale) << "\"/>\n";
      }
      svg << "</g>\n";
    }
    // The row's colour bar: a vertical gradient from 0 (bottom) to the row's largest value.
    const double bx = static_cast<double>(columns) * cell_w + kBarGap - kGap, by = top + kTop;
    const std::string gradient = "bar" + std::to_string(r);
    svg << "<g class=\"colorbar\" data-row=\"" << xml_escape(row.name) << "\" data-min=\"0\" "
        << "data-max=\"" << label(row_max) << "\">\n<defs><linearGradient id=\"" << gradient
        << "\" x1=\"0\" y1=\"1\" x2=\"0\" y2=\"0\">";
    for (int s = 0; s <= 8; ++s)
      svg << "<stop offset=\"" << num(s / 8.0) << "\" stop-color=\"" << colour(s / 8.0) << "\"/>";
    svg << "</linearGradient></defs>\n<rect x=\"" << num(bx) << "\" y=\"" << num(by)
        << "\" width=\"" << num(kBarWidth) << "\" height=\"" << num(ph) << "\" fill=\"url(#"
        << gradient << ")\" stroke=\"#444\"/>\n";
    // Nice ticks, and the row's largest value at the top (ticks too close to it are left out).
    std::vector<double> bar_ticks;
    for (const double t : ticks(0.0, scale))
      if (t < 0.85 * scale) bar_ticks.push_back(t);
    bar_ticks.push_back(row_max);
    for (const double t : bar_ticks)
      svg << "<text class=\"tick\" x=\"" << num(bx + kBarWidth + 4) << "\" y=\""
          << num(by + ph - t / scale * ph + 4) << "\">" << label(t) << "</text>\n";
    const double lx = bx + kBarWidth + kBarLabels - 30, ly = by + ph / 2;
    svg << "<text class=\"label\" x=\"" << num(lx) << "\" y=\"" << num(ly)
        << "\" text-anchor=\"middle\" transform=\"rotate(-90 " << num(lx) << " " << num(ly)
        << ")\">" << xml_escape(options.value_label + ", " + row.name) << "</text>\n</g>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

void write_scatter_grid_svg(const std::filesystem::path& path, const std::vector<ScatterRow>& rows,
                            const ScatterGridOptions& options) {
  write_file_atomically(path, scatter_grid_svg(rows, options));
}

}  // namespace isospring::io
