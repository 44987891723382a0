// Small-multiple scatter maps as SVG (identify's residuals.svg drew both load cases
// over each other, with overlapping labels and an unlabelled colour bar). The document is read
// back as text: one panel per (row, column), every point inside its own panel's frame, panels
// apart and inside the canvas, equal x and y scales, one labelled colour bar per row whose top
// is that row's largest value, and the largest value of EVERY row drawn in the top colour.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include "isospring/io/svg_scatter.hpp"

namespace isospring::io {
namespace {

struct Box {
  double x, y, w, h;
};

double attribute(const std::string& element, const std::string& name) {
  std::smatch m;
  const std::regex r("\\s" + name + "=\"([-0-9.eE+]+)\"");
  if (!std::regex_search(element, m, r)) return NAN;
  return std::stod(m[1].str());
}

std::string text_attribute(const std::string& element, const std::string& name) {
  std::smatch m;
  const std::regex r("\\s" + name + "=\"([^\"]*)\"");
  return std::regex_search(element, m, r) ? m[1].str() : "";
}

std::vector<std::string> all(const std::string& text, const std::string& pattern) {
  std::vector<std::string> out;
  const std::regex r(pattern);
  for (auto it = std::sregex_iterator(text.begin(), text.end(), r); it != std::sregex_iterator();
       ++it)
    out.push_back((*it)[0].str());
  return out;
}

bool overlap(const Box& a, const Box& b) {
  return a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h;
}

TEST(SvgScatter, OnePanelPerLoadCaseAndStageWithItsOwnColourScale) {
  // Two load cases at the SAME marker positions on a 2 x 1 plate; L1's values are 10x L2's.
  std::vector<ScatterRow> rows;
  for (const std::string id : {"L1", "L2"}) {
    ScatterRow row;
    row.name = id;
    const double scale = id == "L1" ? 1e-4 : 1e-5;
    for (const std::string stage : {"before", "after"}) {
      ScatterPanel p;
      p.column = stage;
      p.title = id + ", " + stage + ": rms 1.2e-05 m, max |r| 1e-04 m";
      for (int i = 0; i <= 10; ++i)
        for (int j = 0; j <= 5; ++j) {
          p.x.push_back(0.2 * i);
          p.y.push_back(0.2 * j);
          p.value.push_back(scale * (stage == "before" ? 1.0 : 0.1) * (i + j) / 15.0);
        }
      row.panels.push_back(p);
    }
    rows.push_back(row);
  }
  ScatterGridOptions options;
  options.title = "residuals";
  options.value_label = "|residual| [m]";
  const std::string svg = scatter_grid_svg(rows, options);

  const double width = attribute(svg.substr(svg.find("<svg")), "width");
  const double height = attribute(svg.substr(svg.find("<svg")), "height");
  ASSERT_GT(width, 0);
  ASSERT_GT(height, 0);

  const auto panels = all(svg, "<g class=\"panel\"[\\s\\S]*?</g>");
  ASSERT_EQ(panels.size(), 4u);
  std::vector<Box> frames;
  std::map<std::string, std::vector<std::string>> top_colour_rows;
  for (const std::string& panel : panels) {
    const std::string head = panel.substr(0, panel.find('>'));
    const std::string row = text_attribute(head, "data-row");
    const std::string column = text_attribute(head, "data-column");
    const auto circles = all(panel, "<circle [^>]*>");
    EXPECT_EQ(text_attribute(head, "data-points"), "66") << row << column;
    EXPECT_EQ(circles.size(), 66u) << row << column;
    const std::string frame = all(panel, "<rect class=\"frame\"[^>]*>").at(0);
    const Box box{attribute(frame, "x"), attribute(frame, "y"), attribute(frame, "width"),
                  attribute(frame, "height")};
    // Equal scales: the data (2 x 1, padded alike) keeps its aspect ratio.
    EXPECT_NEAR(box.w / box.h, 2.0, 1e-2) << row << column;
    EXPECT_GE(box.x, 0);
    EXPECT_GE(box.y, 0);
    EXPECT_LE(box.x + box.w, width);
    EXPECT_LE(box.y + box.h, height);
    for (const Box& other : frames) EXPECT_FALSE(overlap(box, other)) << row << column;
    frames.push_back(box);
    for (const std::string& c : circles) {
      const double cx = attribute(c, "cx"), cy = attribute(c, "cy");
      EXPECT_TRUE(cx >= box.x && cx <= box.x + box.w && cy >= box.y && cy <= box.y + box.h)
          << row << column << ": " << c;
      if (text_attribute(c, "fill") == "#fde725") top_colour_rows[row].push_back(column);
    }
    // The title sits above its frame and fits the panel's column (~0.6 em per character).
    const std::string title = all(panel, "<text class=\"panel-title\"[^>]*>[^<]*").at(0);
    EXPECT_LT(attribute(title, "y"), box.y);
    const double title_width = 0.6 * 12.0 * (title.size() - title.find('>') - 1);
    EXPECT_LT(title_width, box.w + 60) << title;
  }
  // Each row's largest value (its "before" panel) reaches the top of the row's own scale: L2,
  // with 10x smaller residuals, is not washed out by L1.
  EXPECT_EQ(top_colour_rows["L1"], std::vector<std::string>{"before"});
  EXPECT_EQ(top_colour_rows["L2"], std::vector<std::string>{"before"});

  const auto bars = all(svg, "<g class=\"colorbar\"[\\s\\S]*?</g>");
  ASSERT_EQ(bars.size(), 2u);
  for (const std::string& bar : bars) {
    const std::string head = bar.substr(0, bar.find('>'));
    const std::string row = text_attribute(head, "data-row");
    EXPECT_EQ(text_attribute(head, "data-max"), row == "L1" ? "0.0001" : "1e-05");
    EXPECT_NE(bar.find("|residual| [m], " + row + "</text>"), std::string::npos) << row;
    const std::string rect = all(bar, "<rect [^>]*>").at(0);
    const Box box{attribute(rect, "x"), attribute(rect, "y"), attribute(rect, "width"),
                  attribute(rect, "height")};
    EXPECT_LE(box.x + box.w + 60, width);  // room for its tick labels
    for (const Box& frame : frames) EXPECT_FALSE(overlap(box, frame)) << row;
  }
}

TEST(SvgScatter, MismatchedSizesAreRefused) {
  ScatterRow row;
  row.panels.push_back({"a", "a", {0.0, 1.0}, {0.0}, {1.0, 2.0}});
  EXPECT_THROW((void)scatter_grid_svg({row}), std::invalid_argument);
}

}  // namespace
}  // namespace isospring::io
