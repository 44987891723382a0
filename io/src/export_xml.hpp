#pragma once
// Private helpers for the XML exporters (MJCF, SOFA): exact numbers and escaping.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "isospring/analysis/spring_network.hpp"

namespace isospring::io::detail {

/// %.17g: reads back to the same double.
std::string number(double value);
/// "x y z" with number().
std::string vector3(const Eigen::Vector3d& v);
/// Space-separated numbers.
std::string numbers(const std::vector<double>& values);
/// Escapes & < > " for attribute values.
std::string xml_escape(const std::string& text);
/// "8 volume terms", "8 shear terms" or "8 volume terms and 8 shear terms" (the cell terms no
/// engine export can express).
std::string cell_terms(const analysis::SpringNetwork& network);
/// Text safe inside <!-- -->: "--" is not allowed there.
std::string xml_comment(const std::string& text);

}  // namespace isospring::io::detail
