#include "isospring/io/patch_file.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "case_file_json.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/io/json_text.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {
using nlohmann::json;
using nurbs::InputError;

namespace {

std::vector<double> numbers(const case_json::Field& array) {
  std::vector<double> out;
  for (const case_json::Field& entry : array.elements()) out.push_back(entry.number());
  return out;
}

// One patch; types and ranges through case_json::Field (the case file's wording), what only a
// NURBS patch needs (matching counts, positive weights, valid knot vectors) here and in nurbs.
nurbs::Patch patch_from_json(const case_json::Field& item) {
  item.expect_object({"degrees", "knots", "control_points", "weights"});
  const case_json::Field degrees_field = item.at("degrees");
  const std::vector<case_json::Field> degree_entries = degrees_field.elements(false);
  if (degree_entries.size() > 3)
    throw InputError(degrees_field.where() + " must be an array of 1 to 3 integers, got " +
                     std::to_string(degree_entries.size()));
  std::vector<int> degrees;
  for (const case_json::Field& degree : degree_entries)
    degrees.push_back(degree.integer_at_least(1));
  const case_json::Field knots_field = item.at("knots");
  const std::vector<case_json::Field> knot_vectors = knots_field.elements();
  if (knot_vectors.size() != degrees.size())
    throw InputError(knots_field.where() + " must hold one knot vector per degree (" +
                     std::to_string(degrees.size()) + "), got " +
                     std::to_string(knot_vectors.size()));

  const case_json::Field points_field = item.at("control_points");
  std::vector<Eigen::Vector3d> points;
  for (const case_json::Field& point : points_field.elements()) {
    const std::vector<double> xyz = numbers(point);
    if (xyz.size() != 3)
      throw InputError(point.where() + " has " + std::to_string(xyz.size()) +
                       " coordinates; always give 3 (x, y, z; z = 0 for 2D geometry)");
    points.emplace_back(xyz[0], xyz[1], xyz[2]);
  }

  // Knot counts per direction must match the control-point count of the whole net.
  std::vector<nurbs::KnotVector> knots;
  size_t product = 1;
  for (size_t d = 0; d < degrees.size(); ++d) {
    knots.emplace_back(degrees[d], numbers(knot_vectors[d]), knot_vectors[d].where());
    product *= static_cast<size_t>(knots.back().num_basis());
  }
  if (product != points.size()) {
    std::ostringstream msg;
    msg << points_field.where() << " has " << points.size() << " points, but the knots give ";
    for (size_t d = 0; d < knots.size(); ++d) msg << (d ? " x " : "") << knots[d].num_basis();
    msg << " = " << product
        << " (each direction: number of knots - degree - 1); fix the knots or the points";
    throw InputError(msg.str());
  }
  std::vector<double> weights;
  if (item.has("weights")) {
    const case_json::Field weights_field = item.at("weights");
    const std::vector<case_json::Field> entries = weights_field.elements();
    if (entries.size() != points.size())
      throw InputError(weights_field.where() + " has " + std::to_string(entries.size()) +
                       " values for " + std::to_string(points.size()) +
                       " control points; give one per point or leave weights out");
    for (const case_json::Field& entry : entries) {
      weights.push_back(entry.number());
      if (weights.back() <= 0.0)
        throw InputError(entry.where() + " = " + std::to_string(weights.back()) +
                         " must be > 0 (NURBS weights are positive)");
    }
  }
  try {
    return nurbs::Patch(std::move(knots), std::move(points), std::move(weights));
  } catch (const InputError& e) {
    throw InputError(item.where() + ": " + e.what());
  }
}

}  // namespace

std::vector<nurbs::Patch> patches_from_json(const json& document, const std::string& source) {
  if (!document.is_object() || !document.contains("patches"))
    throw InputError(source + ": a patch file is an object with a \"patches\" array");
  const case_json::Field root(document, source, "");
  root.expect_object({"patches"});
  const case_json::Field list = root.at("patches");
  if (!list.json().is_array() || list.json().empty())
    throw InputError(source + ": patches must be a non-empty array");
  std::vector<nurbs::Patch> patches;
  for (const case_json::Field& item : list.elements()) patches.push_back(patch_from_json(item));
  return patches;
}

std::vector<nurbs::Patch> read_patch_file(const std::filesystem::path& path) {
  const std::string text = read_text_file(path, "patch file");
  return patches_from_json(parse_json_text(text, path.string(), "patch file"), path.string());
}

json patches_to_json(const std::vector<nurbs::Patch>& patches) {
  json list = json::array();
  for (const nurbs::Patch& patch : patches) {
    json item;
    json degrees = json::array(), knots = json::array();
    for (int d = 0; d < patch.param_dim(); ++d) {
      degrees.push_back(patch.degree(d));
      knots.push_back(patch.knots(d).values());
    }
    item["degrees"] = degrees;
    item["knots"] = knots;
    json points = json::array();
    for (const auto& x : patch.control_points()) points.push_back({x.x(), x.y(), x.z()});
    item["control_points"] = points;
    if (patch.is_rational()) item["weights"] = patch.weights();
    list.push_back(item);
  }
  return json{{"patches", list}};
}

void write_patch_file(const std::filesystem::path& path, const std::vector<nurbs::Patch>& patches) {
  // nlohmann writes doubles with max_digits10, so a round trip is exact.
  write_file_atomically(path, patches_to_json(patches).dump(1) + "\n");
}

}  // namespace isospring::io
