// The measured-data loop on an immersed part (identify_immersed.hpp): the setup the loop runs on,
// made from the immersed assembly instead of a body-fitted problem.
#include "isospring/fitting/identify_immersed.hpp"

#include <omp.h>

#include <Eigen/CholmodSupport>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "identify/immersed_setup.hpp"
#include "isospring/fitting/identify_immersed_check.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::fitting {

namespace {

using identify_loop::Setup;

// The same material and supports in every case, support values zero (each case's right-hand
// side is then its load alone).
void check_cases(const std::vector<ImmersedCalibrationCase>& cases) {
  if (cases.empty()) throw nurbs::InputError("identify: the immersed case has no load case");
  const analysis::ImmersedOptions& first = cases.front().options;
  for (const auto& c : cases) {
    const analysis::Material& m = c.options.material;
    if (m.youngs_modulus != first.material.youngs_modulus ||
        m.poisson_ratio != first.material.poisson_ratio || m.density != first.material.density)
      throw nurbs::InputError("identify: load case \"" + c.id +
                              "\" has another material than the first; one material per case");
    if (c.options.supports.size() != first.supports.size())
      throw nurbs::InputError("identify: load case \"" + c.id +
                              "\" has other supports than the first; every load case must be "
                              "held alike");
    for (size_t s = 0; s < c.options.supports.size(); ++s) {
      const analysis::ImmersedSupport& a = c.options.supports[s];
      const analysis::ImmersedSupport& b = first.supports[s];
      if (a.face != b.face || a.fixed != b.fixed || a.symmetry != b.symmetry)
        throw nurbs::InputError("identify: load case \"" + c.id +
                                "\" has other supports than the first; every load case must be "
                                "held alike");
      if (!a.value.isZero(0.0) || a.value_function)
        throw nurbs::InputError("identify: the support of face " + std::to_string(a.face) +
                                " prescribes a non-zero displacement; an immersed "
                                "identification needs supports that hold at zero (each load "
                                "case's right-hand side must be its load alone)");
    }
  }
}

// The full symmetric matrix of an upper triangle.
Eigen::SparseMatrix<double> full_symmetric(const Eigen::SparseMatrix<double>& upper) {
  Eigen::SparseMatrix<double> full = upper.selfadjointView<Eigen::Upper>();
  return full;
}

// Background basis at a physical point: control points and values (nurbs::Patch::basis at the
// affine box's parameter).
nurbs::RationalBasis basis_at(const geometry::ImmersedDomain& domain,
                              const Eigen::Vector3d& world) {
  const Eigen::Vector3d x = domain.to_grid(world);
  nurbs::Param u{0.0, 0.0, 0.0};
  for (int d = 0; d < domain.dimension; ++d)
    u[static_cast<size_t>(d)] = std::clamp((x[d] - domain.origin[d]) / domain.extent[d], 0.0, 1.0);
  return domain.background.basis(u, 0);
}

// The observation rows of one load case's markers: y = H u with u on the active DOFs.
Observation observe(const geometry::ImmersedDomain& domain, const analysis::ImmersedSystem& system,
                    const std::vector<Marker>& markers, const std::vector<int>& ids) {
  const int dim = system.dim;
  std::vector<Eigen::Triplet<double>> triplets;
  for (size_t k = 0; k < ids.size(); ++k) {
    const nurbs::RationalBasis basis =
        basis_at(domain, markers[static_cast<size_t>(ids[k])].position);
    for (size_t a = 0; a < basis.indices.size(); ++a) {
      const int node = system.node_of_control_point[static_cast<size_t>(basis.indices[a])];
      if (node < 0) continue;  // no DOF: the function does not reach the part
      for (int c = 0; c < dim; ++c)
        triplets.emplace_back(static_cast<Eigen::Index>(k) * dim + c, node * dim + c,
                              basis.values[static_cast<Eigen::Index>(a)]);
    }
  }
  Observation obs;
  obs.operator_.resize(static_cast<Eigen::Index>(ids.size()) * dim,
                       static_cast<Eigen::Index>(system.control_point_of_node.size()) * dim);
  obs.operator_.setFromTriplets(triplets.begin(), triplets.end());
  return obs;
}

// The loads: each case's right-hand side (the first case's from `first`, the system the
// stiffness came from) and the self-weight of a unit gravity per axis. The self-weight acts on
// each component alone (f_ac = rho int N_a g_c), so one assembly with g = (1, 1, 1) gives all
// three: the entries of component c are those of g = e_c.
void assemble_loads(const geometry::ImmersedDomain& domain,
                    const std::vector<ImmersedCalibrationCase>& cases,
                    const analysis::ImmersedSystem& first, Setup& setup) {
  ModelLoads& loads = setup.loads;
  for (size_t l = 0; l < cases.size(); ++l) {
    loads.case_ids.push_back(cases[l].id);
    loads.case_forces.push_back(
        l == 0 ? first.force : analysis::assemble_immersed(domain, cases[l].options).force);
  }
  setup.nominal_loads = loads.case_forces;
  loads.density = cases.front().options.material.density;
  loads.unavailable = immersed_unavailable_effect;
  if (!(loads.density > 0.0)) return;  // gravity is unavailable without a density
  analysis::ImmersedOptions unit = cases.front().options;
  unit.tractions.clear();
  unit.pressures.clear();
  unit.body_force.setZero();
  unit.gravity = Eigen::Vector3d::Ones();
  const Eigen::VectorXd all = analysis::assemble_immersed(domain, unit).force;
  for (int c = 0; c < setup.dim; ++c) {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(all.size());
    for (Eigen::Index k = c; k < all.size(); k += setup.dim) f[k] = all[k];
    loads.unit_gravity.push_back(std::move(f));
  }
}

// Markers grouped by load case, their observations and measured values.
void add_markers(const geometry::ImmersedDomain& domain, const analysis::ImmersedSystem& system,
                 const std::vector<Marker>& markers, Setup& setup) {
  const std::vector<int> outside = immersed_markers_outside(domain, markers);
  if (!outside.empty()) {
    const Marker& m = markers[static_cast<size_t>(outside.front())];
    throw nurbs::InputError("measurements: row " + std::to_string(m.row) + " (and " +
                            std::to_string(outside.size() - 1) +
                            " more): the marker does not lie in a background cell the part "
                            "meets; fix its position or units, or leave it out");
  }
  const int dim = setup.dim;
  for (size_t l = 0; l < setup.loads.case_ids.size(); ++l)
    setup.case_index[setup.loads.case_ids[l]] = static_cast<int>(l);
  setup.markers.resize(setup.loads.case_ids.size());
  for (size_t m = 0; m < markers.size(); ++m) {
    const auto it = setup.case_index.find(markers[m].load_case);
    if (it == setup.case_index.end())
      throw nurbs::InputError("measurements: row " + std::to_string(markers[m].row) +
                              ": load case \"" + markers[m].load_case +
                              "\" is not in the case file; use one of its load_cases ids");
    setup.markers[static_cast<size_t>(it->second)].push_back(static_cast<int>(m));
  }
  setup.context.marker_positions.resize(setup.markers.size());
  for (size_t l = 0; l < setup.markers.size(); ++l) {
    const auto& ids = setup.markers[l];
    Eigen::VectorXd measured(static_cast<Eigen::Index>(ids.size()) * dim);
    Eigen::VectorXd sigma(measured.size());
    for (size_t k = 0; k < ids.size(); ++k) {
      const Marker& marker = markers[static_cast<size_t>(ids[k])];
      for (int c = 0; c < dim; ++c) {
        measured[static_cast<Eigen::Index>(k) * dim + c] = marker.displacement[c];
        sigma[static_cast<Eigen::Index>(k) * dim + c] = marker.sigma;
      }
      setup.context.marker_positions[l].push_back(marker.position);
    }
    setup.observations.push_back(observe(domain, system, markers, ids));
    setup.measured.push_back(measured);
    setup.sigma.push_back(sigma);
  }
}

// What the loop reads of `problem` for a model without one: the material and the load case ids.
analysis::Problem descriptor(const std::vector<ImmersedCalibrationCase>& cases) {
  analysis::Problem problem;
  problem.material = cases.front().options.material;
  problem.formulation = cases.front().options.formulation;
  for (const auto& c : cases) {
    analysis::LoadCase load;
    load.id = c.id;
    problem.load_cases.push_back(load);
  }
  return problem;
}

}  // namespace

namespace identify_loop {

void make_immersed_setup(Setup& setup, const geometry::ImmersedDomain& domain,
                         const std::vector<ImmersedCalibrationCase>& cases,
                         const std::vector<Marker>& markers, bool fit_poisson,
                         const std::function<void(const std::string&)>& say) {
  check_cases(cases);
  if (fit_poisson)
    throw nurbs::InputError(
        "measurements.fit_poisson: not available for an immersed model (its Nitsche penalty "
        "scales with E but is not linear in the two Lame parameters apart); fit E alone");
  if (markers.empty()) throw nurbs::InputError("measurements: no markers to fit");
  setup.dim = domain.dimension;
  setup.material_parameters = 1;
  // Stabilised as solve_immersed's: where Cholesky finds the stiffness not positive definite,
  // the ghost penalty is widened (every load case then takes the widened options' stiffness,
  // which is the only one the loop uses; the loads do not depend on the penalty). The warning
  // goes to IdentifyResult::warnings, which the command prints once.
  const auto positive_definite = [](const analysis::ImmersedSystem& candidate) {
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> cholesky;
    cholesky.compute(candidate.stiffness);
    return cholesky.info() == Eigen::Success;
  };
  const analysis::ImmersedSystem system = analysis::assemble_stabilised_immersed(
      domain, cases.front().options, positive_definite, setup.warnings, "immersed identification");
  setup.num_dofs = static_cast<int>(system.control_point_of_node.size()) * system.dim;
  if (say) say("assembled the immersed stiffness (" + std::to_string(setup.num_dofs) + " DOFs)");
  setup.scaled_stiffness = full_symmetric(system.stiffness);
  assemble_loads(domain, cases, system, setup);
  add_markers(domain, system, markers, setup);

  // Effect context: the part's size (its boundary points' box), the load effects' data.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& b : domain.boundary) lo = lo.cwiseMin(b.point), hi = hi.cwiseMax(b.point);
  if (setup.dim == 2) lo.z() = hi.z() = 0.0;
  EffectContext& context = setup.context;
  context.loads = &setup.loads;
  context.dimension = setup.dim;
  context.centre = 0.5 * (lo + hi);
  context.length = (hi - lo).norm();
  const analysis::Material& material = cases.front().options.material;
  context.youngs_modulus_prior = material.youngs_modulus;
  const double nu = material.poisson_ratio;
  const bool plane_stress =
      cases.front().options.formulation == analysis::Formulation::kPlaneStress;
  context.lambda = linear_coefficient(
      0, material.youngs_modulus *
             (plane_stress ? nu / (1 - nu * nu) : nu / ((1 + nu) * (1 - 2 * nu))));
  context.mu = linear_coefficient(0, material.youngs_modulus / (2 * (1 + nu)));
}

std::vector<bool> active_control_points(const geometry::ImmersedDomain& domain) {
  // At any of a cell's quadrature points every function of the cell is non-zero.
  std::vector<bool> active(static_cast<size_t>(domain.background.num_points()), false);
  for (const auto& cell : domain.cells) {
    if (cell.points.empty()) continue;
    const nurbs::RationalBasis basis = basis_at(domain, cell.points.front());
    for (int index : basis.indices) active[static_cast<size_t>(index)] = true;
  }
  return active;
}

}  // namespace identify_loop

std::string immersed_unavailable_effect(const std::string& effect) {
  if (effect == "support_compliance")
    return "not available for immersed models: their supports are Nitsche terms inside the "
           "stiffness, and a compliant support would need those terms of the held faces apart "
           "(to replace them by face springs), which the immersed assembly does not give";
  if (effect == "stiffness_gradient")
    return "not available for immersed models: the cut-cell assembly integrates one "
           "homogeneous material (a modulus field would have to enter the bulk, the Nitsche "
           "penalty and the ghost penalty alike)";
  if (effect == "geometric_nonlinearity")
    return "not available for immersed models: the immersed path has no nonlinear internal "
           "force (large deformation is implemented on body-fitted patches)";
  return {};
}

std::vector<int> immersed_markers_outside(const geometry::ImmersedDomain& domain,
                                          const std::vector<Marker>& markers) {
  // The basis functions of the part's cells (inside and cut).
  const int dim = domain.dimension;
  std::vector<int> outside;
  const double slack = 1e-9 * domain.extent.head(dim).norm();
  const std::vector<bool> active = identify_loop::active_control_points(domain);
  for (size_t m = 0; m < markers.size(); ++m) {
    const Eigen::Vector3d x = domain.to_grid(markers[m].position);
    bool in = ((x - domain.origin).head(dim).array() >= -slack).all() &&
              ((x - domain.origin - domain.extent).head(dim).array() <= slack).all();
    if (in) {
      const nurbs::RationalBasis basis = basis_at(domain, markers[m].position);
      for (size_t a = 0; a < basis.indices.size() && in; ++a)
        in = basis.values[static_cast<Eigen::Index>(a)] == 0.0 ||
             active[static_cast<size_t>(basis.indices[a])];
    }
    if (!in) outside.push_back(static_cast<int>(m));
  }
  return outside;
}

IdentifyResult identify_immersed(const geometry::ImmersedDomain& domain,
                                 const std::vector<ImmersedCalibrationCase>& cases,
                                 const std::vector<Marker>& markers,
                                 const IdentifyOptions& options) {
  return identify_immersed(domain, cases, markers, options, ImmersedLadder{});
}

IdentifyResult identify_immersed(const geometry::ImmersedDomain& domain,
                                 const std::vector<ImmersedCalibrationCase>& cases,
                                 const std::vector<Marker>& markers, const IdentifyOptions& options,
                                 const ImmersedLadder& ladder) {
  using namespace identify_loop;
  check_cases(cases);
  const analysis::Problem problem = descriptor(cases);
  const std::vector<MarkerPlacement> no_placements;
  std::vector<int> all_rows(markers.size());
  for (size_t m = 0; m < markers.size(); ++m) all_rows[m] = static_cast<int>(m);
  LoopInputs in{problem,
                markers,
                no_placements,
                options,
                options.threads > 0 ? options.threads : omp_get_max_threads(),
                std::vector<bool>(markers.size(), true),
                std::move(all_rows),
                {},
                {},
                {}};
  in.custom_setup = [&](Setup& setup) {
    make_immersed_setup(setup, domain, cases, markers, options.fit_poisson, in.progress());
  };
  if (ladder.level)
    in.custom_check = [&](const Setup& case_setup, const Eigen::VectorXd& theta, double noise,
                          DiscretizationCheck& check) {
      return run_immersed_check(case_setup, domain, cases, markers, theta, noise,
                                options.discretization, ladder, in.progress(), check);
    };
  else
    in.no_discretisation_check =
        "not done: no ladder of background grids was given (identify_immersed without an "
        "ImmersedLadder); `isospring identify` gives one";
  return run_loop(in);
}

std::vector<Eigen::Vector3d> simulate_immersed_markers(
    const geometry::ImmersedDomain& domain, const std::vector<ImmersedCalibrationCase>& cases,
    const std::vector<Marker>& markers,
    const std::vector<std::pair<std::string, Eigen::VectorXd>>& effects) {
  using namespace identify_loop;
  Setup setup;
  make_immersed_setup(setup, domain, cases, markers, false, {});
  return simulate_with_effects(setup, markers.size(), effects, "simulate_immersed_markers");
}

}  // namespace isospring::fitting
