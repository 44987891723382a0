#pragma once
// `isospring analyze` on a case whose geometry is {"type": "immersed", ...} (io/immersed_case.hpp):
// the CAD solid is embedded in a B-spline background grid on its exact B-rep
// (geometry::immerse_solid), every load case is solved by analysis::solve_immersed, and the
// results are evaluated on the part's display triangulation (not on the grid; its triangles split
// to at most a background cell's edge), so ParaView shows the part. Outputs: report.json, report.md
// and result.vtp (displacement_<id> and von_mises_<id> as point data, the face index as cell data),
// and with "output": {"cells": true} cells.vtu (the background cells, io/vtk_immersed_cells.hpp).
#include <Eigen/Core>
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/analysis/immersed.hpp"
#include "isospring/geometry/cad_triangulation.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/io/immersed_case.hpp"
#include "isospring/io/report.hpp"

namespace isospring::workflows {

struct ImmersedLoadCaseResult {
  std::string id;
  analysis::ImmersedResult result;
  /// Force the supports exert on the part, the consistent reaction (analysis::immersed_reaction);
  /// it balances applied_load up to the ghost penalty's share.
  Eigen::Vector3d reaction = Eigen::Vector3d::Zero();
  /// The integral of the traction P sigma(u) n over the supported faces (P: the held
  /// components): the same force from the computed stress on the face, which converges slowly
  /// (about like h) because the stress is least accurate where a support meets a free surface.
  Eigen::Vector3d support_traction = Eigen::Vector3d::Zero();
  /// Body force, gravity and tractions integrated on the domain's quadrature.
  Eigen::Vector3d applied_load = Eigen::Vector3d::Zero();
  double max_displacement = 0;  // largest |u| at the surface triangulation's points
  double max_von_mises = 0;     // the same for the von Mises stress
  std::vector<Eigen::Vector3d> surface_displacement;  // per triangulation point
  std::vector<double> surface_von_mises;
};

struct ImmersedAnalysis {
  io::ImmersedCase c;
  geometry::ImmersedDomain domain;
  geometry::ImmersionStats stats;
  geometry::SolidMeasures occ;         // OpenCascade's (BRepGProp)
  geometry::SolidMeasures quadrature;  // the immersed domain's
  double immersion_seconds = 0, surface_seconds = 0;
  geometry::CadTriangulation surface;  // the solid's faces only
  std::vector<ImmersedLoadCaseResult> load_cases;
};

/// Immerses the case's solid and solves every load case; `method` is the linear solver
/// (analysis::SolverOptions::Method). Throws nurbs::InputError for bad input.
ImmersedAnalysis run_analyze_immersed(const io::ImmersedCase& c,
                                      analysis::SolverOptions::Method method,
                                      const io::Progress& progress);

/// Writes report.json, report.md and result.vtp into `out_dir`; returns report.json's content.
nlohmann::json write_immersed_outputs(const ImmersedAnalysis& a,
                                      const std::filesystem::path& out_dir,
                                      const io::Progress& progress,
                                      std::chrono::steady_clock::time_point start);

}  // namespace isospring::workflows
