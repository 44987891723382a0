#pragma once
// A mass-spring network: the data a real-time engine needs. Built from a NURBS control net by the
// fitting module; its mechanics (forces, stiffness, integrators) live in the analysis module.
#include <Eigen/Core>
#include <vector>

namespace isospring::analysis {

struct Spring {
  int i = 0;  // particle indices, i < j
  int j = 0;
  double stiffness = 0.0;    // k [N/m]
  double damping = 0.0;      // c [N s/m], along the spring
  double rest_length = 0.0;  // L0 [m]
  int group = -1;            // calibration group (rest-length group), -1 when ungrouped
};

struct SpringNetwork {
  std::vector<Eigen::Vector3d> positions;  // rest positions [m]
  std::vector<double> masses;              // [kg]
  std::vector<bool> fixed;                 // particle held in place
  std::vector<Spring> springs;
  int dimension = 3;  // 2 for in-plane models (z ignored)
};

}  // namespace isospring::analysis
