#include "export_xml.hpp"

#include <cstdio>

namespace isospring::io::detail {

std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  return buffer;
}

std::string cell_terms(const analysis::SpringNetwork& network) {
  size_t volume = 0, shear = 0, points = 0;
  for (const auto& t : network.volumes) {
    if (!t.points.empty())
      points += t.kind == analysis::CellEnergy::kShear ? 1 : 0;  // a volume and a shear term each
    else
      ++(t.kind == analysis::CellEnergy::kShear ? shear : volume);
  }
  std::string text;
  if (volume > 0) text = std::to_string(volume) + " volume terms";
  if (shear > 0) text += (text.empty() ? "" : " and ") + std::to_string(shear) + " shear terms";
  if (points > 0)
    text += (text.empty() ? "" : " and ") + std::to_string(points) +
            " strain points (volume and shear energy of the NURBS strain at a point; "
            "calibration.strain_points)";
  return text;
}

std::string vector3(const Eigen::Vector3d& v) {
  return number(v.x()) + " " + number(v.y()) + " " + number(v.z());
}

std::string numbers(const std::vector<double>& values) {
  std::string out;
  for (size_t i = 0; i < values.size(); ++i) {
    if (i > 0) out += ' ';
    out += number(values[i]);
  }
  return out;
}

std::string xml_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string xml_comment(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '-' && !out.empty() && out.back() == '-') out += ' ';
    out += c;
  }
  if (!out.empty() && out.back() == '-') out += ' ';
  return out;
}

}  // namespace isospring::io::detail
