#include "isospring/io/vtk_solution.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "isospring/analysis/post_processing.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {

/// evaluate_field of one load case, remembering the last point: the sampled writer asks for
/// stress, von Mises and energy density at the same parameter one after the other, so each point
/// is evaluated once instead of three times.
class CachedField {
 public:
  CachedField(std::shared_ptr<const analysis::Problem> problem,
              analysis::ControlDisplacements displacements, std::string load_case)
      : problem_(std::move(problem)),
        displacements_(std::move(displacements)),
        load_case_(std::move(load_case)) {}

  /// The fields are evaluated while the VTK files are written. A value that overflows (strains
  /// of a solution near the limits of a double) must stop the run (std::runtime_error: exit
  /// status 3) rather than be written as inf or NaN; only degenerate points carry NaN, on
  /// purpose. The solver has already checked the displacements themselves.
  void check(bool finite, const char* what, int patch) const {
    if (!degenerate_ && !finite)
      throw std::runtime_error("load case '" + load_case_ + "': the " + what +
                               " overflowed (not finite) in patch " + std::to_string(patch) +
                               "; check the material, the loads and their units (SI)");
  }
  double checked(double value, const char* what, int patch) const {
    check(std::isfinite(value), what, patch);
    return value;
  }

  const analysis::FieldPoint& at(int patch, const nurbs::Param& u) {
    if (!valid_ || patch != patch_ || u != u_) {
      degenerate_ = false;
      try {
        point_ = analysis::evaluate_field(*problem_, displacements_, patch, u);
        check(point_.strain.allFinite(), "strain", patch);
        check(point_.stress.allFinite() && std::isfinite(point_.von_mises), "stress", patch);
      } catch (const nurbs::InputError&) {
        degenerate_ = true;
        // The solve succeeded, so the parametrisation is valid inside the elements: this is a
        // degenerate point (det J = 0 at a collapsed edge or corner, e.g. the 1-patch plate
        // with a hole), where strain and stress are undefined. NaN shows that in ParaView.
        const double nan = std::numeric_limits<double>::quiet_NaN();
        point_.strain.setConstant(nan);
        point_.stress.setConstant(nan);
        point_.von_mises = nan;
      }
      patch_ = patch;
      u_ = u;
      valid_ = true;
    }
    return point_;
  }

 private:
  std::shared_ptr<const analysis::Problem> problem_;
  analysis::ControlDisplacements displacements_;
  std::string load_case_;
  bool valid_ = false, degenerate_ = false;
  int patch_ = -1;
  nurbs::Param u_{};
  analysis::FieldPoint point_;
};

Eigen::VectorXd scalar(double value) {
  Eigen::VectorXd out(1);
  out(0) = value;
  return out;
}
}  // namespace

PatchFields solution_fields(const analysis::Problem& problem,
                            const std::vector<analysis::LoadCaseResult>& load_cases) {
  const auto shared = std::make_shared<const analysis::Problem>(problem);
  PatchFields fields;
  for (const analysis::LoadCaseResult& lc : load_cases) {
    fields.control.push_back(
        control_vector_field("displacement_" + lc.id, lc.control_displacements));
    auto cache = std::make_shared<CachedField>(shared, lc.control_displacements, lc.id);
    auto stress = [cache](int p, const nurbs::Param& u) { return cache->at(p, u).stress; };
    fields.evaluated.push_back(stress_tensor_field("stress_" + lc.id, stress));
    fields.evaluated.push_back(PatchField{
        "von_mises_" + lc.id, 1,
        [cache](int p, const nurbs::Param& u) { return scalar(cache->at(p, u).von_mises); }});
    fields.evaluated.push_back(
        PatchField{"strain_energy_density_" + lc.id, 1, [cache](int p, const nurbs::Param& u) {
                     const analysis::FieldPoint& f = cache->at(p, u);
                     return scalar(cache->checked(0.5 * f.stress.cwiseProduct(f.strain).sum(),
                                                  "strain energy density", p));
                   }});
  }
  return fields;
}

}  // namespace isospring::io
