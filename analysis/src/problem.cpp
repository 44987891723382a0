// Side names of the problem contract: u0 u1 v0 v1 w0 w1.
#include "isospring/analysis/problem.hpp"

#include "isospring/nurbs/error.hpp"

namespace isospring::analysis {

Side parse_side(const std::string& name, int patch) {
  if (name.size() == 2 && (name[0] == 'u' || name[0] == 'v' || name[0] == 'w') &&
      (name[1] == '0' || name[1] == '1')) {
    return Side{patch, name[0] - 'u', name[1] - '0'};
  }
  throw nurbs::InputError("unknown side \"" + name + "\" of patch " + std::to_string(patch) +
                          ": use one of u0 u1 v0 v1 w0 w1 (direction u/v/w, end 0 = first knot, "
                          "1 = last knot)");
}

std::string side_name(const Side& side) {
  std::string name;
  name += static_cast<char>('u' + side.dir);
  name += static_cast<char>('0' + side.end);
  return name;
}

}  // namespace isospring::analysis
