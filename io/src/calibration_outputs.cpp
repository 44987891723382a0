#include "isospring/io/calibration_outputs.hpp"

#include <map>

#include "isospring/analysis/dof_map.hpp"
#include "isospring/io/plot.hpp"
#include "isospring/io/vtk_multiblock.hpp"

namespace isospring::io {
namespace {
using Field = std::vector<std::vector<Eigen::Vector3d>>;  // [patch][control point]

/// A per-node vector (DofMap numbering) as a per-control-point field.
Field node_to_control(const analysis::DofMap& dofs, const std::vector<Eigen::Vector3d>& nodes) {
  Field out(static_cast<size_t>(dofs.num_patches()));
  for (int p = 0; p < dofs.num_patches(); ++p)
    for (int n : dofs.patch_nodes(p)) out[static_cast<size_t>(p)].push_back(nodes[n]);
  return out;
}
}  // namespace

CalibrationOutputs write_calibration_outputs(const std::filesystem::path& out_dir,
                                             const analysis::Problem& problem,
                                             const fitting::CalibrationResult& result,
                                             const std::vector<Field>& reference) {
  const analysis::DofMap dofs(problem);
  const analysis::SpringNetwork& network = result.mesh.network;
  const std::vector<int> particle = fitting::particle_of_node(problem, result.mesh);
  std::map<std::string, size_t> case_index;
  for (size_t k = 0; k < problem.load_cases.size(); ++k) case_index[problem.load_cases[k].id] = k;

  VtkScene scene;
  scene.patches = problem.patches;
  scene.network = network;
  for (const auto* cases : {&result.fit, &result.holdout})
    for (const fitting::CaseErrors& e : *cases) {
      const Field& ref = reference.at(case_index.at(e.id));
      const Field error = node_to_control(dofs, e.node_error);
      Field model = ref;
      for (size_t p = 0; p < model.size(); ++p)
        for (size_t i = 0; i < model[p].size(); ++i) model[p][i] += error[p][i];
      scene.fields.control.push_back(control_vector_field("reference_" + e.id, ref));
      scene.fields.control.push_back(control_vector_field("model_" + e.id, model));
      scene.fields.control.push_back(control_vector_field("error_" + e.id, error));

      // Per particle: a merged particle shows the last of its nodes (they agree in u_nmsm).
      PointVectors m{"model_" + e.id, std::vector<Eigen::Vector3d>(network.positions.size(),
                                                                   Eigen::Vector3d::Zero())};
      PointVectors r{"error_" + e.id, m.values};
      for (int p = 0; p < dofs.num_patches(); ++p)
        for (size_t i = 0; i < dofs.patch_nodes(p).size(); ++i)
          m.values[static_cast<size_t>(particle[static_cast<size_t>(dofs.patch_nodes(p)[i])])] =
              model[static_cast<size_t>(p)][i];
      for (size_t a = 0; a < particle.size(); ++a)
        r.values[static_cast<size_t>(particle[a])] = e.node_error[a];
      scene.network_vectors.push_back(std::move(m));
      scene.network_vectors.push_back(std::move(r));
    }
  write_vtk_scene(out_dir / "result.vtm", scene);
  return {write_calibration_figures(out_dir, problem, result)};
}

std::vector<std::string> write_calibration_figures(const std::filesystem::path& out_dir,
                                                   const analysis::Problem& problem,
                                                   const fitting::CalibrationResult& result) {
  const analysis::DofMap dofs(problem);
  std::vector<double> all_errors;
  std::vector<PlotSeries> by_position;
  for (const auto* cases : {&result.fit, &result.holdout})
    for (const fitting::CaseErrors& e : *cases) {
      PlotSeries series{e.id + (cases == &result.fit ? " (fitted)" : " (held out)"), {}, {}};
      for (size_t a = 0; a < e.node_error.size(); ++a) {
        const double percent = 100.0 * e.node_error[a].norm() / e.control.o_max;
        all_errors.push_back(percent);
        series.x.push_back(dofs.node_positions()[a].x());
        series.y.push_back(percent);
      }
      by_position.push_back(std::move(series));
    }
  std::vector<std::string> figures;
  PlotOptions options;
  options.title = "Control-point errors of the spring model (all load cases)";
  options.xlabel = "100 |u_nmsm - u_ref| / o_max [%]";
  options.ylabel = "control points";
  if (plot_histogram(out_dir / "errors_histogram.png", all_errors, 20, options))
    figures.push_back("errors_histogram.png");
  options.title = "Control-point error against position, one panel per load case";
  options.xlabel = "x [m]";
  options.ylabel = "error / o_max [%]";
  if (plot_xy_panels(out_dir / "errors_vs_position.png", by_position, options))
    figures.push_back("errors_vs_position.png");
  return figures;
}

}  // namespace isospring::io
