// analyze's ParaView output (analyze_vtk.hpp). In 3D the default is what stays in proportion to
// the model: the exact Bezier volume (one cell per element, the displacement exact) and the
// outer surface sampled with the stresses; a sampled volume (samples^3 linear cells per element,
// 2.1 M cells and 220 MB for a 32^3 model at 4) only on request.
#include "analyze_vtk.hpp"

#include "isospring/io/vtk_boundary.hpp"
#include "isospring/io/vtk_multiblock.hpp"
#include "isospring/io/vtk_solution.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;

int sampled_volume_samples(const AnalyzeCommandOptions& options, const Case& c) {
  const int asked = options.vtk_samples >= 0 ? options.vtk_samples : c.vtk_samples;
  if (asked >= 0) return asked;
  return c.dimension == 2 ? 4 : 0;
}

namespace detail {

bool analyze_writes_vtk(const AnalyzeCommandOptions& options, const Case& c) {
  return (options.vtk_samples >= 0 ? options.vtk_samples : c.vtk_samples) != 0;
}

std::string write_analyze_vtk(const AnalyzeCommandResult& r, const AnalyzeCommandOptions& options,
                              const std::filesystem::path& out_dir, AnalyzeTimings& timings) {
  const Case& c = r.c;
  VtkScene scene;
  scene.patches = c.problem.patches;
  scene.fields = solution_fields(c.problem, r.result.load_cases);
  scene.samples_per_element = sampled_volume_samples(options, c);
  if (c.dimension == 3) {
    scene.boundary = outer_sides(c.problem);
    scene.boundary_samples_per_element = boundary_samples(c.problem.patches, scene.boundary);
  }
  std::vector<WrittenFile> written;
  write_vtk_scene(out_dir / "result.vtm", scene, &written);
  for (const WrittenFile& file : written) {
    std::error_code error;
    const std::uintmax_t bytes = std::filesystem::file_size(file.path, error);
    timings.outputs.push_back({std::filesystem::relative(file.path, out_dir).generic_string(),
                               file.seconds, error ? 0 : bytes});
  }
  std::string text =
      "ParaView: open `result.vtm`: the exact geometry as Bezier cells with "
      "`displacement_<id>` (block `geometry_bezier`), the control net";
  if (!scene.boundary.empty())
    text += ", the outer surface sampled " + std::to_string(scene.boundary_samples_per_element) +
            " x per element (block `boundary`)";
  if (scene.samples_per_element > 0)
    text += std::string(", the ") + (c.dimension == 3 ? "volume" : "geometry") + " sampled " +
            std::to_string(scene.samples_per_element) + " x per element (block `geometry`)";
  text +=
      "; the sampled blocks carry `displacement_<id>`, `stress_<id>`, `von_mises_<id>` and "
      "`strain_energy_density_<id>` per load case.";
  if (c.dimension == 3 && scene.samples_per_element == 0)
    text += " `--vtk-samples N` adds the volume sampled N x per element.";
  return text;
}

}  // namespace detail
}  // namespace isospring::workflows
