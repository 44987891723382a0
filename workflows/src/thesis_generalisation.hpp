#pragma once
// The generalisation table of `isospring thesis`: per [S15] object, a spring model
// calibrated on the load suite (fitting/load_suite.hpp) with its freedom chosen by
// cross-validation (fitting/generalising_calibration.hpp), measured on validation cases and on
// [S15]'s own load cases, none of them fitted, beside [S15]'s fitted-case error.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/io/report.hpp"

namespace isospring::workflows {

/// Runs the six objects (or those named in `objects`), appends report["generalisation"] and a
/// section of `md`.
void thesis_generalisation(bool quick, const std::vector<std::string>& objects,
                           nlohmann::json& report, io::MarkdownReport& md,
                           const io::Progress& progress);

}  // namespace isospring::workflows
