// vaw-step-import: reads one STEP file with Open CASCADE's XDE and writes what vaw needs (docs/step.md). Its
// stages, one file each: the header check (step_header_check.cpp), the first pass (step_first_pass.cpp),
// the transfer and the assembly tree (step_reader.cpp), the solids with their mass properties and
// tessellation (step_solids.cpp), the faces (step_faces.cpp), and the result and the process around them
// (step_reader_main.cpp). Private to the reader program.
#pragma once

#include <Quantity_Color.hxx>
#include <TDF_Label.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <XCAFDoc_ColorTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <gp_Dir.hxx>
#include <gp_Pnt.hxx>

#include <cstddef>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "step_first_pass.hpp"
#include "step_result.hpp"

namespace vaw::step::reader {

using nlohmann::json;

// OCCT works in millimetres here (xstep.cascade.unit = MM, set before reading); vaw in metres.
constexpr double kMetre = 1e-3;

// A defect of the file itself. Carries the fields of vaw::Diagnostic, which the plugin rebuilds.
struct BadFile {
  std::string field;
  std::string expected;
  std::string found;
};

// One "progress FRACTION STAGE" line on stdout, which the plugin relays.
void progress(double fraction, const std::string& stage);
std::string upper(std::string s);
std::string lower(std::string s);

// The Part 21 header of a file's text: a STEP file of a schema vaw reads, complete. Returns the format
// ("STEP AP214").
std::string checkHeader(const std::string& text);

struct FaceOut {
  vaw::step::SurfaceKind surface = vaw::step::SurfaceKind::Other;
  gp_Pnt point;
  gp_Dir direction{0, 0, 1};
  double radius = 0.0;     // cylinder; cone: at its widest
  double halfAngle = 0.0;  // cone, rad
  bool convex = true;
  double axialMin = 0.0, axialMax = 0.0;
  double area = 0.0;
  bool fromSpline = false;
  std::size_t firstTriangle = 0, triangleCount = 0;
};

// A plane, cylinder, cone, sphere or torus, on which Gauss integration at its fixed order is exact to a few
// 1e-6; a free-form face needs the adaptive one.
bool analytic(const TopoDS_Face& face);

// A face's surface from the exact geometry; `nodes`: its tessellation, for a cylinder's axial extent.
FaceOut classify(const TopoDS_Face& face, double tol, const std::vector<gp_Pnt>& nodes);

json colorJson(const Quantity_Color& c);

class Reader {
 public:
  Reader(double relativeDeflection, double angularDeflection, const vaw::step::FirstPassLimits& limits)
      : relativeDeflection_(relativeDeflection), angularDeflection_(angularDeflection), limits_(limits) {}

  // `scratch`: a private folder for the rewritten copy, when the first pass rewrites the file.
  json read(const std::filesystem::path& file, const std::filesystem::path& scratch);

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

  std::optional<Quantity_Color> colorOf(const TDF_Label& label) const;
  Node collect(const TDF_Label& label, const std::string& instanceName, const TopLoc_Location& location,
               const std::optional<Quantity_Color>& color, int depth);
  void skip(Product& p, const std::string& why);
  // Tessellates and measures one product's solids in its own frame; leaves p.solid null (with a warning)
  // when it has none worth simulating.
  void measure(Product& p);
  // `solid` (meshed) or a copy of it meshed again, whichever leaves its tessellation closed or least open.
  TopoDS_Shape closeTessellation(const TopoDS_Shape& solid, double diagonal, double deflection) const;
  // Some exporters colour the solid (a sub-shape label), not the product.
  std::optional<Quantity_Color> shapeColor(const TopoDS_Shape& kept) const;
  std::optional<json> emit(const Node& n, const std::vector<int>& index) const;
  // Refuses what Open CASCADE would spend minutes on and rewrites what it would crash on (step_first_pass.hpp);
  // the user's file is never written.
  // Returns the file Open CASCADE is to read: `file`, or its rewritten copy in `scratch`.
  std::filesystem::path firstPass(const std::string& text, const std::filesystem::path& file,
                                  const std::filesystem::path& scratch) const;

  double relativeDeflection_, angularDeflection_;
  vaw::step::FirstPassLimits limits_;
  Handle(XCAFDoc_ShapeTool) shapes_;
  Handle(XCAFDoc_ColorTool) colors_;
  std::map<std::string, int> productIndex_;
  std::vector<Product> products_;
  std::vector<std::string> warnings_;
};

}  // namespace vaw::step::reader
