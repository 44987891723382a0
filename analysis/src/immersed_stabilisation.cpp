// The ghost-penalty fallback shared by every immersed solve that factorises a stiffness: the
// static solve, the calibration's reference and the identification's loop.
#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "isospring/analysis/immersed.hpp"

namespace isospring::analysis {

namespace {

// The largest share of a cell below which the fallback still penalises it: beyond it the penalty
// acts on well-cut cells too and costs accuracy (docs/immersed.md).
constexpr double kLargestGhostFraction = 0.16;

std::string fraction_text(double fraction) {
  std::ostringstream text;
  text << fraction;
  return text.str();
}

}  // namespace

ImmersedSystem assemble_stabilised_immersed(
    const geometry::ImmersedDomain& domain, const ImmersedOptions& options,
    const std::function<bool(const ImmersedSystem&)>& factorise, std::vector<std::string>& warnings,
    const std::string& who) {
  ImmersedOptions used = options;
  for (;;) {
    ImmersedSystem system = assemble_immersed(domain, used);
    if (factorise(system)) return system;
    if (used.ghost_penalty <= 0.0 || used.ghost_fraction >= kLargestGhostFraction)
      throw std::runtime_error(
          who +
          ": the stiffness matrix could not be factorised (not positive definite) with "
          "ghost_fraction " +
          fraction_text(used.ghost_fraction) +
          ": a basis function keeps too little of its support in the part; raise "
          "ghost_fraction (the cut cells stabilised by the ghost penalty) or ghost_penalty, or "
          "move the grid (a cell size or margin a little different)");
    // A basis function with a sliver of its support in the part, beside cells whose share lies
    // above the fraction: penalising more cut cells ties it to its neighbours (measured on a
    // turned nut: a larger nitsche_factor or ghost_penalty did not, nor did diagonal scaling).
    const double next = std::min(kLargestGhostFraction,
                                 used.ghost_fraction > 0.0 ? 2.0 * used.ghost_fraction : 0.02);
    warnings.push_back("the stiffness was not positive definite with ghost_fraction " +
                       fraction_text(used.ghost_fraction) +
                       " (a basis function keeps too little of its support in the part); the "
                       "ghost penalty now stabilises every cut cell with less than " +
                       fraction_text(next) + " of the part");
    used.ghost_fraction = next;
  }
}

}  // namespace isospring::analysis
