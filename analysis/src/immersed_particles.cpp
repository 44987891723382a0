// Masses, held control points and field values of immersed domains for spring models (see
// immersed_particles.hpp).
#include "isospring/analysis/immersed_particles.hpp"

#include <algorithm>
#include <string>

#include "immersed_basis.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {

namespace {

// The smallest value a basis function must reach on a supported face to be held. Not any
// non-zero value: OpenCascade's bounding box, and so the background box, is enlarged by the
// edges' tolerance (1e-7 m), so a face meant to lie on the box's boundary lies that far inside
// the first cell, where the next layer's quadratic functions are ~2 d / h ~ 1e-4 instead of 0. A
// function reaching 1e-3 of its peak lies at least ~5e-4 cells into the face (degree 2), a real
// overlap; below that, round-off-sized offsets would decide which layers are held.
constexpr double kHeldShare = 1e-3;

}  // namespace

std::vector<double> immersed_lumped_mass(const geometry::ImmersedDomain& domain, double density,
                                         double thickness) {
  const detail::BackgroundBasis basis(domain);
  std::vector<double> mass(static_cast<size_t>(domain.background.num_points()), 0.0);
  detail::BasisAt at;
  for (const geometry::ImmersedCell& cell : domain.cells) {
    if (cell.points.empty()) continue;
    // The cell's element from its centroid, as the assembly picks it (points may lie on the
    // element's closure, where the neighbour's basis would be picked).
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& x : cell.points) centroid += x;
    const detail::Element e = basis.element_of(centroid / static_cast<double>(cell.points.size()));
    for (size_t q = 0; q < cell.points.size(); ++q) {
      basis.evaluate(e, cell.points[q], at);
      const double w = density * thickness * cell.weights[q];
      for (size_t a = 0; a < at.control_points.size(); ++a)
        mass[static_cast<size_t>(at.control_points[a])] +=
            w * at.values[static_cast<Eigen::Index>(a)];
    }
  }
  return mass;
}

std::vector<int> immersed_face_control_points(const geometry::ImmersedDomain& domain, int face) {
  const detail::BackgroundBasis basis(domain);
  std::vector<char> held(static_cast<size_t>(domain.background.num_points()), 0);
  detail::BasisAt at;
  bool found = false;
  for (const geometry::BoundaryPoint& b : domain.boundary) {
    if (b.face != face) continue;
    found = true;
    basis.evaluate(basis.element_of(b.point), b.point, at);
    for (size_t a = 0; a < at.control_points.size(); ++a)
      if (at.values[static_cast<Eigen::Index>(a)] >= kHeldShare)
        held[static_cast<size_t>(at.control_points[a])] = 1;
  }
  if (!found)
    throw nurbs::InputError("immersed domain: no boundary point lies on face " +
                            std::to_string(face) + "; the part has faces 0.." +
                            std::to_string(domain.face_count - 1));
  std::vector<int> result;
  for (size_t a = 0; a < held.size(); ++a)
    if (held[a]) result.push_back(static_cast<int>(a));
  return result;
}

std::vector<Eigen::Vector3d> evaluate_immersed_field(const geometry::ImmersedDomain& domain,
                                                     const std::vector<Eigen::Vector3d>& values,
                                                     const std::vector<Eigen::Vector3d>& points) {
  if (values.size() != static_cast<size_t>(domain.background.num_points()))
    throw nurbs::InputError("immersed field: " + std::to_string(values.size()) +
                            " control-point values for a background of " +
                            std::to_string(domain.background.num_points()) + " control points");
  const detail::BackgroundBasis basis(domain, false);
  std::vector<Eigen::Vector3d> result;
  result.reserve(points.size());
  detail::BasisAt at;
  for (const Eigen::Vector3d& x : points) {
    basis.evaluate(basis.element_of(x), x, at);
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    for (size_t a = 0; a < at.control_points.size(); ++a)
      u += at.values[static_cast<Eigen::Index>(a)] *
           values[static_cast<size_t>(at.control_points[a])];
    result.push_back(u);
  }
  return result;
}

}  // namespace isospring::analysis
