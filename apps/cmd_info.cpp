// `isospring info FILE`: what a patch file holds: per patch its dimensions, degrees, knot vectors
// (unique knots with multiplicities), control points, elements and bounding box.
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli_util.hpp"
#include "command.hpp"

namespace isospring::apps {
namespace {

void print_patch_summary(std::ostream& out, int index, const nurbs::Patch& patch) {
  static const char* kDirection[] = {"u", "v", "w"};
  out << "patch " << index << ": parametric dimension " << patch.param_dim()
      << ", physical dimension " << patch.physical_dim()
      << (patch.is_rational() ? ", rational" : "") << "\n";
  out << "  control points: " << patch.num_points() << " (";
  for (int d = 0; d < patch.param_dim(); ++d) out << (d ? " x " : "") << patch.num_points(d);
  out << "), elements: " << patch.num_elements() << "\n";
  for (int d = 0; d < patch.param_dim(); ++d) {
    const nurbs::KnotVector& kv = patch.knots(d);
    const auto unique = kv.unique();
    const auto mult = kv.multiplicities();
    out << "  " << kDirection[d] << ": degree " << kv.degree() << ", " << kv.num_elements()
        << " elements, knots (value^multiplicity):";
    for (size_t k = 0; k < unique.size(); ++k) out << " " << unique[k] << "^" << mult[k];
    out << "\n";
  }
  const auto [lo, hi] = patch.control_bounds();
  out << "  bounding box of the control net: [" << lo.x() << ", " << hi.x() << "] x [" << lo.y()
      << ", " << hi.y() << "] x [" << lo.z() << ", " << hi.z() << "]\n";
}

void setup_info(CLI::App& app) {
  auto file = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand(
      "info", "Describe a patch file: patches, degrees, knots, control points, elements, size");
  cmd->add_option("FILE", *file, "Patch file (.json)")->required()->check(CLI::ExistingFile);
  cmd->callback([file] {
    const auto patches = read_patches_any(*file);
    std::cout << *file << ": " << patches.size() << (patches.size() == 1 ? " patch" : " patches")
              << "\n";
    std::cout << std::setprecision(10);
    for (size_t i = 0; i < patches.size(); ++i)
      print_patch_summary(std::cout, static_cast<int>(i), patches[i]);
  });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(10, setup_info);
}  // namespace isospring::apps
