#include "isospring/io/report.hpp"

#include <cassert>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <iostream>

#include "isospring/io/atomic_file.hpp"

namespace isospring::io {

void Progress::operator()(const std::string& message) const {
  if (!quiet_) std::cerr << "[" << command_ << "] " << message << std::endl;
}

void Progress::warn(const std::string& message) const {
  std::cerr << "[" << command_ << "] warning: " << message << std::endl;
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
