#pragma once
// Report helpers shared by every command: a JSON report (machine-readable, full precision), a
// Markdown report (for people) and progress lines on stderr that `--quiet` silences.
//
// Every command writes OUTDIR/report.json and OUTDIR/report.md. The JSON holds the same
// header fields (report_header) so scripts can tell which command and version produced it.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace isospring::io {

/// Progress lines on stderr: "[analyze] solving load case L1 (1/2)". Quiet drops them; warnings
/// are always printed because they say something about the result.
class Progress {
 public:
  Progress(std::string command, bool quiet) : command_(std::move(command)), quiet_(quiet) {}
  void operator()(const std::string& message) const;
  void warn(const std::string& message) const;
  bool quiet() const { return quiet_; }

 private:
  std::string command_;
  bool quiet_ = false;
};

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

/// A number for people: `significant` digits, general format ("0.000123457", "1.5e+06").
std::string format_number(double value, int significant = 6);

/// A number for machines in text files (CSV): %.17g, which reads back to the same double.
std::string format_exact(double value);

}  // namespace isospring::io
