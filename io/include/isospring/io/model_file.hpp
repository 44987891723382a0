#pragma once
// Calibrated spring models as JSON (`model.json`, schema "isospring-spring-model" version 1): the
// hand-off between calibration and every export (MuJoCo, SOFA, VTK) and third-party engines.
//
//   {"format": "isospring-spring-model", "version": 1,
//    "units": {"length": "m", "mass": "kg", "time": "s", "force": "N"},
//    "dimension": 3,                                   // 2: in-plane model, z ignored
//    "particles": [{"x": [0, 0, 0], "mass": 0.01, "fixed": true}, ...],
//    "springs": [{"i": 0, "j": 1, "k": 1200.0, "c": 0.5, "L0": 0.01, "group": 3}, ...],
//    "provenance": {"case": "cantilever", "isospring_version": "0.1.0",
//                   "fit": {"rms_displacement_error": 1.2e-6, ...}}}
//
// Fields: x rest position; mass > 0 (a fixed particle may have mass 0); fixed optional (false);
// springs connect particle indices i != j (0-based), stiffness k >= 0 [N/m], damping c >= 0
// [N s/m] (optional, 0), rest length L0 > 0 [m], group an integer >= -1 (optional, -1 = none).
// "units" and "provenance" are free-form objects kept as written.
//
// Optional loads (still version 1: readers that predate them fail on the unknown key, files
// without them read as before), written by `isospring calibrate` and `demo` (the loads the
// springs were fitted and evaluated under, self-weight included as forces) and by `isospring
// identify` for its recalibrated model (identified gravity separate):
//   "gravity": [0, -9.81, 0],          // acceleration of every particle [m/s^2]: force m_i g
//   "load_cases": [{"id": "L1", "forces": [[i, fx, fy, fz], ...]}, ...]   // external forces [N]
// A load case's total load is its forces plus m_i g on every free particle.
//
// Optional volume terms (written only when the model has them, readers that predate
// them fail on the unknown key): one per control-net cell, energy 1/2 (kappa / |V0|) (V - V0)^2
// with V the volume (2D: area) of the trilinear (bilinear) cell (analysis/spring_volume.hpp):
//   "volumes": [{"particles": [8 corners in tensor order (2D: 4)], "kappa": 3500.0 [Pa; 2D N/m],
//                "V0": 0.064 (signed by the corners' orientation, non-zero), "group": 5}, ...]
// An entry with "mu" [Pa; 2D N/m] instead of "kappa" is a shear term: energy
// mu |V0| |dev G|^2 of the cell's mean Green strain G (analysis::CellEnergy::kShear).
// Every problem found by the
// reader is an nurbs::InputError naming the file and the field, e.g.
//   "model.json: springs[4].k: must be finite and >= 0 (got -3); fix the calibration output".
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "isospring/analysis/spring_network.hpp"

namespace isospring::io {

struct ModelLoadCase {
  std::string id;
  std::vector<std::pair<int, Eigen::Vector3d>> forces;  // particle, force [N]
};

struct SpringModel {
  analysis::SpringNetwork network;
  nlohmann::json units;                               // {"length": "m", ...}
  nlohmann::json provenance;                          // object (empty when absent)
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  // [m/s^2]; zero when absent
  std::vector<ModelLoadCase> load_cases;              // empty when absent
};

/// The document of a model with its loads (gravity and load_cases written when present).
nlohmann::json spring_model_to_json(const SpringModel& model);

/// Writes a model with its loads atomically; InputError for an inconsistent network or loads.
void write_spring_model_json(const std::filesystem::path& path, const SpringModel& model);

/// Flat force vector (particle * dimension + component) of model.load_cases[index], plus the
/// gravity forces m_i g when `with_gravity`.
Eigen::VectorXd model_force_vector(const SpringModel& model, size_t index, bool with_gravity);

/// Flat gravity forces m_i g of every particle (particle * dimension + component).
Eigen::VectorXd model_gravity_vector(const SpringModel& model);

/// A load case from flat forces on the particles (particle * dimension + component, as
/// fitting::CalibrationResult::particle_loads): one entry per particle with a non-zero force.
ModelLoadCase model_load_case(std::string id, const Eigen::VectorXd& flat, int dimension);

/// SI units as written by default.
nlohmann::json default_model_units();

/// The JSON document of a model (full double precision). `provenance` must be an object or null.
nlohmann::json model_to_json(const analysis::SpringNetwork& network,
                             const nlohmann::json& provenance = nlohmann::json::object(),
                             const nlohmann::json& units = default_model_units());

/// Parses and validates a document; `source` (a file name) starts every error message.
SpringModel model_from_json(const nlohmann::json& document, const std::string& source);

/// Writes model.json atomically. Throws InputError when the network itself is inconsistent
/// (sizes disagree, NaN, negative stiffness, bad indices) so a bad model is never written.
void write_model_json(const std::filesystem::path& path, const analysis::SpringNetwork& network,
                      const nlohmann::json& provenance = nlohmann::json::object(),
                      const nlohmann::json& units = default_model_units());

/// Reads and validates model.json.
SpringModel read_model_json(const std::filesystem::path& path);

/// Empty when the network is consistent, else a sentence naming the first bad field
/// ("springs[4].k: ..."); used by the writer and the exporters.
std::string check_spring_network(const analysis::SpringNetwork& network);

}  // namespace isospring::io
