#include "cli_util.hpp"

#include "file_report.hpp"
#include "isospring/analysis/resource_estimate.hpp"
#include "isospring/io/output_guard.hpp"
#include "isospring/io/report.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::apps {

std::vector<std::filesystem::path> in_folder(const std::filesystem::path& folder,
                                             const std::vector<std::string>& names) {
  std::vector<std::filesystem::path> paths;
  for (const std::string& name : names) paths.push_back(folder / name);
  return paths;
}

std::filesystem::path output_folder(const std::string& option_value,
                                    const std::vector<std::filesystem::path>& inputs,
                                    const std::vector<std::string>& names) {
  const std::filesystem::path folder(option_value);
  if (std::filesystem::exists(folder) && !std::filesystem::is_directory(folder))
    throw nurbs::InputError("-o " + option_value +
                            ": exists and is not a folder; give a folder for the outputs");
  io::check_outputs_spare_inputs(inputs, in_folder(folder, names));
  io::check_writable_folder(folder);
  return folder;
}

void check_output_file(const std::filesystem::path& output,
                       const std::vector<std::filesystem::path>& inputs,
                       const std::vector<std::filesystem::path>& extra) {
  if (std::filesystem::is_directory(output))
    throw nurbs::InputError("-o " + output.string() +
                            ": is a folder; give the name of the file to write");
  std::vector<std::filesystem::path> outputs = extra;
  outputs.push_back(output);
  outputs.push_back(file_report_path(output, ".json"));
  outputs.push_back(file_report_path(output, ".md"));
  io::check_outputs_spare_inputs(inputs, outputs);
  io::check_writable_folder(output.parent_path());
  for (const std::filesystem::path& other : extra) io::check_writable_folder(other.parent_path());
}

MemoryLimit memory_limit(double max_memory_gb) {
  MemoryLimit limit{analysis::available_memory_bytes(),
                    "available memory, MemAvailable in /proc/meminfo"};
  if (max_memory_gb > 0 && (limit.bytes <= 0 || max_memory_gb * 1e9 < limit.bytes))
    limit = {max_memory_gb * 1e9, "--max-memory " + io::format_number(max_memory_gb) + " GB"};
  return limit;
}

io::CaseLimits solve_limits(double max_memory_gb) {
  const MemoryLimit limit = memory_limit(max_memory_gb);
  io::CaseLimits limits;
  limits.solve_memory_bytes = limit.bytes;
  limits.solve_memory_source = limit.source;
  return limits;
}

}  // namespace isospring::apps
