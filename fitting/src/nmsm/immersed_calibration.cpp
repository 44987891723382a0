// calibrate_immersed: the immersed model's particles, springs, masses, supports, loads and
// reference fed to calibrate()'s fit stages (see immersed_calibration.hpp). The metrics are in
// immersed_calibration_metrics.cpp.
#include "isospring/fitting/immersed_calibration.hpp"

#include <Eigen/CholmodSupport>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include "isospring/analysis/immersed_particles.hpp"
#include "isospring/fitting/step_cost.hpp"
#include "isospring/nurbs/error.hpp"
#include "nmsm/calibration_stages.hpp"
#include "nmsm/immersed_calibration_stages.hpp"
#include "nmsm/net_springs.hpp"

namespace isospring::fitting {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool contains(const std::vector<std::string>& list, const std::string& id) {
  return std::find(list.begin(), list.end(), id) != list.end();
}

void fail(const std::string& message) {
  throw nurbs::InputError(message);
}

// Stage: settings without an immersed form, unknown ids, cases that disagree.
void check_settings(const std::vector<ImmersedCalibrationCase>& cases,
                    const CalibrationSettings& settings) {
  if (cases.empty()) fail("calibration: the immersed case has no load case");
  for (const auto* list : {&settings.fit_cases, &settings.holdout_cases})
    for (const auto& id : *list)
      if (std::none_of(cases.begin(), cases.end(), [&](const auto& c) { return c.id == id; }))
        fail(std::string("calibration.") + (list == &settings.fit_cases ? "fit" : "holdout") +
             "_cases: no load case '" + id + "' in the case file");
  const std::string immersed = " has no immersed form (it needs a body-fitted model";
  if (settings.matrix_approach)
    fail("calibration.matrix_approach" + immersed +
         "'s IGA stiffness on the spring model's nodes); set it false");
  if (settings.upper_bounds)
    fail("calibration.upper_bounds" + immersed + "'s net cells); set it false");
  if (settings.mass_model != MassModel::kLumpedIga)
    fail("calibration.mass: \"net_cells\"" + immersed +
         "'s net cells); use \"lumped\", the lumped mass over the part");
  if (settings.mesh.strain_points > 0)
    fail("calibration.strain_points" + immersed + "'s knot spans); set it 0");
  if (!settings.reference_displacements.empty())
    fail("calibration: given reference displacements" + immersed + ")");
  if (settings.damping_alpha > 0.0 && settings.damping_ratio > 0.0)
    fail("calibration: give damping_alpha or damping_ratio, not both");
  const auto& first = cases.front().options;
  for (const auto& s : first.supports)
    if (!s.value.isZero(0.0) || s.value_function)
      fail(
          "calibration: support values must be zero (the spring model holds supported control "
          "points in place); remove the prescribed displacement on face " +
          std::to_string(s.face));
  for (const auto& c : cases) {
    const auto& o = c.options;
    bool same = o.supports.size() == first.supports.size() &&
                o.material.youngs_modulus == first.material.youngs_modulus &&
                o.material.poisson_ratio == first.material.poisson_ratio &&
                o.material.density == first.material.density && o.formulation == first.formulation;
    for (size_t s = 0; same && s < o.supports.size(); ++s)
      same = o.supports[s].face == first.supports[s].face &&
             o.supports[s].fixed == first.supports[s].fixed &&
             o.supports[s].symmetry == first.supports[s].symmetry;
    if (!same)
      fail("calibration: load case '" + c.id + "' has other supports or another material than '" +
           cases.front().id + "'; one spring model has one set of supports");
  }
}

// The immersed solution of one assembled case as solve_immersed returns it (its Cholesky solve on
// the same system; the stiffness is the same for every case, so it is factorised once).
analysis::ImmersedResult immersed_solution(
    const analysis::ImmersedSystem& system,
    const Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper>& cholesky) {
  const Eigen::VectorXd u = cholesky.solve(system.force);
  if (!u.allFinite())
    throw std::runtime_error("calibration: the immersed solve gave a non-finite displacement");
  analysis::ImmersedResult result;
  result.dim = system.dim;
  result.dofs = static_cast<int>(system.force.size());
  result.max_nitsche_penalty = system.max_nitsche_penalty;
  result.ghost_faces = system.ghost_faces;
  result.control_displacements.assign(system.node_of_control_point.size(), Eigen::Vector3d::Zero());
  result.active.assign(system.node_of_control_point.size(), false);
  for (size_t node = 0; node < system.control_point_of_node.size(); ++node) {
    const auto cp = static_cast<size_t>(system.control_point_of_node[node]);
    result.active[cp] = true;
    result.control_displacements[cp].head(system.dim) =
        u.segment(static_cast<Eigen::Index>(node) * system.dim, system.dim);
  }
  return result;
}

// Stage: per case the consistent load and the immersed solution, the reference. The supports
// and the material are the same in every case (checked), so the system (the stiffness with its
// Nitsche penalties' eigenvalue problems, most of the time) is assembled and factorised once, and
// each further case assembles its loads alone (assemble_immersed_loads: the vector
// assemble_immersed would give). The particles are the active control points.
void solve_references(const geometry::ImmersedDomain& domain,
                      const std::vector<ImmersedCalibrationCase>& cases,
                      const CalibrationSettings& settings, detail::ImmersedFit& fit,
                      ImmersedCalibrationResult& result) {
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Upper> cholesky;
  analysis::ImmersedSystem system;
  for (size_t c = 0; c < cases.size(); ++c) {
    if (settings.progress) settings.progress("immersed IGA reference: load case " + cases[c].id);
    auto start = std::chrono::steady_clock::now();
    double factorising = 0.0;  // a solve's time, not the assembly's
    if (c == 0) {
      // The reference factorises its own stiffness (once for every case), stabilised as
      // solve_immersed's: the ghost penalty widened where Cholesky finds it not positive definite.
      const auto factorise = [&cholesky, &factorising](const analysis::ImmersedSystem& candidate) {
        const auto begin = std::chrono::steady_clock::now();
        cholesky.compute(candidate.stiffness);
        factorising += seconds_since(begin);
        return cholesky.info() == Eigen::Success;
      };
      std::vector<std::string> warnings;
      system = analysis::assemble_stabilised_immersed(domain, cases[c].options, factorise, warnings,
                                                      "immersed calibration");
      for (const std::string& w : warnings)
        result.calibration.warnings.push_back("immersed IGA reference: " + w);
      fit.node_of_control_point = system.node_of_control_point;
      result.control_point_of_particle = system.control_point_of_node;
    } else {
      system.force = analysis::assemble_immersed_loads(domain, cases[c].options, system);
    }
    result.assembly_seconds += seconds_since(start) - factorising;
    result.calibration.reference_seconds += factorising;
    start = std::chrono::steady_clock::now();
    fit.loads.push_back(system.force);
    result.reference.push_back(immersed_solution(system, cholesky));
    result.reference.back().ghost_fraction = system.options.ghost_fraction;
    result.calibration.reference_seconds += seconds_since(start);
  }
}

// Stage: particles on the active control points, springs (and cell terms) on the complete cells
// of the background net, masses over the part.
SpringMesh immersed_spring_mesh(const geometry::ImmersedDomain& domain,
                                const analysis::ImmersedOptions& options,
                                const std::vector<int>& node_of_control_point,
                                const std::vector<int>& control_point_of_particle,
                                const SpringMeshOptions& mesh_options) {
  if (mesh_options.reach < 1 || mesh_options.reach > 2)
    fail("spring mesh: reach must be 1 (net cells) or 2");
  const analysis::Material& material = options.material;
  if (!(material.density > 0.0) || !std::isfinite(material.density))
    fail("material density = " + std::to_string(material.density) +
         ": the spring model needs a positive density for its masses");
  const nurbs::Patch& grid = domain.background;
  SpringMesh mesh;
  auto& net = mesh.network;
  net.dimension = domain.dimension;
  for (int cp : control_point_of_particle) net.positions.push_back(grid.control_point(cp));
  net.fixed.assign(net.positions.size(), false);
  mesh.particle = {node_of_control_point};
  detail::NetView view;
  for (int d = 0; d < grid.param_dim(); ++d) view.n[static_cast<size_t>(d)] = grid.num_points(d);
  view.particle = [&grid, &node_of_control_point](int i, int j, int k) {
    return node_of_control_point[static_cast<size_t>(grid.index(i, j, k))];
  };
  const double diagonal = detail::bounding_box_diagonal(net.positions);
  std::set<std::pair<int, int>> pairs;
  int collapsed = 0;
  detail::collect_block_pairs(view, mesh_options.reach, net.positions,
                              mesh_options.relative_tolerance * diagonal, pairs, collapsed);
  detail::add_springs(pairs, net);
  const double min_volume = 1e-12 * std::pow(diagonal, net.dimension);
  if (mesh_options.volume_terms)
    detail::add_net_cell_terms(view, analysis::CellEnergy::kVolume, min_volume, net);
  if (mesh_options.shear_terms)
    detail::add_net_cell_terms(view, analysis::CellEnergy::kShear, min_volume, net);
  const double thickness =
      options.formulation == analysis::Formulation::kSolid ? 1.0 : material.thickness;
  const std::vector<double> mass =
      analysis::immersed_lumped_mass(domain, material.density, thickness);
  for (int cp : control_point_of_particle) net.masses.push_back(mass[static_cast<size_t>(cp)]);
  return mesh;
}

// The coordinate axis of a symmetry face's normal; InputError when the face is not normal to one.
int symmetry_axis(const geometry::ImmersedDomain& domain, int face) {
  int axis = -1;
  for (const geometry::BoundaryPoint& b : domain.boundary) {
    if (b.face != face) continue;
    int here = -1;
    for (int c = 0; c < domain.dimension; ++c)
      if (std::abs(b.normal[c]) > 1.0 - 1e-9) here = c;
    if (here < 0 || (axis >= 0 && here != axis))
      fail("calibration: the symmetry support on face " + std::to_string(face) +
           " is not normal to a coordinate axis; the spring model holds displacement components, "
           "so give that face fixed components (\"fix\") or use a symmetry plane normal to x, y "
           "or z");
    axis = here;
  }
  return axis;
}

// Stage: the supported faces' particles held (fixed, or single components).
int hold_supports(const geometry::ImmersedDomain& domain, const analysis::ImmersedOptions& options,
                  const std::vector<int>& node_of_control_point, SpringMesh& mesh,
                  std::vector<int>& extra_constrained) {
  const int dim = domain.dimension;
  std::vector<int> particle_dofs;
  for (const analysis::ImmersedSupport& s : options.supports) {
    std::vector<bool> held(3, false);
    if (s.symmetry)
      held[static_cast<size_t>(symmetry_axis(domain, s.face))] = true;
    else
      for (int c = 0; c < dim; ++c) held[static_cast<size_t>(c)] = s.fixed[static_cast<size_t>(c)];
    for (int cp : analysis::immersed_face_control_points(domain, s.face)) {
      const int particle = node_of_control_point[static_cast<size_t>(cp)];
      if (particle < 0) continue;
      for (int c = 0; c < dim; ++c)
        if (held[static_cast<size_t>(c)]) particle_dofs.push_back(particle * dim + c);
    }
  }
  detail::hold_particle_dofs(particle_dofs, dim, mesh, extra_constrained);
  std::set<int> particles;
  for (int d : particle_dofs) particles.insert(d / dim);
  return static_cast<int>(particles.size());
}

// Stage: the fit's data (FitSetup as calibrate() fills it) from the references and loads.
void prepare_fit_data(const std::vector<ImmersedCalibrationCase>& cases,
                      const CalibrationSettings& settings, const ImmersedCalibrationResult& result,
                      const SpringMesh& mesh, detail::ImmersedFit& fit) {
  detail::FitSetup& setup = fit.setup;
  const int dim = setup.dim;
  const auto& particles = result.control_point_of_particle;
  setup.particle_of_node.resize(particles.size());
  for (size_t a = 0; a < particles.size(); ++a) setup.particle_of_node[a] = static_cast<int>(a);
  for (size_t c = 0; c < cases.size(); ++c) {
    analysis::LoadCaseResult reference;
    reference.id = cases[c].id;
    reference.displacement.resize(static_cast<Eigen::Index>(particles.size()) * dim);
    for (size_t a = 0; a < particles.size(); ++a)
      reference.displacement.segment(static_cast<Eigen::Index>(a) * dim, dim) =
          result.reference[c].control_displacements[static_cast<size_t>(particles[a])].head(dim);
    setup.reference.load_cases.push_back(std::move(reference));
    const bool holdout = contains(settings.holdout_cases, cases[c].id);
    const bool fitted =
        settings.fit_cases.empty() ? !holdout : contains(settings.fit_cases, cases[c].id);
    if (fitted)
      setup.fitted.push_back(static_cast<int>(c));
    else if (holdout)
      setup.held_out.push_back(static_cast<int>(c));
  }
  if (setup.fitted.empty())
    fail(
        "calibration: no load case left to fit; list some in calibration.fit_cases or remove "
        "them from holdout_cases");
  setup.loads = fit.loads;
  DisplacementFitData& data = setup.data;
  data.network = mesh.network;
  data.particle_of_node = setup.particle_of_node;
  for (int c : setup.fitted) {
    data.loads.push_back(setup.loads[static_cast<size_t>(c)]);
    data.references.push_back(setup.reference.load_cases[static_cast<size_t>(c)].displacement);
  }
}

}  // namespace

ImmersedCalibrationResult calibrate_immersed(const geometry::ImmersedDomain& domain,
                                             const std::vector<ImmersedCalibrationCase>& cases,
                                             const CalibrationSettings& settings) {
  check_settings(cases, settings);
  const analysis::ImmersedOptions& options = cases.front().options;
  ImmersedCalibrationResult result;
  CalibrationResult& calibration = result.calibration;
  detail::ImmersedFit fit(domain.dimension);
  solve_references(domain, cases, settings, fit, result);

  calibration.mesh = immersed_spring_mesh(domain, options, fit.node_of_control_point,
                                          result.control_point_of_particle, settings.mesh);
  check_step_budget(calibration.mesh.network, settings.max_step_us);
  result.held_particles = hold_supports(domain, options, fit.node_of_control_point,
                                        calibration.mesh, fit.setup.data.constrained_dofs);
  prepare_fit_data(cases, settings, result, calibration.mesh, fit);
  for (const auto& c : cases) calibration.load_ids.push_back(c.id);
  calibration.particle_loads = fit.setup.loads;

  const detail::FitBounds bounds{{}, detail::volume_term_bound(options.material, domain.dimension)};
  const auto start = std::chrono::steady_clock::now();
  detail::SweepOutcome sweep =
      detail::sweep_gammas(options.material, settings, calibration.mesh, fit.setup, bounds);
  calibration.fit_seconds = seconds_since(start);
  calibration.sweep = std::move(sweep.entries);
  calibration.fit_result = std::move(sweep.fit);
  calibration.grouping = std::move(sweep.grouping);
  calibration.gamma = sweep.gamma;
  detail::apply_fit(settings, calibration);
  detail::evaluate_immersed_cases(domain, cases, settings, fit, result);
  return result;
}

}  // namespace isospring::fitting
