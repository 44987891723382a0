// parse_number_list (see number_list.hpp).
#include "isospring/io/number_list.hpp"

#include <cmath>
#include <sstream>

#include "isospring/nurbs/error.hpp"

namespace isospring::io {

std::vector<double> parse_number_list(const std::string& text, const std::string& option) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(value))
      throw nurbs::InputError(option + ": '" + item + "' in '" + text +
                              "' is not a number; give comma-separated numbers like 0.25,0.5");
    values.push_back(value);
  }
  if (values.empty()) throw nurbs::InputError(option + ": no numbers given");
  return values;
}

}  // namespace isospring::io
