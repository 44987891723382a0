// Every serial solver of `analyze` on the problems where their costs differ, and what
// `--solver auto` chooses (analysis::choose_solver), as the table of README "Performance" and
// docs/performance.md:
//
//   cube        the clamped p = 2 unit cube, 32^3 elements (114,444 free DOFs), nu 0.3, own weight
//   cube_nu049  the same, nu 0.49 (nearly incompressible)
//   cantilever  a 50:1 clamped beam, 50 x 1 x 1, p = 2, 320 x 8 x 8 elements (~1e5 DOFs), own
//   weight l_bracket   examples/l_bracket at degree 3 (57 CAD patches; needs ../shared/cad)
//
// Each (problem, solver) runs in a child process of its own (fork), so that its peak memory
// (getrusage of the child: building the problem included) is its own and a failure or an
// exhausted limit ends only that run. Output: one Markdown row per run with free DOFs,
// iterations, setup (factorisation or preconditioner) and solve seconds, wall seconds of the
// whole solve (assembly included), its CPU seconds (all threads) and peak memory, then what auto
// chooses for each problem with its estimates (the rule reads the problem only; `--solvers auto`
// also runs it).
//
//   cd REPOSITORY && bench_solvers [--problems cube,cube_nu049,cantilever,l_bracket]
//                                  [--solvers cg,amg,cholesky] [--scale S]
// (S < 1: elements per direction times S, for a quick look)
//
// Not a Google Benchmark program: one run per solver is what a user waits for (minutes at this
// size), and the child processes keep the memory figures apart.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "isospring/analysis/blas_runtime.hpp"
#include "isospring/analysis/constraints.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/io/case_file.hpp"

namespace {

using namespace isospring;
using nlohmann::json;
namespace fs = std::filesystem;

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

int scaled(int elements, double scale) {
  return std::max(1, static_cast<int>(elements * scale + 0.5));
}

json box_case(const std::string& name, std::vector<double> size, std::vector<int> elements,
              double nu) {
  return {{"name", name},
          {"units", "SI"},
          {"geometry", {{"type", "box"}, {"size", size}}},
          {"discretization", {{"degree", 2}, {"elements", elements}}},
          {"material", {{"E", 210e9}, {"nu", nu}, {"density", 7800.0}}},
          {"boundary", {{{"side", "u0"}, {"fix", {"x", "y", "z"}}}}},
          {"load_cases", {{{"id", "gravity"}, {"gravity", {0, 0, -9.81}}}}}};
}

// The shipped L-bracket case (run from the repository folder) with its STEP file from the shared
// folder beside the repository (../shared/cad; a worktree's is one level further up).
io::Case l_bracket(double scale) {
  const fs::path case_file = fs::absolute("examples/l_bracket/case.json");
  std::ifstream in(case_file);
  if (!in) throw std::runtime_error("run from the repository folder: no " + case_file.string());
  json document = json::parse(in);
  const fs::path root = case_file.parent_path().parent_path().parent_path();
  for (const fs::path& shared :
       {root.parent_path() / "shared", root.parent_path().parent_path() / "shared"})
    if (fs::exists(shared / "cad" / "l_bracket_caxif.stp"))
      document["geometry"]["file"] = (shared / "cad" / "l_bracket_caxif.stp").string();
  document["discretization"]["elements"] = 2 * scaled(2, scale);  // a multiple of 2 (spans)
  return io::build_case_from_json(document, case_file);
}

io::Case make_case(const std::string& name, double scale) {
  if (name == "cube" || name == "cube_nu049") {
    const int n = scaled(32, scale);
    return io::build_case_from_json(
        box_case(name, {1, 1, 1}, {n, n, n}, name == "cube" ? 0.3 : 0.49), "bench.json");
  }
  if (name == "cantilever")
    return io::build_case_from_json(
        box_case(name, {50, 1, 1}, {scaled(320, scale), scaled(8, scale), scaled(8, scale)}, 0.3),
        "bench.json");
  if (name == "l_bracket") return l_bracket(scale);
  throw std::invalid_argument("unknown problem '" + name + "'");
}

analysis::SolverOptions::Method method_of(const std::string& solver) {
  using Method = analysis::SolverOptions::Method;
  if (solver == "cholesky") return Method::kCholesky;
  if (solver == "cg") return Method::kConjugateGradient;
  if (solver == "amg") return Method::kAmg;
  if (solver == "auto") return Method::kAuto;
  throw std::invalid_argument("unknown solver '" + solver + "'");
}

std::string method_name(analysis::SolverOptions::Method method) {
  using Method = analysis::SolverOptions::Method;
  return method == Method::kCholesky ? "cholesky" : method == Method::kAmg ? "amg" : "cg";
}

// CPU seconds of this process (all its threads): on a shared machine the wall time depends on
// the other users, the CPU time much less.
double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// The child: builds the problem, solves it, prints one JSON line on `fd`.
void run_child(const std::string& problem_name, const std::string& solver, double scale, int fd) {
  json out;
  try {
    const io::Case c = make_case(problem_name, scale);
    analysis::SolverOptions options;
    options.method = method_of(solver);
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = cpu_seconds();
    const analysis::StaticResult result = analysis::solve_static(c.problem, options);
    const double cpu = cpu_seconds() - cpu_start;
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    double solve = 0;
    int iterations = 0;
    for (const auto& lc : result.load_cases) {
      solve += lc.solve_seconds;
      iterations += lc.iterations;
    }
    const analysis::SupportedProblem supported = analysis::number_and_support(c.problem);
    out = {{"dofs", result.dofs},
           {"free_dofs", result.dofs - static_cast<int>(supported.constraints.dofs.size())},
           {"load_cases", result.load_cases.size()},
           {"method", method_name(result.method)},
           {"assembly", result.assembly_seconds},
           {"setup", result.factorization_seconds},
           {"solve", solve},
           {"iterations", iterations},
           {"wall", wall},
           {"cpu", cpu},
           {"max_displacement", result.load_cases.at(0).max_displacement}};
    // What auto chooses (the rule only reads the problem: no solve needed to know it).
    const analysis::SolverChoice choice = analysis::choose_solver(
        analysis::solver_problem_traits(c.problem, supported.dofs, supported.constraints));
    out["auto"] = method_name(choice.method);
    out["reason"] = choice.reason;
  } catch (const std::exception& e) {
    out = {{"error", e.what()}};
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  out["peak_mb"] = static_cast<double>(usage.ru_maxrss) / 1024.0;
  const std::string line = out.dump() + "\n";
  if (write(fd, line.data(), line.size()) < 0) std::perror("write");
}

json run(const std::string& problem_name, const std::string& solver, double scale) {
  int pipe_fd[2];
  if (pipe(pipe_fd) != 0) throw std::runtime_error("pipe failed");
  const pid_t child = fork();
  if (child == 0) {
    close(pipe_fd[0]);
    run_child(problem_name, solver, scale, pipe_fd[1]);
    close(pipe_fd[1]);
    _exit(0);
  }
  close(pipe_fd[1]);
  std::string text;
  char buffer[4096];
  ssize_t n = 0;
  while ((n = read(pipe_fd[0], buffer, sizeof buffer)) > 0)
    text.append(buffer, static_cast<size_t>(n));
  close(pipe_fd[0]);
  int status = 0;
  waitpid(child, &status, 0);
  if (text.empty()) return {{"error", "the run died (status " + std::to_string(status) + ")"}};
  return json::parse(text);
}

}  // namespace

int main(int argc, char** argv) {
  // OpenMP threads sleep at barriers, as in the isospring program (spinning ones take the CPU
  // from the working threads on a shared machine); libgomp reads this before main.
  analysis::restart_with_passive_threads(argv);
  std::vector<std::string> problems = {"cube", "cube_nu049", "cantilever", "l_bracket"};
  std::vector<std::string> solvers = {"cg", "amg", "cholesky"};
  double scale = 1.0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--problems")
      problems = split(value);
    else if (flag == "--solvers")
      solvers = split(value);
    else if (flag == "--scale")
      scale = std::stod(value);
    else {
      std::cerr << "unknown option " << flag << "\n";
      return 2;
    }
  }
  std::printf(
      "| problem | solver | free DOFs | iterations | assembly s | setup s | solve s | wall s | "
      "CPU s | peak MB | max abs(u) |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::fflush(stdout);
  std::vector<std::string> reasons;
  for (const std::string& problem : problems)
    for (const std::string& solver : solvers) {
      const json r = run(problem, solver, scale);
      if (r.contains("error")) {
        std::printf("| %s | %s | failed: %s | | | | | | | %.0f | |\n", problem.c_str(),
                    solver.c_str(), r["error"].get<std::string>().c_str(), r.value("peak_mb", 0.0));
      } else {
        const std::string label =
            solver == "auto" ? "auto (" + r["method"].get<std::string>() + ")" : solver;
        std::printf("| %s | %s | %d | %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f | %.6g |\n",
                    problem.c_str(), label.c_str(), r["free_dofs"].get<int>(),
                    r["iterations"].get<int>(), r["assembly"].get<double>(),
                    r["setup"].get<double>(), r["solve"].get<double>(), r["wall"].get<double>(),
                    r["cpu"].get<double>(), r["peak_mb"].get<double>(),
                    r["max_displacement"].get<double>());
        if (reasons.empty() || reasons.back().rfind(problem + ":", 0) != 0)
          reasons.push_back(problem + ": " + r["auto"].get<std::string>() + "; " +
                            r["reason"].get<std::string>());
      }
      std::fflush(stdout);
    }
  for (const std::string& reason : reasons) std::printf("\n- auto, %s\n", reason.c_str());
  return 0;
}
