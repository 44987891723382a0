// The files of `isospring calibrate` (see calibrate_command.hpp).
#include "isospring/analysis/dof_map.hpp"
#include "isospring/analysis/static_solver.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/calibration_outputs.hpp"
#include "isospring/io/vtk_spring_network.hpp"
#include "isospring/workflows/calibrate_command.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;
namespace {

void write_errors_csv(const std::filesystem::path& path, const analysis::DofMap& dofs,
                      const fitting::CaseErrors& errors) {
  std::string text = "node,x,y,z,ex,ey,ez,error\n";
  for (int a = 0; a < dofs.num_nodes(); ++a) {
    const Eigen::Vector3d& x = dofs.node_positions()[a];
    const Eigen::Vector3d& e = errors.node_error[a];
    text += std::to_string(a);
    for (double v : {x.x(), x.y(), x.z(), e.x(), e.y(), e.z(), e.norm()})
      text += "," + format_exact(v);
    text += "\n";
  }
  write_file_atomically(path, text);
}

}  // namespace

nlohmann::json write_calibrate_outputs(const std::filesystem::path& out_dir,
                                       const CalibrateCommandResult& r,
                                       std::chrono::steady_clock::time_point start) {
  const fitting::CalibrationResult& result = r.calibration;
  const analysis::SpringNetwork& network = result.mesh.network;
  nlohmann::json report = calibrate_report_json(r);
  // Outputs: the model first (its writer refuses an inconsistent network), then the tables.
  std::filesystem::create_directories(out_dir);
  write_spring_model_json(out_dir / "model.json", calibrate_spring_model(r, report));
  const analysis::DofMap dofs(r.problem);
  std::vector<PointVectors> vectors;
  for (const auto* cases : {&result.fit, &result.holdout})
    for (const auto& e : *cases) {
      const std::string csv = e.id + "_errors.csv";
      write_errors_csv(out_dir / csv, dofs, e);
      // Error per particle (a merged particle shows the last of its nodes; they agree in u_nmsm).
      const std::vector<int> particle = fitting::particle_of_node(r.problem, result.mesh);
      PointVectors v{"error_" + e.id, std::vector<Eigen::Vector3d>(network.positions.size(),
                                                                   Eigen::Vector3d::Zero())};
      for (size_t a = 0; a < particle.size(); ++a) v.values[particle[a]] = e.node_error[a];
      vectors.push_back(std::move(v));
    }
  write_spring_network_vtp(out_dir / "springs.vtp", network, vectors);
  // The reference again for the viewer fields (the calibration keeps only the errors): the same
  // deterministic solve, so model = reference + error is the fitted model's response.
  // At large deformation the finite-strain references kept by the calibration.
  std::vector<std::vector<std::vector<Eigen::Vector3d>>> reference;
  if (r.large_deformation)
    reference = r.large_deformation->reference_controls;
  else
    for (const auto& lc : analysis::solve_static(r.problem).load_cases)
      reference.push_back(lc.control_displacements);
  const CalibrationOutputs outputs =
      write_calibration_outputs(out_dir, r.problem, result, reference);
  report["vtk_file"] = "result.vtm";
  report["figures"] = outputs.figures;
  const MarkdownReport md = calibrate_report_markdown(r, report, outputs.figures);
  report["total_seconds"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  write_json_report(out_dir / "report.json", report);
  md.write(out_dir / "report.md");
  return report;
}

}  // namespace isospring::workflows
