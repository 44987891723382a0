#include "isospring/io/vtk_solution.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "isospring/analysis/post_processing.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {

/// evaluate_field of one load case, remembering the last point of each thread: the sampled
/// writer asks for stress, von Mises and energy density at the same parameter one after the
/// other (on the thread that owns the point), so each point is evaluated once instead of three
/// times. Thread-safe: a thread only touches its own slot.
class CachedField {
 public:
  CachedField(std::shared_ptr<const analysis::Problem> problem,
              analysis::ControlDisplacements displacements, std::string load_case)
      : problem_(std::move(problem)),
        displacements_(std::move(displacements)),
        load_case_(std::move(load_case)),
        evaluator_(*problem_, displacements_),
        slots_(static_cast<size_t>(std::max(1, omp_get_max_threads()))) {}

  // evaluator_ points at displacements_: never copied nor moved (held by shared_ptr).
  CachedField(const CachedField&) = delete;
  CachedField& operator=(const CachedField&) = delete;

  /// The fields are evaluated while the VTK files are written. A value that overflows (strains
  /// of a solution near the limits of a double) must stop the run (std::runtime_error: exit
  /// status 3) rather than be written as inf or NaN; only degenerate points carry NaN, on
  /// purpose. The solver has already checked the displacements themselves.
  void check(bool degenerate, bool finite, const char* what, int patch) const {
    if (!degenerate && !finite)
      throw std::runtime_error("load case '" + load_case_ + "': the " + what +
                               " overflowed (not finite) in patch " + std::to_string(patch) +
                               "; check the material, the loads and their units (SI)");
  }

  /// The field at (patch, u) and whether the point is degenerate.
  std::pair<analysis::FieldPoint, bool> at(int patch, const nurbs::Param& u) {
    const auto thread = static_cast<size_t>(omp_get_thread_num());
    // A thread beyond the slots (more threads than when this was made) evaluates uncached.
    Slot fallback;
    Slot& slot = thread < slots_.size() ? slots_[thread] : fallback;
    if (!slot.valid || patch != slot.patch || u != slot.u) {
      slot.degenerate = false;
      try {
        slot.point = evaluator_(patch, u);
        check(false, slot.point.strain.allFinite(), "strain", patch);
        check(false, slot.point.stress.allFinite() && std::isfinite(slot.point.von_mises), "stress",
              patch);
      } catch (const nurbs::InputError&) {
        slot.degenerate = true;
        // The solve succeeded, so the parametrisation is valid inside the elements: this is a
        // degenerate point (det J = 0 at a collapsed edge or corner, e.g. the 1-patch plate
        // with a hole), where strain and stress are undefined. NaN shows that in ParaView.
        const double nan = std::numeric_limits<double>::quiet_NaN();
        slot.point.strain.setConstant(nan);
        slot.point.stress.setConstant(nan);
        slot.point.von_mises = nan;
      }
      slot.patch = patch;
      slot.u = u;
      slot.valid = true;
    }
    return {slot.point, slot.degenerate};
  }

 private:
  struct Slot {
    bool valid = false, degenerate = false;
    int patch = -1;
    nurbs::Param u{};
    analysis::FieldPoint point;
  };
  std::shared_ptr<const analysis::Problem> problem_;
  analysis::ControlDisplacements displacements_;
  std::string load_case_;
  analysis::FieldEvaluator evaluator_;
  std::vector<Slot> slots_;
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
    auto stress = [cache](int p, const nurbs::Param& u) { return cache->at(p, u).first.stress; };
    PatchField stress_field = stress_tensor_field("stress_" + lc.id, stress);
    stress_field.thread_safe = true;
    fields.evaluated.push_back(std::move(stress_field));
    fields.evaluated.push_back(PatchField{
        "von_mises_" + lc.id, 1,
        [cache](int p, const nurbs::Param& u) { return scalar(cache->at(p, u).first.von_mises); },
        true});
    fields.evaluated.push_back(
        PatchField{"strain_energy_density_" + lc.id, 1,
                   [cache](int p, const nurbs::Param& u) {
                     const auto [f, degenerate] = cache->at(p, u);
                     const double energy = 0.5 * f.stress.cwiseProduct(f.strain).sum();
                     cache->check(degenerate, std::isfinite(energy), "strain energy density", p);
                     return scalar(energy);
                   },
                   true});
  }
  return fields;
}

}  // namespace isospring::io
