// The reduced-model document: basis, Ritz values, reduced damping and the step matrix.
#include "isospring/io/export_reduced.hpp"

#include <cmath>
#include <memory>

#include "isospring/nurbs/error.hpp"

namespace isospring::io {
namespace {

nlohmann::json matrix_rows(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index j = 0; j < m.cols(); ++j) row.push_back(m(i, j));
    rows.push_back(std::move(row));
  }
  return rows;
}

nlohmann::json finite_or_null(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json();
}

nlohmann::json vector_list(const Eigen::VectorXd& v) {
  return nlohmann::json(std::vector<double>(v.data(), v.data() + v.size()));
}

}  // namespace

ReducedExport export_reduced_model(const SpringModel& model, const ReducedExportOptions& options,
                                   const nlohmann::json& provenance) {
  if (const std::string bad = check_spring_network(model.network); !bad.empty())
    throw nurbs::InputError("reduced export: " + bad);
  if (options.error_steps < 1)
    throw nurbs::InputError("reduced export: error_steps = " + std::to_string(options.error_steps) +
                            " must be at least 1");
  // The loads: every load case as simulate applies it (with the model's gravity), and gravity.
  std::vector<std::pair<std::string, Eigen::VectorXd>> loads;
  for (size_t k = 0; k < model.load_cases.size(); ++k)
    loads.emplace_back(model.load_cases[k].id, model_force_vector(model, k, true));
  if (model.gravity.norm() > 0.0) loads.emplace_back("gravity", model_gravity_vector(model));
  analysis::ReducedModelOptions reduction;
  reduction.modes = options.modes;
  if (options.load_shapes)
    for (const auto& load : loads)
      if (load.second.norm() > 0.0) reduction.load_shapes.push_back(load.second);
  std::unique_ptr<analysis::CorotatedReducedModel> corotated;
  if (options.corotated)
    corotated = std::make_unique<analysis::CorotatedReducedModel>(
        model.network, options.timestep,
        analysis::CorotatedModelOptions{reduction, options.derivative_modes});
  analysis::ReducedSpringModel reduced =
      corotated ? corotated->linear()
                : analysis::ReducedSpringModel(model.network, options.timestep, reduction);

  ReducedExport out;
  out.basis_size = reduced.size();
  for (const auto& [id, force] : loads)
    if (force.norm() > 0.0)
      out.errors.push_back(
          {id, analysis::reduction_error(model.network, reduced, force, options.error_steps)});

  const analysis::SpringNetwork& net = model.network;
  nlohmann::json& d = out.document;
  d["format"] = "isospring.reduced_spring_model";
  d["version"] = 1;
  d["dimension"] = net.dimension;
  d["units"] = model.units.is_null() ? default_model_units() : model.units;
  d["timestep"] = options.timestep;
  d["particles"] = net.positions.size();
  nlohmann::json rest = nlohmann::json::array(), fixed = nlohmann::json::array();
  for (size_t q = 0; q < net.positions.size(); ++q) {
    nlohmann::json p = nlohmann::json::array();
    for (int c = 0; c < net.dimension; ++c) p.push_back(net.positions[q][c]);
    rest.push_back(std::move(p));
    if (net.fixed[q]) fixed.push_back(q);
  }
  d["rest_positions"] = std::move(rest);
  d["fixed"] = std::move(fixed);
  d["modes"] = options.modes;
  d["load_shapes"] = reduction.load_shapes.size();
  d["eigenvalues"] = vector_list(reduced.eigenvalues());
  d["damping"] = matrix_rows(reduced.damping());
  d["step_inverse"] = matrix_rows(reduced.step_inverse());
  d["basis"] = matrix_rows(reduced.basis());
  if (corotated) {
    d["corotation"] = corotation_document(corotated->corotation());
    d["corotation"]["derivative_modes"] = options.derivative_modes;
  }
  nlohmann::json errors = nlohmann::json::array();
  for (const ReducedLoadError& e : out.errors)
    errors.push_back(
        {{"load", e.load},
         {"static_relative", e.error.static_relative},
         {"projection_relative", e.error.projection_relative},
         // null when the full network's own run diverged (frozen Jacobian at large rotations)
         {"dynamic_relative", finite_or_null(e.error.dynamic_relative)},
         {"dynamic_max", finite_or_null(e.error.dynamic_max)},
         {"full_network_diverged", e.error.exact_diverged},
         {"steps", e.error.steps}});
  d["errors"] = std::move(errors);
  d["provenance"] = provenance;
  return out;
}

}  // namespace isospring::io
