// run_refine and its report (see refine_command.hpp).
#include "isospring/workflows/refine_command.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "isospring/analysis/resource_estimate.hpp"
#include "isospring/io/number_list.hpp"
#include "isospring/io/report_patch.hpp"
#include "isospring/nurbs/error.hpp"
#include "isospring/nurbs/refine.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;
namespace {

int direction_of(const std::string& name) {
  if (name == "u") return 0;
  if (name == "v") return 1;
  if (name == "w") return 2;
  throw nurbs::InputError("--insert: direction '" + name + "' must be u, v or w");
}

nurbs::Patch refine_patch(nurbs::Patch patch, const RefineCommandOptions& options, int index) {
  const std::string where = "patch " + std::to_string(index) + ": ";
  try {
    if (!options.elevate.empty()) {
      if (options.elevate.size() != 1 &&
          static_cast<int>(options.elevate.size()) != patch.param_dim())
        throw nurbs::InputError(
            "--elevate takes one amount for all directions or one per "
            "direction (" +
            std::to_string(patch.param_dim()) + ")");
      for (int d = 0; d < patch.param_dim(); ++d)
        patch = nurbs::elevate_degree(patch, d,
                                      options.elevate.size() == 1
                                          ? options.elevate[0]
                                          : options.elevate[static_cast<size_t>(d)]);
    }
    for (const std::string& spec : options.insert) {
      const size_t eq = spec.find('=');
      if (eq == std::string::npos)
        throw nurbs::InputError("--insert '" + spec + "': use DIRECTION=KNOTS, e.g. u=0.3,0.3");
      const int dir = direction_of(spec.substr(0, eq));
      patch = nurbs::refine_knots(patch, dir, parse_number_list(spec.substr(eq + 1), "--insert"));
    }
    if (options.h > 1) patch = nurbs::refine_uniform(patch, options.h);
  } catch (const nurbs::InputError& e) {
    throw nurbs::InputError(where + e.what());
  }
  return patch;
}

// Refuses, before inserting any knot, a refinement whose control nets cannot fit: `--h 1000000`
// on a surface asks for 10^12 control points and would otherwise run until killed.
void check_refined_size(const std::vector<nurbs::Patch>& patches,
                        const RefineCommandOptions& options) {
  std::vector<analysis::PatchSize> sizes;
  for (size_t p = 0; p < patches.size(); ++p) {
    const nurbs::Patch& patch = patches[p];
    std::array<int, 3> elevate{0, 0, 0};
    std::array<double, 3> inserted{0, 0, 0}, splits{1, 1, 1};
    for (int d = 0; d < patch.param_dim(); ++d) {
      const auto i = static_cast<size_t>(d);
      // (A wrong count of --elevate amounts is reported by refine_patch.)
      if (!options.elevate.empty())
        elevate[i] = options.elevate[std::min(i, options.elevate.size() - 1)];
      splits[i] = options.h;
    }
    for (const std::string& spec : options.insert) {
      const size_t eq = spec.find('=');
      if (eq == std::string::npos) continue;  // refine_patch reports the malformed option
      const std::string name = spec.substr(0, eq);
      const int d = name == "u" ? 0 : name == "v" ? 1 : name == "w" ? 2 : -1;
      if (d >= 0)
        inserted[static_cast<size_t>(d)] +=
            static_cast<double>(std::count(spec.begin(), spec.end(), ',') + 1);
    }
    sizes.push_back(analysis::refined_size(patch, elevate, inserted, splits));
    if (sizes.back().total_points() > std::numeric_limits<int>::max())
      throw nurbs::InputError(
          options.input + ": patch " + std::to_string(p) + ": the refinement gives " +
          format_number(sizes.back().total_points(), 3) +
          " control points, more than isospring supports in one patch (" +
          std::to_string(std::numeric_limits<int>::max()) + "); use a smaller --h or --elevate");
  }
  // The input and the refined patches are held together, and each step (elevation, insertion,
  // splitting) builds a new patch from the previous one: at least twice the refined size.
  const double needed = 2.0 * analysis::geometry_bytes(sizes);
  double points = 0;
  for (const auto& s : sizes) points += s.total_points();
  if (options.memory_limit_bytes > 0 && needed > options.memory_limit_bytes)
    throw nurbs::InputError(options.input + ": the refinement gives " + format_number(points, 3) +
                            " control points, which need at least " +
                            analysis::format_bytes(needed) + " but the limit is " +
                            analysis::format_bytes(options.memory_limit_bytes) + " (" +
                            options.memory_source + "); use a smaller --h or --elevate");
}

// Refinement is exact, so the refined patch must trace the same geometry: the largest distance
// between old and new at 9 parameters per direction (ends and interior), reported per patch. A
// value near round-off (relative to the control net's size) confirms it for the user's file.
double largest_deviation(const nurbs::Patch& before, const nurbs::Patch& after) {
  constexpr int kSamples = 9;
  double largest = 0.0;
  const int dims = before.param_dim();
  const int n2 = dims > 1 ? kSamples : 1, n3 = dims > 2 ? kSamples : 1;
  for (int k = 0; k < n3; ++k)
    for (int j = 0; j < n2; ++j)
      for (int i = 0; i < kSamples; ++i) {
        nurbs::Param u{0.0, 0.0, 0.0};
        const int index[3] = {i, j, k};
        for (int d = 0; d < dims; ++d)
          u[static_cast<size_t>(d)] =
              before.param_min(d) +
              (before.param_max(d) - before.param_min(d)) * index[d] / (kSamples - 1.0);
        largest = std::max(largest, (before.point(u) - after.point(u)).norm());
      }
  return largest;
}

}  // namespace

RefineCommandResult run_refine(const std::vector<nurbs::Patch>& patches,
                               const RefineCommandOptions& options) {
  check_refined_size(patches, options);
  RefineCommandResult r;
  r.before = patches;
  for (size_t i = 0; i < patches.size(); ++i) {
    r.after.push_back(refine_patch(patches[i], options, static_cast<int>(i)));
    r.deviation.push_back(largest_deviation(r.before[i], r.after[i]));
  }
  return r;
}

void refine_report(const RefineCommandResult& r, const RefineCommandOptions& options,
                   const std::string& output, nlohmann::json& j, MarkdownReport& md) {
  const std::vector<nurbs::Patch>& before = r.before;
  const std::vector<nurbs::Patch>& after = r.after;
  j["operations"] = {{"elevate", options.elevate}, {"insert", options.insert}, {"h", options.h}};
  std::vector<std::vector<std::string>> rows;
  double largest = 0.0;
  for (size_t p = 0; p < before.size(); ++p) {
    const auto [lo, hi] = before[p].control_bounds();
    const double deviation = r.deviation[p];
    largest = std::max(largest, deviation);
    // One patch_json each (it integrates the measure): reused for the table row.
    const nlohmann::json b = patch_json(before[p]), a = patch_json(after[p]);
    j["patches"].push_back({{"before", b},
                            {"after", a},
                            {"geometry_deviation", deviation},
                            {"geometry_deviation_relative", deviation / (hi - lo).norm()}});
    rows.push_back(
        {std::to_string(p), b["degrees"].dump() + " -> " + a["degrees"].dump(),
         b["elements"].dump() + " -> " + a["elements"].dump(),
         std::to_string(before[p].num_points()) + " -> " + std::to_string(after[p].num_points()),
         format_number(deviation, 3)});
  }
  j["largest_geometry_deviation"] = largest;
  md.heading(1, "isospring refine: " + options.input);
  std::string ops = "--h " + std::to_string(options.h);
  for (int e : options.elevate) ops += ", --elevate " + std::to_string(e);
  for (const auto& i : options.insert) ops += ", --insert " + i;
  md.paragraph("Operations (degree elevation, then knot insertion, then uniform splitting): " +
               ops + ". Written to " + output + ".");
  md.table({"patch", "degrees", "elements", "control points", "geometry deviation [m]"}, rows);
  md.paragraph(
      "Geometry deviation: largest distance between the patch before and after at 9 parameters "
      "per direction; refinement is exact, so it is round-off.");
}

}  // namespace isospring::workflows
