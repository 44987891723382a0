#pragma once
// The CAD files of a folder and the solids of each, for tests that check every shipped part.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>
#include <vector>

#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/nurbs/error.hpp"

namespace isospring::test {

/// The STEP and IGES files directly in `dir`, sorted.
inline std::vector<std::filesystem::path> cad_files(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  for (const std::filesystem::directory_entry& e : std::filesystem::directory_iterator(dir)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (e.is_regular_file() && (ext == ".step" || ext == ".stp" || ext == ".igs" || ext == ".iges"))
      files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

/// The solids of a file: the only one, or each of several (read_cad_solid refuses a file with
/// several solids unless one is chosen).
inline std::vector<geometry::CadSolid> solids_of(const std::filesystem::path& file) {
  try {
    return {geometry::read_cad_solid(file)};
  } catch (const nurbs::InputError& e) {
    if (std::string(e.what()).find("solids") == std::string::npos) throw;
  }
  std::vector<geometry::CadSolid> solids;
  for (int body = 0;; ++body) {
    try {
      solids.push_back(geometry::read_cad_solid(file, body));
    } catch (const nurbs::InputError&) {
      break;
    }
  }
  return solids;
}

}  // namespace isospring::test
