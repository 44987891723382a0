// Immersed domain of a CAD solid with about 100 faces: classification of the background cells on
// the exact B-rep and the cut-cell and boundary quadrature (immersed_cad.hpp). The part is a
// plate 200 x 100 x 10 mm with an 8 x 4 array of through-holes of radius 4 mm, its four vertical
// edges rounded (r 8 mm) and both rims of every hole rounded (r 1.5 mm above, 1 mm below): 106
// faces (planes, cylinders, tori of the rims and the corner fillets), built with
// OpenCascade (Booleans and fillets make the test part; the immersion itself uses none).
// Counters: the time of each stage (s) and the work (cells, lines, distance queries).
//
// BM_ImmerseFreeformPart: gmsh's t20 nut, every face a trimmed B-spline (the B-spline line
// path), with the default options.
//
// BM_AnalyzeHoledPlate: the same part end to end as `isospring analyze` runs it
// (workflows::run_analyze_immersed from its STEP file): immersion, assembly, solve and the fields
// on the part's triangulation, the plate clamped at x = 0 under gravity, p = 2 with about 50,000
// DOFs at 2.8 mm cells. Counters: the DOFs and the time of each stage (s).
#include <benchmark/benchmark.h>

#include <unistd.h>
#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRep_Builder.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "../geometry/src/cad_solid_shape.hpp"
#include "isospring/geometry/immersed_cad.hpp"
#include "isospring/io/report.hpp"
#include "isospring/workflows/analyze_immersed.hpp"

namespace {

using namespace isospring::geometry;

TopoDS_Shape holed_plate() {
  const double a = 0.2, b = 0.1, t = 0.01;
  TopoDS_Compound holes;
  BRep_Builder builder;
  builder.MakeCompound(holes);
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 4; ++j)
      builder.Add(holes, BRepPrimAPI_MakeCylinder(
                             gp_Ax2(gp_Pnt(0.0265 + 0.021 * i, 0.0175 + 0.0217 * j, -0.001),
                                    gp_Dir(0, 0, 1)),
                             0.004, t + 0.002)
                             .Shape());
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(a, b, t).Shape();
  BRepFilletAPI_MakeFillet corners(box);
  for (TopExp_Explorer e(box, TopAbs_EDGE); e.More(); e.Next()) {
    BRepAdaptor_Curve c(TopoDS::Edge(e.Current()));
    const gp_Pnt p = c.Value(c.FirstParameter()), q = c.Value(c.LastParameter());
    if (std::abs(p.X() - q.X()) < 1e-12 && std::abs(p.Y() - q.Y()) < 1e-12)
      corners.Add(0.008, TopoDS::Edge(e.Current()));
  }
  const TopoDS_Shape plate = BRepAlgoAPI_Cut(corners.Shape(), holes).Shape();
  BRepFilletAPI_MakeFillet rims(plate);
  for (TopExp_Explorer e(plate, TopAbs_EDGE); e.More(); e.Next()) {
    BRepAdaptor_Curve c(TopoDS::Edge(e.Current()));
    if (c.GetType() != GeomAbs_Circle || c.Circle().Radius() > 0.0041) continue;
    const double z = c.Value(c.FirstParameter()).Z();
    if (std::abs(z - t) < 1e-9) rims.Add(0.0015, TopoDS::Edge(e.Current()));
    if (std::abs(z) < 1e-9) rims.Add(0.001, TopoDS::Edge(e.Current()));
  }
  return rims.Shape();
}

// The work and the time of each stage as counters, and the errors against OpenCascade.
void report(benchmark::State& state, const CadSolid& solid, const ImmersedDomain& domain,
            const ImmersionStats& stats) {
  size_t points = 0;
  for (const ImmersedCell& cell : domain.cells) points += cell.points.size();
  const SolidMeasures q = measure_quadrature(domain), o = measure_solid(solid);
  state.counters["faces"] = static_cast<double>(solid.shape().faces.size());
  state.counters["cells"] = static_cast<double>(domain.cells.size());
  state.counters["cut_cells"] = stats.cut_cells;
  state.counters["cut_boxes"] = static_cast<double>(stats.cut_boxes);
  state.counters["points"] = static_cast<double>(points);
  state.counters["boundary_points"] = static_cast<double>(domain.boundary.size());
  state.counters["boundary_s"] = stats.boundary_seconds;
  state.counters["classify_s"] = stats.classification_seconds;
  state.counters["cut_cells_s"] = stats.cut_cell_seconds;
  state.counters["lines"] = static_cast<double>(stats.lines);
  state.counters["classified_lines"] = static_cast<double>(stats.classified_lines);
  state.counters["distances"] = static_cast<double>(stats.distance_queries);
  state.counters["face_lines"] = static_cast<double>(stats.face_lines);
  state.counters["binned_face_lines"] = static_cast<double>(stats.binned_face_lines);
  state.counters["face_classifications"] = static_cast<double>(stats.face_classifications);
  state.counters["threads"] = stats.threads;
  state.counters["volume_err"] = std::abs(q.volume / o.volume - 1.0);
  state.counters["area_err"] = std::abs(q.area / o.area - 1.0);
}

void BM_ImmerseHoledPlate(benchmark::State& state) {
  static const CadSolid solid = detail::make_cad_solid(holed_plate(), "holed plate");
  ImmersionOptions options;
  options.cell_size = 0.001 * static_cast<double>(state.range(0));  // mm
  // The rims' tori meet the planes and cylinders tangentially: a cell there agrees between
  // Gauss orders only slowly, so the defaults (1e-7, four bisections) bisect along every rim;
  // the bench measures the cheaper setting an analysis of this part would use.
  options.tolerance = 1e-6;
  options.max_depth = static_cast<int>(state.range(1));
  options.threads = static_cast<int>(state.range(2));
  ImmersionStats stats;
  ImmersedDomain domain;
  for (auto _ : state) {
    domain = immerse_solid(solid, options, &stats);
    benchmark::DoNotOptimize(domain.cells.data());
  }
  report(state, solid, domain, stats);
}
// {cell size in mm, max_depth, threads}: 10 mm (20 x 10 x 1 cells) and 5 mm (40 x 20 x 2). CPU
// time is the process's (all threads), time the wall clock.
BENCHMARK(BM_ImmerseHoledPlate)
    ->Args({10, 1, 1})
    ->Args({5, 1, 1})
    ->Args({5, 2, 1})
    ->Args({5, 2, 2})
    ->Unit(benchmark::kSecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Iterations(1);

// gmsh's t20 nut (tests/data/parts/SOURCE.md): 21 trimmed B-spline faces, the defaults of
// `isospring analyze` (10 cells along the longest side, degree 2, four bisections).
void BM_ImmerseFreeformPart(benchmark::State& state) {
  static const CadSolid solid = read_cad_solid(std::filesystem::path(ISOSPRING_SOURCE_DIR) /
                                               "tests/data/parts/gmsh_t20_data.step");
  ImmersionOptions options;
  options.threads = static_cast<int>(state.range(0));
  ImmersionStats stats;
  ImmersedDomain domain;
  for (auto _ : state) {
    domain = immerse_solid(solid, options, &stats);
    benchmark::DoNotOptimize(domain.cells.data());
  }
  report(state, solid, domain, stats);
}
BENCHMARK(BM_ImmerseFreeformPart)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kSecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Iterations(1);

// The plate as a STEP file (metres), read back as `isospring analyze` reads it.
std::filesystem::path plate_step() {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() /
      ("isospring_bench_plate-" + std::to_string(::getpid()) + ".step");
  STEPControl_Controller::Init();
  Interface_Static::SetCVal("xstep.cascade.unit", "M");
  Interface_Static::SetCVal("write.step.unit", "M");
  STEPControl_Writer writer;
  writer.Transfer(holed_plate(), STEPControl_AsIs);
  writer.Write(file.string().c_str());
  return file;
}

// The index (as `isospring info` numbers them) of the planar face at x = 0.
int end_face(const CadSolid& solid) {
  const CadSolid::Shape& shape = solid.shape();
  for (size_t f = 0; f < shape.faces.size(); ++f) {
    BRepAdaptor_Surface s(shape.faces[f]);
    if (s.GetType() == GeomAbs_Plane && std::abs(s.Plane().Axis().Direction().X()) > 0.999 &&
        std::abs(s.Value(s.FirstUParameter(), s.FirstVParameter()).X()) < 1e-9)
      return shape.face_index[f];
  }
  return -1;
}

void BM_AnalyzeHoledPlate(benchmark::State& state) {
  static const std::filesystem::path file = plate_step();
  isospring::io::ImmersedCase c;
  c.name = "holed plate";
  c.part = file;
  c.cad = std::make_shared<CadSolid>(read_cad_solid(file));
  c.immersion.cell_size = 0.0001 * static_cast<double>(state.range(0));  // 0.1 mm
  c.immersion.tolerance = 1e-6;
  c.immersion.max_depth = 1;
  c.material = {210e9, 0.3, 7850.0, 1.0};
  isospring::analysis::ImmersedSupport clamp;
  clamp.face = end_face(*c.cad);
  clamp.fixed = {true, true, true};
  c.supports.push_back(clamp);
  isospring::io::ImmersedLoadCase gravity;
  gravity.id = "gravity";
  gravity.gravity = {0.0, 0.0, -9.81};
  c.load_cases.push_back(gravity);
  std::ostringstream log;
  const isospring::io::Progress progress("analyze", true, log, false);
  isospring::workflows::ImmersedAnalysis a;
  for (auto _ : state) {
    try {
      a = isospring::workflows::run_analyze_immersed(
          c, isospring::analysis::SolverOptions::Method::kCholesky, progress);
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      return;
    }
    benchmark::DoNotOptimize(a.load_cases.data());
  }
  const isospring::analysis::ImmersedResult& r = a.load_cases.at(0).result;
  state.counters["dofs"] = r.dofs;
  state.counters["cells"] = static_cast<double>(a.domain.cells.size());
  state.counters["cut_cells"] = a.stats.cut_cells;
  state.counters["immersion_s"] = a.immersion_seconds;
  state.counters["cut_cells_s"] = a.stats.cut_cell_seconds;
  state.counters["assembly_s"] = r.assembly_seconds;
  state.counters["solve_s"] = r.solve_seconds;
  state.counters["surface_s"] = a.surface_seconds;
  state.counters["max_u_um"] = 1e6 * a.load_cases.at(0).max_displacement;
  // In nJ; --benchmark_format=json prints every digit (a change must keep it to ~1e-12).
  state.counters["energy_nJ"] = 1e9 * r.strain_energy;
  state.counters["threads"] = a.stats.threads;
}
// Cell size in 0.1 mm: 2.8 mm gives 72 x 36 x 4 cells, about 50,000 DOFs.
BENCHMARK(BM_AnalyzeHoledPlate)
    ->Arg(28)
    ->Unit(benchmark::kSecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime()
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
