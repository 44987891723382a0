#pragma once
// Helpers for CAD tests on parts made with OpenCascade: write a shape to STEP (metres) and read it
// back through read_cad, and half-spaces for cutting parts.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: CTest runs tests in parallel processes

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepPrimAPI_MakeHalfSpace.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <filesystem>
#include <gp_Pln.hxx>
#include <string>

#include "isospring/geometry/cad.hpp"

namespace isospring::geometry::test {

inline CadModel step_round_trip(const TopoDS_Shape& shape, const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      (std::string("isospring_test_cad_io-") + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  STEPControl_Controller::Init();
  Interface_Static::SetCVal("xstep.cascade.unit", "M");
  Interface_Static::SetCVal("write.step.unit", "M");
  STEPControl_Writer writer;
  EXPECT_EQ(writer.Transfer(shape, STEPControl_AsIs), IFSelect_RetDone);
  EXPECT_EQ(writer.Write((dir / name).string().c_str()), IFSelect_RetDone);
  return read_cad(dir / name);
}

/// Half-space below the plane through `point` with normal `up` (material on the -up side).
inline TopoDS_Shape half_space_below(const gp_Pnt& point, const gp_Dir& up) {
  const TopoDS_Face plane = BRepBuilderAPI_MakeFace(gp_Pln(point, up)).Face();
  return BRepPrimAPI_MakeHalfSpace(plane, point.Translated(-gp_Vec(up))).Solid();
}

}  // namespace isospring::geometry::test
