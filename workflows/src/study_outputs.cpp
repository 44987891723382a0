// The files of `isospring study`: the reports, study.csv and convergence.png (see
// study_command.hpp).
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>

#include "isospring/io/atomic_file.hpp"
#include "isospring/workflows/study_command.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;
namespace {

void plot(const std::filesystem::path& out_dir, const std::vector<StudyRow>& rows, bool analytic,
          const Progress& progress) {
  // One level (or only exact levels) leaves no point on a log scale: nothing to plot, and
  // gnuplot would fail on the empty data.
  if (std::none_of(rows.begin(), rows.end(), [](const StudyRow& r) { return r.error() > 0; })) {
    progress(
        "convergence.png not written: no level has a nonzero error to plot (give --levels 2 "
        "or more)");
    return;
  }
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
    progress.warn("gnuplot is not installed; skipping convergence.png (install gnuplot-nox)");
    return;
  }
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("isospring-study-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::string script = "set terminal pngcairo size 900,650\nset output '" +
                       (dir / "convergence.png").string() +
                       "'\nset logscale xy\nset grid\nset key bottom right\n"
                       "set xlabel 'relative element size h'\nset ylabel '" +
                       (analytic ? "relative error (L2: solid, energy: dashed)"
                                 : "relative error of the study quantity") +
                       "'\nplot ";
  std::vector<int> degrees;
  for (const StudyRow& r : rows)
    if (degrees.empty() || degrees.back() != r.degree) degrees.push_back(r.degree);
  bool first = true;
  for (int p : degrees) {
    const std::string data = (dir / ("p" + std::to_string(p) + ".dat")).string();
    std::ofstream out(data);
    for (const StudyRow& r : rows)
      if (r.degree == p && r.error() > 0)
        out << r.h << ' ' << r.error() << ' ' << (analytic ? r.energy : r.error()) << '\n';
    script += std::string(first ? "" : ", ") + "'" + data +
              "' using 1:2 with linespoints lw 2 title 'p = " + std::to_string(p) + "'";
    if (analytic)
      script += ", '" + data + "' using 1:3 with linespoints dt 2 title 'p = " + std::to_string(p) +
                " energy'";
    first = false;
  }
  std::ofstream(dir / "plot.gp") << script << "\n";
  const std::string command = "gnuplot '" + (dir / "plot.gp").string() + "' > /dev/null 2>&1";
  if (std::system(command.c_str()) == 0 && std::filesystem::exists(dir / "convergence.png")) {
    write_via_temporary(out_dir / "convergence.png", [&](const std::filesystem::path& tmp) {
      std::filesystem::copy_file(dir / "convergence.png", tmp,
                                 std::filesystem::copy_options::overwrite_existing);
    });
  } else {
    progress.warn("gnuplot failed; convergence.png was not written");
  }
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
}

}  // namespace

void write_study_outputs(const std::filesystem::path& out_dir, const StudyCommandResult& r,
                         const Progress& progress) {
  StudyReport report = study_report(r);
  write_file_atomically(out_dir / "study.csv", report.csv);
  add_warnings(report.json, report.markdown, progress);
  write_json_report(out_dir / "report.json", report.json);
  report.markdown.write(out_dir / "report.md");
  plot(out_dir, r.rows, r.analytic(), progress);
}

}  // namespace isospring::workflows
