#pragma once
// Typed reads of JSON fields whose failures name the file and the field ("model.json:
// springs[3].k: must be a number"), shared by both model formats. Private to the runtime.
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "model.hpp"

namespace isospring::runtime {

class JsonFields : public Fields {
 public:
  using Fields::Fields;

  const nlohmann::json& require(const nlohmann::json& object, const std::string& key,
                                const std::string& path) const {
    if (!object.is_object() || !object.contains(key))
      fail(path + key, "missing; add it (see the model file's schema in docs/outputs.md)");
    return object.at(key);
  }

  double number(const nlohmann::json& value, const std::string& field) const {
    if (!value.is_number()) fail(field, "must be a number");
    const double x = value.get<double>();
    if (!std::isfinite(x)) fail(field, "must be finite");
    return x;
  }

  int integer(const nlohmann::json& value, const std::string& field) const {
    if (value.is_number_integer()) {
      const auto q = value.get<long long>();
      if (q > -2000000000LL && q < 2000000000LL) return static_cast<int>(q);
    } else if (value.is_number_float()) {
      const double x = value.get<double>();
      if (std::isfinite(x) && x == std::floor(x) && std::abs(x) < 2e9) return static_cast<int>(x);
    }
    fail(field, "must be an integer");
  }

  const nlohmann::json& array(const nlohmann::json& value, const std::string& field,
                              size_t size) const {
    if (!value.is_array() || value.size() != size)
      fail(field, "must be an array of " + std::to_string(size) + " entries");
    return value;
  }

  /// A particle index in [0, count).
  int index(const nlohmann::json& value, const std::string& field, size_t count) const {
    const int q = integer(value, field);
    if (q < 0 || static_cast<size_t>(q) >= count)
      fail(field, "particle index " + std::to_string(q) + " out of range [0, " +
                      std::to_string(count) + ")");
    return q;
  }
};

/// Readers of the two formats (network_file.cpp, reduced_file.cpp).
void read_network(const nlohmann::json& document, const JsonFields& fields, Model& model);
void read_reduced(const nlohmann::json& document, const JsonFields& fields, Model& model);

}  // namespace isospring::runtime
