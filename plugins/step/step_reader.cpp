// vaw-step-import: reads one STEP file with Open CASCADE's XDE and writes what vaw needs (assembly tree,
// one tessellated and measured solid per product, recognised faces) as CBOR. It runs as a child of the
// STEP importer plugin because OCCT crashes or never returns on some files; the plugin turns that into
// an error naming the file (docs/step.md).
//
//   vaw-step-import FILE --out RESULT [--relative-deflection X] [--angular-deflection A]
//
// stdout: "progress FRACTION STAGE" lines. Exit 0: RESULT written. Exit 3: the file is bad; one line on
// stderr says why, and RESULT holds {"error": {field, expected, found}}. Exit 2: bad arguments.
#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepGProp.hxx>
#include <BRepLProp_SLProps.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <GeomLProp_SLProps.hxx>
#include <GeomLib_IsPlanarSurface.hxx>
#include <Geom_Surface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Check.hxx>
#include <Interface_CheckIterator.hxx>
#include <Interface_InterfaceModel.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_Printer.hxx>
#include <Poly_Triangulation.hxx>
#include <Quantity_Color.hxx>
#include <STEPCAFControl_Reader.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TCollection_AsciiString.hxx>
#include <TDF_LabelSequence.hxx>
#include <TDF_Tool.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <Transfer_TransientProcess.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_ColorTool.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <XSControl_TransferReader.hxx>
#include <Standard_OutOfMemory.hxx>
#include <XSControl_WorkSession.hxx>
#include <gp_Cylinder.hxx>
#include <gp_Pln.hxx>

#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <new>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

using nlohmann::json;

// OCCT works in millimetres here (xstep.cascade.unit = MM, set before reading); vaw in metres.
constexpr double kMetre = 1e-3;

// A defect of the file itself. Carries the fields of vaw::Diagnostic, which the plugin rebuilds.
struct BadFile {
  std::string field;
  std::string expected;
  std::string found;
};

void progress(double fraction, const std::string& stage) {
  std::printf("progress %.3f %s\n", fraction, stage.c_str());
  std::fflush(stdout);
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// ---------------------------------------------------------------------------------------------------
// The Part 21 header, checked before OCCT sees the file: OCCT ignores FILE_SCHEMA (an IFC file loads as
// AP214) and says nothing useful about a file cut short.

std::string checkHeader(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw BadFile{"", "an existing, readable file", "cannot open it"};
  std::string head(256 * 1024, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (head.rfind("\xEF\xBB\xBF", 0) == 0)
    throw BadFile{"", "a STEP file starting with ISO-10303-21;",
                  "a UTF-8 byte-order mark first (Open CASCADE refuses it; remove the first 3 bytes)"};
  std::size_t start = 0;
  while (start < head.size() && std::isspace(static_cast<unsigned char>(head[start]))) ++start;
  if (head.compare(start, 13, "ISO-10303-21;") != 0)
    throw BadFile{"", "a STEP file (ISO 10303-21)", "not a STEP file: no ISO-10303-21 header"};

  const std::string up = upper(head);
  const std::size_t schemaAt = up.find("FILE_SCHEMA");
  const std::size_t dataAt = up.find("DATA;");
  if (schemaAt == std::string::npos || (dataAt != std::string::npos && schemaAt > dataAt))
    throw BadFile{"HEADER.FILE_SCHEMA", "a FILE_SCHEMA of AP203, AP214 or AP242", "no FILE_SCHEMA in the header"};
  const std::size_t schemaEnd = up.find(';', schemaAt);
  const std::string schemaText = up.substr(schemaAt, schemaEnd == std::string::npos ? 400 : schemaEnd - schemaAt);
  std::vector<std::string> names;
  for (std::size_t q = schemaText.find('\''); q != std::string::npos;) {
    const std::size_t e = schemaText.find('\'', q + 1);
    if (e == std::string::npos) break;
    names.push_back(schemaText.substr(q + 1, e - q - 1));
    q = schemaText.find('\'', e + 1);
  }
  std::string format;
  for (const std::string& raw : names) {
    // "AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }": the name is the first word.
    const std::string name = raw.substr(0, raw.find_first_of(" {"));
    if (name.rfind("CONFIG_CONTROL_DESIGN", 0) == 0 || name.rfind("AP203", 0) == 0) format = "STEP AP203";
    else if (name.rfind("AUTOMOTIVE_DESIGN", 0) == 0 || name.rfind("AP214", 0) == 0) format = "STEP AP214";
    else if (name.rfind("AP242", 0) == 0) format = "STEP AP242";
    if (!format.empty()) break;
  }
  if (format.empty()) {
    std::string found = names.empty() ? std::string("an empty FILE_SCHEMA") : "unsupported schema \"" + names.front() + "\"";
    throw BadFile{"HEADER.FILE_SCHEMA",
                  "CONFIG_CONTROL_DESIGN (AP203), AUTOMOTIVE_DESIGN (AP214) or AP242_MANAGED_MODEL_BASED_3D_ENGINEERING (AP242)",
                  found};
  }

  // A file cut short (an interrupted download or copy) lacks the closing keyword.
  in.clear();
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  const std::streamoff tailSize = std::min<std::streamoff>(size, 4096);
  std::string tail(static_cast<std::size_t>(tailSize), '\0');
  in.seekg(size - tailSize);
  in.read(tail.data(), tailSize);
  while (!tail.empty() && std::isspace(static_cast<unsigned char>(tail.back()))) tail.pop_back();
  if (upper(tail).size() < 17 || upper(tail).compare(tail.size() - 17, 17, "END-ISO-10303-21;") != 0) {
    const bool inData = up.find("DATA;") != std::string::npos && upper(tail).rfind("ENDSEC;") == std::string::npos;
    throw BadFile{"", "a complete STEP file ending with END-ISO-10303-21;",
                  std::string("truncated: the file ends after ") + std::to_string(size) + " bytes" +
                      (inData ? ", inside the DATA section" : "") + " without END-ISO-10303-21;"};
  }
  return format;
}

// Collects OCCT's fail and alarm messages (the syntax errors with their line numbers come this way) and
// keeps its chatter off stdout, which carries the progress protocol.
class Collector final : public Message_Printer {
 public:
  mutable std::vector<std::string> messages;

 protected:
  void send(const TCollection_AsciiString& text, const Message_Gravity gravity) const override {
    if (gravity < Message_Alarm || messages.size() >= 50) return;
    // "**** ERR StepFile : Undefined Parsing: Line 8: Incorrect syntax: unexpected ';'    ****"
    std::string s = text.ToCString();
    for (const char* prefix : {"Undefined Parsing: ", "ERR StepFile : "})
      if (const std::size_t at = s.find(prefix); at != std::string::npos) s.erase(0, at + std::strlen(prefix));
    const auto junk = [](char c) { return c == '*' || std::isspace(static_cast<unsigned char>(c)); };
    while (!s.empty() && junk(s.back())) s.pop_back();
    while (!s.empty() && junk(s.front())) s.erase(0, 1);
    if (!s.empty()) messages.push_back(s);
  }
};

// "#12 (line ...): message" for each failed check, at most `limit`.
std::vector<std::string> failures(const Interface_CheckIterator& checks, const Handle(Interface_InterfaceModel) & model,
                                  std::size_t limit) {
  std::vector<std::string> out;
  for (checks.Start(); checks.More() && out.size() < limit; checks.Next()) {
    const Handle(Interface_Check)& check = checks.Value();
    if (check.IsNull()) continue;
    std::string where;
    const Handle(Standard_Transient) entity = check->Entity();
    if (!model.IsNull() && !entity.IsNull()) {
      const Handle(TCollection_HAsciiString) label = model->StringLabel(entity);
      if (!label.IsNull()) where = label->ToCString();
    }
    if (where.empty() && checks.Number() > 0) where = "entity " + std::to_string(checks.Number());
    for (Standard_Integer i = 1; i <= check->NbFails() && out.size() < limit; ++i)
      out.push_back((where.empty() ? std::string() : where + ": ") + check->CFail(i));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------
// Faces

struct FaceOut {
  int surface = 2;  // 0 plane, 1 cylinder, 2 other
  gp_Pnt point;
  gp_Dir direction{0, 0, 1};
  double radius = 0.0;
  bool convex = true;
  double axialMin = 0.0, axialMax = 0.0;
  double area = 0.0;
  bool fromSpline = false;
  std::size_t firstTriangle = 0, triangleCount = 0;
};

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

void setCylinder(FaceOut& f, const gp_Pnt& axisPoint, const gp_Dir& axis, double radius, const std::optional<gp_Dir>& outward,
                 const gp_Pnt& onSurface) {
  f.surface = 1;
  f.point = axisPoint;
  f.direction = axis;
  f.radius = radius;
  // Material inside (a shaft) when the outward normal points away from the axis.
  gp_Vec radial(axisPoint, onSurface);
  radial -= gp_Vec(axis) * radial.Dot(gp_Vec(axis));
  f.convex = !outward || radial.Dot(gp_Vec(*outward)) >= 0.0;
}

FaceOut classify(const TopoDS_Face& face, double tol, const std::vector<gp_Pnt>& nodes) {
  FaceOut f;
  GProp_GProps sp;
  BRepGProp::SurfaceProperties(face, sp, 1e-9);
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
      f.surface = 0;
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
    case GeomAbs_Cone:
    case GeomAbs_Sphere:
    case GeomAbs_Torus: return f;  // analytic, and neither a plane nor a cylinder
    default: break;
  }
  // Free-form: some exporters write every face as a B-spline.
  const Handle(Geom_Surface) s = BRep_Tool::Surface(face);
  if (s.IsNull()) return f;
  GeomLib_IsPlanarSurface planar(s, tol);
  if (planar.IsPlanar()) {
    f.surface = 0;
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
  }
  return f;
}

// ---------------------------------------------------------------------------------------------------
// Products

json colorJson(const Quantity_Color& c) {
  Standard_Real r, g, b;
  c.Values(r, g, b, Quantity_TOC_RGB);
  return json::array({r, g, b});
}

template <typename T>
json blob(const std::vector<T>& v) {
  std::vector<std::uint8_t> bytes(v.size() * sizeof(T));
  if (!v.empty()) std::memcpy(bytes.data(), v.data(), bytes.size());
  return json::binary(std::move(bytes));
}

json point(const gp_XYZ& p, double scale) { return json::array({p.X() * scale, p.Y() * scale, p.Z() * scale}); }

std::string labelName(const TDF_Label& label) {
  Handle(TDataStd_Name) name;
  if (label.IsNull() || !label.FindAttribute(TDataStd_Name::GetID(), name)) return {};
  return TCollection_AsciiString(name->Get()).ToCString();
}

// Open CASCADE names an unnamed component after the label it refers to ("=>[0:1:1:7]") and some files
// carry such entries, or bare ones ("0:1:1:7"), as names: they say nothing to a person.
bool kernelName(const std::string& name) {
  std::string s = name;
  if (s.rfind("=>", 0) == 0) s = s.substr(2);
  if (s.size() >= 2 && s.front() == '[' && s.back() == ']') s = s.substr(1, s.size() - 2);
  if (s.empty()) return !name.empty();
  return s.find_first_not_of("0123456789:") == std::string::npos && s.find(':') != std::string::npos;
}

// A label's own name, else its nearest ancestor's that is a real name (a product with several
// representations keeps its name on the product, not on the shape), up to the shapes' root.
std::string productName(TDF_Label label) {
  for (int depth = 0; !label.IsNull() && depth < 4; ++depth, label = label.Father()) {
    const std::string name = labelName(label);
    if (!name.empty() && !kernelName(name)) return name;
    if (label.Depth() <= 3) break;  // 0:1:1 is the shapes' root, named by nothing in the file
  }
  return {};
}

std::string entry(const TDF_Label& label) {
  TCollection_AsciiString e;
  TDF_Tool::Entry(label, e);
  return e.ToCString();
}

class Reader {
 public:
  Reader(double relativeDeflection, double angularDeflection)
      : relativeDeflection_(relativeDeflection), angularDeflection_(angularDeflection) {}

  json read(const std::filesystem::path& file) {
    progress(0.0, "checking the header");
    const std::string format = checkHeader(file);

    Handle(Collector) collector = new Collector();
    Message::DefaultMessenger()->ChangePrinters().Clear();
    Message::DefaultMessenger()->AddPrinter(collector);

    STEPCAFControl_Reader reader;  // initialises the STEP statics, so set ours after it
    Interface_Static::SetCVal("xstep.cascade.unit", "MM");
    reader.SetNameMode(true);
    reader.SetColorMode(true);
    reader.SetLayerMode(false);
    reader.SetPropsMode(false);
    progress(0.02, "reading " + file.filename().string());
    const IFSelect_ReturnStatus status = reader.ReadFile(file.string().c_str());
    const Handle(XSControl_WorkSession) ws = reader.ChangeReader().WS();
    const Handle(Interface_InterfaceModel) model = ws->Model();
    if (status != IFSelect_RetDone) {
      // The parser's own messages carry the line numbers; the check list names entities.
      std::vector<std::string> why = collector->messages;
      for (const auto& m : failures(ws->ModelCheckList(false), model, 3))
        if (m.find("DATA NOT AVAILABLE") == std::string::npos) why.push_back(m);
      std::string found = status == IFSelect_RetVoid ? "no entities in the DATA section" : "syntax error";
      for (std::size_t i = 0; i < why.size() && i < 3; ++i) found += (i == 0 ? ": " : "; ") + why[i];
      throw BadFile{"", "a STEP file Open CASCADE can parse", found};
    }
    for (const auto& w : failures(ws->ModelCheckList(false), model, 5)) warnings_.push_back("syntax check: " + w);

    // The unit the file declared, before OCCT converts it to millimetres.
    TColStd_SequenceOfAsciiString lengthUnits, angleUnits, solidAngleUnits;
    reader.ChangeReader().FileUnits(lengthUnits, angleUnits, solidAngleUnits);
    std::string unit;
    std::set<std::string> seen;
    for (Standard_Integer i = 1; i <= lengthUnits.Length(); ++i) {
      const std::string u = lower(lengthUnits.Value(i).ToCString());
      if (!u.empty() && seen.insert(u).second) unit += (unit.empty() ? "" : ", ") + u;
    }

    progress(0.30, "transferring shapes, names and colours");
    Handle(TDocStd_Document) doc;
    XCAFApp_Application::GetApplication()->NewDocument("MDTV-XCAF", doc);
    if (!reader.Transfer(doc))
      throw BadFile{"", "a STEP file with at least one solid", "no solid in the file (nothing Open CASCADE could transfer)"};
    const Handle(Transfer_TransientProcess) tp = ws->TransferReader()->TransientProcess();
    if (!tp.IsNull())
      for (const auto& w : failures(tp->CheckList(false), model, 10)) warnings_.push_back("transfer check: " + w);

    shapes_ = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
    colors_ = XCAFDoc_DocumentTool::ColorTool(doc->Main());
    TDF_LabelSequence free;
    shapes_->GetFreeShapes(free);
    std::vector<Node> roots;
    for (Standard_Integer i = 1; i <= free.Length(); ++i) roots.push_back(collect(free.Value(i), {}, TopLoc_Location(), {}, 0));

    for (std::size_t p = 0; p < products_.size(); ++p) {
      progress(0.40 + 0.55 * static_cast<double>(p) / static_cast<double>(products_.size()), "tessellating " + products_[p].name);
      measure(products_[p]);
    }

    json solids = json::array();
    std::vector<int> index(products_.size(), -1);
    for (std::size_t p = 0; p < products_.size(); ++p)
      if (!products_[p].solid.is_null()) {
        index[p] = static_cast<int>(solids.size());
        solids.push_back(std::move(products_[p].solid));
      }
    if (solids.empty()) throw BadFile{"", "a STEP file with at least one solid", "no solid in the file"};

    json root;
    std::vector<json> top;
    for (const Node& n : roots)
      if (auto j = emit(n, index)) top.push_back(std::move(*j));
    if (top.size() == 1) {
      root = std::move(top.front());
    } else {
      root = {{"name", file.stem().string()}, {"children", top}};
    }
    json out = {{"format", format}, {"warnings", warnings_}, {"solids", std::move(solids)}, {"root", std::move(root)}};
    if (!unit.empty()) out["unit"] = unit;
    return out;
  }

 private:
  struct Node {
    std::string name;
    TopLoc_Location location;
    std::optional<Quantity_Color> color;
    int product = -1;  // index into products_, or -1 for an assembly
    std::vector<Node> children;
  };
  struct Product {
    TDF_Label label;
    std::string name;
    json solid;  // null when skipped
  };

  std::optional<Quantity_Color> colorOf(const TDF_Label& label) const {
    Quantity_Color c;
    if (colors_->GetColor(label, XCAFDoc_ColorSurf, c) || colors_->GetColor(label, XCAFDoc_ColorGen, c)) return c;
    return std::nullopt;
  }

  Node collect(const TDF_Label& label, const std::string& instanceName, const TopLoc_Location& location,
               const std::optional<Quantity_Color>& color, int depth) {
    Node node;
    const std::string product = productName(label);
    node.name = instanceName.empty() || kernelName(instanceName) ? product : instanceName;
    node.location = location;
    node.color = color;
    if (depth > 200) {
      warnings_.push_back("\"" + node.name + "\": skipped, assembly nested deeper than 200 levels");
      return node;
    }
    if (shapes_->IsAssembly(label)) {
      TDF_LabelSequence components;
      XCAFDoc_ShapeTool::GetComponents(label, components, false);
      for (Standard_Integer i = 1; i <= components.Length(); ++i) {
        const TDF_Label comp = components.Value(i);
        TDF_Label ref;
        if (!XCAFDoc_ShapeTool::GetReferredShape(comp, ref)) continue;
        node.children.push_back(collect(ref, labelName(comp), XCAFDoc_ShapeTool::GetLocation(comp), colorOf(comp), depth + 1));
      }
      return node;
    }
    const std::string key = entry(label);
    auto [it, inserted] = productIndex_.emplace(key, static_cast<int>(products_.size()));
    if (inserted) products_.push_back(Product{label, product.empty() ? node.name : product, nullptr});
    node.product = it->second;
    return node;
  }

  void skip(Product& p, const std::string& why) { warnings_.push_back("\"" + p.name + "\": skipped, " + why); }

  // Tessellates and measures one product's solids in its own frame; leaves p.solid null (with a warning)
  // when it has none worth simulating.
  void measure(Product& p) {
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
      GProp_GProps props;
      BRepGProp::VolumeProperties(solids[i], props, 1e-9);
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
    BRepMesh_IncrementalMesh mesher(kept, deflection, false, angularDeflection_, false);

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
      json jf = {
          {"surface", f.surface}, {"area", f.area * kMetre * kMetre}, {"first", first}, {"count", triangles.size() / 3 - first}};
      if (f.surface != 2) {
        jf["point"] = point(f.point.XYZ(), kMetre);
        jf["direction"] = point(f.direction.XYZ(), 1.0);
        if (f.fromSpline) jf["fromSpline"] = true;
      }
      if (f.surface == 1) {
        jf["radius"] = f.radius * kMetre;
        jf["convex"] = f.convex;
        jf["axialMin"] = f.axialMin * kMetre;
        jf["axialMax"] = f.axialMax * kMetre;
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
    if (const auto c = colorOf(p.label)) {
      p.solid["color"] = colorJson(*c);
    } else if (const auto s = shapeColor(kept)) {
      p.solid["color"] = colorJson(*s);
    }
  }

  // Some exporters colour the solid (a sub-shape label), not the product.
  std::optional<Quantity_Color> shapeColor(const TopoDS_Shape& kept) const {
    for (TopExp_Explorer e(kept, TopAbs_SOLID); e.More(); e.Next()) {
      Quantity_Color c;
      if (colors_->GetColor(e.Current(), XCAFDoc_ColorSurf, c) || colors_->GetColor(e.Current(), XCAFDoc_ColorGen, c)) return c;
    }
    return std::nullopt;
  }

  std::optional<json> emit(const Node& n, const std::vector<int>& index) const {
    json j = {{"name", n.name}};
    const gp_Trsf t = n.location.Transformation();
    json loc = json::array();
    for (int r = 1; r <= 3; ++r) {
      for (int c = 1; c <= 3; ++c) loc.push_back(t.Value(r, c));
      loc.push_back(t.Value(r, 4) * kMetre);
    }
    j["location"] = std::move(loc);
    if (n.color) j["color"] = colorJson(*n.color);
    if (n.product >= 0) {
      if (index[static_cast<std::size_t>(n.product)] < 0) return std::nullopt;
      j["solid"] = index[static_cast<std::size_t>(n.product)];
      return j;
    }
    json children = json::array();
    for (const Node& c : n.children)
      if (auto cj = emit(c, index)) children.push_back(std::move(*cj));
    // An assembly left without parts (all skipped) is no node of the scene.
    if (children.empty()) return std::nullopt;
    j["children"] = std::move(children);
    return j;
  }

  double relativeDeflection_, angularDeflection_;
  Handle(XCAFDoc_ShapeTool) shapes_;
  Handle(XCAFDoc_ColorTool) colors_;
  std::map<std::string, int> productIndex_;
  std::vector<Product> products_;
  std::vector<std::string> warnings_;
};

void writeResult(const std::filesystem::path& out, const json& j) {
  const std::vector<std::uint8_t> bytes = json::to_cbor(j);
  const std::filesystem::path tmp = out.string() + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!f) throw std::runtime_error("cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, out);
}

int usage(const char* why) {
  std::fprintf(
      stderr,
      "vaw-step-import: %s\nusage: vaw-step-import FILE --out RESULT [--relative-deflection X] [--angular-deflection A]\n"
      "       [--parent PID] [--memory-limit-mb MB]\n", why);
  return 2;
}

// A fault on purpose, for the tests of what the plugin makes of each (VAW_STEP_READER_FAULT, never set in
// use): "crash" dies of SIGSEGV, "hang" never finishes, "memory" allocates until its limit stops it,
// "truncate" writes half a result and reports success.
void injectFault(const std::string& fault, const std::filesystem::path& out) {
  if (fault == "crash") std::raise(SIGSEGV);
  if (fault == "hang")
    for (;;) pause();
  if (fault == "memory") {
    std::vector<std::unique_ptr<char[]>> held;
    for (;;) {
      held.emplace_back(new char[64 << 20]);
      std::memset(held.back().get(), 1, 64 << 20);
    }
  }
  if (fault == "truncate") {
    const std::vector<std::uint8_t> bytes = json::to_cbor(json{{"format", "STEP AP214"}, {"solids", json::array({json::object()})}});
    std::ofstream f(out, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size() / 2));
    std::exit(0);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path file, out;
  double relative = 0.001, angular = 0.35;
  long parent = 0;
  double memoryMB = 0.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool hasValue = i + 1 < argc;
    try {
      if (a == "--out" && hasValue) out = argv[++i];
      else if (a == "--parent" && hasValue) parent = std::stol(argv[++i]);
      else if (a == "--memory-limit-mb" && hasValue) memoryMB = std::stod(argv[++i]);
      else if (a == "--relative-deflection" && hasValue) relative = std::stod(argv[++i]);
      else if (a == "--angular-deflection" && hasValue) angular = std::stod(argv[++i]);
      else if (a.rfind("--", 0) == 0) return usage(("unknown or incomplete option " + a).c_str());
      else if (file.empty()) file = a;
      else return usage("more than one FILE");
    } catch (const std::exception&) {
      return usage(("not a number after " + a).c_str());
    }
  }
  if (file.empty() || out.empty()) return usage("FILE and --out RESULT are required");
  if (!(relative > 0.0 && relative < 1.0) || !(angular > 0.0 && angular < 3.2))
    return usage("deflections must be in (0, 1) (relative) and (0, pi] (angular, radians)");

  // Ends with whoever started it, even when that one is killed: a reader spinning on a hostile file must
  // not outlive the window or command that waits for it. The parent may be gone already by now.
  if (parent > 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != static_cast<pid_t>(parent)) return 6;
  }
  // A file that makes Open CASCADE eat memory ends the reader with a named error, not the machine's OOM
  // killer choosing the window.
  if (memoryMB > 0.0) {
    const auto bytes = static_cast<rlim_t>(memoryMB * 1048576.0);
    const rlimit limit{bytes, bytes};
    setrlimit(RLIMIT_AS, &limit);
  }
  const auto outOfMemory = [&] {
    std::fprintf(stderr, "it needed more memory than the reader's limit of %.0f MB\n", memoryMB);
    return 5;
  };
  try {
    if (const char* fault = std::getenv("VAW_STEP_READER_FAULT")) injectFault(fault, out);
    Reader reader(relative, angular);
    json result = reader.read(file);
    progress(0.97, "writing the result");
    writeResult(out, result);
    progress(1.0, "done");
    return 0;
  } catch (const BadFile& bad) {
    std::fprintf(stderr, "%s\n", bad.found.c_str());
    try {
      writeResult(out, json{{"error", {{"field", bad.field}, {"expected", bad.expected}, {"found", bad.found}}}});
    } catch (const std::exception&) {
      // The stderr line alone still tells the plugin what is wrong.
    }
    return 3;
  } catch (const std::bad_alloc&) {
    return outOfMemory();
  } catch (const Standard_OutOfMemory&) {
    return outOfMemory();
  } catch (const Standard_Failure& f) {
    std::fprintf(stderr, "Open CASCADE failed: %s: %s\n", f.DynamicType()->Name(), f.GetMessageString());
    return 4;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 4;
  }
}
