#pragma once
// One ParaView file per run: a .vtm multiblock that references the pieces (sampled geometry,
// sampled outer surface, Bezier geometry, control net, spring network, markers), written into a
// folder beside it:
//
//   OUT/result.vtm
//   OUT/result/geometry_sampled.vtu  boundary_sampled.vtu  geometry_bezier.vtu  control_net.vtp
//              springs.vtp  markers.vtp
//
// Opening result.vtm in ParaView loads everything as one object with named blocks.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "isospring/analysis/spring_network.hpp"
#include "isospring/io/vtk_boundary.hpp"
#include "isospring/io/vtk_fields.hpp"
#include "isospring/io/vtk_markers.hpp"
#include "isospring/io/vtk_spring_network.hpp"
#include "isospring/nurbs/patch.hpp"

namespace isospring::io {

struct VtkBlock {
  std::string name;
  std::filesystem::path file;  // relative to the .vtm's folder
};

/// Writes a .vtm that references existing files (atomically).
void write_multiblock_vtm(const std::filesystem::path& path, const std::vector<VtkBlock>& blocks);

/// Everything one run can show. Empty parts are skipped.
struct VtkScene {
  std::vector<nurbs::Patch> patches;
  PatchFields fields;  // on the patches (control fields also go on the net and Bezier cells)
  int samples_per_element = 4;      // of the sampled geometry; 0: not written
  std::vector<PatchSide> boundary;  // sides sampled into boundary_sampled.vtu (none: not written)
  int boundary_samples_per_element = 4;
  bool bezier = true;       // also write the exact Bezier-cell geometry
  bool control_net = true;  // also write the control net
  std::optional<analysis::SpringNetwork> network;
  std::vector<PointVectors> network_vectors;  // e.g. displacement per load case
  std::optional<MarkerData> markers;
};

/// A file written and the wall time it took (its fields' evaluation included).
struct WrittenFile {
  std::filesystem::path path;
  double seconds = 0;
};

/// Writes the scene's pieces into `<vtm folder>/<vtm stem>/` and then the .vtm itself (last, so
/// it never references a missing piece). Returns every file written, the .vtm last; with
/// `timings`, also how long each took, in the same order.
std::vector<std::filesystem::path> write_vtk_scene(const std::filesystem::path& vtm,
                                                   const VtkScene& scene,
                                                   std::vector<WrittenFile>* timings = nullptr);

}  // namespace isospring::io
