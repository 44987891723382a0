#pragma once
// The stages of fitting::calibrate (calibration.cpp lists them in order), the state they hand on
// and the helpers more than one of them uses. Private to the fitting module.
#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/spring_static.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/fitting/calibration.hpp"

namespace isospring::fitting::detail {

/// The IGA side of a calibration and the spring model's loads and supports, as the fits and the
/// metrics read them. Filled by calibrate()'s first stages (reference_solution, prepare_fit_data),
/// read-only afterwards. Invariants: `reference` and `loads` have one entry per load case of the
/// problem, in its order; `fitted` and `held_out` are disjoint load-case indices; data.loads and
/// data.references hold the cases of `fitted` in that order; data.network is the spring mesh's
/// network with its supports and masses but no fitted stiffness; particle_of_node maps every
/// DofMap node to its particle.
struct FitSetup {
  explicit FitSetup(const analysis::Problem& problem)
      : dofs(std::in_place, problem), dim(dofs->dofs_per_node()) {}
  /// An immersed model's (immersed_calibration.cpp): its nodes are the active control points.
  explicit FitSetup(int dimension) : dim(dimension) {}
  std::optional<analysis::DofMap> dofs;  // the body-fitted model's DOFs; empty when immersed
  int dim;                               // displacement components per node
  analysis::StaticResult reference;
  std::vector<int> particle_of_node;
  DisplacementFitData data;
  std::vector<int> fitted, held_out;
  std::vector<Eigen::VectorXd> loads;  // per load case, as forces on the particles
};

/// The upper bounds every gamma's fit shares: per spring ([S15 4.19], empty unless
/// settings.upper_bounds) and the one bound of every volume and shear term.
struct FitBounds {
  std::vector<double> spring;
  double volume = 0.0;
};

/// What the gamma sweep hands back: one entry per gamma (SweepEntry) and the kept fit.
struct SweepOutcome {
  std::vector<SweepEntry> entries;
  DisplacementFitResult fit;
  Grouping grouping;
  double gamma = 0.0;
};

/// Stage: the bounds of every fit (sweep_gammas), from the material and the mesh.
FitBounds fit_bounds(const analysis::Problem& problem, const CalibrationSettings& settings,
                     const SpringMesh& mesh, int dim);

/// Stage: fits every gamma of the sweep (or settings.gamma alone) as SweepEntry describes and
/// keeps the usable one of lowest error; throws when none is usable. `material` scales the
/// initial guess.
SweepOutcome sweep_gammas(const analysis::Material& material, const CalibrationSettings& settings,
                          const SpringMesh& mesh, const FitSetup& setup, const FitBounds& bounds);

/// The bound of every volume and shear term: 10 times the constrained modulus (see
/// gamma_sweep.cpp); spring bounds are the caller's.
double volume_term_bound(const analysis::Material& material, int dim);

/// Stage: the kept fit of `result.fit_result` on the calibrated network, its warnings and the
/// damping.
void apply_fit(const CalibrationSettings& settings, CalibrationResult& result);

/// Holds the particle DOFs `particle_dofs` (particle * dim + component, repeats allowed): a
/// particle with every component held becomes fixed, the others' held components go to
/// `extra_constrained` (sorted).
void hold_particle_dofs(std::vector<int> particle_dofs, int dim, SpringMesh& mesh,
                        std::vector<int>& extra_constrained);

/// Stage: the metrics of `network` on the fitted and the held-out load cases (control points,
/// and with settings.field_metrics the field and the physical surface, `inner` naming the sides
/// inside the model); throws when the network's stiffness is singular under the supports.
void evaluate_cases(const analysis::Problem& problem, const CalibrationSettings& settings,
                    const FitSetup& setup, const std::vector<std::array<bool, 6>>& inner,
                    const analysis::SpringNetwork& network, std::vector<CaseErrors>& fit_errors,
                    std::vector<CaseErrors>& holdout_errors);

/// Stage: the matrix approach's models (global, and per element when every patch is linear)
/// beside the calibrated one, evaluated on the same cases.
std::vector<MatrixComparison> compare_matrix_approach(const analysis::Problem& problem,
                                                      const CalibrationSettings& settings,
                                                      const FitSetup& setup,
                                                      const std::vector<std::array<bool, 6>>& inner,
                                                      const SpringMesh& mesh,
                                                      const Grouping& grouping);

/// The fitted stiffnesses and groups on the network's springs and volume terms.
void set_fitted(analysis::SpringNetwork& network, const DisplacementFitResult& fit,
                const Grouping& grouping);

/// A flat vector (point * dim + component) as points.
std::vector<Eigen::Vector3d> to_points(const Eigen::VectorXd& flat, int dim);

/// The linear solver of a calibrated network under the setup's supports (factorised once for
/// every load case it is measured on).
analysis::SpringLinearSolver network_solver(const FitSetup& setup,
                                            const analysis::SpringNetwork& network);

/// Control-point displacements (DofMap node order, as points) of the network of `solver`
/// (network_solver) under load case c.
std::vector<Eigen::Vector3d> model_points(const FitSetup& setup,
                                          const analysis::SpringLinearSolver& solver, int c);

}  // namespace isospring::fitting::detail
