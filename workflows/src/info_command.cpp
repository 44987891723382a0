// `isospring info` (see info_command.hpp).
#include "isospring/workflows/info_command.hpp"

#include <iomanip>
#include <sstream>

#include "isospring/geometry/cad.hpp"
#include "isospring/geometry/measure.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/input_file.hpp"
#include "isospring/io/report_patch.hpp"

namespace isospring::workflows {
// The use cases read and write io's formats; io's names are used unqualified here.
using namespace isospring::io;
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

void print_case_summary(std::ostream& out, const Case& c) {
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

}  // namespace

std::string file_info_text(const std::string& file) {
  std::ostringstream out;
  out << std::setprecision(10);
  switch (input_kind(file)) {
    case InputKind::kCad: {
      const geometry::CadModel model = geometry::read_cad(file);
      out << geometry::describe(model);
      std::vector<nurbs::Patch> patches = model.volume_patches;
      if (patches.empty()) {
        patches = model.face_patches;
        patches.insert(patches.end(), model.split_patches.begin(), model.split_patches.end());
      }
      out << "NURBS patches usable for analysis: " << patches.size() << "\n";
      print_patches(out, patches);
      break;
    }
    case InputKind::kCaseFile: {
      const Case c = read_case_file(file);
      out << file << ": ";
      print_case_summary(out, c);
      print_patches(out, c.problem.patches);
      break;
    }
    case InputKind::kPatchFile: {
      const auto patches = read_patches_any(file);
      out << file << ": " << patches.size() << (patches.size() == 1 ? " patch" : " patches")
          << "\n";
      print_patches(out, patches);
      break;
    }
  }
  return out.str();
}

// The same information as JSON (--json), for scripts: {"file", "kind", "patches": [patch_json],
// "total_measure"} plus "case" (name, formulation, material, supports, load_cases) or "cad"
// (unit, counts, volume, area, faces usable).
nlohmann::json file_info_json(const std::string& file) {
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
                  {"solid_notes", model.solid_notes},
                  {"warnings", model.warnings}};
      break;
    }
    case InputKind::kCaseFile: {
      const Case c = read_case_file(file);
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

}  // namespace isospring::workflows
