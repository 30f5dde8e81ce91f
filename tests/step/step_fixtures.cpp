#include "step_fixtures.hpp"

#include <BRepAlgoAPI_Common.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepBuilderAPI_MakeShell.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepFilletAPI_MakeChamfer.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepGProp.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Vertex.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <BRep_Builder.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Quantity_Color.hxx>
#include <STEPCAFControl_Writer.hxx>
#include <STEPControl_Controller.hxx>
#include <ShapeFix_Face.hxx>
#include <ShapeUpgrade_ShapeDivideClosed.hxx>
#include <ShapeUpgrade_UnifySameDomain.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Solid.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Wire.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_ColorTool.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <gp_Ax1.hxx>
#include <gp_Ax2.hxx>
#include <gp_Circ.hxx>
#include <gp_Trsf.hxx>

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace vaw::steptest {
namespace {

// Open CASCADE's writer settings are process-wide statics.
std::mutex writerMutex;

TopoDS_Shape box(double x0, double y0, double z0, double x1, double y1, double z1) {
  return BRepPrimAPI_MakeBox(gp_Pnt(x0, y0, z0), gp_Pnt(x1, y1, z1)).Shape();
}

TopoDS_Shape cylinder(double x, double y, double z0, double radius, double height) {
  return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(x, y, z0), gp_Dir(0, 0, 1)), radius, height).Shape();
}

TopoDS_Shape cut(const TopoDS_Shape& a, const TopoDS_Shape& b) {
  BRepAlgoAPI_Cut op(a, b);
  if (!op.IsDone()) throw std::runtime_error("step fixtures: boolean cut failed");
  return op.Shape();
}

// Merges the faces a boolean leaves split on one plane or cylinder, as a CAD system's export would.
TopoDS_Shape unify(const TopoDS_Shape& s) {
  ShapeUpgrade_UnifySameDomain u(s, true, true, true);
  u.Build();
  return u.Shape();
}

TopoDS_Shape tube(double inner, double outer, double height) {
  return unify(cut(cylinder(0, 0, 0, outer, height), cylinder(0, 0, -1, inner, height + 2)));
}

TopLoc_Location at(double x, double y, double z) {
  gp_Trsf t;
  t.SetTranslation(gp_Vec(x, y, z));
  return TopLoc_Location(t);
}

// Product frames: each product at its own origin, every instance placed by a non-identity location (the
// writer drops the instance name of an identity placement).
TopoDS_Shape plateShape() {
  // x -60..60, y -40..40, z 0..10; placed at (60, 40, 0). Blind holes from the top, z 2..10.
  TopoDS_Shape s = box(-60, -40, 0, 60, 40, 10);
  s = cut(s, cylinder(-20, 0, 2, 6, 9));
  s = cut(s, cylinder(20, 0, 2, 6, 9));
  s = cut(s, cylinder(45, -25, 2, 5, 9));
  return unify(s);
}

TopoDS_Shape bracketShape() {
  // Placed at (60, 40, 10): flange x 25..95, y 25..59, z 10..18; upright y 51..59, z 18..60, clear of the
  // nuts (outer radius 10 mm about y = 40).
  BRepAlgoAPI_Fuse fuse(box(-35, -15, 0, 35, 19, 8), box(-35, 11, 8, 35, 19, 50));
  if (!fuse.IsDone()) throw std::runtime_error("step fixtures: boolean fuse failed");
  TopoDS_Shape s = fuse.Shape();
  s = cut(s, cylinder(-20, 0, -1, 6.5, 10));
  s = cut(s, cylinder(20, 0, -1, 6.5, 10));
  return unify(s);
}

TopoDS_Shape cylinderAlong(const gp_Pnt& base, const gp_Dir& axis, double radius, double height) {
  return BRepPrimAPI_MakeCylinder(gp_Ax2(base, axis), radius, height).Shape();
}

TopoDS_Shape fuse(const TopoDS_Shape& a, const TopoDS_Shape& b) {
  BRepAlgoAPI_Fuse op(a, b);
  if (!op.IsDone()) throw std::runtime_error("step fixtures: boolean fuse failed");
  return op.Shape();
}

// Each closed face divided into `pieces` faces, as exporters that allow no seam write them.
TopoDS_Shape divideClosed(const TopoDS_Shape& s, int pieces) {
  if (pieces <= 1) return s;
  ShapeUpgrade_ShapeDivideClosed divide(s);
  divide.SetNbSplitPoints(pieces - 1);
  if (!divide.Perform()) throw std::runtime_error("step fixtures: dividing closed faces failed");
  return divide.Result();
}

TopLoc_Location placed(const gp_Trsf& t) { return TopLoc_Location(t); }

// At (x, y, z), turned `turnZ` about its own vertical.
gp_Trsf turnedAt(double x, double y, double z, double turnZ) {
  gp_Trsf t;
  t.SetTranslation(gp_Vec(x, y, z));
  if (turnZ != 0.0) {
    gp_Trsf r;
    r.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), turnZ);
    t = t * r;
  }
  return t;
}

struct Writer {
  Handle(TDocStd_Document) doc;
  Handle(XCAFDoc_ShapeTool) shapes;
  Handle(XCAFDoc_ColorTool) colors;
  bool bspline = false;

  Writer() {
    XCAFApp_Application::GetApplication()->NewDocument("MDTV-XCAF", doc);
    shapes = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
    colors = XCAFDoc_DocumentTool::ColorTool(doc->Main());
  }
  TDF_Label assembly(const char* name) {
    const TDF_Label l = shapes->NewShape();
    TDataStd_Name::Set(l, name);
    return l;
  }
  TDF_Label product(const char* name, const TopoDS_Shape& shape, std::vector<double> rgb = {}) {
    const TopoDS_Shape s = bspline ? BRepBuilderAPI_NurbsConvert(shape, true).Shape() : shape;
    const TDF_Label l = shapes->AddShape(s, false);
    TDataStd_Name::Set(l, name);
    if (rgb.size() == 3) colors->SetColor(l, Quantity_Color(rgb[0], rgb[1], rgb[2], Quantity_TOC_RGB), XCAFDoc_ColorGen);
    return l;
  }
  void instance(const TDF_Label& parent, const TDF_Label& product, const char* name, const TopLoc_Location& where) {
    const TDF_Label c = shapes->AddComponent(parent, product, where);
    // Without a name of its own a component keeps the one XCAF gives it, its product's label entry.
    if (name != nullptr) TDataStd_Name::Set(c, name);
  }
  void write(const std::filesystem::path& file, const std::string& schema, bool inches) {
    shapes->UpdateAssemblies();
    std::lock_guard<std::mutex> lock(writerMutex);
    // The writer's statistics would fill the test logs.
    Message::DefaultMessenger()->ChangePrinters().Clear();
    if (schema != "AP203" && schema != "AP214" && schema != "AP242")
      throw std::invalid_argument("step fixtures: schema " + schema + " (expected AP203, AP214 or AP242)");
    // The writer reads the schema and unit when it creates its model, in its constructor: the statics
    // must exist (Init) and be set before it.
    STEPControl_Controller::Init();
    Interface_Static::SetCVal("write.step.schema", schema == "AP203" ? "AP203" : schema == "AP242" ? "AP242DIS" : "AP214IS");
    Interface_Static::SetCVal("write.step.unit", inches ? "INCH" : "MM");
    STEPCAFControl_Writer writer;
    writer.SetNameMode(true);
    writer.SetColorMode(true);
    const bool ok = writer.Transfer(doc, STEPControl_AsIs) && writer.Write(file.string().c_str()) == IFSelect_RetDone;
    Interface_Static::SetCVal("write.step.schema", "AP214IS");
    Interface_Static::SetCVal("write.step.unit", "MM");
    if (!ok) throw std::runtime_error("step fixtures: cannot write " + file.string());
  }
};

}  // namespace

void writeBoltedBracket(const std::filesystem::path& file, const FixtureOptions& options) {
  Writer w;
  w.bspline = options.bsplineFaces;
  const TDF_Label root = w.assembly("bolted-bracket");
  const TDF_Label plate = w.product("plate", plateShape(), {0.6, 0.6, 0.62});
  const TDF_Label bracket = w.product("bracket", bracketShape(), {0.2, 0.35, 0.8});
  const TDF_Label stud = w.product("stud-m12", cylinder(0, 0, 0, 6, 34), {0.75, 0.75, 0.7});
  const TDF_Label nut = w.product("nut-m12", tube(6, 10, 8), {0.8, 0.65, 0.2});
  const TDF_Label pins = w.assembly("pin-assembly");
  const TDF_Label pin = w.product("pin", cylinder(0, 0, 0, 5, 30));
  const TDF_Label sleeve = w.product("sleeve", tube(5.2, 9, 15));
  w.instance(root, plate, "base-plate", at(60, 40, 0));
  w.instance(root, bracket, "bracket", at(60, 40, 10));
  w.instance(root, stud, "stud-1", at(40, 40, 2));
  w.instance(root, stud, "stud-2", at(80, 40, 2));
  w.instance(root, nut, "nut-1", at(40, 40, 18));
  w.instance(root, nut, "nut-2", at(80, 40, 18));
  // The sub-assembly's frame is the pin's axis at the plate's bottom face.
  w.instance(pins, pin, "pin", at(0, 0, 2));
  w.instance(pins, sleeve, "sleeve", at(0, 0, 10));
  w.instance(root, pins, "pin-assembly", at(105, 15, 0));
  if (options.wireframeBeside) {
    BRep_Builder b;
    TopoDS_Compound lines;
    b.MakeCompound(lines);
    b.Add(lines, BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, 0), gp_Pnt(120, 0, 0)).Edge());
    b.Add(lines, BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, 0), gp_Pnt(0, 80, 0)).Edge());
    b.Add(lines, BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, 0), gp_Pnt(0, 0, 60)).Edge());
    TopoDS_Compound empty;
    b.MakeCompound(empty);
    const bool bspline = w.bspline;
    w.bspline = false;
    w.instance(root, w.product("construction-lines", lines), "construction-lines", at(0, 0, 1));
    w.instance(root, w.product("empty-rep", empty), "empty-rep", at(0, 0, 2));
    w.bspline = bspline;
  }
  w.write(file, options.schema, options.inches);
}

void writeManyParts(const std::filesystem::path& file, int count, bool distinctProducts) {
  if (count < 1) throw std::invalid_argument("step fixtures: writeManyParts needs count >= 1");
  Writer w;
  const TDF_Label root = w.assembly("many-parts");
  const int others = count - 1;
  const int columns = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(others)))));
  const double pitch = 30.0;
  const double width = pitch * columns + 20, depth = pitch * std::max(1, (others + columns - 1) / columns) + 20;
  const TDF_Label plate = w.product("base-plate", box(0, 0, 0, width, depth, 10), {0.6, 0.6, 0.62});
  // A product no instance uses would be a root of its own: the shared ones are made only when shared.
  TDF_Label kinds[4];
  if (!distinctProducts) {
    kinds[0] = w.product("stud-m12", cylinder(0, 0, 0, 6, 34), {0.75, 0.75, 0.7});
    kinds[1] = w.product("nut-m12", tube(6, 10, 8), {0.8, 0.65, 0.2});
    kinds[2] = w.product("pin", cylinder(0, 0, 0, 5, 30));
    kinds[3] = w.product("sleeve", tube(5.2, 9, 15));
  }
  const char* names[4] = {"stud", "nut", "pin", "sleeve"};
  w.instance(root, plate, "base-plate", at(0, 0, -10));
  for (int i = 0; i < others; ++i) {
    const int k = i % 4;
    const std::string name = std::string(names[k]) + "-" + std::to_string(i / 4 + 1);
    // Distinct products (each its own radius, so each is tessellated and measured) cost what a real
    // assembly of that many different parts costs; shared ones only what the instances add.
    const double r = 5.0 + 0.01 * i;
    const TDF_Label product =
        !distinctProducts ? kinds[k]
        : k == 0          ? w.product(name.c_str(), cylinder(0, 0, 0, r, 34))
        : k == 1          ? w.product(name.c_str(), tube(r, r + 4, 8))
        : k == 2          ? w.product(name.c_str(), cylinder(0, 0, 0, r, 30))
                          : w.product(name.c_str(), tube(r, r + 3.8, 15));
    w.instance(root, product, name.c_str(), at(20 + pitch * (i % columns), 20 + pitch * (i / columns), 0));
  }
  w.write(file, "AP214", false);
}

void writeEdgeTouchingBoxes(const std::filesystem::path& file) {
  Writer w;
  const TDF_Label root = w.assembly("edge-touching-boxes");
  const TDF_Label a = w.product("box-a", box(0, 0, 0, 20, 20, 20), {0.8, 0.3, 0.3});
  const TDF_Label b = w.product("box-b", box(0, 0, 0, 20, 20, 20), {0.3, 0.3, 0.8});
  // box-a spans x, y 0..20, box-b 20..40: they share only the edge x = y = 20.
  w.instance(root, a, "box-a", at(0, 0, 0.5));
  w.instance(root, b, "box-b", at(20, 20, 0.5));
  w.write(file, "AP214", false);
}

void writePegUnderCover(const std::filesystem::path& file) {
  Writer w;
  const TDF_Label root = w.assembly("peg-under-cover");
  // Plate 80 x 80 x 10 mm with a blind hole r 5 mm, z 2..10; the peg r 5 mm stands z 2..22; the cover's
  // pocket (20 x 20 mm, up to z 25) leaves 3 mm over the peg.
  TopoDS_Shape plate = unify(cut(box(-40, -40, 0, 40, 40, 10), cylinder(0, 0, 2, 5, 9)));
  TopoDS_Shape cover = unify(cut(box(-20, -20, 0, 20, 20, 20), box(-10, -10, -1, 10, 10, 15)));
  w.instance(root, w.product("plate", plate, {0.6, 0.6, 0.62}), "plate", at(40, 40, 0));
  w.instance(root, w.product("peg", cylinder(0, 0, 0, 5, 20), {0.8, 0.65, 0.2}), "peg", at(40, 40, 2));
  w.instance(root, w.product("cover", cover, {0.2, 0.35, 0.8}), "cover", at(40, 40, 10));
  w.write(file, "AP214", false);
}

void writeCaptiveRing(const std::filesystem::path& file) {
  Writer w;
  const TDF_Label root = w.assembly("captive-ring");
  // Base: plate 60 x 60 x 10 mm, shaft r 5 mm z 10..50, flange r 12 mm z 50..55. The ring (r 5..10 mm,
  // 10 mm high) sits on the plate round the shaft; the cap (a disc r 12 mm) lies on the flange.
  BRepAlgoAPI_Fuse shaft(box(-30, -30, 0, 30, 30, 10), cylinder(0, 0, 10, 5, 40));
  if (!shaft.IsDone()) throw std::runtime_error("step fixtures: boolean fuse failed");
  BRepAlgoAPI_Fuse flange(shaft.Shape(), cylinder(0, 0, 50, 12, 5));
  if (!flange.IsDone()) throw std::runtime_error("step fixtures: boolean fuse failed");
  w.instance(root, w.product("base", unify(flange.Shape()), {0.6, 0.6, 0.62}), "base", at(30, 30, 0));
  w.instance(root, w.product("ring", tube(5, 10, 10), {0.8, 0.65, 0.2}), "ring", at(30, 30, 10));
  w.instance(root, w.product("cap", cylinder(0, 0, 0, 12, 4), {0.2, 0.35, 0.8}), "cap", at(30, 30, 55));
  w.write(file, "AP214", false);
}

namespace {

// The bolted rod's bolt positions (x, y) in its model: bracket 1's three, then bracket 2's (its flange
// turned 180 degrees).
constexpr double kRodBolts[6][2] = {{30, 38}, {30, 62}, {58, 50}, {170, 62}, {170, 38}, {142, 50}};
// The tiled product's tile pitch and dowel pins (x, y), clear of the brackets' flanges.
constexpr double kTilePitchX = 210, kTilePitchY = 110;
constexpr double kTileDowels[4][2] = {{100, 15}, {100, 85}, {8, 8}, {192, 92}};

// The bolted rod's parts but the plate, each in its own frame (step_fixtures.hpp, writeBoltedRod).
struct RodUnitShapes {
  TopoDS_Shape bracket, bolt, nut, rod, rodNut;
};

RodUnitShapes rodUnitShapes() {
  RodUnitShapes u;
  // Bracket frame: flange x -30..30, y -25..25, z 0..8; upright x 22..30 up to z 50 with the rod's bore
  // (r 5.25 along x at z 30); flange holes at (-20, -12), (-20, 12), (8, 0).
  TopoDS_Shape bracket = fuse(box(-30, -25, 0, 30, 25, 8), box(22, -25, 8, 30, 25, 50));
  for (const auto& h : {std::pair{-20.0, -12.0}, std::pair{-20.0, 12.0}, std::pair{8.0, 0.0}})
    bracket = cut(bracket, cylinder(h.first, h.second, -1, 4.25, 10));
  u.bracket = unify(cut(bracket, cylinderAlong(gp_Pnt(20, 0, 30), gp_Dir(1, 0, 0), 5.25, 12)));
  // Bolt frame: shank r 4 z 0..30, head r 6.5 z 30..35.5.
  u.bolt = unify(fuse(cylinder(0, 0, 0, 4, 30), cylinder(0, 0, 30, 6.5, 5.5)));
  u.nut = tube(4, 7, 8);
  u.rod = cylinderAlong(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0), 5, 80);
  u.rodNut = unify(cut(cylinderAlong(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0), 8, 8), cylinderAlong(gp_Pnt(-1, 0, 0), gp_Dir(1, 0, 0), 5, 10)));
  return u;
}

// A plate x0..x1, y0..y1, z 0..thickness with round through holes (x, y, r): the outline and the holes'
// circles as one face, extruded. A boolean cut per hole would take minutes for hundreds of holes.
TopoDS_Shape plateWithHoles(double x0, double y0, double x1, double y1, double thickness,
                            const std::vector<std::array<double, 3>>& holes) {
  BRepBuilderAPI_MakePolygon outline(gp_Pnt(x0, y0, 0), gp_Pnt(x1, y0, 0), gp_Pnt(x1, y1, 0), gp_Pnt(x0, y1, 0), true);
  BRepBuilderAPI_MakeFace face(outline.Wire(), true);
  for (const auto& h : holes) {
    const gp_Circ circle(gp_Ax2(gp_Pnt(h[0], h[1], 0), gp_Dir(0, 0, 1)), h[2]);
    // A hole's wire runs the other way round from the outline's.
    face.Add(TopoDS::Wire(BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(circle).Edge()).Wire().Reversed()));
  }
  if (!face.IsDone()) throw std::runtime_error("step fixtures: the plate's face could not be made");
  ShapeFix_Face fix(face.Face());
  fix.Perform();
  return BRepPrimAPI_MakePrism(fix.Face(), gp_Vec(0, 0, thickness)).Shape();
}

}  // namespace

void writeBoltedRod(const std::filesystem::path& file, const ExportStyle& style) {
  if (style.splits != 1 && style.splits != 2 && style.splits != 4)
    throw std::invalid_argument("step fixtures: writeBoltedRod splits 1, 2 or 4");
  Writer w;
  w.bspline = style.bsplineFaces;
  const auto real = [&](const TopoDS_Shape& shape) { return divideClosed(shape, style.splits); };
  const auto& bolts = kRodBolts;
  TopoDS_Shape plate = box(0, 0, 0, 200, 100, 10);
  for (const auto& b : bolts) plate = cut(plate, cylinder(b[0], b[1], -1, 4.25, 12));
  const RodUnitShapes unit = rodUnitShapes();
  const TopoDS_Shape &bracket = unit.bracket, &bolt = unit.bolt, &nut = unit.nut, &rod = unit.rod, &rodNut = unit.rodNut;

  const TDF_Label root = w.assembly("BOLTED-ROD");
  // The plate's own frame at its centre, so that its instance has a placement (and keeps its name).
  gp_Trsf centre;
  centre.SetTranslation(gp_Vec(-100, -50, 0));
  plate = BRepBuilderAPI_Transform(unify(plate), centre, true).Shape();
  const TDF_Label plateL = w.product("PLATE", real(plate), {0.6, 0.6, 0.62});
  const TDF_Label bracketL = w.product("L-BRACKET", real(bracket), {0.2, 0.35, 0.8});
  const TDF_Label boltL = w.product("BOLT", real(bolt), {0.75, 0.75, 0.7});
  const TDF_Label nutL = w.product("NUT", real(nut), {0.8, 0.65, 0.2});
  const TDF_Label rodL = w.product("ROD", real(rod), {0.7, 0.7, 0.75});
  const TDF_Label rodNutL = w.product("ROD-NUT", real(rodNut), {0.8, 0.65, 0.2});

  // The model's frame written as the file's: Z up, or Y up (model +Z along file +Y: a turn of -90 degrees
  // about x).
  gp_Trsf toFile;
  if (style.yUp) toFile.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0)), -M_PI / 2);
  const auto at3 = [&](double x, double y, double z, double turnZ = 0.0) { return placed(toFile * turnedAt(x, y, z, turnZ)); };
  const auto named = [&](const std::string& n) -> std::string { return style.namedInstances ? n : std::string(); };
  const auto add = [&](const TDF_Label& product, const std::string& name, const TopLoc_Location& where) {
    w.instance(root, product, name.empty() ? nullptr : name.c_str(), where);
  };
  add(plateL, named("plate"), at3(100, 50, 0));
  add(bracketL, named("bracket-1"), at3(50, 50, 10));
  add(bracketL, named("bracket-2"), at3(150, 50, 10, M_PI));
  for (int k = 0; k < 6; ++k) add(boltL, named("bolt-" + std::to_string(k + 1)), at3(bolts[k][0], bolts[k][1], -12));
  for (int k = 0; k < 6; ++k) add(nutL, named("nut-" + std::to_string(k + 1)), at3(bolts[k][0], bolts[k][1], -8));
  add(rodL, named("rod"), at3(60, 50, 40));
  add(rodNutL, named("rod-nut-1"), at3(64, 50, 40));
  add(rodNutL, named("rod-nut-2"), at3(128, 50, 40));
  w.write(file, style.schema, style.inches);
}

void writeTiledProduct(const std::filesystem::path& file, int tilesX, int tilesY, bool emptyHoles) {
  if (tilesX < 1 || tilesY < 1) throw std::invalid_argument("step fixtures: writeTiledProduct needs at least one tile");
  Writer w;
  // Every tile's six bolt holes and four dowel holes in the one plate.
  std::vector<std::array<double, 3>> holes;
  for (int i = 0; i < tilesX; ++i)
    for (int j = 0; j < tilesY; ++j) {
      const double ox = kTilePitchX * i, oy = kTilePitchY * j;
      for (const auto& b : kRodBolts) holes.push_back({ox + b[0], oy + b[1], 4.25});
      for (const auto& d : kTileDowels) holes.push_back({ox + d[0], oy + d[1], 3.2});
      if (emptyHoles)
        for (const double y : {40.0, 60.0}) holes.push_back({ox + 100, oy + y, 4.25});
    }
  // The plate's own frame at its centre, so that its instance has a placement (and keeps its name).
  const double x0 = -10, y0 = -10, x1 = kTilePitchX * tilesX, y1 = kTilePitchY * tilesY;
  const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  for (auto& h : holes) h[0] -= cx, h[1] -= cy;
  const TopoDS_Shape plate = plateWithHoles(x0 - cx, y0 - cy, x1 - cx, y1 - cy, 10, holes);
  const RodUnitShapes unit = rodUnitShapes();

  const TDF_Label root = w.assembly("TILED-PRODUCT");
  const TDF_Label plateL = w.product("BASE-PLATE", plate, {0.6, 0.6, 0.62});
  const TDF_Label tile = w.assembly("TILE");
  const TDF_Label bracketL = w.product("L-BRACKET", unit.bracket, {0.2, 0.35, 0.8});
  const TDF_Label boltL = w.product("BOLT", unit.bolt, {0.75, 0.75, 0.7});
  const TDF_Label nutL = w.product("NUT", unit.nut, {0.8, 0.65, 0.2});
  const TDF_Label rodL = w.product("ROD", unit.rod, {0.7, 0.7, 0.75});
  const TDF_Label dowelL = w.product("DOWEL", cylinder(0, 0, 0, 3, 22), {0.5, 0.5, 0.55});
  const auto at3 = [](double x, double y, double z, double turnZ = 0.0) { return placed(turnedAt(x, y, z, turnZ)); };
  // The tile in the bolted rod's model frame (plate top at z 10).
  w.instance(tile, bracketL, "bracket-1", at3(50, 50, 10));
  w.instance(tile, bracketL, "bracket-2", at3(150, 50, 10, M_PI));
  for (int k = 0; k < 6; ++k) w.instance(tile, boltL, ("bolt-" + std::to_string(k + 1)).c_str(), at3(kRodBolts[k][0], kRodBolts[k][1], -12));
  for (int k = 0; k < 6; ++k) w.instance(tile, nutL, ("nut-" + std::to_string(k + 1)).c_str(), at3(kRodBolts[k][0], kRodBolts[k][1], -8));
  // No end nuts on the rod: with a tile beside it on the rod's line, a nut outside an upright could leave
  // along the rod only through the next tile, so a row of such tiles has no order by translations.
  w.instance(tile, rodL, "rod", at3(60, 50, 40));
  for (int k = 0; k < 4; ++k) w.instance(tile, dowelL, ("dowel-" + std::to_string(k + 1)).c_str(), at3(kTileDowels[k][0], kTileDowels[k][1], 2));
  w.instance(root, plateL, "base-plate", at3(cx, cy, 0));
  int n = 0;
  for (int j = 0; j < tilesY; ++j)
    for (int i = 0; i < tilesX; ++i)
      w.instance(root, tile, ("tile-" + std::to_string(++n)).c_str(), at3(kTilePitchX * i, kTilePitchY * j, 0.0));
  w.write(file, "AP214", false);
}

void writeRigProduct(const std::filesystem::path& file, int tilesX, int tilesY) {
  if (tilesX < 1 || tilesY < 1) throw std::invalid_argument("step fixtures: writeRigProduct needs at least one tile");
  constexpr double pitchX = 400, pitchY = 300;
  // Holes in a tile's frame (its corner on the plate's top): through r 5.25 for the bolts, blind r 4 (8 deep)
  // for the pins; the last three through and the last two blind stay empty.
  const std::vector<std::array<double, 2>> through = {
      {95, 130}, {95, 170}, {130, 130}, {130, 170},      // bracket 1's bolts (its frame at (120, 150))
      {305, 170}, {305, 130}, {270, 170}, {270, 130},    // bracket 2's, turned half round at (280, 150)
      {42, 55}, {98, 55}, {302, 245}, {358, 245},        // the covers' bolts
      {200, 40}, {200, 260}, {30, 280}};
  const std::vector<std::array<double, 2>> blind = {{70, 40}, {70, 70}, {330, 230}, {330, 260}, {370, 40}, {370, 120}};
  const double cx = 0.5 * pitchX * tilesX, cy = 0.5 * pitchY * tilesY;
  std::vector<std::array<double, 3>> holes;
  std::vector<std::array<double, 2>> blindAt;
  for (int i = 0; i < tilesX; ++i)
    for (int j = 0; j < tilesY; ++j) {
      for (const auto& h : through) holes.push_back({pitchX * i + h[0] - cx, pitchY * j + h[1] - cy, 5.25});
      for (const auto& h : blind) blindAt.push_back({pitchX * i + h[0] - cx, pitchY * j + h[1] - cy});
    }
  // The plate in its own frame (centre of its top face at the origin), through holes in the extruded face,
  // the blind ones cut in one boolean with every drill as a tool (one cut each would take minutes).
  gp_Trsf down;
  down.SetTranslation(gp_Vec(0, 0, -12));
  TopoDS_Shape plate = BRepBuilderAPI_Transform(plateWithHoles(-cx, -cy, cx, cy, 12, holes), down, true).Shape();
  {
    TopTools_ListOfShape arguments, tools;
    arguments.Append(plate);
    for (const auto& b : blindAt) tools.Append(cylinder(b[0], b[1], -8, 4, 9));
    BRepAlgoAPI_Cut op;
    op.SetArguments(arguments);
    op.SetTools(tools);
    op.SetRunParallel(true);
    op.Build();
    if (!op.IsDone()) throw std::runtime_error("step fixtures: the rig plate's blind holes could not be cut");
    plate = unify(op.Shape());
  }

  // The bracket, its frame on the flange's top: flange x -40..40, y -30..30, z -10..0 with four bolt holes;
  // upright x 30..40 up to z 60 with the rod's bore (r 6.25 along x at z 35).
  TopoDS_Shape bracket = fuse(box(-40, -30, -10, 40, 30, 0), box(30, -30, 0, 40, 30, 60));
  for (const auto& h : {std::pair{-25.0, -20.0}, std::pair{-25.0, 20.0}, std::pair{10.0, -20.0}, std::pair{10.0, 20.0}})
    bracket = cut(bracket, cylinder(h.first, h.second, -11, 5.25, 12));
  bracket = unify(cut(bracket, cylinderAlong(gp_Pnt(25, 0, 35), gp_Dir(1, 0, 0), 6.25, 20)));
  // Bolt: shank r 5, z 0..34, head r 8, z 34..40. Nut r 5..9, 8 high.
  const TopoDS_Shape bolt = unify(fuse(cylinder(0, 0, 0, 5, 34), cylinder(0, 0, 34, 8, 6)));
  // Cover, its frame on its top: 80 x 50 x 6 with bolt holes at (+-28, 0) and the pins' holes (r 4.05) at
  // (0, +-15).
  TopoDS_Shape cover = box(-40, -25, -6, 40, 25, 0);
  for (const double x : {-28.0, 28.0}) cover = cut(cover, cylinder(x, 0, -7, 5.25, 8));
  for (const double y : {-15.0, 15.0}) cover = cut(cover, cylinder(0, y, -7, 4.05, 8));
  cover = unify(cover);
  // Rod r 6 along x, 140 long from its frame; collars r 6.1..11, 10 long.
  const TopoDS_Shape rod = cylinderAlong(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0), 6, 140);
  const TopoDS_Shape collar =
      unify(cut(cylinderAlong(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0), 11, 10), cylinderAlong(gp_Pnt(-1, 0, 0), gp_Dir(1, 0, 0), 6.1, 12)));

  Writer w;
  const TDF_Label root = w.assembly("RIG");
  const TDF_Label plateL = w.product("RIG-PLATE", plate, {0.55, 0.57, 0.6});
  const TDF_Label bracketL = w.product("RIG-BRACKET", bracket, {0.25, 0.45, 0.3});
  const TDF_Label boltL = w.product("RIG-BOLT", bolt, {0.75, 0.75, 0.7});
  const TDF_Label nutL = w.product("RIG-NUT", tube(5, 9, 8), {0.8, 0.65, 0.2});
  const TDF_Label coverL = w.product("RIG-COVER", cover, {0.7, 0.3, 0.2});
  const TDF_Label rodL = w.product("RIG-ROD", rod, {0.7, 0.7, 0.75});
  const TDF_Label collarL = w.product("RIG-COLLAR", collar, {0.8, 0.65, 0.2});
  const TDF_Label pinL = w.product("RIG-PIN", cylinder(0, 0, 0, 4, 18), {0.5, 0.5, 0.55});
  const auto at3 = [](double x, double y, double z, double turnZ = 0.0) { return placed(turnedAt(x, y, z, turnZ)); };

  const TDF_Label bracketAssembly = w.assembly("BRACKET-ASSEMBLY");
  // Each product's frame is off its instance's origin: the writer drops the name of an identity placement.
  w.instance(bracketAssembly, bracketL, "bracket", at3(0, 0, 10));
  const double bracketBolts[4][2] = {{-25, -20}, {-25, 20}, {10, -20}, {10, 20}};
  for (int k = 0; k < 4; ++k) {
    w.instance(bracketAssembly, boltL, ("bolt-" + std::to_string(k + 1)).c_str(), at3(bracketBolts[k][0], bracketBolts[k][1], -24));
    w.instance(bracketAssembly, nutL, ("nut-" + std::to_string(k + 1)).c_str(), at3(bracketBolts[k][0], bracketBolts[k][1], -20));
  }
  const TDF_Label coverAssembly = w.assembly("COVER-ASSEMBLY");
  w.instance(coverAssembly, coverL, "cover", at3(0, 0, 6));
  for (int k = 0; k < 2; ++k) {
    const double x = k == 0 ? -28 : 28;
    // Heads under the plate: the bolt turned upside down, its shank from the head at z -12 up to z 22.
    gp_Trsf flip;
    flip.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0)), M_PI);
    w.instance(coverAssembly, boltL, ("bolt-" + std::to_string(k + 1)).c_str(), placed(turnedAt(x, 0, 22, 0) * flip));
    w.instance(coverAssembly, nutL, ("nut-" + std::to_string(k + 1)).c_str(), at3(x, 0, 6));
  }
  const TDF_Label rodAssembly = w.assembly("ROD-ASSEMBLY");
  w.instance(rodAssembly, rodL, "rod", at3(-70, 0, 0));
  w.instance(rodAssembly, collarL, "collar-1", at3(-35, 0, 0));
  w.instance(rodAssembly, collarL, "collar-2", at3(25, 0, 0));

  const TDF_Label tile = w.assembly("RIG-TILE");
  w.instance(tile, bracketAssembly, "bracket-assembly-1", at3(120, 150, 0));
  w.instance(tile, bracketAssembly, "bracket-assembly-2", at3(280, 150, 0, M_PI));
  w.instance(tile, coverAssembly, "cover-assembly-1", at3(70, 55, 0));
  w.instance(tile, coverAssembly, "cover-assembly-2", at3(330, 245, 0));
  w.instance(tile, rodAssembly, "rod-assembly", at3(200, 150, 45));
  const double pins[4][2] = {{70, 40}, {70, 70}, {330, 230}, {330, 260}};
  for (int k = 0; k < 4; ++k) w.instance(tile, pinL, ("pin-" + std::to_string(k + 1)).c_str(), at3(pins[k][0], pins[k][1], -8));

  // The product stands far from the file's origin, as a rig in a plant's layout does.
  const double ox = 2500, oy = 1200, oz = 750;
  w.instance(root, plateL, "plate", at3(ox + cx, oy + cy, oz));
  int n = 0;
  for (int j = 0; j < tilesY; ++j)
    for (int i = 0; i < tilesX; ++i)
      w.instance(root, tile, ("tile-" + std::to_string(++n)).c_str(), at3(ox + pitchX * i, oy + pitchY * j, oz));
  w.write(file, "AP214", false);
}

namespace {

// Edges whose two ends satisfy `pick` (both within the test), chamfered by `d` or filleted by `r`.
using EdgePick = std::function<bool(const gp_Pnt&, const gp_Pnt&)>;

std::vector<TopoDS_Edge> edgesWhere(const TopoDS_Shape& s, const EdgePick& pick) {
  std::vector<TopoDS_Edge> out;
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(s, TopAbs_EDGE, edges);
  for (int i = 1; i <= edges.Extent(); ++i) {
    const TopoDS_Edge e = TopoDS::Edge(edges(i));
    if (BRep_Tool::Degenerated(e)) continue;
    const gp_Pnt a = BRep_Tool::Pnt(TopExp::FirstVertex(e)), b = BRep_Tool::Pnt(TopExp::LastVertex(e));
    if (pick(a, b)) out.push_back(e);
  }
  return out;
}

TopoDS_Shape chamfered(const TopoDS_Shape& s, double d, const EdgePick& pick) {
  BRepFilletAPI_MakeChamfer op(s);
  for (const TopoDS_Edge& e : edgesWhere(s, pick)) op.Add(d, e);
  op.Build();
  if (!op.IsDone()) throw std::runtime_error("step fixtures: chamfer failed");
  return op.Shape();
}

TopoDS_Shape filleted(const TopoDS_Shape& s, double r, const EdgePick& pick) {
  BRepFilletAPI_MakeFillet op(s);
  for (const TopoDS_Edge& e : edgesWhere(s, pick)) op.Add(r, e);
  op.Build();
  if (!op.IsDone()) throw std::runtime_error("step fixtures: fillet failed");
  return op.Shape();
}

// A cone along z from radius r0 at z0 to radius r1 at z1.
TopoDS_Shape coneZ(double x, double y, double z0, double r0, double z1, double r1) {
  return BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(x, y, z0), gp_Dir(0, 0, 1)), r0, r1, z1 - z0).Shape();
}

// A blind hole as a twist drill leaves it: radius r from z `top` down to `bottom`, a 118 degree point below.
TopoDS_Shape drilled(double x, double y, double top, double bottom, double r) {
  const double point = r / std::tan(59.0 * M_PI / 180.0);
  return fuse(cylinder(x, y, bottom, r, top - bottom + 1), coneZ(x, y, bottom - point, 0.0, bottom, r));
}

bool near(double a, double b) { return std::abs(a - b) < 1e-6; }

// The fastened block's products, each in its own frame, and every instance: product, name, placement.
struct Fastened {
  std::map<std::string, TopoDS_Shape> products;
  struct Use {
    std::string product, name;
    double x, y, z;
  };
  std::vector<Use> uses;
};

Fastened fastenedBlock(const DesignerStyle& style) {
  Fastened f;
  // BASE: x -60..60, y -40..40, z 0..20 (placed at (60, 40, 0)); tapped M6 at (+-20, 0) down to z 6; dowel
  // holes r 3 at (0, +-12), z 12..20.
  TopoDS_Shape base = chamfered(box(-60, -40, 0, 60, 40, 20), 1.0, [](const gp_Pnt& a, const gp_Pnt& b) { return near(a.Z(), 20) && near(b.Z(), 20); });
  for (const double x : {-20.0, 20.0}) base = cut(base, drilled(x, 0, 20, 6, 2.5));
  for (const double y : {-12.0, 12.0}) base = cut(base, cylinder(0, y, 12, 3.0, 9));
  f.products["BASE"] = unify(base);
  // BRACKET: x -30..30, y -20..20, z 0..15 (placed at (60, 40, 20)); counterbores at (+-20, 0); dowel holes
  // r 3.01 from below to z 9; tapped M5 at (15, 9) and (-15, -9) from z 15 down to 3.
  TopoDS_Shape bracket = filleted(box(-30, -20, 0, 30, 20, 15), 3.0, [](const gp_Pnt& a, const gp_Pnt& b) {
    return near(a.X(), b.X()) && near(a.Y(), b.Y());
  });
  for (const double x : {-20.0, 20.0}) bracket = cut(cut(bracket, cylinder(x, 0, -1, 3.2, 17)), cylinder(x, 0, 8.5, 5.5, 7.5));
  for (const double y : {-12.0, 12.0}) bracket = cut(bracket, cylinder(0, y, -1, 3.01, 10));
  for (const auto& [x, y] : {std::pair{15.0, 9.0}, std::pair{-15.0, -9.0}}) bracket = cut(bracket, drilled(x, y, 15, 3, 2.1));
  f.products["BRACKET"] = unify(bracket);
  // COVER: x -25..25, y -17..17, z 0..4 (placed at (60, 40, 35)); countersinks at (15, 9), (-15, -9): a
  // 90 degree cone from r 5 at the top to r 2.75, the hole r 2.75 below.
  TopoDS_Shape cover = box(-25, -17, 0, 25, 17, 4);
  for (const auto& [x, y] : {std::pair{15.0, 9.0}, std::pair{-15.0, -9.0}})
    cover = cut(cut(cover, cylinder(x, y, -1, 2.75, 3)), coneZ(x, y, 1.75, 2.75, 4.5, 5.5));
  f.products["COVER"] = unify(cover);
  // ISO 4762 M6x20: shank r 3 z 0..20, head r 5 z 20..26; the tip and the head's top edge chamfered 0.5.
  TopoDS_Shape cap = fuse(cylinder(0, 0, 0, 3, 20), cylinder(0, 0, 20, 5, 6));
  cap = chamfered(unify(cap), 0.5, [](const gp_Pnt& a, const gp_Pnt& b) { return (near(a.Z(), 0) && near(b.Z(), 0)) || (near(a.Z(), 26) && near(b.Z(), 26)); });
  f.products["ISO 4762 M6x20"] = cap;
  // ISO 10642 M5x12: shank r 2.5 z 0..12, a 90 degree head from r 2.5 at z 12 to r 5 at z 14.5.
  f.products["ISO 10642 M5x12"] = unify(fuse(cylinder(0, 0, 0, 2.5, 12), coneZ(0, 0, 12, 2.5, 14.5, 5.0)));
  // ISO 8734 6x16: r 3.003 (r 3.3 for the clash), z 0..16, both ends chamfered 0.5.
  const auto dowel = [](double r) {
    return chamfered(cylinder(0, 0, 0, r, 16), 0.5, [](const gp_Pnt& a, const gp_Pnt& b) { return near(a.Z(), b.Z()); });
  };
  f.products["ISO 8734 6x16"] = dowel(3.003);
  if (style.clash) f.products["DOWEL 6.6x16"] = dowel(3.3);
  f.uses = {{"BASE", "base", 60, 40, 0},
            {"BRACKET", "bracket", 60, 40, 20},
            {"COVER", "cover", 60, 40, 35},
            {style.clash ? "DOWEL 6.6x16" : "ISO 8734 6x16", "dowel-1", 60, 28, 12},
            {"ISO 8734 6x16", "dowel-2", 60, 52, 12},
            {"ISO 4762 M6x20", "cap-screw-1", 40, 40, 8.5},
            {"ISO 4762 M6x20", "cap-screw-2", 80, 40, 8.5},
            {"ISO 10642 M5x12", "csk-screw-1", 75, 49, 24.5},
            {"ISO 10642 M5x12", "csk-screw-2", 45, 31, 24.5}};
  return f;
}

}  // namespace

void writeFastenedBlock(const std::filesystem::path& file, const DesignerStyle& style) {
  Writer w;
  w.bspline = style.bsplineFaces;
  const Fastened f = fastenedBlock(style);
  const TDF_Label root = w.assembly("FASTENED-BLOCK");
  std::map<std::string, TDF_Label> labels;
  for (const auto& [name, shape] : f.products) labels[name] = w.product(name.c_str(), shape);
  for (const auto& u : f.uses) w.instance(root, labels.at(u.product), u.name.c_str(), at(u.x, u.y, u.z));
  w.write(file, "AP214", style.inches);
}

double fastenedBlockOverlap(const std::string& a, const std::string& b, const DesignerStyle& style) {
  const Fastened f = fastenedBlock(style);
  const auto placedShape = [&](const std::string& name) {
    for (const auto& u : f.uses)
      if (u.name == name) {
        gp_Trsf t;
        t.SetTranslation(gp_Vec(u.x, u.y, u.z));
        return BRepBuilderAPI_Transform(f.products.at(u.product), t, true).Shape();
      }
    throw std::invalid_argument("step fixtures: no instance " + name);
  };
  BRepAlgoAPI_Common common(placedShape(a), placedShape(b));
  if (!common.IsDone()) throw std::runtime_error("step fixtures: boolean common failed");
  GProp_GProps props;
  BRepGProp::VolumeProperties(common.Shape(), props, 1e-9);
  return props.Mass();
}

void writeKeyedHub(const std::filesystem::path& file, const DesignerStyle& style) {
  Writer w;
  w.bspline = style.bsplineFaces;
  const TDF_Label root = w.assembly("KEYED-HUB");
  const gp_Dir radial(1, 0, 0);
  // A stadium along z at the shaft's +x side: width 6 (y -3..3), its round ends' centres at z0 and z1,
  // from x `inner` to `outer`.
  const auto stadium = [&](double inner, double outer, double z0, double z1) {
    return unify(fuse(fuse(box(inner, -3, z0, outer, 3, z1), cylinderAlong(gp_Pnt(inner, 0, z0), radial, 3, outer - inner)),
                      cylinderAlong(gp_Pnt(inner, 0, z1), radial, 3, outer - inner)));
  };
  // SHAFT: r 10, z 0..60, the top edge chamfered 1; the keyway a closed pocket 3.5 deep (floor at x 6.5)
  // for z 35..55.
  TopoDS_Shape shaft = chamfered(cylinder(0, 0, 0, 10, 60), 1.0,
                                 [](const gp_Pnt& a, const gp_Pnt& b) { return near(a.Z(), 60) && near(b.Z(), 60); });
  shaft = unify(cut(shaft, stadium(6.5, 11, 38, 52)));
  // KEY, DIN 6885 A 6 x 6 x 20 (round ends): x 0..6 from the keyway's floor.
  const TopoDS_Shape key = stadium(0, 6, 3, 17);
  // HUB: r 10.01 .. 25, 20 long, its slot 6 wide through its length with its floor at x 12.8 (0.3 above
  // the key); the outer edges chamfered 1.
  TopoDS_Shape hub = tube(10.01, 25, 20);
  hub = chamfered(hub, 1.0, [](const gp_Pnt& a, const gp_Pnt& b) {
    return near(std::hypot(a.X(), a.Y()), 25) && near(std::hypot(b.X(), b.Y()), 25);
  });
  hub = unify(cut(hub, box(9, -3, -1, 12.8, 3, 21)));
  // BASE: 120 x 120 x 15, the shaft's seat a blind bore r 10, 10 deep, at its middle.
  const TopoDS_Shape base = unify(cut(box(-60, -60, 0, 60, 60, 15), cylinder(0, 0, 5, 10, 11)));
  w.instance(root, w.product("BASE", base), "base", at(60, 60, 0));
  w.instance(root, w.product("SHAFT", shaft), "shaft", at(60, 60, 5));
  w.instance(root, w.product("DIN 6885 A 6x6x20", key), "key", at(66.5, 60, 40));
  w.instance(root, w.product("HUB", hub), "hub", at(60, 60, 40));
  w.write(file, "AP214", style.inches);
}

void writeBearingInHousing(const std::filesystem::path& file) {
  Writer w;
  const TDF_Label root = w.assembly("BEARING-IN-HOUSING");
  // HOUSING: x -20..20, y -20..20, z 0..12 with the bearing's seat r 11 z 5..12 and a through hole r 6.
  const TopoDS_Shape housing = unify(cut(cut(box(-20, -20, 0, 20, 20, 12), cylinder(0, 0, 5, 11, 8)), cylinder(0, 0, -1, 6, 14)));
  // The rings 7 wide (z 0..7), grooved for the balls: a torus (r 7.75 about the axis, tube r 1.75) at z 3.5.
  const TopoDS_Shape groove = BRepPrimAPI_MakeTorus(gp_Ax2(gp_Pnt(0, 0, 3.5), gp_Dir(0, 0, 1)), 7.75, 1.75).Shape();
  const TopoDS_Shape inner = cut(tube(4, 6.5, 7), groove);
  const TopoDS_Shape outer = cut(tube(9, 11, 7), groove);
  const TopoDS_Shape ball = BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 0), 1.75).Shape();
  const TDF_Label bearing = w.assembly("BEARING-608");
  w.instance(bearing, w.product("RING-INNER", inner), "ring-inner", at(0, 0, 0.001));
  w.instance(bearing, w.product("RING-OUTER", outer), "ring-outer", at(0, 0, -0.001));
  const TDF_Label ballL = w.product("BALL", ball);
  for (int k = 0; k < 8; ++k) {
    const double a = 2.0 * M_PI * k / 8.0;
    w.instance(bearing, ballL, ("ball-" + std::to_string(k + 1)).c_str(), at(7.75 * std::cos(a), 7.75 * std::sin(a), 3.5));
  }
  w.instance(root, w.product("HOUSING", housing), "housing", at(20, 20, 0));
  w.instance(root, bearing, "bearing", at(20, 20, 5));
  w.instance(root, w.product("SHAFT", cylinder(0, 0, 0, 4, 30)), "shaft", at(20, 20, -5));
  w.write(file, "AP214", false);
}

void writeUnsewnAndHollow(const std::filesystem::path& file) {
  Writer w;
  const TDF_Label root = w.assembly("UNSEWN-AND-HOLLOW");
  // Six faces, each with its own edges and vertices, in one shell: closed in space, open in topology.
  const double X = 40, Y = 30, Z = 20;
  const gp_Pnt c[8] = {{0, 0, 0}, {X, 0, 0}, {X, Y, 0}, {0, Y, 0}, {0, 0, Z}, {X, 0, Z}, {X, Y, Z}, {0, Y, Z}};
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  BRep_Builder b;
  TopoDS_Shell shell;
  b.MakeShell(shell);
  for (const auto& q : quads) b.Add(shell, BRepBuilderAPI_MakeFace(BRepBuilderAPI_MakePolygon(c[q[0]], c[q[1]], c[q[2]], c[q[3]], true).Wire()).Face());
  TopoDS_Solid unsewn;
  b.MakeSolid(unsewn);
  b.Add(unsewn, shell);
  const TopoDS_Shape hollow = cut(box(0, 0, 0, 40, 40, 40), box(10, 10, 10, 30, 30, 30));
  const bool bspline = w.bspline;
  w.instance(root, w.product("UNSEWN-BOX", unsewn), "unsewn-box", at(0, 0, 0.5));
  w.instance(root, w.product("HOLLOW-BOX", hollow), "hollow-box", at(60, 0, 0.5));
  w.bspline = bspline;
  w.write(file, "AP214", false);
}

std::string withMoreUses(const std::string& text, int copies) {
  const std::size_t use = text.find("NEXT_ASSEMBLY_USAGE_OCCURRENCE(");
  if (use == std::string::npos) throw std::invalid_argument("no NEXT_ASSEMBLY_USAGE_OCCURRENCE in the text");
  const std::size_t start = text.rfind("\n#", use) + 1, end = text.find(";\n", use) + 2;
  const std::size_t equals = text.find('=', start);
  const std::string body = text.substr(equals, end - equals);
  std::string out = text.substr(0, end);
  for (int i = 0; i < copies; ++i) out += "#" + std::to_string(900000 + i) + " " + body;
  return out + text.substr(end);
}

}  // namespace vaw::steptest
