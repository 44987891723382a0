#include "isospring/io/vtk_solution.hpp"

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
              analysis::ControlDisplacements displacements)
      : problem_(std::move(problem)), displacements_(std::move(displacements)) {}

  const analysis::FieldPoint& at(int patch, const nurbs::Param& u) {
    if (!valid_ || patch != patch_ || u != u_) {
      try {
        point_ = analysis::evaluate_field(*problem_, displacements_, patch, u);
      } catch (const nurbs::InputError&) {
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
  bool valid_ = false;
  int patch_ = -1;
  nurbs::Param u_{};
  analysis::FieldPoint point_;
};

Eigen::VectorXd scalar(double value) {
  Eigen::VectorXd out(1);
  out(0) = value;
  return out;
}
// The fields are evaluated while the VTK files are written; a value that overflows (stresses
// of a solution near the limits of a double) must stop the run (exit status 3) rather than be
// written as inf or NaN. The solver has already checked the displacements themselves.
PatchField finite_only(PatchField field) {
  auto evaluate = std::move(field.evaluate);
  const std::string name = field.name;
  field.evaluate = [evaluate, name](int p, const nurbs::Param& u) {
    Eigen::VectorXd value = evaluate(p, u);
    if (!value.allFinite())
      throw std::runtime_error(name + " overflowed (not finite) in patch " + std::to_string(p) +
                               "; check the material and the loads and their units (SI)");
    return value;
  };
  return field;
}
}  // namespace

PatchFields solution_fields(const analysis::Problem& problem,
                            const std::vector<analysis::LoadCaseResult>& load_cases) {
  const auto shared = std::make_shared<const analysis::Problem>(problem);
  PatchFields fields;
  for (const analysis::LoadCaseResult& lc : load_cases) {
    fields.control.push_back(
        control_vector_field("displacement_" + lc.id, lc.control_displacements));
    auto cache = std::make_shared<CachedField>(shared, lc.control_displacements);
    auto stress = [cache](int p, const nurbs::Param& u) { return cache->at(p, u).stress; };
    fields.evaluated.push_back(finite_only(stress_tensor_field("stress_" + lc.id, stress)));
    fields.evaluated.push_back(
        finite_only(PatchField{"von_mises_" + lc.id, 1, [cache](int p, const nurbs::Param& u) {
                                 return scalar(cache->at(p, u).von_mises);
                               }}));
    fields.evaluated.push_back(finite_only(
        PatchField{"strain_energy_density_" + lc.id, 1, [cache](int p, const nurbs::Param& u) {
                     const analysis::FieldPoint& f = cache->at(p, u);
                     return scalar(0.5 * f.stress.cwiseProduct(f.strain).sum());
                   }}));
  }
  return fields;
}

}  // namespace isospring::io
