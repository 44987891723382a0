#pragma once
// Measured marker displacements from CSV, and the `"measurements"` object of a case file.
//
//   "measurements": {
//     "file": "markers.csv",           // relative to the case file
//     "units": "m" | "mm",             // of positions, displacements, sigma and noise_sigma
//     "columns": {"x": "x-coordinate [mm]", ...},  // CSV header names; defaults below
//     "load_case": "L1",               // the load case of files without a load_case column
//     "noise_sigma": 1e-6,             // optional; estimated from the data when absent
//     "placement_tolerance": 1e-4,     // optional; farther markers are outside (default 1e-3 L)
//     "fit_poisson": false, "significance": 0.01, "holdout": true,
//     "effects": ["gravity", ...],     // optional; candidate effects (default: all)
//     "discretization_check": true,    // refine the reference until its marker error < target
//     "discretization_target": 0.333,  //   x noise (rms), within "max_dofs" DOFs (25000)
//     "max_dofs": 25000
//   }
//
// Default header: load_case,x,y,z,ux,uy,uz[,sigma]; 2D data may omit z and uz. Column names are
// matched exactly (after trimming spaces); other columns are ignored.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "isospring/fitting/identify.hpp"
#include "isospring/fitting/measure.hpp"

namespace isospring::io {

struct MarkerColumns {
  std::string load_case = "load_case";
  std::string x = "x", y = "y", z = "z";
  std::string ux = "ux", uy = "uy", uz = "uz";
  std::string sigma = "sigma";
};

struct MarkerFileOptions {
  MarkerColumns columns;
  double unit_scale = 1.0;              // file units -> metres
  std::string default_load_case;        // for files without a load_case column
  int dimension = 3;                    // 2: z and uz optional (taken as 0)
  std::vector<std::string> load_cases;  // ids of the case file; others are an InputError
};

/// Reads markers; every problem is a nurbs::InputError naming the file, the row (1-based line)
/// and the column: missing columns, non-numeric or NaN/inf values, two markers of one load case at
/// the same position, load cases not in `load_cases`, a file without markers.
fitting::Measurements read_markers_csv(const std::filesystem::path& path,
                                       const MarkerFileOptions& options);

/// The measured-data settings of a case file's `"measurements"` object.
struct MeasurementSettings {
  std::filesystem::path file;
  MarkerFileOptions file_options;
  fitting::IdentifyOptions identify;          // noise_sigma in metres
  std::optional<double> placement_tolerance;  // metres
};

/// Validates the object (unknown fields with their valid names, types, ranges); `where` prefixes
/// messages ("case.json: measurements"), `case_folder` anchors the data file.
MeasurementSettings read_measurement_settings(const nlohmann::json& measurements,
                                              const std::filesystem::path& case_folder,
                                              int dimension,
                                              const std::vector<std::string>& load_cases,
                                              const std::string& where);

}  // namespace isospring::io
