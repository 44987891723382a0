#pragma once
// The use case behind `isospring refine`: exact h-, p- and k-refinement of every patch of a
// patch file. Order of operations: degree elevation first, then explicit knot insertion, then
// uniform splitting (elevating before splitting is k-refinement: maximal continuity).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/io/report.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::workflows {

struct RefineCommandOptions {
  int h = 1;                        // split every knot span into h equal spans
  std::vector<int> elevate;         // one amount for all directions, or one per direction
  std::vector<std::string> insert;  // "DIRECTION=KNOTS", e.g. "u=0.3,0.3"
  /// > 0: refuse, before inserting any knot, a refinement needing more memory; `memory_source`
  /// says where the limit comes from ("--max-memory 2 GB").
  double memory_limit_bytes = 0;
  std::string memory_source;
  std::string input;  // names the input in messages and the report
};

struct RefineCommandResult {
  std::vector<nurbs::Patch> before, after;
  /// Per patch: the largest distance between before and after at 9 parameters per direction
  /// (refinement is exact: round-off).
  std::vector<double> deviation;
};

/// Refines `patches`. Throws nurbs::InputError for bad options (naming the patch) and for a
/// refinement too large to hold.
RefineCommandResult run_refine(const std::vector<nurbs::Patch>& patches,
                               const RefineCommandOptions& options);

/// The report's content beside the output `output` (FileReport's json and markdown).
void refine_report(const RefineCommandResult& r, const RefineCommandOptions& options,
                   const std::string& output, nlohmann::json& json, io::MarkdownReport& md);

}  // namespace isospring::workflows
