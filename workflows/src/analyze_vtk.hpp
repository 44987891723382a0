#pragma once
// The ParaView output of `analyze` (result.vtm and result/): which pieces, at which resolution.
#include <filesystem>
#include <string>

#include "isospring/io/analyze_timings.hpp"
#include "isospring/workflows/analyze_command.hpp"

namespace isospring::workflows::detail {

/// False when neither the options nor the case want result.vtm (--vtk-samples 0).
bool analyze_writes_vtk(const AnalyzeCommandOptions& options, const io::Case& c);

/// Writes result.vtm and its pieces into `out_dir`, each timed into `timings`; returns the
/// sentence report.md says about them.
std::string write_analyze_vtk(const AnalyzeCommandResult& r, const AnalyzeCommandOptions& options,
                              const std::filesystem::path& out_dir, io::AnalyzeTimings& timings);

}  // namespace isospring::workflows::detail
