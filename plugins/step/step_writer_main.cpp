// vaw-step-write: writes a closed triangle mesh as one named STEP solid, a B-rep of plane faces in which
// coplanar triangles are merged into polygons (a voxel surface becomes a few large faces, not millions of triangles). The
// STEP plugin runs it as a child, as it does the reader: Open CASCADE stays out of vaw's own processes
// (docs/step.md, docs/swept-volume.md).
//
//   vaw-step-write MESH.stl --out FILE.step --unit mm|inch|m [--name NAME] [--parent PID] [--memory-limit-mb MB]
//
// MESH is a binary STL in the unit given, whose triangles face outwards and share their corners (a closed
// manifold). Progress goes to stdout as the reader's does ("progress 0.350 making faces"). Exit 0: FILE
// written. Exit 3: it could not be; one line on stderr says why. Exit 5: it needed more memory than its
// limit. Exit 6: its parent was gone. Exit 2: bad arguments.
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRep_Builder.hxx>
#include <Interface_Static.hxx>
#include <Poly_Triangulation.hxx>
#include <RWStl.hxx>
#include <STEPCAFControl_Writer.hxx>
#include <StepData_StepModel.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <Bnd_Box.hxx>
#include <BRep_Tool.hxx>
#include <Geom2d_Line.hxx>
#include <Geom_Plane.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <Precision.hxx>
#include <Standard_Failure.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <Standard_OutOfMemory.hxx>
#include <gp_Pln.hxx>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>
#include <unordered_map>
#include <string>
#include <utility>
#include <vector>

#include "step_child.hpp"

namespace {

[[noreturn]] void refuse(const std::string& why) {
  std::fprintf(stderr, "%s\n", why.c_str());
  std::exit(3);
}

void progress(double fraction, const std::string& stage) {
  std::printf("progress %.3f %s\n", fraction, stage.c_str());
  std::fflush(stdout);
}

// The mesh as a B-rep of plane faces, each a largest region of coplanar triangles joined across their
// edges (a voxel surface's plane patches), bounded by one outer wire and its holes. The edges between two
// regions are straight runs of the mesh's edges, each run one B-rep edge shared by the two faces on either
// side, ending wherever a third region meets or the run turns: the faces meet edge to edge with no vertex of
// one lying inside another's edge (no T-junctions), so the shell is closed by construction, with no sewing
// and no later merging. A mesh of no coplanar neighbours becomes one face per triangle.
TopoDS_Shape solidOf(const Handle(Poly_Triangulation)& mesh) {
  const int nodes = mesh->NbNodes(), count = mesh->NbTriangles();
  std::vector<gp_Pnt> point(static_cast<std::size_t>(nodes));
  Bnd_Box box;
  for (int i = 0; i < nodes; ++i) {
    point[static_cast<std::size_t>(i)] = mesh->Node(i + 1);
    box.Add(point[static_cast<std::size_t>(i)]);
  }
  const double tol = 1e-6 * std::sqrt(box.SquareExtent());  // STL's single-precision coordinates
  std::vector<std::array<int, 3>> tri(static_cast<std::size_t>(count));
  std::vector<gp_Dir> normal(static_cast<std::size_t>(count));
  for (int t = 0; t < count; ++t) {
    Standard_Integer n[3];
    mesh->Triangle(t + 1).Get(n[0], n[1], n[2]);
    auto& c = tri[static_cast<std::size_t>(t)];
    for (int k = 0; k < 3; ++k) c[static_cast<std::size_t>(k)] = n[k] - 1;
    const gp_Vec v = gp_Vec(point[static_cast<std::size_t>(c[0])], point[static_cast<std::size_t>(c[1])])
                         .Crossed(gp_Vec(point[static_cast<std::size_t>(c[0])], point[static_cast<std::size_t>(c[2])]));
    if (v.Magnitude() <= 1e-12) refuse("triangle " + std::to_string(t + 1) + " has no area");
    normal[static_cast<std::size_t>(t)] = gp_Dir(v);
  }
  const auto at = [&](int v) -> const gp_Pnt& { return point[static_cast<std::size_t>(v)]; };
  const auto key = [](int a, int b) { return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b)); };

  // Each edge's two triangles; anything else is not a closed manifold.
  std::unordered_map<std::uint64_t, std::array<int, 2>> sides;
  sides.reserve(static_cast<std::size_t>(count) * 2);
  for (int t = 0; t < count; ++t)
    for (int k = 0; k < 3; ++k) {
      const auto& c = tri[static_cast<std::size_t>(t)];
      auto [it, fresh] = sides.try_emplace(key(c[static_cast<std::size_t>(k)], c[static_cast<std::size_t>((k + 1) % 3)]), std::array<int, 2>{t, -1});
      if (fresh) continue;
      if (it->second[1] >= 0) refuse("edge of triangle " + std::to_string(t + 1) + " has more than two triangles: not a closed manifold");
      it->second[1] = t;
    }
  for (const auto& [k, s] : sides)
    if (s[1] < 0) refuse("the mesh has an open edge: not a closed manifold");

  // Regions: coplanar triangles joined across an edge.
  progress(0.05, "merging coplanar triangles");
  std::vector<int> parent(static_cast<std::size_t>(count));
  for (int t = 0; t < count; ++t) parent[static_cast<std::size_t>(t)] = t;
  const auto find = [&](int t) {
    while (parent[static_cast<std::size_t>(t)] != t) t = parent[static_cast<std::size_t>(t)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(t)])];
    return t;
  };
  const auto coplanar = [&](int a, int b) {
    if (!normal[static_cast<std::size_t>(a)].IsEqual(normal[static_cast<std::size_t>(b)], 1e-6)) return false;
    const gp_Pnt& p = at(tri[static_cast<std::size_t>(a)][0]);
    for (const int v : tri[static_cast<std::size_t>(b)])
      if (std::abs(gp_Vec(p, at(v)).Dot(gp_Vec(normal[static_cast<std::size_t>(a)]))) > tol) return false;
    return true;
  };
  for (const auto& [k, s] : sides)
    if (coplanar(s[0], s[1])) parent[static_cast<std::size_t>(find(s[0]))] = find(s[1]);
  std::vector<int> region(static_cast<std::size_t>(count));
  for (int t = 0; t < count; ++t) region[static_cast<std::size_t>(t)] = find(t);
  const auto crease = [&](const std::array<int, 2>& s) { return region[static_cast<std::size_t>(s[0])] != region[static_cast<std::size_t>(s[1])]; };
  progress(0.2, "finding the plane regions' borders");

  // The crease graph: mesh edges between two regions, chained into straight runs through vertices where
  // only the run itself passes.
  std::unordered_map<int, std::vector<int>> creaseAt;  // vertex -> its crease neighbours
  for (const auto& [k, s] : sides)
    if (crease(s)) {
      const int a = static_cast<int>(k >> 32), b = static_cast<int>(k & 0xffffffffu);
      creaseAt[a].push_back(b);
      creaseAt[b].push_back(a);
    }
  std::vector<TopoDS_Vertex> vertex(static_cast<std::size_t>(nodes));
  const auto vertexOf = [&](int v) -> const TopoDS_Vertex& {
    TopoDS_Vertex& x = vertex[static_cast<std::size_t>(v)];
    if (x.IsNull()) x = BRepBuilderAPI_MakeVertex(at(v)).Vertex();
    return x;
  };
  struct Run { int from, to; TopoDS_Edge edge; };
  std::vector<Run> runs;
  std::unordered_map<std::uint64_t, int> runOf;  // crease edge -> its run
  const auto straightOn = [&](int prev, int v) {
    // The run goes on through v when v joins only it and it does not turn there.
    const auto& n = creaseAt[v];
    if (n.size() != 2) return -1;
    const int next = n[0] == prev ? n[1] : n[0];
    const gp_Vec in(at(prev), at(v)), out(at(v), at(next));
    return in.Crossed(out).Magnitude() <= tol * in.Magnitude() && in.Dot(out) > 0.0 ? next : -1;
  };
  for (const auto& [k, s] : sides) {
    if (!crease(s) || runOf.contains(k)) continue;
    const int a = static_cast<int>(k >> 32), b = static_cast<int>(k & 0xffffffffu);
    std::vector<int> chain = {a, b};
    for (int prev = a, v = b, next; (next = straightOn(prev, v)) >= 0 && next != chain.front(); prev = v, v = next) chain.push_back(next);
    for (int prev = b, v = a, next; (next = straightOn(prev, v)) >= 0 && next != chain.back(); prev = v, v = next) chain.insert(chain.begin(), next);
    const int id = static_cast<int>(runs.size());
    for (std::size_t i = 0; i + 1 < chain.size(); ++i) runOf[key(chain[i], chain[i + 1])] = id;
    runs.push_back({chain.front(), chain.back(), BRepBuilderAPI_MakeEdge(vertexOf(chain.front()), vertexOf(chain.back())).Edge()});
  }
  progress(0.4, "making " + std::to_string(runs.size()) + " edges into faces");

  // Each region's border, as its triangles wind it (outward normal: the outer loop counterclockwise, holes
  // clockwise), walked into loops; where the region touches itself at a vertex the walk turns most to the
  // left there, so each loop stays simple.
  std::unordered_map<int, std::vector<std::pair<int, int>>> border;  // region -> half-edges (from, to)
  for (int t = 0; t < count; ++t)
    for (int k = 0; k < 3; ++k) {
      const auto& c = tri[static_cast<std::size_t>(t)];
      const int a = c[static_cast<std::size_t>(k)], b = c[static_cast<std::size_t>((k + 1) % 3)];
      if (crease(sides.at(key(a, b)))) border[region[static_cast<std::size_t>(t)]].emplace_back(a, b);
    }
  BRep_Builder builder;
  TopoDS_Shell shell;
  builder.MakeShell(shell);
  std::size_t faces = 0;
  for (auto& [r, halves] : border) {
    const gp_Dir n = normal[static_cast<std::size_t>(r)];
    std::unordered_map<int, std::vector<std::size_t>> leaving;
    for (std::size_t i = 0; i < halves.size(); ++i) leaving[halves[i].first].push_back(i);
    std::vector<char> used(halves.size(), 0);
    std::vector<TopoDS_Wire> outer, holes;
    for (std::size_t first = 0; first < halves.size(); ++first) {
      if (used[first]) continue;
      std::vector<std::size_t> loop;
      for (std::size_t h = first;;) {
        used[h] = 1;
        loop.push_back(h);
        const auto [from, to] = halves[h];
        const gp_Vec in(at(from), at(to));
        std::size_t best = halves.size();
        double bestTurn = -10.0;
        for (const std::size_t o : leaving[to]) {
          if (used[o] && o != first) continue;
          const gp_Vec out(at(to), at(halves[o].second));
          const double turn = std::atan2(gp_Vec(n).Dot(in.Crossed(out)), in.Dot(out));
          if (turn > bestTurn) bestTurn = turn, best = o;
        }
        if (best == halves.size()) refuse("a plane region's border does not close");
        if (best == first) break;
        h = best;
      }
      // The loop as runs: started where a run begins, consecutive half-edges of one run one edge.
      std::size_t start = 0;
      while (start < loop.size()) {
        const auto [from, to] = halves[loop[start]];
        const auto [pf, pt] = halves[loop[(start + loop.size() - 1) % loop.size()]];
        if (runOf.at(key(from, to)) != runOf.at(key(pf, pt))) break;
        ++start;
      }
      if (start == loop.size()) refuse("a plane region's border is one straight run");
      TopoDS_Wire wire;
      builder.MakeWire(wire);
      double area = 0.0;  // twice the loop's signed area about n
      const gp_Pnt& o = at(halves[loop[start]].first);
      for (std::size_t i = 0; i < loop.size(); ++i) {
        const auto [from, to] = halves[loop[(start + i) % loop.size()]];
        area += gp_Vec(n).Dot(gp_Vec(o, at(from)).Crossed(gp_Vec(o, at(to))));
        const int id = runOf.at(key(from, to));
        const auto& before = halves[loop[(start + i + loop.size() - 1) % loop.size()]];
        if (i > 0 && runOf.at(key(before.first, before.second)) == id) continue;  // the same run goes on
        const Run& run = runs[static_cast<std::size_t>(id)];
        builder.Add(wire, from == run.from ? run.edge : TopoDS::Edge(run.edge.Reversed()));
      }
      wire.Closed(Standard_True);
      (area > 0.0 ? outer : holes).push_back(wire);
    }
    if (outer.size() != 1) refuse("a plane region with " + std::to_string(outer.size()) + " outer borders");
    TopoDS_Face face;
    const gp_Pln plane(at(halves.front().first), n);
    builder.MakeFace(face, new Geom_Plane(plane), Precision::Confusion());
    builder.Add(face, outer.front());
    for (const TopoDS_Wire& w : holes) builder.Add(face, w);
    // Each edge's line in the plane's parameters, given rather than left to be projected: the STEP writer
    // asks a face's bounds for every edge, and projecting each edge for each ask made it quadratic in a
    // face's edges (8 of the 11 s of the gear's 1 mm volume).
    const gp_Ax3& frame = plane.Position();
    const auto uv = [&](const gp_Pnt& p) {
      const gp_Vec d(frame.Location(), p);
      return gp_Pnt2d(d.Dot(gp_Vec(frame.XDirection())), d.Dot(gp_Vec(frame.YDirection())));
    };
    for (TopExp_Explorer e(face, TopAbs_EDGE); e.More(); e.Next()) {
      const TopoDS_Edge& edge = TopoDS::Edge(e.Current());
      const gp_Pnt2d a = uv(BRep_Tool::Pnt(TopExp::FirstVertex(edge))), b = uv(BRep_Tool::Pnt(TopExp::LastVertex(edge)));
      builder.UpdateEdge(edge, new Geom2d_Line(a, gp_Dir2d(gp_Vec2d(a, b))), face, Precision::Confusion());
    }
    builder.Add(shell, face);
    if (++faces % 5000 == 0) progress(0.4 + 0.3 * static_cast<double>(faces) / static_cast<double>(border.size()), "making faces");
  }
  shell.Closed(Standard_True);
  TopoDS_Solid solid;
  builder.MakeSolid(solid);
  builder.Add(solid, shell);
  return solid;
}

}  // namespace

int usage() {
  std::fprintf(stderr, "usage: vaw-step-write MESH.stl --out FILE.step --unit mm|inch|m [--name NAME] [--parent PID] [--memory-limit-mb MB]\n");
  return 2;
}

int main(int argc, char** argv) {
  std::string in, out, unit, name = "vaw solid";
  long parent = 0;
  double memoryMB = 0.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    try {
      if ((a == "--out" || a == "--unit" || a == "--name") && i + 1 < argc) {
        (a == "--out" ? out : a == "--unit" ? unit : name) = argv[++i];
      } else if (a == "--parent" && i + 1 < argc) {
        parent = std::stol(argv[++i]);
      } else if (a == "--memory-limit-mb" && i + 1 < argc) {
        memoryMB = std::stod(argv[++i]);
      } else if (!a.empty() && a[0] != '-' && in.empty()) {
        in = a;
      } else {
        return usage();
      }
    } catch (const std::exception&) {
      return usage();
    }
  }
  const char* stepUnit = unit == "mm" ? "MM" : unit == "inch" ? "INCH" : unit == "m" ? "M" : nullptr;
  if (in.empty() || out.empty() || stepUnit == nullptr) return usage();
  if (!vaw::step::containChild(parent, memoryMB)) return 6;
  const auto outOfMemory = [&] {
    std::fprintf(stderr, "it needed more memory than the writer's limit of %.0f MB\n", memoryMB);
    return 5;
  };
  progress(0.0, "reading the mesh");
  try {
    const Handle(Poly_Triangulation) mesh = RWStl::ReadFile(in.c_str());
    if (mesh.IsNull() || mesh->NbTriangles() == 0) refuse(in + ": no triangles");
    const TopoDS_Shape shape = solidOf(mesh);
    progress(0.7, "putting the solid into STEP");
    // The solid goes in as a named product, so a CAD system lists it by that name.
    Handle(TDocStd_Document) doc;
    XCAFApp_Application::GetApplication()->NewDocument("MDTV-XCAF", doc);
    // The shape is in the file's unit already: the document says so, and nothing is scaled.
    XCAFDoc_DocumentTool::SetLengthUnit(doc, unit == "mm" ? 0.001 : unit == "inch" ? 0.0254 : 1.0);
    const Handle(XCAFDoc_ShapeTool) shapes = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
    const TDF_Label label = shapes->AddShape(shape, Standard_False);
    TDataStd_Name::Set(label, TCollection_ExtendedString(name.c_str(), Standard_True));
    STEPCAFControl_Writer writer;  // sets up the STEP statics: the unit is set after, or it is reset
    Interface_Static::SetCVal("write.step.unit", stepUnit);
    // Plane faces bounded by straight edges need no curves in the planes' parameters: without them the file
    // is a fraction of the size, and a CAD system computes them on reading.
    Interface_Static::SetIVal("write.surfacecurve.mode", 0);
    // The unit the numbers are written in, in millimetres: the shape's own, so they are not scaled.
    writer.ChangeWriter().Model()->SetWriteLengthUnit(unit == "mm" ? 1.0 : unit == "inch" ? 25.4 : 1000.0);
    if (!writer.Transfer(doc, STEPControl_AsIs)) refuse("the solid could not be put into STEP");
    progress(0.85, "writing the file");
    if (writer.Write(out.c_str()) != IFSelect_RetDone) refuse(out + ": cannot write");
    progress(1.0, "done");
    // The file is closed; taking the document and the STEP model apart again cost the gear's volume a
    // second, for memory the process gives back by ending.
    std::fflush(nullptr);
    std::_Exit(0);
  } catch (const std::bad_alloc&) {
    return outOfMemory();
  } catch (const Standard_OutOfMemory&) {
    return outOfMemory();
  } catch (const Standard_Failure& e) {
    refuse(std::string("Open CASCADE: ") + (e.GetMessageString() != nullptr ? e.GetMessageString() : "failed"));
  } catch (const std::exception& e) {
    refuse(e.what());
  }
  return 0;
}
