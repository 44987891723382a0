#pragma once
// The viewer and figure outputs of `isospring calibrate` and `isospring demo` (the reports are
// in calibrate_command.hpp):
//
//   OUT/result.vtm + OUT/result/  geometry (sampled and Bezier) and control net with, per load
//       case <id>, reference_<id> (IGA), model_<id> (spring model) and error_<id> (model -
//       reference) as control-point fields; the spring network with model_<id> and error_<id>
//       per particle.
//   OUT/errors_histogram.png      relative control-point errors 100 |e| / o_max of every load
//       case (fitted and held out), 20 bins.
//   OUT/errors_vs_position.png    the same errors against the control point's x coordinate, one
//       panel per load case (plot_xy_panels).
#include <filesystem>
#include <string>
#include <vector>

#include "isospring/analysis/problem.hpp"
#include "isospring/fitting/calibration.hpp"

namespace isospring::io {

struct CalibrationOutputs {
  std::vector<std::string> figures;  // file names of the figures written (gnuplot may be absent)
};

/// `reference` holds the IGA control displacements [patch][control point] of every load case of
/// the problem, in the problem's order.
CalibrationOutputs write_calibration_outputs(
    const std::filesystem::path& out_dir, const analysis::Problem& problem,
    const fitting::CalibrationResult& result,
    const std::vector<std::vector<std::vector<Eigen::Vector3d>>>& reference);

/// Only the two figures (errors_histogram.png, errors_vs_position.png) of `result`'s fitted and
/// held-out cases; returns the file names written (none when gnuplot is absent).
std::vector<std::string> write_calibration_figures(const std::filesystem::path& out_dir,
                                                   const analysis::Problem& problem,
                                                   const fitting::CalibrationResult& result);

}  // namespace isospring::io
