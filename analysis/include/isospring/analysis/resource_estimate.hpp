#pragma once
// Memory estimates made BEFORE refining or assembling, so a discretisation far beyond the
// machine is refused in a second with the numbers, instead of running until it is killed.
//
// The estimates are lower bounds derived from the sizes alone (no fill-in is guessed): a run
// refused by them could not have fitted, and --max-memory lets a user set a tighter limit.
#include <array>
#include <string>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::analysis {

/// The size of one patch: control points per parametric direction (doubles, since refused
/// sizes overflow an int) and degrees.
struct PatchSize {
  int param_dim = 3;
  std::array<double, 3> points{1, 1, 1};
  std::array<int, 3> degree{0, 0, 0};
  double total_points() const { return points[0] * points[1] * points[2]; }
};

/// The size of `patch` after raising the degree along d by elevate[d], inserting inserted[d]
/// knots and then splitting every knot span into splits[d] equal spans: the order of
/// nurbs::k_refine and `isospring refine`. Exact when the inserted knots are new values (each
/// then adds a span); an upper bound otherwise. Computed without refining.
PatchSize refined_size(const nurbs::Patch& patch, const std::array<int, 3>& elevate,
                       const std::array<double, 3>& inserted, const std::array<double, 3>& splits);

struct SolveEstimate {
  double dofs = 0;
  double nonzeros = 0;  // stored upper triangle of K
  double bytes = 0;     // lower bound of the memory the static solve needs
};

/// Stiffness of linear elasticity with `dofs_per_node` components on these patches. A basis
/// function of degree p overlaps (2p+1)^d others (fewer when the patch has fewer points), each
/// coupling dofs_per_node^2 entries; the solver keeps the upper triangle of K, the reduced K of
/// the free DOFs and its Cholesky factor (at least as many nonzeros again), 12 bytes per nonzero
/// (value and row index) each, plus the control points (32 bytes each).
SolveEstimate estimate_static_solve(const std::vector<PatchSize>& patches, int dofs_per_node);

/// Bytes of the refined control nets alone (x, y, z, w per point).
double geometry_bytes(const std::vector<PatchSize>& patches);

/// MemAvailable of /proc/meminfo (bytes); sysconf's available physical pages where that file is
/// missing; 0 when neither is known.
double available_memory_bytes();

/// "3.2 GB" (decimal units, 3 significant digits).
std::string format_bytes(double bytes);

}  // namespace isospring::analysis
