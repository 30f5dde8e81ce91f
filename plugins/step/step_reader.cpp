// vaw-step-import, the transfer and the tree (step_reader.hpp): Open CASCADE parses the file (after the
// first pass, step_first_pass.hpp), transfers it into an XDE document, and the assembly tree is collected
// with its names, placements and colours; each product is measured in step_solids.cpp.
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Check.hxx>
#include <Interface_CheckIterator.hxx>
#include <Interface_InterfaceModel.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_Printer.hxx>
#include <Quantity_Color.hxx>
#include <STEPCAFControl_Reader.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TCollection_AsciiString.hxx>
#include <TDF_LabelSequence.hxx>
#include <TDF_Tool.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopLoc_Location.hxx>
#include <Transfer_TransientProcess.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>

#include <algorithm>
#include <cctype>
#include <compare>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "step_reader.hpp"
#include "step_first_pass.hpp"
#include "step_result.hpp"

namespace vaw::step::reader {

namespace {

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

// "#13-#19, #25" for entity numbers (sorted, each once), at most `shown` runs and a count of the rest.
std::string entityRuns(std::vector<long> ids, std::size_t shown = 6) {
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  std::string out;
  std::size_t runs = 0, i = 0;
  for (; i < ids.size() && runs < shown; ++runs) {
    std::size_t j = i;
    while (j + 1 < ids.size() && ids[j + 1] == ids[j] + 1) ++j;
    out += (out.empty() ? "#" : ", #") + std::to_string(ids[i]) + (j > i ? "-#" + std::to_string(ids[j]) : "");
    i = j + 1;
  }
  if (i < ids.size()) out += " and " + std::to_string(ids.size() - i) + " more";
  return out;
}

// A failed check in a person's words: what one entity has ("name is not a quoted string"), what many have,
// and what was made of it; for the checks without a rewording, "entity" and Open CASCADE's own words.
struct CheckKind {
  std::string one, many, outcome;
  auto operator<=>(const CheckKind&) const = default;
};

CheckKind checkKind(const std::string& message) {
  // "Parameter n0.1 (property_definition.name) not a quoted String": a $ or a number where Part 21 wants a string.
  static const std::regex notQuoted(R"(Parameter n[0-9.]+ \(([\w.]*?)(\w+)\) not a quoted String)");
  std::smatch m;
  if (std::regex_search(message, m, notQuoted)) {
    const std::string field = m[2];
    return {field + " is not a quoted string", field + "s are not quoted strings", "read as empty"};
  }
  return {"entity", "entities", message};
}

// One readable line per kind of failed check, counted, naming the entities: the check lists hold a line
// per entity ("#13: Parameter n0.1 (name) not a quoted String").
std::vector<std::string> checkSummary(const Interface_CheckIterator& checks, const Handle(Interface_InterfaceModel) & model) {
  std::map<CheckKind, std::vector<long>> byKind;  // the kind -> the entities it is about
  std::vector<CheckKind> order;
  for (checks.Start(); checks.More(); checks.Next()) {
    const Handle(Interface_Check)& check = checks.Value();
    if (check.IsNull()) continue;
    long id = checks.Number();
    if (const Handle(Standard_Transient) entity = check->Entity(); !model.IsNull() && !entity.IsNull()) {
      const Handle(TCollection_HAsciiString) label = model->StringLabel(entity);
      if (!label.IsNull() && label->ToCString()[0] == '#') id = std::atol(label->ToCString() + 1);
    }
    for (Standard_Integer i = 1; i <= check->NbFails(); ++i) {
      const CheckKind kind = checkKind(check->CFail(i));
      auto [it, added] = byKind.try_emplace(kind);
      if (added) order.push_back(kind);
      if (id > 0) it->second.push_back(id);
    }
  }
  std::vector<std::string> out;
  for (const CheckKind& kind : order) {
    const std::vector<long>& ids = byKind[kind];
    const std::size_t n = std::max<std::size_t>(ids.size(), 1);
    const std::string where = ids.empty() ? std::string() : " (" + entityRuns(ids) + ")";
    out.push_back(std::to_string(n) + " " + (n == 1 ? kind.one : kind.many) + where + ": " + kind.outcome);
  }
  return out;
}

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

// What CAD systems and Open CASCADE write where a shape or an instance has no name of its own: the kind of
// shape ("SOLID", "Body1", "Solid.2"), SolidWorks' usage ids ("NAUO12", its instances' names being blank),
// blanks. A part named so says nothing; its product's or its instance's name is used instead.
bool genericName(const std::string& name) {
  static const std::regex generic(R"(\s*((solid|shell|compound|compsolid|face|body|brep|mesh|nauo)[ ._#-]*[0-9]*)?\s*)",
                                  std::regex::icase);
  return kernelName(name) || std::regex_match(name, generic);
}

// A label's own name, else its nearest ancestor's that is a real name (a product with several
// representations keeps its name on the product, not on the shape), up to the shapes' root.
std::string productName(TDF_Label label) {
  for (int depth = 0; !label.IsNull() && depth < 4; ++depth, label = label.Father()) {
    const std::string name = labelName(label);
    if (!name.empty() && !genericName(name)) return name;
    if (label.Depth() <= 3) break;  // 0:1:1 is the shapes' root, named by nothing in the file
  }
  return {};
}

std::string entry(const TDF_Label& label) {
  TCollection_AsciiString e;
  TDF_Tool::Entry(label, e);
  return e.ToCString();
}

}  // namespace

// `scratch`: a private folder for the rewritten copy, when the first pass rewrites the file.
json Reader::read(const std::filesystem::path& file, const std::filesystem::path& scratch) {
  progress(0.0, "checking the header");
  std::filesystem::path toRead;
  std::string format;
  {
    // Read once for both checks; the text is gone before Open CASCADE reads the file again.
    std::ifstream in(file, std::ios::binary);
    if (!in) throw BadFile{"", "an existing, readable file", "cannot open it"};
    std::ostringstream all;
    all << in.rdbuf();
    const std::string text = std::move(all).str();
    format = checkHeader(text);
    progress(0.01, "first pass over " + file.filename().string());
    toRead = firstPass(text, file, scratch);
  }

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
  const IFSelect_ReturnStatus status = reader.ReadFile(toRead.string().c_str());
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
  for (const auto& w : checkSummary(ws->ModelCheckList(false), model)) warnings_.push_back("syntax check: " + w);

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
    for (const auto& w : checkSummary(tp->CheckList(false), model)) warnings_.push_back("transfer check: " + w);

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
  // The same warning for many products (six surface bodies skipped) is one line with its count.
  std::vector<std::string> warnings;
  std::map<std::string, std::size_t> times;
  for (const std::string& w : warnings_)
    if (times[w]++ == 0) warnings.push_back(w);
  for (std::string& w : warnings)
    if (times[w] > 1) w += " (" + std::to_string(times[w]) + " times)";
  json out = {{"version", vaw::step::kResultVersion}, {"format", format}, {"warnings", warnings}, {"solids", std::move(solids)}, {"root", std::move(root)}};
  if (!unit.empty()) out["unit"] = unit;
  return out;
}

std::optional<Quantity_Color> Reader::colorOf(const TDF_Label& label) const {
  Quantity_Color c;
  if (colors_->GetColor(label, XCAFDoc_ColorSurf, c) || colors_->GetColor(label, XCAFDoc_ColorGen, c)) return c;
  return std::nullopt;
}

// A product with several shape representations (a solid beside a surface body or an empty wireframe, as
// Pro/ENGINEER and Fusion 360 write them) reaches XCAF as an assembly whose components are its
// representations, placed where the product is and named by Open CASCADE after their labels. It is one
// part: the product, holding what its representations hold.
// What tells them from an assembly whose instances are unnamed: each representation is placed where the
// product is (no placement of its own) and named by the kind of shape it is, never like a product.
bool severalRepresentations(const TDF_Label& label) {
  TDF_LabelSequence components;
  XCAFDoc_ShapeTool::GetComponents(label, components, false);
  if (components.Length() == 0) return false;
  for (Standard_Integer i = 1; i <= components.Length(); ++i) {
    const TDF_Label& c = components.Value(i);
    TDF_Label ref;
    if (!kernelName(labelName(c)) || !XCAFDoc_ShapeTool::GetReferredShape(c, ref) || XCAFDoc_ShapeTool::IsAssembly(ref) ||
        !XCAFDoc_ShapeTool::GetLocation(c).IsIdentity())
      return false;
    if (const std::string own = labelName(ref); !own.empty() && !genericName(own)) return false;
  }
  return true;
}

Reader::Node Reader::collect(const TDF_Label& label, const std::string& instanceName, const TopLoc_Location& location,
             const std::optional<Quantity_Color>& color, int depth) {
  Node node;
  const std::string product = productName(label);
  node.name = instanceName.empty() || genericName(instanceName) ? product : instanceName;
  node.location = location;
  node.color = color;
  if (depth > vaw::step::kMaxAssemblyDepth) {
    warnings_.push_back("\"" + node.name + "\": skipped, assembly nested deeper than " +
                        std::to_string(vaw::step::kMaxAssemblyDepth) + " levels");
    return node;
  }
  if (shapes_->IsAssembly(label) && !severalRepresentations(label)) {
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

std::optional<json> Reader::emit(const Node& n, const std::vector<int>& index) const {
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

// Refuses what Open CASCADE would spend minutes on and rewrites what it would crash on (step_first_pass.hpp);
// the user's file is never written.
std::filesystem::path Reader::firstPass(const std::string& text, const std::filesystem::path& file,
                                        const std::filesystem::path& scratch) const {
  vaw::step::FirstPassResult pass;
  try {
    pass = vaw::step::firstPass(text, limits_);
  } catch (const vaw::step::FirstPassRefusal& r) {
    throw BadFile{r.field, r.expected, r.found};
  }
  if (pass.rewritten == 0) return file;
  const std::filesystem::path copy = scratch / ("rewritten" + file.extension().string());
  std::ofstream out(copy, std::ios::binary | std::ios::trunc);
  out.write(pass.text.data(), static_cast<std::streamsize>(pass.text.size()));
  if (!out) throw std::runtime_error("cannot write " + copy.string());
  return copy;
}

}  // namespace vaw::step::reader
