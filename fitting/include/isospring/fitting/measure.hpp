#pragma once
// Measured marker displacements and their placement on the model (closest point on the patches).
//
// A marker is one measured point of one load case: its position in the undeformed configuration
// and its displacement, in metres. The CSV reader (io/markers.hpp) produces these; the
// identification loop (identify.hpp) consumes them.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "isospring/nurbs/patch.hpp"

namespace isospring::fitting {

struct Marker {
  std::string load_case;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();      // [m], z = 0 in 2D
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();  // [m], uz = 0 in 2D
  double sigma = 0.0;  // [m] per-marker noise standard deviation; 0 when not given
  int row = 0;         // 1-based line of the data file, for messages
};

struct Measurements {
  std::string source;  // the data file, as named in messages
  int dimension = 3;   // 2: only x and y (and ux, uy) are meaningful
  std::vector<Marker> markers;
};

/// Where a marker sits on the model.
struct MarkerPlacement {
  int patch = -1;
  nurbs::Param param{0.0, 0.0, 0.0};
  double distance = 0.0;  // from the marker to its closest model point [m]
};

struct PlacementResult {
  std::vector<MarkerPlacement> placements;  // one per marker (also for those outside)
  std::vector<int> outside;                 // indices of markers farther than the tolerance
};

/// Closest point of every marker over all patches (nurbs::invert_point; markers at the same
/// position are placed once). A marker is outside when its distance exceeds `tolerance` [m].
PlacementResult place_markers(const std::vector<nurbs::Patch>& patches,
                              const std::vector<Marker>& markers, double tolerance);

}  // namespace isospring::fitting
