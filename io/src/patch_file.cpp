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

/// "file.json: patches[2].knots[1]" and friends.
struct Where {
  std::string source;
  std::string path;
  std::string operator()(const std::string& field) const {
    return source + ": " + path + (field.empty() ? "" : "." + field);
  }
};

double number_at(const json& value, const std::string& where) {
  if (!value.is_number())
    throw InputError(where + " must be a number, got " + std::string(value.type_name()));
  const double x = value.get<double>();
  if (!std::isfinite(x)) throw InputError(where + " is not finite (NaN or inf)");
  return x;
}

std::vector<double> numbers_at(const json& value, const std::string& where) {
  if (!value.is_array())
    throw InputError(where + " must be an array of numbers, got " + std::string(value.type_name()));
  std::vector<double> out;
  out.reserve(value.size());
  for (size_t i = 0; i < value.size(); ++i)
    out.push_back(number_at(value[i], where + "[" + std::to_string(i) + "]"));
  return out;
}

nurbs::Patch patch_from_json(const json& item, const Where& where) {
  if (!item.is_object()) throw InputError(where("") + " must be an object");
  case_json::reject_unknown_fields(item, {"degrees", "knots", "control_points", "weights"},
                                   where("") + ".");
  for (const char* required : {"degrees", "knots", "control_points"})
    if (!item.contains(required)) throw InputError(where(required) + " is missing");

  const json& degrees_json = item["degrees"];
  if (!degrees_json.is_array() || degrees_json.empty() || degrees_json.size() > 3)
    throw InputError(where("degrees") + " must be an array of 1 to 3 integers");
  std::vector<int> degrees;
  for (size_t d = 0; d < degrees_json.size(); ++d) {
    const std::optional<int> degree = json_int(degrees_json[d]);
    if (!degree)
      throw InputError(where("degrees[" + std::to_string(d) + "]") + " must be an integer, got " +
                       degrees_json[d].dump());
    degrees.push_back(*degree);
  }
  const json& knots_json = item["knots"];
  if (!knots_json.is_array() || knots_json.size() != degrees.size())
    throw InputError(where("knots") + " must hold one knot vector per degree (" +
                     std::to_string(degrees.size()) + ")");

  const json& points_json = item["control_points"];
  if (!points_json.is_array()) throw InputError(where("control_points") + " must be an array");
  std::vector<Eigen::Vector3d> points;
  points.reserve(points_json.size());
  for (size_t i = 0; i < points_json.size(); ++i) {
    const std::string at = where("control_points[" + std::to_string(i) + "]");
    const std::vector<double> xyz = numbers_at(points_json[i], at);
    if (xyz.size() != 3)
      throw InputError(at + " has " + std::to_string(xyz.size()) +
                       " coordinates; always give 3 (x, y, z; z = 0 for 2D geometry)");
    points.emplace_back(xyz[0], xyz[1], xyz[2]);
  }

  // Knot counts per direction must match the control-point count of the whole net.
  std::vector<nurbs::KnotVector> knots;
  size_t product = 1;
  for (size_t d = 0; d < degrees.size(); ++d) {
    const std::string at = where("knots[" + std::to_string(d) + "]");
    std::vector<double> values = numbers_at(knots_json[d], at);
    knots.emplace_back(degrees[d], std::move(values), at);
    product *= static_cast<size_t>(knots.back().num_basis());
  }
  if (product != points.size()) {
    std::ostringstream msg;
    msg << where("control_points") << " has " << points.size() << " points, but the knots give ";
    for (size_t d = 0; d < knots.size(); ++d) msg << (d ? " x " : "") << knots[d].num_basis();
    msg << " = " << product
        << " (each direction: number of knots - degree - 1); fix the knots or the points";
    throw InputError(msg.str());
  }
  std::vector<double> weights;
  if (item.contains("weights")) {
    weights = numbers_at(item["weights"], where("weights"));
    if (weights.size() != points.size())
      throw InputError(where("weights") + " has " + std::to_string(weights.size()) +
                       " values for " + std::to_string(points.size()) +
                       " control points; give one per point or leave weights out");
    for (size_t i = 0; i < weights.size(); ++i)
      if (weights[i] <= 0.0)
        throw InputError(where("weights[" + std::to_string(i) + "]") + " = " +
                         std::to_string(weights[i]) + " must be > 0 (NURBS weights are positive)");
  }
  try {
    return nurbs::Patch(std::move(knots), std::move(points), std::move(weights));
  } catch (const InputError& e) {
    throw InputError(where("") + ": " + e.what());
  }
}

}  // namespace

std::vector<nurbs::Patch> patches_from_json(const json& document, const std::string& source) {
  if (!document.is_object() || !document.contains("patches"))
    throw InputError(source + ": a patch file is an object with a \"patches\" array");
  case_json::reject_unknown_fields(document, {"patches"}, source + ": ");
  const json& list = document["patches"];
  if (!list.is_array() || list.empty())
    throw InputError(source + ": patches must be a non-empty array");
  std::vector<nurbs::Patch> patches;
  for (size_t i = 0; i < list.size(); ++i)
    patches.push_back(
        patch_from_json(list[i], Where{source, "patches[" + std::to_string(i) + "]"}));
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
