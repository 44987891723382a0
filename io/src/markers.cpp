// CSV markers and the case file's "measurements" settings.
#include "isospring/io/markers.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "case_file_json.hpp"
#include "isospring/fitting/effect.hpp"
#include "isospring/io/atomic_file.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {

namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r\"");
  if (a == std::string::npos) return "";
  const auto b = s.find_last_not_of(" \t\r\"");
  return s.substr(a, b - a + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream stream(line);
  std::string cell;
  while (std::getline(stream, cell, ',')) cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

}  // namespace

fitting::Measurements read_markers_csv(const std::filesystem::path& path,
                                       const MarkerFileOptions& options) {
  std::string text = read_text_file(path, "marker file");
  const std::string name = path.string();
  // A UTF-8 byte order mark (spreadsheet exports) is not part of the first column's name.
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);
  // strtod stops at a NUL, so "1.5<NUL>7" would silently read as 1.5: a text CSV has none.
  if (const auto nul = text.find('\0'); nul != std::string::npos)
    throw nurbs::InputError(
        name + ": line " + std::to_string(1 + std::count(text.begin(), text.begin() + nul, '\n')) +
        " holds a NUL byte: not a text CSV file (binary or corrupted); export the markers again");
  std::stringstream stream(text);
  std::string line;
  int line_number = 0;
  std::vector<std::string> header;
  while (header.empty() && std::getline(stream, line)) {
    ++line_number;
    if (!trim(line).empty()) header = split(line);
  }
  if (header.empty()) throw nurbs::InputError(name + ": the file is empty; expected a header line");
  auto column = [&](const std::string& wanted, bool required) -> int {
    const auto it = std::find(header.begin(), header.end(), wanted);
    if (it != header.end()) return static_cast<int>(it - header.begin());
    if (required) {
      std::string have;
      for (const auto& h : header) have += (have.empty() ? "\"" : ", \"") + h + "\"";
      throw nurbs::InputError(name + ": no column \"" + wanted + "\" in the header (columns: " +
                              have + "); name the column in measurements.columns");
    }
    return -1;
  };
  const MarkerColumns& c = options.columns;
  const bool three_d = options.dimension == 3;
  const int col_case = column(c.load_case, false);
  const int cols[6] = {column(c.x, true),  column(c.y, true),  column(c.z, three_d),
                       column(c.ux, true), column(c.uy, true), column(c.uz, three_d)};
  const int col_sigma = column(c.sigma, false);
  if (col_case < 0 && options.default_load_case.empty())
    throw nurbs::InputError(name + ": no \"" + c.load_case +
                            "\" column and the case has several load cases; add the column or "
                            "set measurements.load_case");
  const std::set<std::string> known(options.load_cases.begin(), options.load_cases.end());

  fitting::Measurements data;
  data.source = name;
  data.dimension = options.dimension;
  std::set<std::tuple<std::string, double, double, double>> seen;
  std::map<std::tuple<std::string, double, double, double>, int> first_row;
  while (std::getline(stream, line)) {
    ++line_number;
    if (trim(line).empty()) continue;
    const std::vector<std::string> cells = split(line);
    const std::string where = name + ": row " + std::to_string(line_number);
    auto number = [&](int col, const std::string& column_name) {
      if (col < 0) return 0.0;
      if (col >= static_cast<int>(cells.size()))
        throw nurbs::InputError(where + ", column \"" + column_name +
                                "\": missing value (the row has " + std::to_string(cells.size()) +
                                " cells)");
      const std::string& cell = cells[static_cast<size_t>(col)];
      char* end = nullptr;
      const double value = std::strtod(cell.c_str(), &end);
      if (cell.empty() || end != cell.c_str() + cell.size())
        throw nurbs::InputError(where + ", column \"" + column_name + "\": \"" + cell +
                                "\" is not a number");
      if (!std::isfinite(value))
        throw nurbs::InputError(where + ", column \"" + column_name + "\": " + cell +
                                " (every value must be finite; remove the row)");
      return value;
    };
    fitting::Marker marker;
    marker.row = line_number;
    if (col_case >= 0) {
      if (col_case >= static_cast<int>(cells.size()) ||
          cells[static_cast<size_t>(col_case)].empty())
        throw nurbs::InputError(where + ", column \"" + c.load_case + "\": missing load case");
      marker.load_case = cells[static_cast<size_t>(col_case)];
    } else {
      marker.load_case = options.default_load_case;
    }
    if (!known.empty() && !known.count(marker.load_case)) {
      std::string ids;
      for (const auto& id : options.load_cases) ids += (ids.empty() ? "" : ", ") + id;
      throw nurbs::InputError(where + ", column \"" + c.load_case + "\": load case \"" +
                              marker.load_case +
                              "\" is not in the case file (its load cases: " + ids + ")");
    }
    const std::string* names[6] = {&c.x, &c.y, &c.z, &c.ux, &c.uy, &c.uz};
    for (int k = 0; k < 3; ++k) {
      marker.position[k] = options.unit_scale * number(cols[k], *names[k]);
      marker.displacement[k] = options.unit_scale * number(cols[k + 3], *names[k + 3]);
    }
    if (!three_d) marker.position.z() = marker.displacement.z() = 0.0;
    if (col_sigma >= 0) {
      marker.sigma = options.unit_scale * number(col_sigma, c.sigma);
      if (!(marker.sigma > 0.0))
        throw nurbs::InputError(where + ", column \"" + c.sigma + "\": must be positive");
    }
    const auto key = std::make_tuple(marker.load_case, marker.position.x(), marker.position.y(),
                                     marker.position.z());
    const auto [it, inserted] = first_row.emplace(key, line_number);
    if (!inserted)
      throw nurbs::InputError(where + ": duplicate marker: load case \"" + marker.load_case +
                              "\" already has a marker at this position (row " +
                              std::to_string(it->second) + "); remove one of the rows");
    data.markers.push_back(marker);
  }
  if (data.markers.empty()) throw nurbs::InputError(name + ": no marker rows after the header");
  return data;
}

MeasurementSettings read_measurement_settings(const nlohmann::json& m,
                                              const std::filesystem::path& case_folder,
                                              int dimension,
                                              const std::vector<std::string>& load_cases,
                                              const std::string& where) {
  if (!m.is_object()) throw nurbs::InputError(where + ": must be an object with at least \"file\"");
  static const std::set<std::string> fields{"file",
                                            "units",
                                            "columns",
                                            "load_case",
                                            "noise_sigma",
                                            "component_weights",
                                            "placement_tolerance",
                                            "fit_poisson",
                                            "significance",
                                            "holdout",
                                            "effects",
                                            "discretization_check",
                                            "max_dofs",
                                            "discretization_target"};
  case_json::reject_unknown_fields(m, std::vector<std::string>(fields.begin(), fields.end()),
                                   where + ".");
  // Types and ranges: case_json::Field, the one wording of every io reader.
  const case_json::Field field = case_json::Field::at_where(m, where);
  auto string_field = [&](const std::string& key) { return field.at(key).string(); };
  auto number_field = [&](const std::string& key, double lo, double hi) {
    return field.at(key).within(lo, hi, true, true);
  };
  auto bool_field = [&](const std::string& key) { return field.at(key).boolean(); };
  MeasurementSettings s;
  if (!m.contains("file")) throw nurbs::InputError(where + ".file: missing (the marker CSV file)");
  s.file = case_folder / string_field("file");
  s.file_options.dimension = dimension;
  s.file_options.load_cases = load_cases;
  if (m.contains("units")) {
    const std::string units = string_field("units");
    if (units == "m")
      s.file_options.unit_scale = 1.0;
    else if (units == "mm")
      s.file_options.unit_scale = 1e-3;
    else
      throw nurbs::InputError(where + ".units: \"" + units + "\"; use \"m\" or \"mm\"");
  }
  if (m.contains("columns")) {
    const auto& cols = m.at("columns");
    if (!cols.is_object()) throw nurbs::InputError(where + ".columns: must be an object");
    MarkerColumns& c = s.file_options.columns;
    std::map<std::string, std::string*> slots{{"load_case", &c.load_case},
                                              {"x", &c.x},
                                              {"y", &c.y},
                                              {"z", &c.z},
                                              {"ux", &c.ux},
                                              {"uy", &c.uy},
                                              {"uz", &c.uz},
                                              {"sigma", &c.sigma}};
    for (const auto& [key, value] : cols.items()) {
      if (!slots.count(key))
        throw nurbs::InputError(where + ".columns." + key +
                                ": unknown; valid: load_case, x, y, z, ux, uy, uz, sigma");
      if (!value.is_string())
        throw nurbs::InputError(where + ".columns." + key + ": must be the column's header name");
      *slots[key] = value.get<std::string>();
    }
  }
  if (m.contains("load_case")) {
    s.file_options.default_load_case = string_field("load_case");
    if (std::find(load_cases.begin(), load_cases.end(), s.file_options.default_load_case) ==
        load_cases.end())
      throw nurbs::InputError(where + ".load_case: \"" + s.file_options.default_load_case +
                              "\" is not a load case of the case file");
  } else if (load_cases.size() == 1) {
    s.file_options.default_load_case = load_cases.front();
  }
  const double scale = s.file_options.unit_scale;
  if (m.contains("noise_sigma"))
    s.identify.noise_sigma = scale * number_field("noise_sigma", 0, 1e300);
  if (m.contains("component_weights")) {
    const auto& w = m.at("component_weights");
    if (w.is_string() && w.get<std::string>() == "mean_abs") {
      s.identify.component_weights_mean_abs = true;
    } else if (w.is_array() && static_cast<int>(w.size()) == dimension) {
      for (const case_json::Field& weight : field.at("component_weights").elements())
        s.identify.component_weights.push_back(weight.at_least(0.0, true));
    } else {
      throw nurbs::InputError(where + ".component_weights: must be \"mean_abs\" or a list of " +
                              std::to_string(dimension) +
                              " positive relative weights (one per displacement component), got " +
                              w.dump());
    }
  }
  if (m.contains("placement_tolerance"))
    s.placement_tolerance = scale * number_field("placement_tolerance", 0, 1e300);
  if (m.contains("fit_poisson")) s.identify.fit_poisson = bool_field("fit_poisson");
  if (m.contains("holdout")) s.identify.holdout = bool_field("holdout");
  if (m.contains("significance")) s.identify.significance = number_field("significance", 0, 0.5);
  if (m.contains("discretization_check"))
    s.identify.discretization.enabled = bool_field("discretization_check");
  if (m.contains("max_dofs")) {
    const double dofs = number_field("max_dofs", 0, 1e9);
    if (dofs != std::floor(dofs))
      throw nurbs::InputError(where + ".max_dofs: must be a whole number of DOFs");
    s.identify.discretization.max_dofs = static_cast<long>(dofs);
  }
  if (m.contains("discretization_target"))
    s.identify.discretization.target_fraction = number_field("discretization_target", 0, 1.0001);
  if (m.contains("effects")) {
    const auto& effects = m.at("effects");
    const auto names = fitting::effect_names();
    if (!effects.is_array()) throw nurbs::InputError(where + ".effects: must be a list of names");
    s.identify.candidates.emplace();  // [] is the nominal fit alone
    for (const auto& e : effects) {
      if (!e.is_string() ||
          std::find(names.begin(), names.end(), e.get<std::string>()) == names.end()) {
        std::string list;
        for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
        throw nurbs::InputError(where + ".effects: " + e.dump() +
                                " is not an effect; use: " + list);
      }
      s.identify.candidates->push_back(e.get<std::string>());
    }
  }
  return s;
}

}  // namespace isospring::io
