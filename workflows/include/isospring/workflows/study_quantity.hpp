#pragma once
// The scalar a refinement study follows at every level (`study --quantity`): the strain energy
// (the default: a global functional converging monotonically at O(h^2p) for loads with fixed
// supports), the maximum control displacement (control points are not on the displacement
// field, so O(h^2) whatever the degree), or one displacement component at a parametric point.
// It is what Richardson extrapolation works on when the case has no analytic solution.
#include <optional>
#include <string>

#include "isospring/analysis/post_processing.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/io/case_file.hpp"

namespace isospring::workflows {

struct StudyQuantity {
  enum class Kind { kMaxDisplacement, kStrainEnergy, kDisplacement } kind = Kind::kStrainEnergy;
  int patch = 0;
  nurbs::Param param{0, 0, 0};
  int component = -1;  // 0..2 = x..z, -1 = magnitude (kDisplacement)
  std::string label;   // for the reports, e.g. "u_y at patch 0 (u, v) = (1, 0.5)"

  /// The value on one level's solution.
  double evaluate(const analysis::Problem& problem, const analysis::LoadCaseResult& result) const;
  /// The analytic solution's value, when the case has one and the quantity is a point value.
  std::optional<double> exact(const io::Case& c) const;
};

/// From `--quantity NAME` (strain_energy, max_displacement, displacement), `--point
/// PATCH:U,V[,W]` and `--component x|y|z|magnitude`; throws nurbs::InputError naming the option.
StudyQuantity parse_study_quantity(const std::string& quantity, const std::string& point,
                                   const std::string& component, const io::Case& c);

}  // namespace isospring::workflows
