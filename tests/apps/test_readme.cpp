// The README's examples, run exactly as written ("a README that runs"). Every inline
// code span of README.md that is an `isospring` command with arguments, and every line of its
// ```sh blocks, is extracted from the README itself; each is either run here, in README order,
// in one scratch folder that holds a link to the shipped `examples/` (the README's commands are
// written from the repository folder and use each other's outputs: `refine block.json` needs
// `import`'s block.json, `simulate cal/model.json` needs `calibrate`'s cal/), or listed in
// kNotRun with the reason. A command the README gains or changes is therefore run, or the test
// fails until it is listed; a listed command the README no longer has fails the test too.
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

// Commands the README shows that this test does not run, and why.
const std::map<std::string, std::string> kNotRun{
    {"bash scripts/demo.sh",
     "installs Debian packages (root) and builds the project; its last step, `isospring demo`, "
     "is run here through the command table's `isospring demo -o isospring-out`"},
    {"bash scripts/test.sh", "installs packages, builds everything and runs this very suite"},
    {"bash scripts/sanitize.sh", "a separate clang build with sanitizers (scripts/sanitize.sh)"},
    {"bash scripts/fuzz.sh 600 fuzz_markers_csv", "ten minutes of fuzzing"},
    {"source scripts/sanitizer-options.sh && build-asan/fuzz/fuzz_step crash-file",
     "needs the sanitizer build and a crash file (a placeholder name)"},
    {"mpirun -np 2 isospring analyze examples/cantilever_box.json -o out --backend petsc",
     "OpenMPI refuses to start as root (CI) without --allow-run-as-root; tests/mpi (label mpi, "
     "PETSc builds) runs this command with that flag and checks it against the serial solve"},
    {"isospring thesis -o OUT", "OUT is a placeholder for the full run below"},
    {"isospring thesis -o thesis",
     "the full run: several minutes on 2 cores; the command table's quick example (one object of "
     "the generalisation table, ~10 s) is run instead"},
    {"isospring thesis --generalisation-only",
     "a fragment of a command (227-265 s); the command table's quick example is run instead"},
};

// Warnings the README's examples print on purpose (the README shows or explains them); any
// other warning (e.g. a `simulate` example whose last frame has not settled) fails the test.
const std::vector<std::string> kExpectedWarnings{
    "stiffness groups sit at the lower bound",  // the demo block: README, "A five-minute tour"
    "exceeds the target",                       // thesis square: README, generalisation table
};

// Text of the README with fenced blocks removed (returned separately, per language).
struct ReadmeParts {
  std::string prose;
  std::vector<std::string> sh_lines;  // lines of ```sh blocks, comments stripped, trimmed
};

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t");
  return s.substr(a, b - a + 1);
}

ReadmeParts split_readme(const std::string& text) {
  ReadmeParts parts;
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

}  // namespace

TEST(Readme, EveryExampleCommandRunsAsWritten) {
  const std::string readme = file_contents(std::string(ISOSPRING_SOURCE_DIR) + "/README.md");
  ASSERT_FALSE(readme.empty());
  const ReadmeParts parts = split_readme(readme);
  std::vector<std::string> commands = inline_commands(parts.prose);
  for (const auto& line : parts.sh_lines) commands.push_back(line);
  ASSERT_GE(commands.size(), 20u) << "the README's examples were not found";

  // Every exclusion is still in the README (a stale list would hide nothing, but says so).
  const std::set<std::string> shown(commands.begin(), commands.end());
  for (const auto& [command, why] : kNotRun)
    EXPECT_TRUE(shown.count(command))
        << "kNotRun lists a command the README no longer shows: " << command;

  TemporaryFolder scratch;
  fs::create_directory_symlink(fs::path(ISOSPRING_SOURCE_DIR) / "examples",
                               scratch.path() / "examples");
  const std::string bin = fs::path(ISOSPRING_EXECUTABLE).parent_path().string();
  // In README order; a command shown twice runs once (its outputs are already there).
  std::set<std::string> done;
  double total = 0.0;
  int run = 0;
  for (const std::string& command : commands) {
    if (kNotRun.count(command) || !done.insert(command).second) continue;
    ASSERT_EQ(command.find('\''), std::string::npos) << command;
    const std::string shell = "cd '" + scratch.path().string() + "' && PATH='" + bin +
                              "':\"$PATH\" timeout 300 sh -c '" + command + "'";
    const auto start = std::chrono::steady_clock::now();
    const isospring::testing::ProgramResult result = isospring::testing::run_program(shell);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    total += seconds;
    ++run;
    std::printf("%6.2f s  %s\n", seconds, command.c_str());
    const std::string& output = result.output;
    EXPECT_EQ(result.exit_code, 0)
        << "README command failed: " << command << "\n"
        << output.substr(output.size() > 4000 ? output.size() - 4000 : 0);
    std::istringstream lines(output);
    for (std::string line; std::getline(lines, line);) {
      if (line.find("warning:") == std::string::npos) continue;
      EXPECT_TRUE(
          std::any_of(kExpectedWarnings.begin(), kExpectedWarnings.end(),
                      [&](const std::string& w) { return line.find(w) != std::string::npos; }))
          << "unexpected warning from the README's `" << command << "`: " << line;
    }
  }
  std::printf("%d README commands in %.1f s; not run: %zu (kNotRun)\n", run, total, kNotRun.size());
}
