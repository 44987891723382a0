#pragma once
// The unseen-data suite of `isospring identify`: specimens, the effects hidden in each
// dataset and how CalculiX is told about them. Shared by the generator (writes the datasets with
// ccx) and the test (runs identify on them and compares with the truth stored beside the data).
//
// Every dataset is a declared case (what a user would write: nominal geometry, supports, loads,
// a Young's modulus 20-25 % off, a deliberately modest discretisation) plus markers computed by
// CalculiX on the TRUE problem: true modulus, the hidden effects, its own finer mesh of 20-node
// hexahedra (8-node quadrilaterals in 2D). Nothing of identify's model enters the data.
#include <Eigen/Core>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace isospring::identify_suite {

/// What is hidden in the data. The names are identify's effect names.
struct Hidden {
  bool gravity = false;      // self-weight, g = 9.81 m/s^2 (the case declares none)
  double soft_layer = 0.0;   // > 0: modulus factor of the first element slab at the clamp
  double gradient = 0.0;     // E(x) = E (1 + gradient (x_axis - centre) / length)
  double load_scale = 1.0;   // the second load case's actual load / its nominal load
  bool nonlinear = false;    // large deformation (ccx NLGEOM), loads raised by load_factor
  double load_factor = 1.0;  // all loads (declared and true) times this
  Eigen::Vector3d frame_translation = Eigen::Vector3d::Zero();  // measuring-frame motion [m]
  Eigen::Vector3d frame_rotation = Eigen::Vector3d::Zero();     // [rad] about the centre
};

/// A reference mesh finer where the solution varies fastest: spans of the truth mesh split before
/// the mesh check doubles every span. Splits are powers of 2, so every node of the uniform truth
/// mesh (the markers' positions) stays a node. Empty: the uniform truth mesh.
struct Grading {
  int clamp_spans = 0;     // spans next to the clamp (along the specimen's axis) split ...
  int clamp_splits = 1;    // ... into this many
  int lateral_splits = 1;  // the outermost span at each lateral face split into this many
  bool empty() const { return clamp_spans == 0 && lateral_splits == 1; }
};

struct Dataset {
  std::string name;
  std::string specimen;              // cantilever, plate_with_hole, tube
  std::vector<std::string> effects;  // the true effect set, as identify names them
  double noise_fraction = 2e-3;      // noise sigma / largest displacement
  unsigned seed = 1;
  Hidden hidden;
  std::string note;  // one line for the README
  /// Poisson's ratio, declared and true alike; 0: the specimen's own (0.3 or 0.35). The
  /// tissue-like datasets (soft tissue, gels, elastomers) use 0.45 and 0.49.
  double poisson_ratio = 0.0;
  /// The reference mesh graded towards the clamp where the uniform one fails its mesh check.
  Grading grading;
};

/// The suite: 14 datasets on three specimens, clean ones at two noise levels, and 18 tissue-like
/// cantilever datasets (nu = 0.45 and 0.49: every hidden effect, and two pairs of effects).
std::vector<Dataset> datasets();

/// A specimen: its declared case, its true problem and where its markers are.
struct Specimen {
  nlohmann::json declared;  // the case file without "measurements"
  double true_modulus = 0.0;
  std::vector<int> truth_elements;  // ccx mesh (per direction, every patch)
  int gradient_axis = 0;            // the axis the graded modulus and the soft layer vary along
  double slab = 0.0;                // soft layer: x_axis below this is the first element slab
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  // the hidden self-weight's g
  std::function<bool(const Eigen::Vector3d&)> is_marker;
  int stride = 1;
};

Specimen specimen(const std::string& name, const Hidden& hidden);

/// The dataset's specimen, with its Poisson's ratio.
Specimen specimen(const Dataset& dataset);

/// The candidates every dataset's case offers (all six of identify's library).
inline std::vector<std::string> candidate_effects() {
  return {"gravity",      "support_compliance", "stiffness_gradient",
          "rigid_offset", "load_scale",         "geometric_nonlinearity"};
}

}  // namespace isospring::identify_suite
