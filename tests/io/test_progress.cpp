// Progress on stderr ("progress a person can read"): on a terminal, the iterations of a
// stage rewrite ONE status line (carriage return + clear line) that the next milestone replaces;
// elsewhere (logs, pipes) only milestone lines are written; warnings are always written and kept
// for the reports.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "isospring/io/report.hpp"

namespace isospring::io {
namespace {

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(Progress, TerminalShowsIterationsOnOneUpdatingLine) {
  std::ostringstream out;
  {
    const Progress progress("calibrate", false, out, true);
    progress("reading case.json");
    for (int i = 1; i <= 50; ++i) progress.update("fit (gamma 0.05)", i, 1.0 / i);
    progress("fitted");
  }
  const std::string text = out.str();
  // 50 iterations within far less than 0.1 s: drawn once (10 redraws a second at most), on a
  // line that starts with a carriage return and clear-to-end and ends without a newline.
  EXPECT_EQ(count(text, "iteration "), 1u) << text;
  EXPECT_NE(text.find("\r\033[K[calibrate] fit (gamma 0.05): iteration 1, cost 1, "),
            std::string::npos)
      << text;
  // The milestone clears the status line first and then stands on its own line.
  EXPECT_NE(text.find(" s\r\033[K[calibrate] fitted\n"), std::string::npos) << text;
  EXPECT_EQ(text.rfind("[calibrate] reading case.json\n", 0), 0u) << text;
}

TEST(Progress, LogsGetMilestonesOnly) {
  std::ostringstream out;
  const Progress progress("demo", false, out, false);
  progress("1/6 CAD -> NURBS");
  for (int i = 1; i <= 86; ++i) progress.update("fit (gamma 0.05)", i, 0.5);
  progress("4/6 NMSM calibration");
  EXPECT_EQ(out.str(), "[demo] 1/6 CAD -> NURBS\n[demo] 4/6 NMSM calibration\n");
}

TEST(Progress, QuietKeepsWarningsAndEveryWarningIsKept) {
  std::ostringstream out;
  const Progress progress("demo", true, out, true);
  progress("a milestone");
  progress.update("fit", 1, 1.0);
  progress.warn("2 of 14 stiffness groups sit at the lower bound");
  progress.warn("second");
  EXPECT_EQ(out.str(),
            "[demo] warning: 2 of 14 stiffness groups sit at the lower bound\n"
            "[demo] warning: second\n");
  ASSERT_EQ(progress.warnings().size(), 2u);
  EXPECT_EQ(progress.warnings()[0], "2 of 14 stiffness groups sit at the lower bound");
}

TEST(Progress, WarningsGoIntoBothReports) {
  std::ostringstream out;
  const Progress progress("study", false, out, false);
  nlohmann::json report = {{"warnings", {"from the computation"}}};
  MarkdownReport md;
  md.heading(1, "study");
  add_warnings(report, md, progress);  // none printed: the report keeps its own
  EXPECT_EQ(report["warnings"], nlohmann::json({"from the computation"}));
  EXPECT_EQ(md.text().find("Warning"), std::string::npos);
  progress.warn("gnuplot is not installed");
  add_warnings(report, md, progress);
  EXPECT_EQ(report["warnings"],
            nlohmann::json({"from the computation", "gnuplot is not installed"}));
  EXPECT_NE(md.text().find("- Warning: gnuplot is not installed\n"), std::string::npos);
  nlohmann::json fresh = nlohmann::json::object();
  add_warnings(fresh, md, progress);
  EXPECT_EQ(fresh["warnings"], nlohmann::json({"gnuplot is not installed"}));
}

}  // namespace
}  // namespace isospring::io
