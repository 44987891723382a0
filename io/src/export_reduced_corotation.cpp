// The "corotation" object of a corotated reduced-model document (docs/reduced_model.md).
#include "isospring/io/export_reduced.hpp"

namespace isospring::io {

nlohmann::json corotation_document(const analysis::CorotatedForces& corotation) {
  const int d = corotation.dimension();
  const auto bs = static_cast<size_t>(d * d);
  const std::vector<int>& offsets = corotation.offsets();
  nlohmann::json neighbours = nlohmann::json::array(), stiffness = nlohmann::json::array(),
                 damping = nlohmann::json::array(), row_stiffness = nlohmann::json::array(),
                 row_damping = nlohmann::json::array(), rest_inverse = nlohmann::json::array();
  auto slice = [](const std::vector<double>& values, size_t first, size_t count) {
    return nlohmann::json(
        std::vector<double>(values.begin() + static_cast<std::ptrdiff_t>(first),
                            values.begin() + static_cast<std::ptrdiff_t>(first + count)));
  };
  for (size_t i = 0; i + 1 < offsets.size(); ++i) {
    const auto first = static_cast<size_t>(offsets[i]), last = static_cast<size_t>(offsets[i + 1]);
    neighbours.push_back(std::vector<int>(corotation.columns().begin() + offsets[i],
                                          corotation.columns().begin() + offsets[i + 1]));
    stiffness.push_back(slice(corotation.stiffness_blocks(), first * bs, (last - first) * bs));
    damping.push_back(slice(corotation.damping_blocks(), first * bs, (last - first) * bs));
    row_stiffness.push_back(slice(corotation.row_sum_stiffness(), i * bs, bs));
    row_damping.push_back(slice(corotation.row_sum_damping(), i * bs, bs));
    nlohmann::json inverse = nlohmann::json::array();
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b) inverse.push_back(corotation.rest_inverse()[i](a, b));
    rest_inverse.push_back(std::move(inverse));
  }
  return {{"neighbours", std::move(neighbours)},   {"stiffness", std::move(stiffness)},
          {"damping", std::move(damping)},         {"row_stiffness", std::move(row_stiffness)},
          {"row_damping", std::move(row_damping)}, {"rest_inverse", std::move(rest_inverse)}};
}

}  // namespace isospring::io
