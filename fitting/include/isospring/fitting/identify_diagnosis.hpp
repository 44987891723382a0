#pragma once
// A description of a residual (measured minus model marker displacements), for people deciding
// what the model misses:
//   per component   RMS of each displacement component
//   per load case   RMS, the load's size (norm of the nominal nodal load vector and its
//                   resultant) and their ratio; across >= 3 load cases, the correlation of RMS
//                   with load size (a residual that grows with the load is a model error, one
//                   that does not is a measurement artefact or noise)
//   spatial         share of the residual energy explained, per load case and component, by a
//                   constant and by linear functions of x, y (, z): rigid motions of the measuring
//                   frame and uniform strain errors live there, noise spreads evenly over all
//                   directions (pure noise puts about `noise_fraction` of its energy in them)
#include <Eigen/Core>
#include <string>
#include <vector>

namespace isospring::fitting {

struct ResidualCaseDescription {
  std::string id;
  int markers = 0;
  double rms = 0.0;                                         // [m]
  Eigen::Vector3d component_rms = Eigen::Vector3d::Zero();  // [m]
  double load_norm = 0.0;                                   // |f| of the nominal nodal load [N]
  Eigen::Vector3d resultant = Eigen::Vector3d::Zero();      // sum of the nominal nodal forces [N]
  double rms_per_load = 0.0;                                // rms / load_norm [m/N], 0 without load
};

struct ResidualDescription {
  int dimension = 3;
  double rms = 0.0;
  Eigen::Vector3d component_rms = Eigen::Vector3d::Zero();
  std::vector<ResidualCaseDescription> load_cases;
  double load_correlation = 0.0;   // Pearson, rms vs load_norm; NaN with fewer than 3 cases
  double constant_fraction = 0.0;  // energy share of per-case, per-component constants
  double linear_fraction = 0.0;    // further share of the linear terms
  double noise_fraction = 0.0;     // expected constant + linear share of pure noise (modes/rows)
  std::string summary;             // one sentence
};

/// `group[m]`: load case index of marker m (into `case_ids`, `case_loads`); `case_loads`: the
/// nominal nodal load vector per load case (DOF space, `dimension` components per node). Positions
/// are centred on `centre` and divided by `length` before fitting the linear modes.
ResidualDescription describe_residual(const std::vector<Eigen::Vector3d>& positions,
                                      const std::vector<Eigen::Vector3d>& residuals,
                                      const std::vector<int>& group,
                                      const std::vector<std::string>& case_ids,
                                      const std::vector<Eigen::VectorXd>& case_loads, int dimension,
                                      const Eigen::Vector3d& centre, double length);

}  // namespace isospring::fitting
