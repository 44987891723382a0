#pragma once
// Small multiples of coloured scatter maps as a self-contained SVG (no gnuplot needed), e.g.
// identify's residuals.svg: one ROW per load case, one PANEL per stage (before, after), each
// point at its (x, y) position coloured by its value on the row's own colour scale [0, row max],
// so a load case with small residuals is not washed out by one with large ones, and load cases
// whose markers share positions are never drawn over each other.
//
// Layout: panels keep the data's aspect ratio (equal x and y scales) within a size limit, with
// ticks and axis labels on every panel, a title above each, and one labelled colour bar at the
// end of each row. The elements carry classes and data attributes so tools and tests can read
// the structure back:
//   <g class="panel" data-row="L1" data-column="before" data-points="N">
//     <rect class="frame" x=".." y=".." width=".." height=".."/> <circle .../> ...
//   <g class="colorbar" data-row="L1" data-min="0" data-max="1.0e-4"> ... <text class="label">
#include <filesystem>
#include <string>
#include <vector>

namespace isospring::io {

struct ScatterPanel {
  std::string column;  // e.g. "before"
  std::string title;   // shown above the panel
  std::vector<double> x, y, value;
};

struct ScatterRow {
  std::string name;  // e.g. the load case id
  std::vector<ScatterPanel> panels;
};

struct ScatterGridOptions {
  std::string title;  // above everything (may be empty)
  std::string xlabel = "x [m]", ylabel = "y [m]";
  std::string value_label = "value";  // colour bar label, e.g. "|residual| [m]"
  double panel_size = 340.0;          // longest side of a panel's plot area [px]
};

/// The SVG document. Rows may have different numbers of panels; empty panels are drawn empty.
/// Throws std::invalid_argument when a panel's x, y and value sizes differ.
std::string scatter_grid_svg(const std::vector<ScatterRow>& rows,
                             const ScatterGridOptions& options = {});

/// Writes scatter_grid_svg atomically.
void write_scatter_grid_svg(const std::filesystem::path& path, const std::vector<ScatterRow>& rows,
                            const ScatterGridOptions& options = {});

}  // namespace isospring::io
