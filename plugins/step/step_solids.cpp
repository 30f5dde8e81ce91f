// vaw-step-import, the solids (step_reader.hpp): each product's solids kept or skipped with the reason,
// their exact mass properties (Gauss integration: adaptive, 1e-9, on free-form faces), their tessellation,
// and their faces classified (step_faces.cpp), in metres.
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_Copy.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepGProp.hxx>
#include <BRepMesh_Context.hxx>
#include <BRepMesh_DelabellaMeshAlgoFactory.hxx>
#include <BRepMesh_FaceDiscret.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <Geom2d_Line.hxx>
#include <Geom2d_TrimmedCurve.hxx>
#include <IMeshTools_Parameters.hxx>
#include <Poly_Triangulation.hxx>
#include <Quantity_Color.hxx>
#include <TDF_LabelSequence.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopTools_MapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Iterator.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <XCAFDoc_ShapeTool.hxx>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "step_reader.hpp"
#include "step_result.hpp"
#include "vaw/mesh.hpp"

namespace vaw::step::reader {

json colorJson(const Quantity_Color& c) {
  Standard_Real r, g, b;
  c.Values(r, g, b, Quantity_TOC_RGB);
  return json::array({r, g, b});
}

namespace {

template <typename T>
json blob(const std::vector<T>& v) {
  std::vector<std::uint8_t> bytes(v.size() * sizeof(T));
  if (!v.empty()) std::memcpy(bytes.data(), v.data(), bytes.size());
  return json::binary(std::move(bytes));
}

json point(const gp_XYZ& p, double scale) { return json::array({p.X() * scale, p.Y() * scale, p.Z() * scale}); }

// Open CASCADE's incremental mesher with Delabella's Delaunay triangulation, not its default: a planar face
// with hundreds of holes (a large base plate) took the default seconds, all of it in its circumcircle search.
void tessellate(const TopoDS_Shape& shape, double deflection, double angle) {
  IMeshTools_Parameters parameters;
  parameters.Deflection = deflection;
  parameters.Angle = angle;
  // The faces meshed on every core (each face alone, so the result does not depend on it).
  parameters.InParallel = Standard_True;
  BRepMesh_IncrementalMesh mesher;
  mesher.SetShape(shape);
  mesher.ChangeParameters() = parameters;
  Handle(IMeshTools_Context) context = new BRepMesh_Context();
  context->SetFaceDiscret(new BRepMesh_FaceDiscret(new BRepMesh_DelabellaMeshAlgoFactory()));
  mesher.Perform(context);
}

// The edges a solid's tessellation leaves open once welded and mended as the core will (vaw::repairMesh); a
// face the mesher left without triangles shows as its boundary. The mesher's own status is no guide:
// Delabella returns part of a face without a failure.
std::size_t openEdges(const TopoDS_Shape& solid, double diagonal) {
  vaw::TriMesh m;
  for (TopExp_Explorer e(solid, TopAbs_FACE); e.More(); e.Next()) {
    const TopoDS_Face face = TopoDS::Face(e.Current());
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, loc);
    if (tri.IsNull()) continue;
    const gp_Trsf t = loc.Transformation();
    const auto base = static_cast<int>(m.vertices.size());
    for (Standard_Integer i = 1; i <= tri->NbNodes(); ++i) {
      const gp_Pnt q = tri->Node(i).Transformed(t);
      m.vertices.emplace_back(q.X(), q.Y(), q.Z());
    }
    const bool reversed = face.Orientation() == TopAbs_REVERSED;
    for (Standard_Integer i = 1; i <= tri->NbTriangles(); ++i) {
      Standard_Integer a, b, c;
      tri->Triangle(i).Get(a, b, c);
      if (reversed) std::swap(b, c);
      m.triangles.emplace_back(base + a - 1, base + b - 1, base + c - 1);
    }
  }
  if (m.triangles.empty()) return std::numeric_limits<std::size_t>::max();
  const vaw::MeshCheck check = vaw::repairMesh(m, 1e-9 * diagonal, 1e-14 * diagonal * diagonal).check;
  return check.boundaryEdges + check.nonManifoldEdges;
}

// A straight parameter line within 1e-9 of an axis made exactly parallel to it, or null when it is not such
// a line. A cone's seam written 3e-16 off the v direction leaves the mesher without a triangle on that face.
Handle(Geom2d_Curve) snapped(const Handle(Geom2d_Curve) & curve) {
  Handle(Geom2d_Line) line = Handle(Geom2d_Line)::DownCast(curve);
  if (const Handle(Geom2d_TrimmedCurve) trimmed = Handle(Geom2d_TrimmedCurve)::DownCast(curve); !trimmed.IsNull())
    line = Handle(Geom2d_Line)::DownCast(trimmed->BasisCurve());
  if (line.IsNull()) return {};
  const gp_Dir2d d = line->Direction();
  gp_Dir2d exact = d;
  if (std::abs(d.X()) < 1e-9 && d.X() != 0.0) exact = gp_Dir2d(0.0, d.Y() > 0.0 ? 1.0 : -1.0);
  else if (std::abs(d.Y()) < 1e-9 && d.Y() != 0.0) exact = gp_Dir2d(d.X() > 0.0 ? 1.0 : -1.0, 0.0);
  else return {};
  return new Geom2d_Line(line->Location(), exact);
}

// A copy of `solid`, without its tessellation, whose nearly axis-parallel parameter lines are exact.
TopoDS_Shape withSnappedParameterLines(const TopoDS_Shape& solid) {
  const TopoDS_Shape copy = BRepBuilderAPI_Copy(solid, Standard_True, Standard_False).Shape();
  BRep_Builder builder;
  for (TopExp_Explorer f(copy, TopAbs_FACE); f.More(); f.Next()) {
    // Forward: Open CASCADE hands out a reversed face's seam curves the other way round, while UpdateEdge
    // takes them in the edge's own order.
    const TopoDS_Face face = TopoDS::Face(f.Current().Oriented(TopAbs_FORWARD));
    TopTools_MapOfShape done;
    for (TopExp_Explorer e(face, TopAbs_EDGE); e.More(); e.Next()) {
      const TopoDS_Edge edge = TopoDS::Edge(e.Current().Oriented(TopAbs_FORWARD));
      if (!done.Add(edge)) continue;
      const double tol = BRep_Tool::Tolerance(edge);
      Standard_Real first, last;
      const Handle(Geom2d_Curve) c1 = BRep_Tool::CurveOnSurface(edge, face, first, last);
      if (c1.IsNull()) continue;
      if (BRep_Tool::IsClosed(edge, face)) {  // a seam: one parameter line on each side
        const Handle(Geom2d_Curve) c2 = BRep_Tool::CurveOnSurface(TopoDS::Edge(edge.Reversed()), face, first, last);
        const Handle(Geom2d_Curve) s1 = snapped(c1), s2 = c2.IsNull() ? Handle(Geom2d_Curve)() : snapped(c2);
        if (!s1.IsNull() || !s2.IsNull()) builder.UpdateEdge(edge, s1.IsNull() ? c1 : s1, s2.IsNull() ? c2 : s2, face, tol);
      } else if (const Handle(Geom2d_Curve) s1 = snapped(c1); !s1.IsNull()) {
        builder.UpdateEdge(edge, s1, face, tol);
      }
    }
  }
  return copy;
}

// The closed volumes `shape`'s faces make once sewn, the sewing tolerance the largest of the file's own edge
// tolerances (at least 1e-6 mm): a gap the file itself accepts is no gap.
std::vector<TopoDS_Solid> sewnSolids(const TopoDS_Shape& shape) {
  double tolerance = 1e-6;
  for (TopExp_Explorer e(shape, TopAbs_EDGE); e.More(); e.Next())
    tolerance = std::max(tolerance, BRep_Tool::Tolerance(TopoDS::Edge(e.Current())));
  BRepBuilderAPI_Sewing sewing(2.0 * tolerance);
  for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) sewing.Add(e.Current());
  sewing.Perform();
  std::vector<TopoDS_Solid> out;
  for (TopExp_Explorer e(sewing.SewedShape(), TopAbs_SHELL); e.More(); e.Next()) {
    const TopoDS_Shell shell = TopoDS::Shell(e.Current());
    if (!BRep_Tool::IsClosed(shell)) continue;
    BRepBuilderAPI_MakeSolid make(shell);
    if (!make.IsDone()) continue;
    TopoDS_Solid solid = make.Solid();
    // Sewn faces keep their own orientations: a solid turned inside out has a negative volume.
    GProp_GProps props;
    BRepGProp::VolumeProperties(solid, props);
    if (props.Mass() < 0.0) solid.Reverse();
    out.push_back(solid);
  }
  return out;
}

// The volume, centroid and inertia of a closed solid: Gauss integration at its fixed order where every face
// is a plane, cylinder, cone, sphere or torus (within a few 1e-6 of the adaptive integration), the adaptive
// one to 1e-9 where any face is free-form, on which the fixed order is a percent off (a rational B-spline).
// The adaptive integration on every solid took a third of the reader's time on a SolidWorks export. (Faces
// integrated in two groups do not add up to the solid's adaptive result in Open CASCADE 7.6, so a solid is
// integrated whole.)
GProp_GProps volumeProperties(const TopoDS_Shape& solid) {
  bool allAnalytic = true;
  for (TopExp_Explorer e(solid, TopAbs_FACE); e.More() && allAnalytic; e.Next())
    allAnalytic = analytic(TopoDS::Face(e.Current()));
  GProp_GProps props;
  if (allAnalytic) BRepGProp::VolumeProperties(solid, props);
  else BRepGProp::VolumeProperties(solid, props, 1e-9);
  return props;
}

}  // namespace

// A solid whose tessellation is open although its B-rep is closed is meshed again: with its parameter lines
// snapped, then finer (a tenth of the deflection: chords across edges a fraction of a millimetre long), then
// both; the first that closes is kept, else the one with the fewest open edges, which the core keeps with a
// warning. Returns the solid to use, meshed.
TopoDS_Shape Reader::closeTessellation(const TopoDS_Shape& solid, double diagonal, double deflection) const {
  std::size_t open = openEdges(solid, diagonal);
  if (open == 0) return solid;
  TopoDS_Shape best = solid;
  for (const auto& [snap, fine] : {std::pair{true, 1.0}, std::pair{false, 0.1}, std::pair{true, 0.1}}) {
    const TopoDS_Shape again =
        snap ? withSnappedParameterLines(solid) : BRepBuilderAPI_Copy(solid, Standard_True, Standard_False).Shape();
    tessellate(again, fine * deflection, angularDeflection_);
    const std::size_t o = openEdges(again, diagonal);
    if (o < open) {
      open = o;
      best = again;
    }
    if (open == 0) break;
  }
  return best;
}

void Reader::skip(Product& p, const std::string& why) { warnings_.push_back("\"" + p.name + "\": skipped, " + why); }

// Tessellates and measures one product's solids in its own frame; leaves p.solid null (with a warning)
// when it has none worth simulating.
void Reader::measure(Product& p) {
  const TopoDS_Shape shape = XCAFDoc_ShapeTool::GetShape(p.label);
  if (shape.IsNull()) return skip(p, "no solid (empty representation)");
  std::vector<TopoDS_Solid> solids;
  for (TopExp_Explorer e(shape, TopAbs_SOLID); e.More(); e.Next()) solids.push_back(TopoDS::Solid(e.Current()));
  std::size_t openShells = 0, looseFaces = 0, edges = 0;
  for (TopExp_Explorer e(shape, TopAbs_SHELL, TopAbs_SOLID); e.More(); e.Next()) {
    const TopoDS_Shell shell = TopoDS::Shell(e.Current());
    if (BRep_Tool::IsClosed(shell)) {
      // A closed shell is a solid the exporter did not wrap.
      BRepBuilderAPI_MakeSolid make(shell);
      if (make.IsDone()) solids.push_back(make.Solid());
    } else {
      ++openShells;
    }
  }
  for (TopExp_Explorer e(shape, TopAbs_FACE, TopAbs_SHELL); e.More(); e.Next()) ++looseFaces;
  for (TopExp_Explorer e(shape, TopAbs_EDGE, TopAbs_FACE); e.More(); e.Next()) ++edges;
  if (solids.empty() && openShells + looseFaces > 0) {
    // Faces that close a volume but share no edges (written unsewn): sewn within the file's own tolerance.
    solids = sewnSolids(shape);
    if (!solids.empty())
      warnings_.push_back("\"" + p.name + "\": its faces shared no edges; sewn into " + std::to_string(solids.size()) +
                          (solids.size() == 1 ? " closed solid" : " closed solids"));
  }
  if (solids.empty()) {
    if (openShells + looseFaces > 0) return skip(p, "no solid (an open shell or loose faces, not a closed volume)");
    if (edges > 0) return skip(p, "no solid (wireframe representation)");
    return skip(p, "no solid (empty representation)");
  }

  GProp_GProps mass;
  BRep_Builder builder;
  TopoDS_Compound kept;
  builder.MakeCompound(kept);
  std::size_t keptCount = 0;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    const std::string which =
        solids.size() > 1 ? "solid " + std::to_string(i + 1) + " of \"" + p.name + "\"" : "\"" + p.name + "\"";
    bool open = false;
    for (TopExp_Explorer e(solids[i], TopAbs_SHELL); e.More(); e.Next()) open = open || !BRep_Tool::IsClosed(e.Current());
    if (open) {
      warnings_.push_back(which + ": skipped, its shell is not closed");
      continue;
    }
    const GProp_GProps props = volumeProperties(solids[i]);
    if (!(std::isfinite(props.Mass()) && props.Mass() > 0.0)) {
      warnings_.push_back(which + ": skipped, volume " + std::to_string(props.Mass()) + " mm^3 is not positive and finite");
      continue;
    }
    mass.Add(props);
    builder.Add(kept, solids[i]);
    ++keptCount;
  }
  if (keptCount == 0) return;

  Bnd_Box box;
  BRepBndLib::Add(kept, box);
  if (box.IsVoid()) return skip(p, "empty bounding box");
  Standard_Real x0, y0, z0, x1, y1, z1;
  box.Get(x0, y0, z0, x1, y1, z1);
  for (const double v : {x0, y0, z0, x1, y1, z1})
    if (!std::isfinite(v) || std::abs(v) > 1e12) return skip(p, "its bounding box is not finite");
  const double diagonal = gp_Pnt(x0, y0, z0).Distance(gp_Pnt(x1, y1, z1));
  const double deflection = std::max(relativeDeflection_ * diagonal, 1e-7);
  tessellate(kept, deflection, angularDeflection_);
  const TopoDS_Compound asRead = kept;  // the file's own shapes, which its colours name
  {
    TopoDS_Compound closed;
    builder.MakeCompound(closed);
    for (TopoDS_Iterator it(kept); it.More(); it.Next()) builder.Add(closed, closeTessellation(it.Value(), diagonal, deflection));
    kept = closed;
  }

  std::vector<double> vertices;
  std::vector<std::int32_t> triangles;
  json faces = json::array();
  double area = 0.0;
  std::size_t unmeshed = 0;
  const double tol = 1e-6 * diagonal;
  for (TopExp_Explorer e(kept, TopAbs_FACE); e.More(); e.Next()) {
    const TopoDS_Face face = TopoDS::Face(e.Current());
    TopLoc_Location loc;
    const Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(face, loc);
    std::vector<gp_Pnt> nodes;
    const std::size_t first = triangles.size() / 3;
    if (tri.IsNull()) {
      ++unmeshed;
    } else {
      const gp_Trsf t = loc.Transformation();
      const auto base = static_cast<std::int32_t>(vertices.size() / 3);
      nodes.reserve(static_cast<std::size_t>(tri->NbNodes()));
      for (Standard_Integer i = 1; i <= tri->NbNodes(); ++i) {
        const gp_Pnt q = tri->Node(i).Transformed(t);
        nodes.push_back(q);
        vertices.insert(vertices.end(), {q.X() * kMetre, q.Y() * kMetre, q.Z() * kMetre});
      }
      const bool reversed = face.Orientation() == TopAbs_REVERSED;
      for (Standard_Integer i = 1; i <= tri->NbTriangles(); ++i) {
        Standard_Integer a, b, c;
        tri->Triangle(i).Get(a, b, c);
        if (reversed) std::swap(b, c);
        triangles.insert(triangles.end(), {base + a - 1, base + b - 1, base + c - 1});
      }
    }
    FaceOut f = classify(face, tol, nodes);
    area += f.area;
    json jf = {{"surface", static_cast<int>(f.surface)},
               {"area", f.area * kMetre * kMetre},
               {"first", first},
               {"count", triangles.size() / 3 - first}};
    if (f.surface != vaw::step::SurfaceKind::Other) {
      jf["point"] = point(f.point.XYZ(), kMetre);
      jf["direction"] = point(f.direction.XYZ(), 1.0);
      if (f.fromSpline) jf["fromSpline"] = true;
    }
    if (f.surface == vaw::step::SurfaceKind::Cylinder || f.surface == vaw::step::SurfaceKind::Cone) {
      jf["radius"] = f.radius * kMetre;
      jf["convex"] = f.convex;
      jf["axialMin"] = f.axialMin * kMetre;
      jf["axialMax"] = f.axialMax * kMetre;
      if (f.surface == vaw::step::SurfaceKind::Cone) jf["halfAngle"] = f.halfAngle;
    }
    faces.push_back(std::move(jf));
  }
  if (unmeshed > 0)
    warnings_.push_back("\"" + p.name + "\": " + std::to_string(unmeshed) +
                        " faces could not be tessellated (holes in its mesh)");

  const gp_Mat I = mass.MatrixOfInertia();
  json inertia = json::array();
  // OCCT's matrix is for density 1 in mm^5; vaw's in m^5.
  for (int r = 1; r <= 3; ++r)
    for (int c = 1; c <= 3; ++c) inertia.push_back(I.Value(r, c) * 1e-15);
  p.solid = {{"product", p.name},
             {"volume", mass.Mass() * 1e-9},
             {"centroid", point(mass.CentreOfMass().XYZ(), kMetre)},
             {"inertia", std::move(inertia)},
             {"area", area * kMetre * kMetre},
             {"deflection", deflection * kMetre},
             {"vertices", blob(vertices)},
             {"triangles", blob(triangles)},
             {"faces", std::move(faces)}};
  // A product of several representations (step_reader.cpp) may carry its colour on the one that is a solid.
  std::optional<Quantity_Color> own = colorOf(p.label);
  TDF_LabelSequence representations;
  XCAFDoc_ShapeTool::GetComponents(p.label, representations, false);
  for (Standard_Integer i = 1; i <= representations.Length() && !own; ++i) {
    TDF_Label ref;
    if (XCAFDoc_ShapeTool::GetReferredShape(representations.Value(i), ref)) own = colorOf(ref);
  }
  if (const auto c = own) {
    p.solid["color"] = colorJson(*c);
  } else if (const auto s = shapeColor(asRead)) {
    p.solid["color"] = colorJson(*s);
  }
}

// Some exporters colour the solid (a sub-shape label), not the product.
std::optional<Quantity_Color> Reader::shapeColor(const TopoDS_Shape& kept) const {
  for (TopExp_Explorer e(kept, TopAbs_SOLID); e.More(); e.Next()) {
    Quantity_Color c;
    if (colors_->GetColor(e.Current(), XCAFDoc_ColorSurf, c) || colors_->GetColor(e.Current(), XCAFDoc_ColorGen, c)) return c;
  }
  return std::nullopt;
}

}  // namespace vaw::step::reader
