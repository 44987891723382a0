#pragma once
// MuJoCo export (MJCF XML, checked with MuJoCo 2.2.2): the spring model as MuJoCo bodies and
// tendons, so MuJoCo reproduces the model's statics and dynamics.
//
//  - every free particle i is a body "particle_i" at its rest position with an explicit point
//    mass (<inertial>; a contact-free sphere geom shows it) and slide joints "particle_i_x",
//    "_y" (and "_z" in 3D): its generalized coordinates are exactly its displacement;
//  - a fixed particle is a site in <worldbody> (welded to the world, no joints);
//  - every spring s is a spatial tendon "spring_s" between the two particles' sites with
//    stiffness k, damping c and springlength L0: MuJoCo's tendon force -k (L - L0) - c dL/dt is
//    the model's spring force;
//  - volume, shear and strain-point terms (SpringNetwork::volumes), which MuJoCo has no element
//    for, stay in a model.json next to the scene (write_mjcf writes it, "<stem>.isospring.json",
//    named in the scene's <custom><text name="isospring_model">): an engine evaluates them with
//    the isospring runtime (runtime/include/isospring/runtime/runtime.h) in MuJoCo's
//    passive-force callback mjcb_passive, springs masked out (examples/mujoco);
//  - contacts are disabled; gravity and the time step are options.
//  - a flat (2D) model has slide joints in x and y only: gravity along z could never move it, so
//    such a document is refused (engine_gravity() gives 2D models an in-plane default, -y).
#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>

#include "isospring/analysis/spring_network.hpp"

namespace isospring::io {

struct MjcfOptions {
  std::string model_name = "isospring_spring_model";
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};  // [m/s^2]
  /// [s]; 0 chooses 0.2 x the explicit stability limit 2 / omega_max, with omega_max^2 bounded
  /// by Gershgorin: max over particles of 2 sum(k of its springs) / mass.
  double timestep = 0.0;
  /// Sphere radius shown for particles [m]; 0 chooses 10% of the shortest rest length.
  double particle_radius = 0.0;
  bool implicit_integrator = true;  // MuJoCo's "implicit" integrator (damping implicit)
  std::string comment;              // provenance written as an XML comment
  /// File name (relative to the scene) of the model.json that carries the network's volume,
  /// shear and strain-point terms for the runtime; write_mjcf sets it. Required when the network
  /// has such terms, unused otherwise.
  std::string runtime_model;
  /// > 0: every slide joint gets damping = rate x particle mass [N s/m] (a drag towards rest
  /// velocity, absent at equilibrium), so that a static load settles in a few of the slowest
  /// periods; 0: only the springs' own damping.
  double particle_damping_rate = 0.0;
};

/// The gravity an engine export (MuJoCo, SOFA) of `network` should carry: `given` when set; else
/// `model_gravity` when it is non-zero (a model.json with "gravity"); else 9.81 m/s^2 along -z for
/// a 3D model and along -y for a flat (2D) one, whose particles move in the x-y plane only.
/// Throws nurbs::InputError when a 2D model would get a gravity with a z component (it would
/// never move under it), naming the fix.
Eigen::Vector3d engine_gravity(const analysis::SpringNetwork& network,
                               const Eigen::Vector3d& model_gravity,
                               const std::optional<Eigen::Vector3d>& given);

/// The automatic time step described at MjcfOptions::timestep. With volume, shear or
/// strain-point terms the bound on omega_max^2 is Gershgorin's on M^-1 K of the whole rest
/// stiffness (analysis::rest_stiffness): max over DOFs of sum_j |K_ij| / m_i.
double suggested_timestep(const analysis::SpringNetwork& network);

/// The MJCF document. Throws nurbs::InputError when the network is invalid, a 2D network is
/// given a gravity with a z component, or the network has volume, shear or strain-point terms
/// and options.runtime_model does not name the file that carries them.
std::string mjcf_document(const analysis::SpringNetwork& network, const MjcfOptions& options = {});

/// Writes the MJCF file atomically; with volume, shear or strain-point terms first the model.json
/// that carries them next to it ("<stem>.isospring.json", also atomically).
void write_mjcf(const std::filesystem::path& path, const analysis::SpringNetwork& network,
                const MjcfOptions& options = {});

}  // namespace isospring::io
