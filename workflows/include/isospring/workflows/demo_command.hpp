#pragma once
// The use case behind `isospring demo` as one library call: the whole pipeline on a case that
// names a CAD part, into one folder:
//   1. CAD -> NURBS      import the STEP part as exact NURBS
//   2. refinement        k-refine it to the case's degrees and elements
//   3. IGA reference     linear elasticity, every load case (displacement, von Mises)
//   4. NMSM calibration  springs on the control net, stiffnesses fitted with Ceres (the case's
//                        "calibration" object)
//   5. VTK               one .vtm for ParaView: exact Bezier geometry, fields, net, springs
//   6. exports           model.json, MuJoCo MJCF, SOFA scene; report.json and report.md
#include <filesystem>
#include <string>
#include <vector>

#include "isospring/io/report.hpp"

namespace isospring::workflows {

/// The files run_demo writes into its folder.
std::vector<std::string> demo_output_files();

/// Runs the pipeline on `case_file` and writes every file of demo_output_files into `out_dir`
/// (report.json and report.md last); returns the run time in seconds.
double run_demo(const std::filesystem::path& case_file, const std::filesystem::path& out_dir,
                const io::Progress& progress);

}  // namespace isospring::workflows
