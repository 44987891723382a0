#include <cstdlib>
#include <sstream>

#include "isospring/io/atomic_file.hpp"
#include "isospring/io/calculix.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::io {

// ccx prints, for every *NODE PRINT request and increment,
//    displacements (vx,vy,vz) for set NALL and time  0.1000000E+01
//   <blank line>
//          1  1.234567E-03 -2.345678E-04  0.000000E+00
// and ends the block at the next blank line.
namespace {

// The blocks whose header line contains `header` (vectors per node, same layout for every
// quantity).
std::vector<CalculixDisplacements> read_blocks(const std::filesystem::path& path,
                                               const std::string& header) {
  const std::string text = read_text_file(path, "CalculiX results (.dat)");
  std::istringstream in(text);
  std::vector<CalculixDisplacements> blocks;
  std::string line;
  bool in_block = false;
  while (std::getline(in, line)) {
    if (line.find(header) != std::string::npos) {
      CalculixDisplacements block;
      const size_t at = line.find("time");
      if (at != std::string::npos) block.time = std::strtod(line.c_str() + at + 4, nullptr);
      blocks.push_back(block);
      in_block = true;
      continue;
    }
    if (!in_block) continue;
    std::istringstream fields(line);
    int node = 0;
    Eigen::Vector3d u;
    if (fields >> node >> u.x() >> u.y() >> u.z()) {
      blocks.back().nodes[node] = u;
    } else if (!blocks.back().nodes.empty()) {
      in_block = false;  // the blank line after the data
    }
  }
  return blocks;
}

}  // namespace

std::vector<CalculixDisplacements> read_calculix_dat(const std::filesystem::path& path) {
  auto blocks = read_blocks(path, "displacements (vx,vy,vz)");
  if (blocks.empty())
    throw nurbs::InputError(path.string() +
                            ": no displacement block; the deck must request *NODE PRINT U and "
                            "ccx must have finished (see the .sta and console output)");
  return blocks;
}

std::vector<CalculixDisplacements> read_calculix_reactions(const std::filesystem::path& path) {
  auto blocks = read_blocks(path, "forces (fx,fy,fz)");
  if (blocks.empty())
    throw nurbs::InputError(path.string() +
                            ": no force block; the deck must request *NODE PRINT RF "
                            "(CalculixOptions::print_reactions) and ccx must have finished");
  return blocks;
}

}  // namespace isospring::io
