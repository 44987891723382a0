// Reports beside the output file of the single-file commands (file_report.hpp).
#include "file_report.hpp"

namespace isospring::apps {

namespace fs = std::filesystem;

fs::path file_report_path(const fs::path& output, const std::string& extension) {
  return output.parent_path() / (output.filename().string() + ".report" + extension);
}

FileReport::FileReport(const std::string& command, const fs::path& input, const fs::path& output)
    : json(io::report_header(command, io::isospring_version(), input)),
      output_(output),
      start_(std::chrono::steady_clock::now()) {
  json["output"] = output.string();
}

fs::path FileReport::write() {
  json["seconds"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const fs::path json_path = file_report_path(output_, ".json");
  io::write_json_report(json_path, json);
  markdown.write(file_report_path(output_, ".md"));
  return json_path;
}

}  // namespace isospring::apps
