#pragma once
// Parts with closed-form elasticity solutions for the immersed use-case tests, built with
// OpenCascade and written to STEP in a temporary folder, with their immersed case files.
#include <unistd.h>  // getpid: CTest runs tests in parallel processes

#include <BRepAlgoAPI_Common.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace isospring::testing {

/// The octant x, y, z >= 0 of a hollow sphere (radii ri < ro, metres), as a STEP file in `dir`.
inline std::filesystem::path write_sphere_octant(const std::filesystem::path& dir, double ri,
                                                 double ro) {
  const TopoDS_Shape shell =
      BRepAlgoAPI_Cut(BRepPrimAPI_MakeSphere(ro).Shape(), BRepPrimAPI_MakeSphere(ri).Shape())
          .Shape();
  const TopoDS_Shape octant =
      BRepAlgoAPI_Common(shell,
                         BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), ro * 1.5, ro * 1.5, ro * 1.5).Shape())
          .Shape();
  STEPControl_Controller::Init();
  Interface_Static::SetCVal("xstep.cascade.unit", "M");  // the shape is in metres
  Interface_Static::SetCVal("write.step.unit", "M");
  STEPControl_Writer writer;
  const std::filesystem::path file = dir / "sphere_octant.step";
  if (writer.Transfer(octant, STEPControl_AsIs) != IFSelect_RetDone ||
      writer.Write(file.string().c_str()) != IFSelect_RetDone)
    throw std::runtime_error("could not write " + file.string());
  return file;
}

/// The immersed case of the octant under internal pressure P: symmetry on its three planes (by
/// plane selectors), the pressure on the inner sphere (the only face inside the box [0, ri]^3),
/// and the closed form `hollow_sphere` (benchmarks.md) as its analytic solution.
inline nlohmann::json sphere_octant_case(const std::string& step, double ri, double ro, double P,
                                         int cells, int degree) {
  using nlohmann::json;
  json boundary = json::array();
  for (int d = 0; d < 3; ++d) {
    json normal = {0, 0, 0};
    normal[static_cast<size_t>(d)] = -1;
    boundary.push_back(
        {{"face", {{"plane", {{"point", {0, 0, 0}}, {"normal", normal}}}}}, {"symmetry", true}});
  }
  const double e = 1e-6 * ro;
  return {
      {"name", "sphere_octant"},
      {"geometry",
       {{"type", "immersed"},
        {"file", step},
        {"cells", {cells, cells, cells}},
        {"degree", degree}}},
      {"material", {{"E", 1e5}, {"nu", 0.3}, {"density", 1000.0}}},
      {"boundary", boundary},
      {"load_cases",
       {{{"id", "pressure"},
         {"pressures",
          {{{"face", {{"box", {{"min", {-e, -e, -e}}, {"max", {ri + e, ri + e, ri + e}}}}}},
            {"value", P}}}}}}},
      {"analytic",
       {{"type", "hollow_sphere"}, {"inner_radius", ri}, {"outer_radius", ro}, {"pressure", P}}}};
}

/// A fresh temporary folder, removed with its content at the end of the scope.
struct ScratchFolder {
  std::filesystem::path path;
  explicit ScratchFolder(const std::string& name)
      : path(std::filesystem::temp_directory_path() /
             ("isospring-" + name + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~ScratchFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

inline std::filesystem::path write_json(const std::filesystem::path& file,
                                        const nlohmann::json& j) {
  std::ofstream(file) << j.dump(2) << "\n";
  return file;
}

}  // namespace isospring::testing
