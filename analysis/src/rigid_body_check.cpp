// Which rigid-body motions do the supports leave free? Checked per connected part of the model
// before factorising, so the user gets a sentence instead of a failed Cholesky.
#include <Eigen/Dense>
#include <algorithm>
#include <numeric>
#include <set>
#include <sstream>

#include "isospring/analysis/constraints.hpp"
#include "isospring/nurbs/error.hpp"
#include "rigid_modes.hpp"

namespace isospring::analysis {

namespace {

int find_root(std::vector<int>& parent, int i) {
  while (parent[static_cast<size_t>(i)] != i)
    i = parent[static_cast<size_t>(i)] =
        parent[static_cast<size_t>(parent[static_cast<size_t>(i)])];
  return i;
}

}  // namespace

void check_rigid_body_modes(const Problem& problem, const DofMap& dofs,
                            const Constraints& constraints) {
  if (!dofs.unglued_interfaces().empty()) {
    // A patch side lying on another one without shared control points: the parts would move
    // independently there, a silently wrong answer rather than a singular system.
    const auto side = [](int dir, int end) {
      return std::string(1, "uvw"[dir]) + (end ? "1" : "0");
    };
    const DofMap::UngluedInterface& f = dofs.unglued_interfaces().front();
    std::ostringstream message;
    message << "patch " << f.patch_a << " side " << side(f.dir_a, f.end_a) << " and patch "
            << f.patch_b << " side " << side(f.dir_b, f.end_b) << " lie on each other but their "
            << "control points differ (" << dofs.unglued_interfaces().size()
            << " such interface(s)): the knots or degrees along the interface do not match, so "
               "the patches would not be joined there. Refine every patch alike: the same "
               "\"degree\" and \"elements\" in every direction (one number each), which keeps "
               "conforming interfaces conforming";
    throw nurbs::InputError(message.str());
  }
  const int dim = dofs.dofs_per_node();
  const int num_patches = dofs.num_patches();
  // Patches sharing a node move together.
  std::vector<int> parent(static_cast<size_t>(num_patches));
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<int> owner(static_cast<size_t>(dofs.num_nodes()), -1);
  for (int p = 0; p < num_patches; ++p)
    for (int node : dofs.patch_nodes(p)) {
      int& o = owner[static_cast<size_t>(node)];
      if (o < 0)
        o = p;
      else
        parent[static_cast<size_t>(find_root(parent, p))] = find_root(parent, o);
    }
  std::vector<char> constrained(static_cast<size_t>(dofs.num_dofs()), 0);
  for (int d : constraints.dofs) constrained[static_cast<size_t>(d)] = 1;

  const int num_modes = dim == 2 ? 3 : 6;
  for (int root = 0; root < num_patches; ++root) {
    if (find_root(parent, root) != root) continue;
    std::set<int> nodes;
    std::vector<int> patches;
    for (int p = 0; p < num_patches; ++p)
      if (find_root(parent, p) == root) {
        patches.push_back(p);
        nodes.insert(dofs.patch_nodes(p).begin(), dofs.patch_nodes(p).end());
      }
    // Rigid motions in coordinates centred and scaled by the part's size, so every entry is O(1).
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (int n : nodes) {
      lo = lo.cwiseMin(dofs.node_positions()[static_cast<size_t>(n)]);
      hi = hi.cwiseMax(dofs.node_positions()[static_cast<size_t>(n)]);
    }
    const Eigen::Vector3d centre = 0.5 * (lo + hi);
    const double size = std::max((hi - lo).norm(), 1e-300);
    // Gram matrix of the rigid modes restricted to the constrained DOFs.
    Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(num_modes, num_modes);
    for (int n : nodes) {
      const Eigen::Vector3d x = (dofs.node_positions()[static_cast<size_t>(n)] - centre) / size;
      for (int c = 0; c < dim; ++c) {
        if (!constrained[static_cast<size_t>(n * dim + c)]) continue;
        const Eigen::VectorXd row = detail::rigid_mode_row(x, c, dim);
        gram.noalias() += row * row.transpose();
      }
    }
    std::ostringstream owner;
    owner << "patch" << (patches.size() > 1 ? "es" : "");
    for (size_t k = 0; k < patches.size(); ++k) owner << (k ? ", " : " ") << patches[k];
    detail::throw_if_rigid_modes_free(gram, dim, owner.str(), "fixed components or symmetry sides");
  }
  (void)problem;
}

namespace detail {

Eigen::VectorXd rigid_mode_row(const Eigen::Vector3d& x, int c, int dim) {
  Eigen::VectorXd row = Eigen::VectorXd::Zero(dim == 2 ? 3 : 6);
  row[c] = 1.0;  // translation along c
  if (dim == 2) {
    row[2] = c == 0 ? -x.y() : x.x();  // rotation about z: (-y, x)
    return row;
  }
  // rotation about axis r: (e_r x x)_c
  const Eigen::Matrix3d rot = (Eigen::Matrix3d() << 0, -x.z(), x.y(),  // about x
                               x.z(), 0, -x.x(),                       // about y
                               -x.y(), x.x(), 0)                       // about z
                                  .finished();
  for (int r = 0; r < 3; ++r) row[3 + r] = rot(r, c);
  return row;
}

void throw_if_rigid_modes_free(const Eigen::MatrixXd& gram, int dim, const std::string& owner,
                               const std::string& remedy) {
  const int num_modes = dim == 2 ? 3 : 6;
  const std::vector<std::string> names =
      dim == 2
          ? std::vector<std::string>{"translation x", "translation y", "rotation about z"}
          : std::vector<std::string>{"translation x",    "translation y",    "translation z",
                                     "rotation about x", "rotation about y", "rotation about z"};
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);
  const double tolerance = 1e-10 * std::max(1.0, eigen.eigenvalues().maxCoeff());
  std::vector<Eigen::VectorXd> free_modes;
  for (int k = 0; k < num_modes; ++k)
    if (eigen.eigenvalues()[k] <= tolerance) free_modes.push_back(eigen.eigenvectors().col(k));
  if (free_modes.empty()) return;
  // Name the free motions by the pivots of the null space's reduced row echelon form, taking
  // rotation columns first: a rotation about some point is a rotation plus translations and is
  // named by its rotation; a null vector without rotation is a translation.
  Eigen::MatrixXd basis(static_cast<Eigen::Index>(free_modes.size()), num_modes);
  for (size_t k = 0; k < free_modes.size(); ++k)
    basis.row(static_cast<Eigen::Index>(k)) = free_modes[k].transpose();
  const int translations = dim;
  std::vector<int> column_order;
  for (int c = translations; c < num_modes; ++c) column_order.push_back(c);
  for (int c = 0; c < translations; ++c) column_order.push_back(c);
  std::vector<int> pivots;
  Eigen::Index r = 0;
  for (int c : column_order) {
    if (r >= basis.rows()) break;
    Eigen::Index pivot;
    const double largest = basis.col(c).tail(basis.rows() - r).cwiseAbs().maxCoeff(&pivot);
    if (largest < 1e-6) continue;
    basis.row(r).swap(basis.row(r + pivot));
    basis.row(r) /= basis(r, c);
    for (Eigen::Index i = 0; i < basis.rows(); ++i)
      if (i != r) basis.row(i) -= basis(i, c) * basis.row(r);
    pivots.push_back(c);
    ++r;
  }
  std::sort(pivots.begin(), pivots.end());
  std::vector<std::string> free_names;
  for (int c : pivots) free_names.push_back(names[static_cast<size_t>(c)]);
  std::ostringstream message;
  message << "the supports leave free: ";
  for (size_t k = 0; k < free_names.size(); ++k) message << (k ? ", " : "") << free_names[k];
  message << " (rigid-body motion of " << owner << "); add supports (" << remedy << ") that block "
          << (free_names.size() > 1 ? "these motions" : "this motion");
  throw nurbs::InputError(message.str());
}

}  // namespace detail

}  // namespace isospring::analysis
