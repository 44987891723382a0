// `isospring info FILE`: what a patch file, a case file or a CAD part holds: per patch its
// dimensions, degrees, knot vectors (unique knots with multiplicities), control points, elements,
// bounding box and length/area/volume; for a case file also its material, supports and loads; for
// a CAD part OpenCascade's own report (units, faces, volume and area).
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli_util.hpp"
#include "command.hpp"
#include "file_report.hpp"
#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/measure.hpp"
#include "isospring/io/case_file.hpp"

namespace isospring::apps {
namespace {

void print_patch_summary(std::ostream& out, int index, const nurbs::Patch& patch) {
  static const char* kDirection[] = {"u", "v", "w"};
  out << "patch " << index << ": parametric dimension " << patch.param_dim()
      << ", physical dimension " << patch.physical_dim()
      << (patch.is_rational() ? ", rational" : "") << "\n";
  out << "  control points: " << patch.num_points() << " (";
  for (int d = 0; d < patch.param_dim(); ++d) out << (d ? " x " : "") << patch.num_points(d);
  out << "), elements: " << patch.num_elements() << "\n";
  for (int d = 0; d < patch.param_dim(); ++d) {
    const nurbs::KnotVector& kv = patch.knots(d);
    const auto unique = kv.unique();
    const auto mult = kv.multiplicities();
    out << "  " << kDirection[d] << ": degree " << kv.degree() << ", " << kv.num_elements()
        << " elements, knots (value^multiplicity):";
    for (size_t k = 0; k < unique.size(); ++k) out << " " << unique[k] << "^" << mult[k];
    out << "\n";
  }
  const auto [lo, hi] = patch.control_bounds();
  out << "  bounding box of the control net: [" << lo.x() << ", " << hi.x() << "] x [" << lo.y()
      << ", " << hi.y() << "] x [" << lo.z() << ", " << hi.z() << "]\n";
  static const char* kMeasure[] = {"", "length", "area", "volume"};
  out << "  " << kMeasure[patch.param_dim()] << ": " << geometry::measure(patch) << "\n";
}

void print_patches(std::ostream& out, const std::vector<nurbs::Patch>& patches) {
  for (size_t i = 0; i < patches.size(); ++i)
    print_patch_summary(out, static_cast<int>(i), patches[i]);
  if (patches.size() > 1) {
    static const char* kMeasure[] = {"", "length", "area", "volume"};
    out << "total " << kMeasure[patches.front().param_dim()] << ": " << geometry::measure(patches)
        << "\n";
  }
}

void print_case_summary(std::ostream& out, const io::Case& c) {
  const analysis::Problem& problem = c.problem;
  static const char* kFormulation[] = {"plane stress", "plane strain", "3D solid"};
  out << "case '" << c.name << "': " << kFormulation[static_cast<int>(problem.formulation)]
      << ", E = " << problem.material.youngs_modulus
      << " Pa, nu = " << problem.material.poisson_ratio
      << ", density = " << problem.material.density << " kg/m^3";
  if (problem.formulation != analysis::Formulation::kSolid)
    out << ", thickness = " << problem.material.thickness << " m";
  out << "\n"
      << problem.supports.size() << " supports, " << problem.load_cases.size() << " load cases:";
  for (const auto& load_case : problem.load_cases) out << " " << load_case.id;
  out << "\n" << problem.patches.size() << " discretised patches:\n";
}

// The same information as JSON (--json), for scripts: {"file", "kind", "patches": [patch_json],
// "total_measure"} plus "case" (name, formulation, material, supports, load_cases) or "cad"
// (unit, counts, volume, area, faces usable).
nlohmann::json info_json(const std::string& file) {
  nlohmann::json j = {{"file", file}};
  std::vector<nurbs::Patch> patches;
  switch (input_kind(file)) {
    case InputKind::kCad: {
      const geometry::CadModel model = geometry::read_cad(file);
      patches = model.volume_patches;
      if (patches.empty()) {
        patches = model.face_patches;
        patches.insert(patches.end(), model.split_patches.begin(), model.split_patches.end());
      }
      int usable = 0;
      nlohmann::json faces = nlohmann::json::array();
      for (const auto& f : model.face_reports) {
        usable += f.natural || f.coons || f.split > 0;
        // How the face will be analysed: one exact patch, the Coons patch of its 4 edges, cut
        // into conforming patches, or not at all (and why).
        const std::string how = f.natural ? "exact patch"
                                : f.coons ? "Coons patch"
                                : f.split ? "split"
                                          : "not supported";
        faces.push_back({{"index", f.index},
                         {"surface_type", f.surface_type},
                         {"analysis", how},
                         {"patches", f.natural || f.coons ? 1 : f.split},
                         {"area", f.area},
                         {"note", f.note}});
      }
      j["kind"] = "cad";
      j["cad"] = {{"file_unit", model.file_unit},
                  {"solids", model.solids},
                  {"faces", model.faces},
                  {"edges", model.edges},
                  {"usable_faces", usable},
                  {"volume", model.volume},
                  {"area", model.area},
                  {"face_analysis", faces},
                  {"solid_notes", model.solid_notes}};
      break;
    }
    case InputKind::kCaseFile: {
      const io::Case c = io::read_case_file(file);
      const analysis::Problem& problem = c.problem;
      static const char* kFormulation[] = {"plane_stress", "plane_strain", "solid"};
      patches = problem.patches;
      j["kind"] = "case";
      nlohmann::json ids = nlohmann::json::array();
      for (const auto& lc : problem.load_cases) ids.push_back(lc.id);
      j["case"] = {{"name", c.name},
                   {"formulation", kFormulation[static_cast<int>(problem.formulation)]},
                   {"E", problem.material.youngs_modulus},
                   {"nu", problem.material.poisson_ratio},
                   {"density", problem.material.density},
                   {"thickness", problem.material.thickness},
                   {"supports", problem.supports.size()},
                   {"load_cases", ids}};
      break;
    }
    case InputKind::kPatchFile:
      patches = read_patches_any(file);
      j["kind"] = "patches";
      break;
  }
  j["patches"] = nlohmann::json::array();
  for (const auto& p : patches) j["patches"].push_back(patch_json(p));
  j["total_measure"] = patches.empty() ? 0.0 : geometry::measure(patches);
  return j;
}

void setup_info(CLI::App& app) {
  auto file = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand(
      "info",
      "Describe a patch file, case file or STEP/IGES part: patches, degrees, knots, "
      "control points, elements, size");
  cmd->add_option("FILE", *file, "Patch file or case file (.json), or CAD part (.step/.iges)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_flag("--json", *json,
                "Print JSON instead (patches with degrees, control points, elements, bounds, "
                "measure; case or CAD summary), full precision");
  cmd->callback([file, json] {
    if (*json) {
      std::cout << info_json(*file).dump(2) << "\n";
      return;
    }
    std::cout << std::setprecision(10);
    switch (input_kind(*file)) {
      case InputKind::kCad: {
        const geometry::CadModel model = geometry::read_cad(*file);
        std::cout << geometry::describe(model);
        std::vector<nurbs::Patch> patches = model.volume_patches;
        if (patches.empty()) {
          patches = model.face_patches;
          patches.insert(patches.end(), model.split_patches.begin(), model.split_patches.end());
        }
        std::cout << "NURBS patches usable for analysis: " << patches.size() << "\n";
        print_patches(std::cout, patches);
        break;
      }
      case InputKind::kCaseFile: {
        const io::Case c = io::read_case_file(*file);
        std::cout << *file << ": ";
        print_case_summary(std::cout, c);
        print_patches(std::cout, c.problem.patches);
        break;
      }
      case InputKind::kPatchFile: {
        const auto patches = read_patches_any(*file);
        std::cout << *file << ": " << patches.size()
                  << (patches.size() == 1 ? " patch" : " patches") << "\n";
        print_patches(std::cout, patches);
        break;
      }
    }
  });
}

}  // namespace
ISOSPRING_REGISTER_COMMAND(10, setup_info);
}  // namespace isospring::apps
