#pragma once
// "0.3,0.5" -> {0.3, 0.5}: the comma-separated numbers of command-line options (--at, --gravity,
// --insert, --degrees, --point), here so that the library's use cases that take such text
// (study_quantity.hpp) and the program read them alike.
#include <string>
#include <vector>

namespace isospring::io {

/// Throws nurbs::InputError naming `option` on anything but finite comma-separated numbers.
std::vector<double> parse_number_list(const std::string& text, const std::string& option);

}  // namespace isospring::io
