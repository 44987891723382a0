#pragma once
// Reduced-model export: the subspace model of a calibrated spring network
// (analysis/spring_reduced_model.hpp) as a JSON document an engine steps at haptic rates without
// the network: O(r^2) per step, O(r) per particle read or pushed. Format and step in
// docs/reduced_model.md ("isospring.reduced_spring_model", version 1).
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isospring/analysis/spring_reduced_corotated.hpp"
#include "isospring/analysis/spring_reduced_model.hpp"
#include "isospring/io/model_file.hpp"

namespace isospring::io {

struct ReducedExportOptions {
  int modes = 32;           // lowest natural modes
  double timestep = 1e-3;   // [s]: 1 kHz
  bool load_shapes = true;  // the model's load cases (and its gravity) join the basis
  int error_steps = 200;    // steps of the error run against the full network, per load
  /// The corotated model (analysis/spring_reduced_corotated.hpp): the basis gains the modal
  /// derivatives of the `derivative_modes` lowest vectors and the document a "corotation" object
  /// (docs/reduced_model.md). `errors` stay those of the linear step on the same basis.
  bool corotated = false;
  int derivative_modes = 6;
};

/// The reduced model's error on one of the model's loads (reduction_error against the full
/// LinearImplicitIntegrator, same time step).
struct ReducedLoadError {
  std::string load;  // a load case id, or "gravity"
  analysis::ReductionError error;
};

struct ReducedExport {
  nlohmann::json document;  // the file's content
  int basis_size = 0;
  std::vector<ReducedLoadError> errors;  // per load case (with the model's gravity) and gravity
};

/// Builds the reduced model of `model` with the model's load cases (each with the model's
/// gravity, as `simulate` applies them) and its gravity alone as load shapes, measures each
/// load's error, and returns the document. Throws nurbs::InputError for a bad option or a model
/// that cannot be reduced (see ReducedSpringModel).
ReducedExport export_reduced_model(const SpringModel& model, const ReducedExportOptions& options,
                                   const nlohmann::json& provenance = nlohmann::json::object());

/// The "corotation" object of a corotated reduced document: per particle its neighbours and the
/// rest stiffness and damping blocks, their row sums and the neighbourhood's rest inverse
/// (analysis::CorotatedForces' storage).
nlohmann::json corotation_document(const analysis::CorotatedForces& corotation);

}  // namespace isospring::io
