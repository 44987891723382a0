// The manual's examples, run exactly as written ("a manual that runs"). Every inline code span
// of README.md and of the pages docs/*.md that is an `isospring` command with arguments, and every
// line of their ```sh blocks, is extracted from the page itself; each is either run here or listed
// in kNotRun with the reason. README.md's commands run in README order in one scratch folder that
// holds a link to the shipped `examples/` (they are written from the repository folder and use
// each other's outputs: `refine block.json` needs `import`'s block.json, `simulate cal/model.json`
// needs `calibrate`'s cal/). Every docs page is read on its own, so its commands run in page order
// in a scratch folder of its own, using only the shipped examples and the page's earlier outputs.
// A command a page gains or changes is therefore run, or the test fails until it is listed; a
// listed command the page no longer shows fails the test too.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "run_program.hpp"

namespace {
namespace fs = std::filesystem;
using isospring::testing::file_contents;
using isospring::testing::TemporaryFolder;

// Commands a page shows that this test does not run, and why. A long run is listed only when a
// shorter variant of it runs (the reason names it).
struct NotRun {
  std::string page;  // README.md or docs/NAME.md
  std::string command;
  std::string why;
};
const std::vector<NotRun> kNotRun{
    {"README.md", "bash scripts/demo.sh",
     "installs Debian packages (root) and builds the project; its last step, `isospring demo`, "
     "is run here through the command table's `isospring demo -o isospring-out`"},
    {"README.md", "bash scripts/test.sh",
     "installs packages, builds everything and runs this very suite"},
    {"docs/hardening.md", "bash scripts/sanitize.sh",
     "a separate clang build with sanitizers (scripts/sanitize.sh, the CI's hardening job)"},
    {"docs/hardening.md", "bash scripts/fuzz.sh 600 fuzz_markers_csv", "ten minutes of fuzzing"},
    {"docs/hardening.md",
     "source scripts/sanitizer-options.sh && build-asan/fuzz/fuzz_step crash-file",
     "needs the sanitizer build and a crash file (a placeholder name)"},
    {"docs/cluster.md",
     "mpirun -np 2 isospring analyze examples/cantilever_box.json -o out --backend petsc",
     "OpenMPI refuses to start as root (CI) without --allow-run-as-root; tests/mpi (label mpi, "
     "PETSc builds) runs this command with that flag and checks it against the serial solve"},
    {"docs/program.md", "isospring thesis -o thesis",
     "the full run: several minutes on 2 cores; the README's quick example (one object of the "
     "generalisation table, ~10 s) is run instead"},
    {"docs/nmsm-results.md", "isospring thesis -o thesis",
     "the full run: several minutes on 2 cores; the README's quick example is run instead"},
    {"docs/nmsm-results.md", "isospring thesis --generalisation-only",
     "a fragment naming the run that measured the table (minutes per object, an hour for the "
     "spheroid); the README's quick example runs its square"},
    {"docs/calibration.md", "isospring thesis --generalisation-only",
     "a fragment naming the run that measured the numbers quoted (minutes per object); the "
     "README's quick example runs its square"},
    {"docs/frontier.md", "isospring thesis --frontier --combine A/report.json B/report.json -o all",
     "joins the reports of two earlier runs (A and B name them); FrontierCells.* in "
     "tests/workflows combines two runs and checks the merged rows and Pareto flags"},
    {"docs/frontier.md", "isospring thesis --frontier -o frontier",
     "the full run: the six objects, tens of minutes on 2 cores; the page's square run "
     "(`--quick --object square`) is run instead"},
    {"docs/runtime.md", "isospring export model.json -o scene.xml",
     "needs a calibrated model with volume or strain-point terms (minutes to calibrate); "
     "tests/mujoco exports such models and steps them in MuJoCo"},
    {"docs/outputs.md", "isospring export MODEL.json -o SCENE.xml",
     "a synopsis with placeholders; tests/mujoco runs the export it describes"},
};

// Warnings the examples print on purpose (their page shows or explains them); any other warning
// (e.g. a `simulate` example whose last frame has not settled) fails the test.
const std::vector<std::string> kExpectedWarnings{
    "stiffness groups sit at the lower bound",  // the demo block: README, "A five-minute tour"
    "exceeds the target",  // the README's quick thesis run on the square: docs/nmsm-results.md
};

// Text of a page with fenced blocks removed (returned separately, per language).
struct PageParts {
  std::string prose;
  std::vector<std::string> sh_lines;  // lines of ```sh blocks, comments stripped, trimmed
};

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t");
  return s.substr(a, b - a + 1);
}

PageParts split_page(const std::string& text) {
  PageParts parts;
  std::istringstream in(text);
  std::string line, fence;
  bool inside = false;
  while (std::getline(in, line)) {
    if (line.rfind("```", 0) == 0) {
      inside = !inside;
      fence = inside ? line.substr(3) : "";
      parts.prose += "\n";
      continue;
    }
    if (!inside) {
      parts.prose += line + "\n";
    } else if (fence == "sh") {
      const std::string command = trim(line.substr(0, line.find(" #")));
      if (!command.empty() && command[0] != '#') parts.sh_lines.push_back(command);
    }
  }
  return parts;
}

// Inline code spans as CommonMark reads them: a run of N backticks opens a span that the next
// run of exactly N backticks closes, within one paragraph (``a `b` c`` is one span), so
// `isospring ...` commands broken over lines are found whole. Those that are isospring commands
// with arguments are the examples; a bare `isospring NAME` is a mention of the command.
std::vector<std::string> inline_commands(const std::string& prose) {
  std::vector<std::string> commands;
  auto run_length = [&](size_t at) {
    size_t n = 0;
    while (at + n < prose.size() && prose[at + n] == '`') ++n;
    return n;
  };
  size_t i = 0;
  while (i < prose.size()) {
    if (prose[i] != '`') {
      ++i;
      continue;
    }
    const size_t open = run_length(i);
    size_t j = i + open, close = std::string::npos;
    while (j < prose.size()) {
      if (prose.compare(j, 2, "\n\n") == 0) break;  // a span never crosses a paragraph
      if (prose[j] == '`') {
        const size_t n = run_length(j);
        if (n == open) {
          close = j;
          break;
        }
        j += n;
      } else {
        ++j;
      }
    }
    if (close == std::string::npos) {  // no closing run: literal backticks
      i += open;
      continue;
    }
    std::string code =
        std::regex_replace(prose.substr(i + open, close - i - open), std::regex("\\s+"), " ");
    code = trim(code);
    i = close + open;
    if (code.rfind("isospring ", 0) != 0) continue;
    if (std::count(code.begin(), code.end(), ' ') < 2) continue;  // `isospring demo`: a name
    commands.push_back(code);
  }
  return commands;
}

// Runs the commands a page shows, in page order, in `folder` (which links the shipped examples),
// except those kNotRun lists for the page; returns how many ran.
int run_page_commands(const std::string& page, const std::vector<std::string>& commands,
                      const fs::path& folder) {
  SCOPED_TRACE(page);
  // Every exclusion is still on its page (a stale list would hide nothing, but says so).
  const std::set<std::string> shown(commands.begin(), commands.end());
  std::set<std::string> listed;
  for (const NotRun& entry : kNotRun) {
    if (entry.page != page) continue;
    listed.insert(entry.command);
    EXPECT_TRUE(shown.count(entry.command))
        << "kNotRun lists a command " << page << " no longer shows: " << entry.command;
  }
  fs::create_directory_symlink(fs::path(ISOSPRING_SOURCE_DIR) / "examples", folder / "examples");
  const std::string bin = fs::path(ISOSPRING_EXECUTABLE).parent_path().string();
  // In page order; a command shown twice runs once (its outputs are already there).
  std::set<std::string> done;
  double total = 0.0;
  int run = 0;
  for (const std::string& command : commands) {
    if (listed.count(command) || !done.insert(command).second) continue;
    EXPECT_EQ(command.find('\''), std::string::npos) << command;
    if (command.find('\'') != std::string::npos) continue;
    const std::string shell = "cd '" + folder.string() + "' && PATH='" + bin +
                              "':\"$PATH\" timeout 300 sh -c '" + command + "'";
    const auto start = std::chrono::steady_clock::now();
    const isospring::testing::ProgramResult result = isospring::testing::run_program(shell);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    total += seconds;
    ++run;
    std::printf("%6.2f s  %s: %s\n", seconds, page.c_str(), command.c_str());
    const std::string& output = result.output;
    EXPECT_EQ(result.exit_code, 0)
        << "command of " << page << " failed: " << command << "\n"
        << output.substr(output.size() > 4000 ? output.size() - 4000 : 0);
    std::istringstream lines(output);
    for (std::string line; std::getline(lines, line);) {
      if (line.find("warning:") == std::string::npos) continue;
      EXPECT_TRUE(
          std::any_of(kExpectedWarnings.begin(), kExpectedWarnings.end(),
                      [&](const std::string& w) { return line.find(w) != std::string::npos; }))
          << "unexpected warning from " << page << "'s `" << command << "`: " << line;
    }
  }
  std::printf("%s: %d commands in %.1f s; not run: %zu (kNotRun)\n", page.c_str(), run, total,
              listed.size());
  return run;
}

// The commands of a page: its inline ones in text order, then its ```sh lines.
std::vector<std::string> page_commands(const std::string& text) {
  const PageParts parts = split_page(text);
  std::vector<std::string> commands = inline_commands(parts.prose);
  for (const auto& line : parts.sh_lines) commands.push_back(line);
  return commands;
}

}  // namespace

TEST(Readme, EveryExampleCommandRunsAsWritten) {
  const std::string readme = file_contents(std::string(ISOSPRING_SOURCE_DIR) + "/README.md");
  ASSERT_FALSE(readme.empty());
  const std::vector<std::string> commands = page_commands(readme);
  ASSERT_GE(commands.size(), 20u) << "the README's examples were not found";
  TemporaryFolder scratch;
  run_page_commands("README.md", commands, scratch.path());
}

// The pages of docs/, each in a folder of its own, in file-name order.
TEST(Readme, EveryDocsPageCommandRunsAsWritten) {
  const fs::path docs = fs::path(ISOSPRING_SOURCE_DIR) / "docs";
  std::vector<std::string> pages;
  for (const auto& entry : fs::directory_iterator(docs))
    if (entry.path().extension() == ".md")
      pages.push_back("docs/" + entry.path().filename().string());
  std::sort(pages.begin(), pages.end());
  ASSERT_GE(pages.size(), 10u) << "the docs pages were not found in " << docs;
  // Every page kNotRun names exists (a renamed page must take its list along).
  for (const NotRun& entry : kNotRun)
    EXPECT_TRUE(entry.page == "README.md" ||
                std::find(pages.begin(), pages.end(), entry.page) != pages.end())
        << "kNotRun names a page that does not exist: " << entry.page;
  size_t shown = 0;
  int run = 0;
  for (const std::string& page : pages) {
    const std::vector<std::string> commands =
        page_commands(file_contents((fs::path(ISOSPRING_SOURCE_DIR) / page).string()));
    shown += commands.size();  // a page without commands still checks its kNotRun entries
    TemporaryFolder scratch;
    run += run_page_commands(page, commands, scratch.path());
  }
  // The pages show examples of import, calibrate, identify and study at least.
  EXPECT_GE(run, 5) << "the docs pages' examples were not found (" << shown << " shown)";
}
