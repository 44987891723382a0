#pragma once
// Conversions between OpenCascade B-spline surfaces and isospring patches (exact: same knots,
// poles and weights).
#include <Geom_BSplineCurve.hxx>
#include <Geom_BSplineSurface.hxx>

#include "isospring/nurbs/patch.hpp"

namespace isospring::geometry::detail {

/// A non-periodic OCCT B-spline surface as a patch (u of OCCT = direction 0).
nurbs::Patch patch_from_occt(const Handle(Geom_BSplineSurface) & surface);

/// A non-periodic, clamped OCCT B-spline curve as a curve patch (param_dim 1).
nurbs::Patch patch_from_occt(const Handle(Geom_BSplineCurve) & curve);

/// A surface patch as an OCCT B-spline surface.
Handle(Geom_BSplineSurface) occt_from_patch(const nurbs::Patch& patch);

}  // namespace isospring::geometry::detail
