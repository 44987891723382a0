#pragma once
// A cantilever beam of spring particles for the large-rotation tests: nx x ny x nz particles at
// unit spacing, every particle to its 13 forward neighbours (cell edges, face and body
// diagonals: the NMSM topology of a regular net), stiffness `k` L0, masses `mass`, face x = 0
// fixed, 5 % damping ratio.
#include <Eigen/Geometry>
#include <cmath>

#include "isospring/analysis/spring_mechanics.hpp"
#include "isospring/analysis/spring_network.hpp"

namespace isospring::analysis {

inline SpringNetwork beam_lattice(int nx, int ny, int nz, double k, double mass) {
  SpringNetwork net;
  auto index = [nx, ny](int i, int j, int l) { return (l * ny + j) * nx + i; };
  for (int l = 0; l < nz; ++l)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        net.positions.emplace_back(i, j, l);
        net.masses.push_back(mass);
        net.fixed.push_back(i == 0);
      }
  for (int l = 0; l < nz; ++l)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (int dl = 0; dl <= 1; ++dl)
          for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
              const bool forward = dl > 0 || dj > 0 || (dj == 0 && di > 0);
              const int a = i + di, b = j + dj, c = l + dl;
              if (!forward || a < 0 || b < 0 || a >= nx || b >= ny || c >= nz) continue;
              Spring s;
              s.i = index(i, j, l);
              s.j = index(a, b, c);
              s.rest_length = std::sqrt(static_cast<double>(di * di + dj * dj + dl * dl));
              s.stiffness = k * s.rest_length;
              net.springs.push_back(s);
            }
  assign_damping_ratio(net, 0.05);
  return net;
}

// Load on the particles of the end face x = nx - 1: `bend` along -y on each, and a torque about
// the face's centre line (axis x): each particle pushed along x_hat x (p - centre) scaled by
// `twist`.
inline Eigen::VectorXd beam_tip_load(const SpringNetwork& net, double bend, double twist) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(net.positions.size()) * 3);
  double x_max = -1e300, y_max = 0.0, z_max = 0.0;
  for (const auto& p : net.positions) {
    x_max = std::max(x_max, p.x());
    y_max = std::max(y_max, p.y());
    z_max = std::max(z_max, p.z());
  }
  const Eigen::Vector3d centre(x_max, 0.5 * y_max, 0.5 * z_max);
  for (size_t q = 0; q < net.positions.size(); ++q) {
    if (net.positions[q].x() < x_max - 0.5) continue;
    const Eigen::Vector3d arm = net.positions[q] - centre;
    f.segment<3>(static_cast<Eigen::Index>(q) * 3) =
        Eigen::Vector3d(0.0, -bend, 0.0) + twist * Eigen::Vector3d::UnitX().cross(arm);
  }
  return f;
}

}  // namespace isospring::analysis
