// vaw-step-import: each face of a solid as vaw needs it (step_reader.hpp): plane, cylinder or cone (analytic,
// or a B-spline that is one within tolerance) or other, with its outward side and axial extent.
#include <BRepAdaptor_Surface.hxx>
#include <BRepGProp.hxx>
#include <BRepLProp_SLProps.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <GeomLProp_SLProps.hxx>
#include <GeomLib_IsPlanarSurface.hxx>
#include <Geom_Surface.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Cone.hxx>
#include <gp_Cylinder.hxx>
#include <gp_Pln.hxx>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "step_reader.hpp"

namespace vaw::step::reader {

namespace {

// The material's outward normal at the middle of the face's parameter range.
std::optional<gp_Dir> outwardNormal(const TopoDS_Face& face, const BRepAdaptor_Surface& surface) {
  Standard_Real u1, u2, v1, v2;
  BRepTools::UVBounds(face, u1, u2, v1, v2);
  BRepLProp_SLProps props(surface, 0.5 * (u1 + u2), 0.5 * (v1 + v2), 1, 1e-9);
  if (!props.IsNormalDefined()) return std::nullopt;
  gp_Dir n = props.Normal();
  if (face.Orientation() == TopAbs_REVERSED) n.Reverse();
  return n;
}

struct CylinderFit {
  gp_Pnt axisPoint;
  gp_Dir axis;
  double radius;
};

double distanceToAxis(const gp_Pnt& p, const gp_Pnt& a, const gp_Dir& d) {
  const gp_Vec v(a, p);
  return v.Crossed(gp_Vec(d)).Magnitude();
}

// A free-form surface that is a cylinder within `tol`: the axis from the principal curvatures at the
// middle, then every point of a grid over the face's parameter range within `tol` of that cylinder.
// (OCCT 7.6 has no GeomConvert_SurfToAnaSurf.)
std::optional<CylinderFit> recogniseCylinder(const Handle(Geom_Surface) & s, double u1, double u2, double v1, double v2,
                                             double tol) {
  GeomLProp_SLProps mid(s, 0.5 * (u1 + u2), 0.5 * (v1 + v2), 2, 1e-9);
  if (!mid.IsCurvatureDefined()) return std::nullopt;
  const double kMax = mid.MaxCurvature(), kMin = mid.MinCurvature();
  const bool maxIsRound = std::abs(kMax) >= std::abs(kMin);
  const double k = maxIsRound ? kMax : kMin;
  if (std::abs(k) < 1e-12) return std::nullopt;
  gp_Dir dMax, dMin;
  mid.CurvatureDirections(dMax, dMin);
  const gp_Dir axis = maxIsRound ? dMin : dMax;
  const double r = 1.0 / std::abs(k);
  const gp_Pnt p = mid.Value();
  const gp_Vec n(mid.Normal());
  for (const double sign : {1.0, -1.0}) {
    const gp_Pnt a = p.Translated(n * (sign * r));
    bool fits = true;
    constexpr int kSteps = 8;
    for (int i = 0; i <= kSteps && fits; ++i)
      for (int j = 0; j <= kSteps && fits; ++j) {
        const gp_Pnt q = s->Value(u1 + (u2 - u1) * i / kSteps, v1 + (v2 - v1) * j / kSteps);
        fits = std::abs(distanceToAxis(q, a, axis) - r) <= tol;
      }
    if (fits) return CylinderFit{a, axis, r};
  }
  return std::nullopt;
}

struct ConeFit {
  gp_Pnt apex;
  gp_Dir axis;  // from the apex, the way the cone widens
  double halfAngle;
};

// A free-form surface that is a cone within `tol`: the straight line through each of three points of the
// face (the principal direction without curvature) meets the others at the apex, and the axis makes one
// angle with all three; then every point of a grid over the face within `tol` of that cone.
std::optional<ConeFit> recogniseCone(const Handle(Geom_Surface) & s, double u1, double u2, double v1, double v2, double tol) {
  const auto ruling = [&](double u, double v) -> std::optional<std::pair<gp_Pnt, gp_Vec>> {
    GeomLProp_SLProps props(s, u, v, 2, 1e-9);
    if (!props.IsCurvatureDefined() || props.IsUmbilic()) return std::nullopt;
    gp_Dir dMax, dMin;
    props.CurvatureDirections(dMax, dMin);
    const bool minIsStraight = std::abs(props.MinCurvature()) <= std::abs(props.MaxCurvature());
    const double straight = minIsStraight ? props.MinCurvature() : props.MaxCurvature();
    const double round = minIsStraight ? props.MaxCurvature() : props.MinCurvature();
    if (std::abs(straight) > 1e-6 * std::abs(round)) return std::nullopt;
    return std::pair{props.Value(), gp_Vec(minIsStraight ? dMin : dMax)};
  };
  const double um = 0.5 * (u1 + u2), vm = 0.5 * (v1 + v2);
  // Three points across the rulings: along whichever parameter runs round the cone.
  for (const bool alongU : {true, false}) {
    std::optional<std::pair<gp_Pnt, gp_Vec>> r[3];
    for (int k = 0; k < 3; ++k) {
      const double f = 0.2 + 0.3 * k;
      r[k] = alongU ? ruling(u1 + (u2 - u1) * f, vm) : ruling(um, v1 + (v2 - v1) * f);
      if (!r[k]) break;
    }
    if (!r[0] || !r[1] || !r[2]) continue;
    // The point nearest the three lines (least squares): sum (I - d d^T) (x - p) = 0.
    gp_Mat m(0, 0, 0, 0, 0, 0, 0, 0, 0);
    gp_XYZ rhs(0, 0, 0);
    for (const auto& line : r) {
      const gp_XYZ d = line->second.XYZ();
      gp_Mat proj;
      for (int i = 1; i <= 3; ++i)
        for (int j = 1; j <= 3; ++j) proj.SetValue(i, j, (i == j ? 1.0 : 0.0) - d.Coord(i) * d.Coord(j));
      m += proj;
      rhs += line->first.XYZ().Multiplied(proj);  // proj times the point
    }
    if (std::abs(m.Determinant()) < 1e-12) continue;
    const gp_Pnt apex(rhs.Multiplied(m.Inverted()));
    gp_Vec d[3];
    for (int k = 0; k < 3; ++k) {
      d[k] = r[k]->second;
      if (gp_Vec(apex, r[k]->first).Dot(d[k]) < 0) d[k].Reverse();
    }
    const gp_Vec n = (d[0] - d[1]).Crossed(d[0] - d[2]);
    if (n.Magnitude() < 1e-9) continue;
    gp_Dir axis(n);
    if (gp_Vec(axis).Dot(d[0]) < 0) axis.Reverse();
    const double half = std::acos(std::clamp(gp_Vec(axis).Dot(d[0]), -1.0, 1.0));
    if (!(half > 1e-3 && half < 0.5 * M_PI - 1e-3)) continue;
    bool fits = true;
    constexpr int kSteps = 8;
    for (int i = 0; i <= kSteps && fits; ++i)
      for (int j = 0; j <= kSteps && fits; ++j) {
        const gp_Vec q(apex, s->Value(u1 + (u2 - u1) * i / kSteps, v1 + (v2 - v1) * j / kSteps));
        const double t = q.Dot(gp_Vec(axis));
        const double rho = (q - gp_Vec(axis) * t).Magnitude();
        fits = t > -tol && std::abs(rho * std::cos(half) - t * std::sin(half)) <= tol;
      }
    if (fits) return ConeFit{apex, axis, half};
  }
  return std::nullopt;
}

// The face's extent along the axis, from its triangulation (nodes on its boundary are on the true edges).
void axialExtent(FaceOut& f, const std::vector<gp_Pnt>& nodes) {
  double lo = 1e300, hi = -1e300;
  const gp_Vec d(f.direction);
  for (const gp_Pnt& q : nodes) {
    const double t = gp_Vec(f.point, q).Dot(d);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  if (lo <= hi) f.axialMin = lo, f.axialMax = hi;
}

// Material inside (a shaft, a countersunk head) when the outward normal at a point of the surface points
// away from the axis.
bool materialInside(const gp_Pnt& axisPoint, const gp_Dir& axis, const std::optional<gp_Dir>& outward, const gp_Pnt& onSurface) {
  gp_Vec radial(axisPoint, onSurface);
  radial -= gp_Vec(axis) * radial.Dot(gp_Vec(axis));
  return !outward || radial.Dot(gp_Vec(*outward)) >= 0.0;
}

void setCylinder(FaceOut& f, const gp_Pnt& axisPoint, const gp_Dir& axis, double radius, const std::optional<gp_Dir>& outward,
                 const gp_Pnt& onSurface) {
  f.surface = vaw::step::SurfaceKind::Cylinder;
  f.point = axisPoint;
  f.direction = axis;
  f.radius = radius;
  f.convex = materialInside(axisPoint, axis, outward, onSurface);
}

void setCone(FaceOut& f, const gp_Pnt& apex, const gp_Dir& axis, double halfAngle, const std::optional<gp_Dir>& outward,
             const gp_Pnt& onSurface, const std::vector<gp_Pnt>& nodes) {
  f.surface = vaw::step::SurfaceKind::Cone;
  f.point = apex;
  f.direction = axis;
  f.halfAngle = halfAngle;
  f.convex = materialInside(apex, axis, outward, onSurface);
  axialExtent(f, nodes);
  f.radius = std::max(0.0, f.axialMax) * std::tan(halfAngle);
}

}  // namespace

bool analytic(const TopoDS_Face& face) {
  switch (BRepAdaptor_Surface(face, false).GetType()) {
    case GeomAbs_Plane:
    case GeomAbs_Cylinder:
    case GeomAbs_Cone:
    case GeomAbs_Sphere:
    case GeomAbs_Torus: return true;
    default: return false;
  }
}

FaceOut classify(const TopoDS_Face& face, double tol, const std::vector<gp_Pnt>& nodes) {
  FaceOut f;
  // The area as the volume is integrated (step_solids.cpp, volumeProperties): at a fixed order on an analytic
  // surface, adaptively on a free-form one.
  GProp_GProps sp;
  if (analytic(face)) BRepGProp::SurfaceProperties(face, sp);
  else BRepGProp::SurfaceProperties(face, sp, 1e-9);
  f.area = sp.Mass();
  const gp_Pnt centre = sp.CentreOfMass();
  const BRepAdaptor_Surface surface(face, true);
  const std::optional<gp_Dir> outward = outwardNormal(face, surface);
  Standard_Real u1, u2, v1, v2;
  BRepTools::UVBounds(face, u1, u2, v1, v2);
  const gp_Pnt mid = surface.Value(0.5 * (u1 + u2), 0.5 * (v1 + v2));
  switch (surface.GetType()) {
    case GeomAbs_Plane: {
      const gp_Pln pl = surface.Plane();
      f.surface = vaw::step::SurfaceKind::Plane;
      gp_Dir n = pl.Axis().Direction();
      if (outward && gp_Vec(n).Dot(gp_Vec(*outward)) < 0) n.Reverse();
      f.direction = n;
      // The face's centroid is on the plane; the plane's own origin may be far from the part.
      f.point = centre;
      return f;
    }
    case GeomAbs_Cylinder: {
      const gp_Cylinder c = surface.Cylinder();
      setCylinder(f, c.Location(), c.Axis().Direction(), c.Radius(), outward, mid);
      axialExtent(f, nodes);
      return f;
    }
    case GeomAbs_Cone: {
      const gp_Cone c = surface.Cone();
      // The cone's own axis points where it widens only for a positive semi-angle.
      gp_Dir axis = c.Axis().Direction();
      if (c.SemiAngle() < 0.0) axis.Reverse();
      setCone(f, c.Apex(), axis, std::abs(c.SemiAngle()), outward, mid, nodes);
      return f;
    }
    case GeomAbs_Sphere:
    case GeomAbs_Torus: return f;  // analytic, and none of the above
    default: break;
  }
  // Free-form: some exporters write every face as a B-spline.
  const Handle(Geom_Surface) s = BRep_Tool::Surface(face);
  if (s.IsNull()) return f;
  GeomLib_IsPlanarSurface planar(s, tol);
  if (planar.IsPlanar()) {
    f.surface = vaw::step::SurfaceKind::Plane;
    f.fromSpline = true;
    gp_Dir n = planar.Plan().Axis().Direction();
    if (outward && gp_Vec(n).Dot(gp_Vec(*outward)) < 0) n.Reverse();
    f.direction = n;
    f.point = centre;
    return f;
  }
  if (const auto cyl = recogniseCylinder(s, u1, u2, v1, v2, tol)) {
    setCylinder(f, cyl->axisPoint, cyl->axis, cyl->radius, outward, mid);
    f.fromSpline = true;
    axialExtent(f, nodes);
    return f;
  }
  if (const auto cone = recogniseCone(s, u1, u2, v1, v2, tol)) {
    setCone(f, cone->apex, cone->axis, cone->halfAngle, outward, mid, nodes);
    f.fromSpline = true;
  }
  return f;
}

}  // namespace vaw::step::reader
