// A patch in reports (see report_patch.hpp).
#include "isospring/io/report_patch.hpp"

#include "isospring/geometry/measure.hpp"
#include "isospring/io/report.hpp"

namespace isospring::io {

namespace {
std::string joined(const std::vector<int>& values, const char* separator) {
  std::string text;
  for (size_t i = 0; i < values.size(); ++i)
    text += (i ? separator : "") + std::to_string(values[i]);
  return text;
}
}  // namespace

nlohmann::json patch_json(const nurbs::Patch& patch) {
  std::vector<int> degrees, points, elements;
  for (int d = 0; d < patch.param_dim(); ++d) {
    degrees.push_back(patch.degree(d));
    points.push_back(patch.num_points(d));
    elements.push_back(patch.knots(d).num_elements());
  }
  const auto [lo, hi] = patch.control_bounds();
  return {{"parametric_dimension", patch.param_dim()},
          {"physical_dimension", patch.physical_dim()},
          {"rational", patch.is_rational()},
          {"degrees", degrees},
          {"control_points", points},
          {"elements", elements},
          {"control_net_bounds", {{lo.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), hi.z()}}},
          {"measure", geometry::measure(patch)}};
}

std::vector<std::string> patch_table_header() {
  return {"patch", "dimension", "degrees", "control points", "elements", "length/area/volume"};
}

std::vector<std::vector<std::string>> patch_table_rows(const std::vector<nurbs::Patch>& patches) {
  std::vector<std::vector<std::string>> rows;
  for (size_t i = 0; i < patches.size(); ++i) {
    const nlohmann::json j = patch_json(patches[i]);
    rows.push_back({std::to_string(i), std::to_string(patches[i].param_dim()),
                    joined(j["degrees"].get<std::vector<int>>(), ", "),
                    joined(j["control_points"].get<std::vector<int>>(), " x "),
                    joined(j["elements"].get<std::vector<int>>(), " x "),
                    format_number(j["measure"].get<double>())});
  }
  return rows;
}

}  // namespace isospring::io
