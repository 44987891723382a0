#include "isospring/io/export_sofa.hpp"

#include <algorithm>
#include <sstream>
#include <vector>

#include "export_xml.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/export_mjcf.hpp"
#include "isospring/io/model_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {

std::string sofa_scene(const analysis::SpringNetwork& network, const SofaOptions& options) {
  if (const std::string problem = check_spring_network(network); !problem.empty())
    throw nurbs::InputError("cannot export to SOFA: the spring model is invalid: " + problem);
  if (!network.volumes.empty())
    throw nurbs::InputError(
        "cannot export to SOFA: the spring model has " + detail::cell_terms(network) +
        " (calibration.volume_terms, shear_terms) and SOFA v22.12 has no force field for the "
        "volume or mean-strain shear energy of a trilinear cell (StiffSpringForceField is central "
        "springs only); export "
        "model.json (which carries "
        "them, and which `isospring simulate` runs) or calibrate with volume_terms and shear_terms "
        "off for a "
        "plain spring model");
  if (network.dimension == 2 && options.gravity.z() != 0.0)
    throw nurbs::InputError(
        "cannot export a flat (2D) spring model to SOFA with gravity along z: its Vec2d particles "
        "move in x and y only and would never move; give an in-plane gravity (e.g. 0,-9.81,0, the "
        "default of `isospring export` for 2D models)");
  using detail::number;
  const bool planar = network.dimension == 2;
  const double timestep = options.timestep > 0 ? options.timestep : suggested_timestep(network);

  std::vector<double> positions, free_masses;
  std::vector<double> all_masses(network.masses.begin(), network.masses.end());
  std::string fixed;
  for (size_t p = 0; p < network.positions.size(); ++p) {
    for (int c = 0; c < (planar ? 2 : 3); ++c) positions.push_back(network.positions[p](c));
    if (network.fixed[p]) {
      fixed += (fixed.empty() ? "" : " ") + std::to_string(p);
    } else {
      free_masses.push_back(network.masses[p]);
    }
  }
  // A fixed particle never moves, so its mass only matters for a uniform-mass shortcut: give it
  // the common value when every free particle has the same mass.
  const bool uniform =
      !free_masses.empty() && std::all_of(free_masses.begin(), free_masses.end(),
                                          [&](double m) { return m == free_masses.front(); });

  std::ostringstream edges, springs;
  for (size_t s = 0; s < network.springs.size(); ++s) {
    const analysis::Spring& spring = network.springs[s];
    edges << (s ? "  " : "") << spring.i << ' ' << spring.j;
    springs << (s ? "  " : "") << spring.i << ' ' << spring.j << ' ' << number(spring.stiffness)
            << ' ' << number(spring.damping) << ' ' << number(spring.rest_length);
  }

  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n"
      << "<!-- Exported by isospring from a spring model (model.json schema version 1).\n"
      << "     Written for SOFA v22.12 (component names of that release; from v23.12\n"
      << "     FixedConstraint is called FixedProjectiveConstraint). Indices are 0-based;\n"
      << "     spring = \"i j stiffness damping rest_length\" per spring. -->\n";
  if (!options.comment.empty()) out << "<!-- " << detail::xml_comment(options.comment) << " -->\n";
  out << "<Node name=\"root\" gravity=\"" << detail::vector3(options.gravity) << "\" dt=\""
      << number(timestep) << "\">\n";
  for (const char* plugin :
       {"Sofa.Component.StateContainer", "Sofa.Component.Mass",
        "Sofa.Component.SolidMechanics.Spring", "Sofa.Component.Constraint.Projective",
        "Sofa.Component.ODESolver.Backward", "Sofa.Component.LinearSolver.Iterative",
        "Sofa.Component.Topology.Container.Constant"})
    out << "  <RequiredPlugin name=\"" << plugin << "\"/>\n";
  out << "  <Node name=\"SpringModel\">\n"
      << "    <EulerImplicitSolver name=\"odesolver\" rayleighStiffness=\"0\" "
         "rayleighMass=\"0\"/>\n"
      << "    <CGLinearSolver name=\"linearsolver\" iterations=\"1000\" tolerance=\"1e-12\" "
         "threshold=\"1e-18\"/>\n"
      << "    <MechanicalObject name=\"particles\" template=\"" << (planar ? "Vec2d" : "Vec3d")
      << "\" position=\"" << detail::numbers(positions) << "\"/>\n"
      << "    <MeshTopology name=\"topology\" edges=\"" << edges.str() << "\"/>\n";
  if (uniform)
    out << "    <UniformMass name=\"mass\" vertexMass=\"" << number(free_masses.front())
        << "\"/>\n";
  else
    out << "    <DiagonalMass name=\"mass\" topology=\"@topology\" vertexMass=\""
        << detail::numbers(all_masses) << "\"/>\n";
  out << "    <StiffSpringForceField name=\"springs\" spring=\"" << springs.str() << "\"/>\n";
  if (!fixed.empty()) out << "    <FixedConstraint name=\"fixed\" indices=\"" << fixed << "\"/>\n";
  out << "  </Node>\n</Node>\n";
  return out.str();
}

void write_sofa_scene(const std::filesystem::path& path, const analysis::SpringNetwork& network,
                      const SofaOptions& options) {
  write_file_atomically(path, sofa_scene(network, options));
}

}  // namespace isospring::io
