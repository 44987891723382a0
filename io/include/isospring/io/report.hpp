#pragma once
// Report helpers shared by every command: a JSON report (machine-readable, full precision), a
// Markdown report (for people) and progress lines on stderr that `--quiet` silences.
//
// Every command writes OUTDIR/report.json and OUTDIR/report.md. The JSON holds the same
// header fields (report_header) so scripts can tell which command and version produced it.
#include <filesystem>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace isospring::io {

/// Progress on stderr for people: milestone lines "[analyze] solving load case L1 (1/2)" and,
/// for the iterations of a long stage (update()), ONE status line rewritten in place
/// ("[calibrate] fit (gamma 0.05): iteration 12, cost 1.2e-05, 3.4 s") when stderr is a
/// terminal; when it is not (a log file, a pipe, a test), iterations print nothing except one
/// plain line every 30 s of a long stage, so logs hold the milestones only. Quiet drops milestones
/// and iterations; warnings are always printed (they say something about the result) and kept
/// (warnings()) so that commands also put them in report.json and report.md.
class Progress {
 public:
  /// stderr; a terminal when isatty(2) and TERM is not "dumb".
  Progress(std::string command, bool quiet);
  /// For tests: `out` instead of stderr, `terminal` as given.
  Progress(std::string command, bool quiet, std::ostream& out, bool terminal);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void operator()(const std::string& message) const;
  void warn(const std::string& message) const;
  /// One iteration of `stage` (e.g. "fit (gamma 0.05)"): the status line on a terminal.
  void update(const std::string& stage, int iteration, double cost) const;
  bool quiet() const { return quiet_; }
  bool terminal() const { return terminal_; }
  /// Every warning printed so far, without the "[command] warning: " prefix.
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  void clear_status() const;
  double elapsed() const;

  std::string command_;
  bool quiet_ = false;
  std::ostream* out_;
  bool terminal_ = false;
  double start_ = 0.0;                 // steady clock [s]
  mutable bool status_shown_ = false;  // a status line is on the terminal, unterminated
  mutable double last_update_ = -1e9;  // when the status line was last drawn [s]
  mutable double last_plain_ = 0.0;    // when the last plain line was written [s]
  mutable std::vector<std::string> warnings_;
};

/// The library's version (the project's), as the reports and model files name it.
std::string isospring_version();

/// {"command", "isospring_version", "input", "created_utc"}: keys every report.json has (JSON
/// objects are written with sorted keys).
nlohmann::json report_header(const std::string& command, const std::string& isospring_version,
                             const std::filesystem::path& input);

/// Writes a JSON report atomically, indented by 2; doubles round-trip exactly (shortest form that
/// reads back to the same bits). Non-finite numbers are written as null.
void write_json_report(const std::filesystem::path& path, const nlohmann::json& report);

/// A Markdown document built piece by piece; tables are GitHub-flavoured pipe tables.
class MarkdownReport {
 public:
  void heading(int level, const std::string& text);
  void paragraph(const std::string& text);
  void bullets(const std::vector<std::string>& items);
  /// Every row must have as many cells as `header` (asserted by the caller's construction).
  void table(const std::vector<std::string>& header,
             const std::vector<std::vector<std::string>>& rows);
  const std::string& text() const { return text_; }
  /// Writes the document atomically.
  void write(const std::filesystem::path& path) const;

 private:
  std::string text_;
};

/// The progress's warnings into a report: appended to report["warnings"] (created as an array)
/// and, when there are any, as "Warning: ..." bullets at the end of the Markdown report.
void add_warnings(nlohmann::json& report, MarkdownReport& markdown, const Progress& progress);

/// A number for people: `significant` digits, general format ("0.000123457", "1.5e+06").
std::string format_number(double value, int significant = 6);

/// A number for machines in text files (CSV): %.17g, which reads back to the same double.
std::string format_exact(double value);

}  // namespace isospring::io
