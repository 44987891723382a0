// Patch files and case files (io module) for Python: isospring.read_patch_file,
// isospring.write_patch_file and isospring.read_case, which returns an isospring.Case, the
// validated and discretised case as `isospring analyze` reads it.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "bindings.hpp"
#include "isospring/io/case_file.hpp"
#include "isospring/io/patch_file.hpp"
#include "isospring/io/report_case.hpp"

namespace py = pybind11;

namespace isospring::python {
namespace {

std::vector<int> used_entries(const std::array<int, 3>& values, const io::Case& c) {
  const int d = c.geometry.empty() ? 0 : c.geometry.front().param_dim();
  return {values.begin(), values.begin() + d};
}

}  // namespace

void bind_io(py::module_& m) {
  m.def("read_patch_file", &io::read_patch_file, py::arg("path"),
        "The patches of a patch file (docs/case-files.md, \"Patch files\"); raises InputError "
        "naming the file, the patch and the field when it is invalid.");
  m.def("write_patch_file", &io::write_patch_file, py::arg("path"), py::arg("patches"),
        "Writes patches as a patch file (atomically, full double precision).");

  py::class_<io::Case>(m, "Case",
                       "A validated case file: exact geometry, the discretised patches, material, "
                       "supports and load cases (docs/case-files.md).")
      .def_readonly("name", &io::Case::name)
      .def_property_readonly("file", [](const io::Case& c) { return c.file; })
      .def_readonly("dimension", &io::Case::dimension, "2 (plane) or 3 (solid).")
      .def_property_readonly(
          "formulation",
          [](const io::Case& c) { return io::formulation_name(c.problem.formulation); })
      .def_readonly("geometry", &io::Case::geometry, "The exact patches, before refinement.")
      .def_property_readonly(
          "patches", [](const io::Case& c) { return c.problem.patches; },
          "The patches at the case's discretisation (what the analysis solves on).")
      .def_property_readonly(
          "degree", [](const io::Case& c) { return used_entries(c.discretization.degree, c); })
      .def_property_readonly(
          "elements", [](const io::Case& c) { return used_entries(c.discretization.elements, c); })
      .def_property_readonly("material",
                             [](const io::Case& c) {
                               const analysis::Material& mat = c.problem.material;
                               py::dict d;
                               d["E"] = mat.youngs_modulus;
                               d["nu"] = mat.poisson_ratio;
                               d["density"] = mat.density;
                               d["thickness"] = mat.thickness;
                               return d;
                             })
      .def_property_readonly("load_case_ids",
                             [](const io::Case& c) {
                               std::vector<std::string> ids;
                               for (const auto& lc : c.problem.load_cases) ids.push_back(lc.id);
                               return ids;
                             })
      .def("__repr__", [](const io::Case& c) {
        return "<isospring.Case '" + c.name + "' " + std::to_string(c.dimension) + "D, " +
               std::to_string(c.problem.patches.size()) + " patch(es), " +
               std::to_string(c.problem.load_cases.size()) + " load case(s)>";
      });

  m.def(
      "read_case", [](const std::filesystem::path& path) { return io::read_case_file(path); },
      py::arg("path"),
      "Reads, validates and discretises a case file; raises InputError with the message "
      "`isospring` prints for the same file.");
}

}  // namespace isospring::python
