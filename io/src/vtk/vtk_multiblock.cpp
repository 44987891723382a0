#include "isospring/io/vtk_multiblock.hpp"

#include <chrono>
#include <functional>
#include <ostream>

#include "export_xml.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/vtk_control_net.hpp"
#include "isospring/io/vtk_patches.hpp"

namespace isospring::io {
namespace fs = std::filesystem;

using detail::xml_escape;

void write_multiblock_vtm(const fs::path& path, const std::vector<VtkBlock>& blocks) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
        << "  <vtkMultiBlockDataSet>\n";
    for (size_t b = 0; b < blocks.size(); ++b)
      out << "    <DataSet index=\"" << b << "\" name=\"" << xml_escape(blocks[b].name)
          << "\" file=\"" << xml_escape(blocks[b].file.generic_string()) << "\"/>\n";
    out << "  </vtkMultiBlockDataSet>\n</VTKFile>\n";
  });
}

std::vector<fs::path> write_vtk_scene(const fs::path& vtm, const VtkScene& scene,
                                      std::vector<WrittenFile>* timings) {
  const fs::path folder = vtm.parent_path();
  const fs::path pieces = vtm.stem();  // relative to folder
  std::vector<VtkBlock> blocks;
  std::vector<fs::path> written;
  // Writes one piece through `write` and records it (block, path, seconds).
  auto add = [&](const std::string& name, const std::string& file,
                 const std::function<void(const fs::path&)>& write) {
    const auto start = std::chrono::steady_clock::now();
    write(folder / pieces / file);
    blocks.push_back({name, pieces / file});
    written.push_back(folder / pieces / file);
    if (timings)
      timings->push_back(
          {written.back(),
           std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
  };
  if (!scene.patches.empty()) {
    if (scene.samples_per_element > 0)
      add("geometry", "geometry_sampled.vtu", [&](const fs::path& path) {
        write_patches_sampled_vtu(path, scene.patches, scene.fields, scene.samples_per_element);
      });
    if (!scene.boundary.empty())
      add("boundary", "boundary_sampled.vtu", [&](const fs::path& path) {
        write_boundary_sampled_vtu(path, scene.patches, scene.boundary, scene.fields,
                                   scene.boundary_samples_per_element);
      });
    if (scene.bezier)
      add("geometry_bezier", "geometry_bezier.vtu", [&](const fs::path& path) {
        write_patches_bezier_vtu(path, scene.patches, scene.fields.control);
      });
    if (scene.control_net)
      add("control_net", "control_net.vtp", [&](const fs::path& path) {
        write_control_net_vtp(path, scene.patches, scene.fields.control);
      });
  }
  if (scene.network)
    add("springs", "springs.vtp", [&](const fs::path& path) {
      write_spring_network_vtp(path, *scene.network, scene.network_vectors);
    });
  if (scene.markers)
    add("markers", "markers.vtp",
        [&](const fs::path& path) { write_markers_vtp(path, *scene.markers); });
  const auto start = std::chrono::steady_clock::now();
  write_multiblock_vtm(vtm, blocks);
  written.push_back(vtm);
  if (timings)
    timings->push_back(
        {vtm, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()});
  return written;
}

}  // namespace isospring::io
