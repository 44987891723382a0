// Immersed domain of a CAD solid with about 100 faces: classification of the background cells on
// the exact B-rep and the cut-cell and boundary quadrature (immersed_cad.hpp). The part is a
// plate 200 x 100 x 10 mm with an 8 x 4 array of through-holes of radius 4 mm, its four vertical
// edges rounded (r 8 mm) and both rims of every hole rounded (r 1.5 mm above, 1 mm below): 106
// faces (planes, cylinders, tori of the rims and the corner fillets), built with
// OpenCascade (Booleans and fillets make the test part; the immersion itself uses none).
// Counters: the time of each stage (s) and the work (cells, lines, distance queries).
#include <benchmark/benchmark.h>

#include <BRepAdaptor_Curve.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRep_Builder.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <cstdio>

#include "../geometry/src/cad_solid_shape.hpp"
#include "isospring/geometry/immersed_cad.hpp"

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

void BM_ImmerseHoledPlate(benchmark::State& state) {
  static const CadSolid solid = detail::make_cad_solid(holed_plate(), "holed plate");
  ImmersionOptions options;
  options.cell_size = 0.001 * static_cast<double>(state.range(0));  // mm
  // The rims' tori meet the planes and cylinders tangentially: a cell there agrees between
  // Gauss orders only slowly, so the defaults (1e-7, four bisections) bisect along every rim;
  // the bench measures the cheaper setting an analysis of this part would use.
  options.tolerance = 1e-6;
  options.max_depth = static_cast<int>(state.range(1));
  ImmersionStats stats;
  ImmersedDomain domain;
  for (auto _ : state) {
    domain = immerse_solid(solid, options, &stats);
    benchmark::DoNotOptimize(domain.cells.data());
  }
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
  state.counters["volume_err"] = std::abs(q.volume / o.volume - 1.0);
  state.counters["area_err"] = std::abs(q.area / o.area - 1.0);
}
// {cell size in mm, max_depth}: 10 mm (20 x 10 x 1 cells) and 5 mm (40 x 20 x 2).
BENCHMARK(BM_ImmerseHoledPlate)
    ->Args({10, 1})
    ->Args({5, 1})
    ->Args({5, 2})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
