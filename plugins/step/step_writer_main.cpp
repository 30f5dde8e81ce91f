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
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
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
#include <ShapeUpgrade_UnifySameDomain.hxx>
#include <Standard_Failure.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <Standard_OutOfMemory.hxx>
#include <gp_Pln.hxx>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>
#include <map>
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

TopoDS_Shape solidOf(const Handle(Poly_Triangulation)& mesh) {
  std::vector<TopoDS_Vertex> vertex(static_cast<std::size_t>(mesh->NbNodes()) + 1);
  for (Standard_Integer i = 1; i <= mesh->NbNodes(); ++i) vertex[i] = BRepBuilderAPI_MakeVertex(mesh->Node(i)).Vertex();
  // One edge per pair of corners, shared by the two triangles on either side: the shell is closed by
  // construction, with no sewing.
  std::map<std::pair<Standard_Integer, Standard_Integer>, TopoDS_Edge> edges;
  const auto edge = [&](Standard_Integer a, Standard_Integer b) {
    const std::pair<Standard_Integer, Standard_Integer> key = std::minmax(a, b);
    auto it = edges.find(key);
    if (it == edges.end()) it = edges.emplace(key, BRepBuilderAPI_MakeEdge(vertex[key.first], vertex[key.second]).Edge()).first;
    return it->second;
  };
  BRep_Builder builder;
  TopoDS_Shell shell;
  builder.MakeShell(shell);
  const Standard_Integer count = mesh->NbTriangles();
  for (Standard_Integer t = 1; t <= count; ++t) {
    if (t % 20000 == 0) progress(0.05 + 0.45 * t / count, "making faces (" + std::to_string(t) + " of " + std::to_string(count) + " triangles)");
    Standard_Integer n[3];
    mesh->Triangle(t).Get(n[0], n[1], n[2]);
    const gp_Pnt p0 = mesh->Node(n[0]), p1 = mesh->Node(n[1]), p2 = mesh->Node(n[2]);
    const gp_Vec normal = gp_Vec(p0, p1).Crossed(gp_Vec(p0, p2));
    if (normal.Magnitude() <= 1e-12) refuse("triangle " + std::to_string(t) + " has no area");
    BRepBuilderAPI_MakeWire wire(edge(n[0], n[1]), edge(n[1], n[2]), edge(n[2], n[0]));
    if (!wire.IsDone()) refuse("triangle " + std::to_string(t) + ": its edges make no wire");
    // The plane's normal is the triangle's outward one, so the face faces out.
    BRepBuilderAPI_MakeFace face(gp_Pln(p0, gp_Dir(normal)), wire.Wire(), Standard_True);
    if (!face.IsDone()) refuse("triangle " + std::to_string(t) + ": no face");
    builder.Add(shell, face.Face());
  }
  shell.Closed(Standard_True);
  TopoDS_Solid solid;
  builder.MakeSolid(solid);
  builder.Add(solid, shell);
  // Coplanar neighbours merged into one polygon face each; their shared straight edges into one.
  progress(0.5, "merging coplanar faces");
  ShapeUpgrade_UnifySameDomain unify(solid, Standard_True, Standard_True, Standard_False);
  unify.Build();
  return unify.Shape();
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
    // The unit the numbers are written in, in millimetres: the shape's own, so they are not scaled.
    writer.ChangeWriter().Model()->SetWriteLengthUnit(unit == "mm" ? 1.0 : unit == "inch" ? 25.4 : 1000.0);
    if (!writer.Transfer(doc, STEPControl_AsIs)) refuse("the solid could not be put into STEP");
    progress(0.85, "writing the file");
    if (writer.Write(out.c_str()) != IFSelect_RetDone) refuse(out + ": cannot write");
    progress(1.0, "done");
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
