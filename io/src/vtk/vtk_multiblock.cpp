#include "isospring/io/vtk_multiblock.hpp"

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

std::vector<fs::path> write_vtk_scene(const fs::path& vtm, const VtkScene& scene) {
  const fs::path folder = vtm.parent_path();
  const fs::path pieces = vtm.stem();  // relative to folder
  std::vector<VtkBlock> blocks;
  std::vector<fs::path> written;
  auto add = [&](const std::string& name, const std::string& file) {
    blocks.push_back({name, pieces / file});
    written.push_back(folder / pieces / file);
    return folder / pieces / file;
  };
  if (!scene.patches.empty()) {
    write_patches_sampled_vtu(add("geometry", "geometry_sampled.vtu"), scene.patches, scene.fields,
                              scene.samples_per_element);
    if (scene.bezier)
      write_patches_bezier_vtu(add("geometry_bezier", "geometry_bezier.vtu"), scene.patches,
                               scene.fields.control);
    if (scene.control_net)
      write_control_net_vtp(add("control_net", "control_net.vtp"), scene.patches,
                            scene.fields.control);
  }
  if (scene.network)
    write_spring_network_vtp(add("springs", "springs.vtp"), *scene.network, scene.network_vectors);
  if (scene.markers) write_markers_vtp(add("markers", "markers.vtp"), *scene.markers);
  write_multiblock_vtm(vtm, blocks);
  written.push_back(vtm);
  return written;
}

}  // namespace isospring::io
