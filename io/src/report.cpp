#include "isospring/io/report.hpp"

#include <cassert>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <iostream>
#include <string>

#include <sys/ioctl.h>
#include <unistd.h>

#include "isospring/io/atomic_file.hpp"

namespace isospring::io {

namespace {

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

bool stderr_is_terminal() {
  const char* term = std::getenv("TERM");
  return isatty(STDERR_FILENO) == 1 && !(term != nullptr && std::string(term) == "dumb");
}

// Columns of the terminal on stderr (80 when unknown): the status line must not wrap, or "\r"
// no longer returns to its start.
size_t terminal_columns() {
  winsize size{};
  if (ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 10) return size.ws_col;
  return 80;
}

}  // namespace

Progress::Progress(std::string command, bool quiet)
    : Progress(std::move(command), quiet, std::cerr, stderr_is_terminal()) {}

Progress::Progress(std::string command, bool quiet, std::ostream& out, bool terminal)
    : command_(std::move(command)),
      quiet_(quiet),
      out_(&out),
      terminal_(terminal),
      start_(now_seconds()),
      last_plain_(start_) {}

Progress::~Progress() {
  clear_status();
}

double Progress::elapsed() const {
  return now_seconds() - start_;
}

void Progress::clear_status() const {
  if (!status_shown_) return;
  *out_ << "\r\033[K" << std::flush;
  status_shown_ = false;
}

void Progress::operator()(const std::string& message) const {
  if (quiet_) return;
  clear_status();
  *out_ << "[" << command_ << "] " << message << std::endl;
  last_plain_ = now_seconds();
}

void Progress::warn(const std::string& message) const {
  warnings_.push_back(message);
  clear_status();
  *out_ << "[" << command_ << "] warning: " << message << std::endl;
  last_plain_ = now_seconds();
}

void Progress::update(const std::string& stage, int iteration, double cost) const {
  if (quiet_) return;
  const double now = now_seconds();
  char numbers[128];
  std::snprintf(numbers, sizeof numbers, ": iteration %d, cost %.4g, %.1f s", iteration, cost,
                now - start_);
  const std::string head = "[" + command_ + "] ";
  if (terminal_) {
    if (now - last_update_ < 0.1) return;  // at most 10 redraws a second
    last_update_ = now;
    // One terminal line: a long stage name is shortened, never the numbers.
    const size_t width = terminal_columns() - 1, fixed = head.size() + std::strlen(numbers);
    std::string name = stage;
    if (fixed + name.size() > width)
      name = fixed + 4 < width ? name.substr(0, width - fixed - 3) + "..." : std::string();
    *out_ << "\r\033[K" << head << name << numbers << std::flush;
    status_shown_ = true;
  } else if (now - last_plain_ >= 30.0) {
    *out_ << head << stage << numbers << std::endl;
    last_plain_ = now;
  }
}

std::string isospring_version() {
  return ISOSPRING_VERSION;
}

nlohmann::json report_header(const std::string& command, const std::string& isospring_version,
                             const std::filesystem::path& input) {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof(stamp), "%Y-%m-%dT%H:%M:%SZ", &utc);
  nlohmann::json header;
  header["command"] = command;
  header["isospring_version"] = isospring_version;
  header["input"] = input.string();
  header["created_utc"] = stamp;
  return header;
}

void add_warnings(nlohmann::json& report, MarkdownReport& markdown, const Progress& progress) {
  if (!report.contains("warnings") || !report["warnings"].is_array())
    report["warnings"] = nlohmann::json::array();
  std::vector<std::string> items;
  for (const std::string& warning : progress.warnings()) {
    report["warnings"].push_back(warning);
    items.push_back("Warning: " + warning);
  }
  if (!items.empty()) markdown.bullets(items);
}

void write_json_report(const std::filesystem::path& path, const nlohmann::json& report) {
  // nlohmann::json writes doubles in the shortest round-trip form and NaN/inf as null.
  write_file_atomically(path, report.dump(2) + "\n");
}

void MarkdownReport::heading(int level, const std::string& text) {
  if (!text_.empty()) text_ += "\n";
  text_ += std::string(static_cast<size_t>(level), '#') + " " + text + "\n";
}

void MarkdownReport::paragraph(const std::string& text) {
  text_ += "\n" + text + "\n";
}

void MarkdownReport::bullets(const std::vector<std::string>& items) {
  text_ += "\n";
  for (const std::string& item : items) text_ += "- " + item + "\n";
}

void MarkdownReport::table(const std::vector<std::string>& header,
                           const std::vector<std::vector<std::string>>& rows) {
  auto line = [](const std::vector<std::string>& cells) {
    std::string out = "|";
    for (const std::string& cell : cells) out += " " + cell + " |";
    return out + "\n";
  };
  text_ += "\n" + line(header);
  text_ += line(std::vector<std::string>(header.size(), "---"));
  for (const auto& row : rows) {
    assert(row.size() == header.size());
    text_ += line(row);
  }
}

void MarkdownReport::write(const std::filesystem::path& path) const {
  write_file_atomically(path, text_);
}

std::string format_number(double value, int significant) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*g", significant, value);
  return buffer;
}

std::string format_exact(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  return buffer;
}

}  // namespace isospring::io
