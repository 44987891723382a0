#pragma once
// The use case behind `isospring thesis` as one library call: regenerates the [S15] chapter-5
// tables (5.3 for the six objects of Table 5.1, 5.4 net resolution, 5.5 gamma sweep, 5.6 / 5.7
// against the matrix approach) beside the published numbers, with per-spring fits and the
// acceleration objective [S15 4.1-4.5] as baselines, and the generalisation table (load suite,
// cross-validated freedom). Protocol: fitting/thesis_experiments.hpp,
// examples/thesis/README.md. The run takes minutes (--quick: fewer); the result is the two
// reports, built table by table as the fits finish.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/io/report.hpp"

namespace isospring::workflows {

struct ThesisCommandOptions {
  /// Skip the cube 6^3 and 9^3 of Table 5.4 and the cube's per-spring fit; fewer candidates and
  /// iterations in the generalisation table.
  bool quick = false;
  bool generalisation_only = false;  // only the generalisation table
  std::vector<std::string> objects;  // generalisation table: these objects only (empty: all six)
};

/// report.json and report.md of `isospring thesis`.
struct ThesisReport {
  nlohmann::json json;
  io::MarkdownReport markdown;
};

ThesisReport run_thesis(const ThesisCommandOptions& options, const io::Progress& progress);

}  // namespace isospring::workflows
