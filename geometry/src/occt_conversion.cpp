#include "occt_conversion.hpp"

#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <stdexcept>

namespace isospring::geometry::detail {

namespace {
// Distinct knots and multiplicities of one of our knot vectors, as OCCT wants them.
void occt_knots(const nurbs::KnotVector& kv, TColStd_Array1OfReal& knots,
                TColStd_Array1OfInteger& mults) {
  const std::vector<double> unique = kv.unique();
  const std::vector<int> multiplicities = kv.multiplicities();
  knots.Resize(1, static_cast<int>(unique.size()), false);
  mults.Resize(1, static_cast<int>(unique.size()), false);
  for (size_t i = 0; i < unique.size(); ++i) {
    knots.SetValue(static_cast<int>(i) + 1, unique[i]);
    mults.SetValue(static_cast<int>(i) + 1, multiplicities[i]);
  }
}
}  // namespace

nurbs::Patch patch_from_occt(const Handle(Geom_BSplineSurface) & surface) {
  if (surface->IsUPeriodic() || surface->IsVPeriodic())
    throw std::logic_error("patch_from_occt: make the surface non-periodic first");
  const int nu = surface->NbUPoles(), nv = surface->NbVPoles();
  TColStd_Array1OfReal uk(1, nu + surface->UDegree() + 1), vk(1, nv + surface->VDegree() + 1);
  surface->UKnotSequence(uk);
  surface->VKnotSequence(vk);
  std::vector<double> u_knots(uk.begin(), uk.end()), v_knots(vk.begin(), vk.end());
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  for (int j = 1; j <= nv; ++j)
    for (int i = 1; i <= nu; ++i) {
      const gp_Pnt p = surface->Pole(i, j);
      points.emplace_back(p.X(), p.Y(), p.Z());
      weights.push_back(surface->Weight(i, j));
    }
  return nurbs::Patch({nurbs::KnotVector(surface->UDegree(), u_knots, "CAD surface u knots"),
                       nurbs::KnotVector(surface->VDegree(), v_knots, "CAD surface v knots")},
                      points, weights);
}

nurbs::Patch patch_from_occt(const Handle(Geom_BSplineCurve) & curve) {
  if (curve->IsPeriodic()) throw std::logic_error("patch_from_occt: make the curve non-periodic");
  TColStd_Array1OfReal knots(1, curve->NbPoles() + curve->Degree() + 1);
  curve->KnotSequence(knots);
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  for (int i = 1; i <= curve->NbPoles(); ++i) {
    const gp_Pnt p = curve->Pole(i);
    points.emplace_back(p.X(), p.Y(), p.Z());
    weights.push_back(curve->Weight(i));
  }
  return nurbs::Patch(
      {nurbs::KnotVector(curve->Degree(), std::vector<double>(knots.begin(), knots.end()),
                         "CAD edge curve knots")},
      points, weights);
}

Handle(Geom_BSplineSurface) occt_from_patch(const nurbs::Patch& patch) {
  if (patch.param_dim() != 2) throw std::logic_error("occt_from_patch: surfaces only");
  const int nu = patch.num_points(0), nv = patch.num_points(1);
  TColgp_Array2OfPnt poles(1, nu, 1, nv);
  TColStd_Array2OfReal weights(1, nu, 1, nv);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const Eigen::Vector3d& x = patch.control_point(patch.index(i, j));
      poles.SetValue(i + 1, j + 1, gp_Pnt(x.x(), x.y(), x.z()));
      weights.SetValue(i + 1, j + 1, patch.weight(patch.index(i, j)));
    }
  TColStd_Array1OfReal uk(1, 1), vk(1, 1);
  TColStd_Array1OfInteger um(1, 1), vm(1, 1);
  occt_knots(patch.knots(0), uk, um);
  occt_knots(patch.knots(1), vk, vm);
  return new Geom_BSplineSurface(poles, weights, uk, vk, um, vm, patch.degree(0), patch.degree(1));
}

}  // namespace isospring::geometry::detail
