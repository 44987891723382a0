#pragma once
// Time series for dynamic runs of the spring model: a ParaView .pvd collection of one .vtp per
// frame (the network at its deformed positions, with "displacement" and optional "velocity").
//
//   SpringTimeSeriesWriter series("out/dynamics.pvd", network);
//   for (...) series.add_frame(t, u, v);
//   series.finish();  // writes out/dynamics.pvd last, referencing out/dynamics/frame_000000.vtp...
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "isospring/analysis/spring_network.hpp"

namespace isospring::io {

struct PvdEntry {
  double time = 0;
  std::filesystem::path file;  // relative to the .pvd's folder
};

/// Writes a .pvd collection atomically.
void write_pvd(const std::filesystem::path& path, const std::vector<PvdEntry>& entries);

class SpringTimeSeriesWriter {
 public:
  SpringTimeSeriesWriter(std::filesystem::path pvd, analysis::SpringNetwork network);
  /// Writes one frame now; times must increase. `velocity` may be empty.
  void add_frame(double time, const std::vector<Eigen::Vector3d>& displacement,
                 const std::vector<Eigen::Vector3d>& velocity = {});
  /// Writes the .pvd; call once after the last frame.
  void finish();
  int frames() const { return static_cast<int>(entries_.size()); }

 private:
  std::filesystem::path pvd_;
  analysis::SpringNetwork network_;
  std::vector<PvdEntry> entries_;
};

}  // namespace isospring::io
