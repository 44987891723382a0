#include "isospring/io/vtk_fields.hpp"

#include <cmath>
#include <stdexcept>

namespace isospring::io {

ControlField control_vector_field(const std::string& name,
                                  const std::vector<std::vector<Eigen::Vector3d>>& values) {
  ControlField field;
  field.name = name;
  field.components = 3;
  for (const auto& patch_values : values) {
    Eigen::MatrixXd c(3, static_cast<Eigen::Index>(patch_values.size()));
    for (size_t i = 0; i < patch_values.size(); ++i)
      c.col(static_cast<Eigen::Index>(i)) = patch_values[i];
    field.coefficients.push_back(std::move(c));
  }
  return field;
}

ControlField control_field_difference(const std::string& name, const ControlField& reference,
                                      const ControlField& model) {
  if (reference.components != model.components ||
      reference.coefficients.size() != model.coefficients.size())
    throw std::invalid_argument("control_field_difference: '" + reference.name + "' and '" +
                                model.name + "' have different shapes");
  ControlField difference{name, reference.components, {}};
  for (size_t p = 0; p < reference.coefficients.size(); ++p) {
    if (reference.coefficients[p].cols() != model.coefficients[p].cols())
      throw std::invalid_argument("control_field_difference: patch " + std::to_string(p) +
                                  " has different control point counts");
    difference.coefficients.push_back(reference.coefficients[p] - model.coefficients[p]);
  }
  return difference;
}

Eigen::VectorXd evaluate_control_field(const nurbs::Patch& patch, const Eigen::MatrixXd& values,
                                       const nurbs::Param& u) {
  const nurbs::RationalBasis basis = patch.basis(u, 0);
  Eigen::VectorXd value = Eigen::VectorXd::Zero(values.rows());
  for (size_t a = 0; a < basis.indices.size(); ++a)
    value += basis.values(static_cast<Eigen::Index>(a)) * values.col(basis.indices[a]);
  return value;
}

PatchField magnitude_field(const std::string& name, const std::vector<nurbs::Patch>& patches,
                           const ControlField& field) {
  // Copies: the returned callback may outlive the caller's vectors.
  return PatchField{name, 1,
                    [patches, coefficients = field.coefficients](int p, const nurbs::Param& u) {
                      const auto index = static_cast<size_t>(p);
                      Eigen::VectorXd out(1);
                      out(0) =
                          evaluate_control_field(patches[index], coefficients[index], u).norm();
                      return out;
                    },
                    true};
}

PatchField stress_tensor_field(const std::string& name,
                               std::function<Eigen::Matrix3d(int, const nurbs::Param&)> stress) {
  return PatchField{name, 9, [stress = std::move(stress)](int p, const nurbs::Param& u) {
                      const Eigen::Matrix3d s = stress(p, u);
                      Eigen::VectorXd out(9);
                      for (int r = 0; r < 3; ++r)
                        for (int c = 0; c < 3; ++c) out(3 * r + c) = s(r, c);
                      return out;
                    }};
}

double von_mises(const Eigen::Matrix3d& stress) {
  const Eigen::Matrix3d deviator = stress - stress.trace() / 3.0 * Eigen::Matrix3d::Identity();
  return std::sqrt(1.5 * deviator.cwiseProduct(deviator).sum());
}

PatchField von_mises_field(const std::string& name,
                           std::function<Eigen::Matrix3d(int, const nurbs::Param&)> stress) {
  return PatchField{name, 1, [stress = std::move(stress)](int p, const nurbs::Param& u) {
                      Eigen::VectorXd out(1);
                      out(0) = von_mises(stress(p, u));
                      return out;
                    }};
}

}  // namespace isospring::io
