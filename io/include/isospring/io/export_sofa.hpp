#pragma once
// SOFA export (scene .scn XML, written for SOFA v22.12): the spring model as
//
//   <Node name="root" gravity=... dt=...>
//     <RequiredPlugin .../>                      the v22.12 component modules used below
//     <Node name="SpringModel">
//       <EulerImplicitSolver/> <CGLinearSolver/>
//       <MechanicalObject name="particles" template="Vec3d" (Vec2d in 2D) position="x y z ..."/>
//       <MeshTopology name="topology" edges="i j ..."/>        (the springs as edges)
//       <UniformMass vertexMass=m/> when every free particle has the same mass, else
//       <DiagonalMass vertexMass="m0 m1 ..." topology="@topology"/>
//       <StiffSpringForceField spring="i j ks kd L0  i j ks kd L0 ..."/>   0-based indices
//       <FixedConstraint indices="..."/>          (FixedProjectiveConstraint from SOFA v23.12)
//
// Numbers are written with 17 significant digits, so the scene reproduces the model exactly.
#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "isospring/analysis/spring_network.hpp"

namespace isospring::io {

struct SofaOptions {
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};  // [m/s^2]
  double timestep = 0.0;                     // [s]; 0 = suggested_timestep() of the MJCF export
  std::string comment;                       // provenance written as an XML comment
};

/// The scene document. Throws nurbs::InputError when the network is invalid or a flat (2D)
/// network, whose Vec2d particles move in x-y only, is given a gravity with a z component
/// (io::engine_gravity in export_mjcf.hpp gives such models an in-plane default).
std::string sofa_scene(const analysis::SpringNetwork& network, const SofaOptions& options = {});

/// Writes the scene atomically.
void write_sofa_scene(const std::filesystem::path& path, const analysis::SpringNetwork& network,
                      const SofaOptions& options = {});

}  // namespace isospring::io
