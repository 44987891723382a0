// Stage timings of `analyze` (analyze_timings.hpp).
#include "isospring/io/analyze_timings.hpp"

#include <chrono>
#include <cstdio>
#include <functional>

namespace isospring::io {

void add_solver_timings(const analysis::StaticResult& result, AnalyzeTimings& timings) {
  timings.assembly_seconds = result.assembly_seconds;
  timings.setup_seconds = result.factorization_seconds;
  for (const analysis::LoadCaseResult& lc : result.load_cases) {
    timings.solve_seconds += lc.solve_seconds - lc.post_seconds;
    timings.post_processing_seconds += lc.post_seconds;
  }
}

void timed_output(const std::filesystem::path& out_dir, const std::string& file,
                  AnalyzeTimings& timings, const std::function<void()>& write) {
  const auto start = std::chrono::steady_clock::now();
  write();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::error_code error;
  const std::uintmax_t bytes = std::filesystem::file_size(out_dir / file, error);
  timings.outputs.push_back({file, seconds, error ? 0 : bytes});
}

nlohmann::json timings_json(const AnalyzeTimings& timings) {
  nlohmann::json out = {{"read_seconds", timings.read_seconds},
                        {"refinement_seconds", timings.refinement_seconds},
                        {"assembly_seconds", timings.assembly_seconds},
                        {"setup_seconds", timings.setup_seconds},
                        {"solve_seconds", timings.solve_seconds},
                        {"post_processing_seconds", timings.post_processing_seconds}};
  double seconds = 0;
  std::uintmax_t bytes = 0;
  out["outputs"] = nlohmann::json::array();
  for (const OutputTiming& o : timings.outputs) {
    out["outputs"].push_back({{"file", o.file}, {"seconds", o.seconds}, {"bytes", o.bytes}});
    seconds += o.seconds;
    bytes += o.bytes;
  }
  out["output_seconds"] = seconds;
  out["output_bytes"] = bytes;
  return out;
}

std::string timings_table(const nlohmann::json& timings, double total_seconds) {
  std::string text;
  char line[256];
  auto row = [&](const std::string& what, double seconds, const std::string& size) {
    std::snprintf(line, sizeof line, "%-36s %9.3f s  %s\n", what.c_str(), seconds, size.c_str());
    text += line;
  };
  const std::pair<const char*, const char*> stages[] = {
      {"reading", "read_seconds"},      {"refinement", "refinement_seconds"},
      {"assembly", "assembly_seconds"}, {"factorisation / preconditioner setup", "setup_seconds"},
      {"solves", "solve_seconds"},      {"post-processing", "post_processing_seconds"}};
  for (const auto& [label, key] : stages) row(label, timings.value(key, 0.0), "");
  auto megabytes = [&](double bytes) {
    std::snprintf(line, sizeof line, "%8.2f MB", bytes / 1e6);
    return std::string(line);
  };
  for (const nlohmann::json& o : timings.at("outputs"))
    row(o.at("file").get<std::string>(), o.at("seconds").get<double>(),
        megabytes(o.at("bytes").get<double>()));
  row("outputs", timings.value("output_seconds", 0.0),
      megabytes(timings.value("output_bytes", 0.0)));
  row("total (report.json total_seconds)", total_seconds, "");
  return text;
}

}  // namespace isospring::io
