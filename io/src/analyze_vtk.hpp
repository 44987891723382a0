#pragma once
// The ParaView output of `analyze` (result.vtm and result/): which pieces, at which resolution.
#include <filesystem>
#include <string>

#include "isospring/io/analyze_command.hpp"
#include "isospring/io/analyze_timings.hpp"

namespace isospring::io::detail {

/// False when neither the options nor the case want result.vtm (--vtk-samples 0).
bool analyze_writes_vtk(const AnalyzeCommandOptions& options, const Case& c);

/// Writes result.vtm and its pieces into `out_dir`, each timed into `timings`; returns the
/// sentence report.md says about them.
std::string write_analyze_vtk(const AnalyzeCommandResult& r, const AnalyzeCommandOptions& options,
                              const std::filesystem::path& out_dir, AnalyzeTimings& timings);

}  // namespace isospring::io::detail
