// Reading a scene file: its schema, section by section, into an assembly. Mesh files, whether a
// scene's shapes or opened bare, are mesh_import.cpp's.
#include "vaw/scene_loader.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <tuple>

#include "../base/json_node.hpp"
#include "load_detail.hpp"
#include "mesh_import.hpp"
#include "vaw/cad_assembly.hpp"
#include "vaw/dynamics/hinge.hpp"
#include "vaw/limits.hpp"
#include "vaw/paths.hpp"
#include "vaw/primitives.hpp"
#include "vaw/property_file.hpp"

namespace vaw {

using detail::Imported;
using detail::MeshCache;
using detail::Node;
using detail::Progress;
using detail::toString;

namespace {

struct Units {
  LengthUnit length = LengthUnit::Metre;
  double L = 1.0;  // metres per file unit
  double M = 1.0;  // kilograms per file unit
};

Eigen::Isometry3d readPose(const Node& n, double L) {
  n.allowOnly({"position", "rotation"});
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  if (auto p = n.opt("position")) pose.translation() = p->position(L);
  if (auto r = n.opt("rotation")) pose.linear() = r->rotation();
  return pose;
}

Eigen::Vector3f readColor(const Node& n) {
  const std::string s = n.string();
  auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  if (s.size() != 7 || s[0] != '#') n.fail("a colour \"#rrggbb\"");
  float rgb[3];
  for (int i = 0; i < 3; ++i) {
    const int hi = hex(s[static_cast<std::size_t>(1 + 2 * i)]), lo = hex(s[static_cast<std::size_t>(2 + 2 * i)]);
    if (hi < 0 || lo < 0) n.fail("a colour \"#rrggbb\"");
    rgb[i] = static_cast<float>(hi * 16 + lo) / 255.0f;
  }
  return {rgb[0], rgb[1], rgb[2]};
}

double readDensity(const Node& n) {
  std::optional<double> rho;
  if (n.json().is_number()) rho = n.number();
  else if (n.json().is_string()) rho = parseDensity(n.string());
  else n.fail("a density: a number in kg/m^3 or \"<value> kg/m^3|g/cm^3|lb/in^3\"");
  if (!rho) n.fail("a density with a known unit: kg/m^3, g/cm^3 or lb/in^3");
  if (!(*rho >= limits::kMinDensity && *rho <= limits::kMaxDensity))
    n.failWith("a density from " + toString(limits::kMinDensity) + " to " + toString(limits::kMaxDensity) + " kg/m^3",
               toString(*rho) + " kg/m^3");
  return *rho;
}

TriMesh readPrimitive(const Node& n, double L) {
  n.requireObject();
  const std::string type = n.get("type").string();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  if (auto p = n.opt("pose")) pose = readPose(*p, L);
  auto segments = [&](const char* key, int def, int minimum) {
    if (auto s = n.opt(key)) return s->integer(minimum, limits::kMaxSegments);
    return def;
  };
  // A length in file units, within the world's size bounds once converted.
  auto length = [L](const Node& v) {
    const double x = v.positive() * L;
    if (!(x >= limits::kMinSize && x <= limits::kMaxSize))
      v.failWith("a length from " + toString(limits::kMinSize) + " m to " + toString(limits::kMaxSize) + " m", toString(x) + " m");
    return x;
  };
  TriMesh m;
  if (type == "box") {
    n.allowOnly({"type", "size", "pose"});
    const Node s = n.get("size");
    if (!s.json().is_array() || s.size() != 3) s.fail("three positive lengths");
    m = primitives::box({length(s.at(0)), length(s.at(1)), length(s.at(2))});
  } else if (type == "cylinder") {
    n.allowOnly({"type", "radius", "height", "segments", "pose"});
    m = primitives::cylinder(length(n.get("radius")), length(n.get("height")), segments("segments", 64, 3));
  } else if (type == "tube") {
    n.allowOnly({"type", "outer_radius", "inner_radius", "height", "segments", "pose"});
    const double ro = length(n.get("outer_radius"));
    const Node inner = n.get("inner_radius");
    const double ri = length(inner);
    if (ri >= ro) inner.fail("an inner radius smaller than outer_radius");
    m = primitives::tube(ro, ri, length(n.get("height")), segments("segments", 64, 3));
  } else if (type == "sphere") {
    n.allowOnly({"type", "radius", "segments", "rings", "pose"});
    m = primitives::sphere(length(n.get("radius")), segments("segments", 64, 3), segments("rings", 32, 2));
  } else {
    n.get("type").fail("a primitive type: \"box\", \"cylinder\", \"tube\" or \"sphere\"");
  }
  m.transform(pose);
  return m;
}

struct PartSpec {
  Node node;
  Eigen::Isometry3d parentPose;
  TreeNode* treeNode;  // filled in once the part exists
};

class SceneReader {
 public:
  SceneReader(const std::filesystem::path& file, const ImporterRegistry& importers, const LoadOptions& options,
              const ProgressFn& progress)
      : path_(file), file_(file.string()), dir_(file.parent_path()), options_(options), progress_(progress),
        importers_(importers), meshes_(importers, options.import) {}

  Assembly read() {
    progress_.report(0.0, "reading " + path_.filename().string());
    json_ = detail::readJsonFile(path_);
    const Node root(json_, "", file_);
    root.requireFormat("vaw-scene");
    const Node version = root.get("version");
    const int v = version.integer();
    if (v < 1 || v > kSceneFormatVersion)
      version.fail("version 1 to " + std::to_string(kSceneFormatVersion) + " (the versions this vaw reads)");
    if (root.has("cad")) {
      if (v < 3) root.get("cad").fail("a scene of version 3 or later (\"cad\" came with version 3)");
      return readCad(root);
    }
    if (v >= 2)
      root.allowOnly({"format", "version", "name", "description", "units", "materials", "parts", "base", "environment",
                      "constraints", "tools", "settings"});
    else
      root.allowOnly({"format", "version", "name", "description", "units", "materials", "parts", "base", "environment",
                      "constraints"});
    if (auto d = root.opt("description")) (void)d->string();

    assembly_.name = root.get("name").string();
    assembly_.source = path_;
    assembly_.categorySettings = options_.categories;
    readUnits(root.get("units"));
    assembly_.units = units_.length;
    readMaterials(root.get("materials"));

    assembly_.tree.kind = TreeNode::Kind::Assembly;
    assembly_.tree.name = assembly_.name;
    const Node parts = root.get("parts");
    parts.requireArray();
    if (parts.size() == 0) parts.fail("at least one part");
    collectParts(parts, Eigen::Isometry3d::Identity(), assembly_.tree, 0);
    for (std::size_t i = 0; i < specs_.size(); ++i) {
      progress_.report(0.05 + 0.85 * static_cast<double>(i) / static_cast<double>(specs_.size()),
                       "part " + std::to_string(i + 1) + " of " + std::to_string(specs_.size()));
      readPart(specs_[i], i);
    }
    if (auto b = root.opt("base")) {
      const auto id = assembly_.findPart(b->string());
      if (!id) b->fail("the name of a part in this scene");
      assembly_.base = id;
    }
    progress_.report(0.9, "environment");
    if (auto env = root.opt("environment")) readEnvironment(*env);
    if (auto cons = root.opt("constraints")) readConstraints(*cons);
    if (auto tools = root.opt("tools")) readTools(*tools);
    if (auto settings = root.opt("settings")) readSettings(*settings);
    progress_.report(1.0, "done");
    return std::move(assembly_);
  }

 private:
  // A scene over a CAD file (docs/scene-format.md, "cad"): the parts, tree and poses come from the file, the
  // scene holds the base, the constraints and the tuning. A file that changed since the scene was saved
  // is read anew: its constraints are found again and the saved ones are not applied.
  Assembly readCad(const Node& root) {
    root.allowOnly({"format", "version", "name", "description", "units", "cad", "constraints", "settings"});
    if (auto d = root.opt("description")) (void)d->string();
    const Node cad = root.get("cad");
    cad.requireObject();
    cad.allowOnly({"file", "hash", "base", "units", "up", "units_apart", "units_joined"});
    const Node fileNode = cad.get("file");
    const std::filesystem::path cadFile = dir_ / fileNode.string();
    if (const std::string problem = fileProblem(cadFile); !problem.empty())
      fileNode.failWith("an existing, readable CAD file", "\"" + cadFile.string() + "\": " + problem);
    if (!importers_.find(cadFile))
      fileNode.failWith("a STEP file (the Open CASCADE plugin reads it) or a mesh file of several parts",
                        "\"" + cadFile.extension().string() + "\" with no importer for it");
    LoadOptions opts = options_;
    // A base chosen by the caller (re-basing a saved scene) wins over the one the scene saved.
    if (auto b = cad.opt("base"); b && !options_.cadBase) opts.cadBase = b->string();
    if (auto u = cad.opt("up"); u && !options_.cadUp) {
      if (!validUpChoice(u->string())) u->fail(kUpChoices);
      opts.cadUp = u->string();
    }
    // The units the user took apart or joined (docs/step.md, "Units"); a choice the caller makes now wins.
    const auto names = [](const Node& list) {
      list.requireArray();
      std::set<std::string> out;
      for (std::size_t i = 0; i < list.size(); ++i) {
        const Node e = list.at(i);
        if (!e.json().is_string() || e.string().empty()) e.fail("the instance name of a sub-assembly in the CAD file");
        out.insert(e.string());
      }
      return out;
    };
    std::set<std::string> savedSplit, savedJoin;
    if (auto list = cad.opt("units_apart")) savedSplit = names(*list);
    if (auto list = cad.opt("units_joined")) savedJoin = names(*list);
    for (const std::string& n : savedSplit)
      if (!options_.cadJoin.count(n)) opts.cadSplit.insert(n);
    for (const std::string& n : savedJoin)
      if (!options_.cadSplit.count(n)) opts.cadJoin.insert(n);
    // The saved constraints name the parts those units gave: with other units they are found anew.
    const bool unitsChanged = opts.cadSplit != savedSplit || opts.cadJoin != savedJoin;
    // The unit assumed for a mesh file, which declares none.
    if (auto u = cad.opt("units")) {
      const auto unit = parseLengthUnit(u->string());
      if (!unit) u->fail("a length unit: \"m\", \"mm\" or \"inch\"");
      opts.bareMeshUnits = *unit;
    }
    try {
      assembly_ = loadMeshFile(cadFile, importers_, opts, progress_.sub(0.0, 0.9));
    } catch (const InputError& e) {
      // The base named in the scene is no part of the file any more: say where it was named.
      if (e.diagnostic().field == "base" && cad.has("base") && !options_.cadBase) cad.get("base").fail("the name of a part in " + cadFile.string());
      throw;
    }
    if (assembly_.cadFile.empty()) fileNode.failWith("a CAD file with solids or a mesh file of several parts", "a mesh file of one part");
    assembly_.source = path_;
    assembly_.name = root.get("name").string();
    assembly_.tree.name = assembly_.name;
    static const detail::Json metres = "m";
    readUnits(root.has("units") ? root.get("units") : Node(metres, "units", file_));
    const std::string savedHash = cad.has("hash") ? cad.get("hash").string() : std::string();
    // The saved constraints are relative to the saved base: with another one they are found anew.
    const bool rebased = options_.cadBase && (!cad.has("base") || cad.get("base").string() != *options_.cadBase);
    if (auto cons = root.opt("constraints"); cons && unitsChanged && !rebased) {
      assembly_.warnings.push_back({Diagnostic::Severity::Warning, file_, "cad.units_apart", "the units the scene was saved with",
                                    "other units chosen now: the constraints were found anew and the saved ones not applied"});
    } else if (cons && !rebased) {
      // A scene saved before file hashes were XXH3 holds FNV-1a's: that file is hashed again the old way.
      const bool unchanged = savedHash == assembly_.cadHash || (savedHash.starts_with("fnv1a64:") && savedHash == fileContentHashFnv(cadFile));
      if (unchanged) {
        assembly_.constraints.clear();
        readConstraints(*cons);
      } else {
        assembly_.warnings.push_back({Diagnostic::Severity::Warning, file_, "cad.hash", "the hash of the file when the scene was saved, " + savedHash,
                                      assembly_.cadHash + ": " + cadFile.string() +
                                          " changed since; its constraints were found anew and the saved ones not applied"});
      }
    }
    if (auto settings = root.opt("settings")) readSettings(*settings);
    progress_.report(1.0, "done");
    return std::move(assembly_);
  }

  void readUnits(const Node& n) {
    std::string length = "m", mass = "kg";
    const Node* lengthNode = &n;
    std::optional<Node> ln, mn;
    if (n.json().is_string()) {
      length = n.string();
    } else if (n.json().is_object()) {
      n.allowOnly({"length", "mass"});
      ln = n.get("length");
      length = ln->string();
      lengthNode = &*ln;
      if ((mn = n.opt("mass"))) {
        mass = mn->string();
        if (!parseMassUnit(mass)) mn->fail("a mass unit: \"kg\", \"g\" or \"lb\"");
      }
    } else {
      n.fail("a length unit (\"m\", \"mm\", \"inch\") or {\"length\": ..., \"mass\": ...}");
    }
    const auto lu = parseLengthUnit(length);
    if (!lu) lengthNode->fail("a length unit: \"m\", \"mm\" or \"inch\"");
    units_.length = *lu;
    units_.L = toMetres(*lu);
    units_.M = toKilograms(*parseMassUnit(mass));
  }

  void readMaterials(const Node& n) {
    n.requireObject();
    for (const auto& [key, value] : n.json().items()) {
      if (!key.empty() && key[0] == '_') continue;
      const Node m(value, n.path() + "." + key, file_);
      m.allowOnly({"density", "friction", "color"});
      Material mat;
      mat.name = key;
      if (auto d = m.opt("density")) mat.density = readDensity(*d);
      if (auto f = m.opt("friction")) {
        f->allowOnly({"static", "kinetic", "rotational"});
        const Node st = f->get("static");
        mat.staticFriction = st.number(0.0, limits::kMaxFriction, "");
        const Node kin = f->get("kinetic");
        mat.kineticFriction = kin.number(0.0, limits::kMaxFriction, "");
        if (mat.kineticFriction > mat.staticFriction)
          kin.fail("a kinetic coefficient no larger than the static one (" + toString(mat.staticFriction) + ")");
        if (auto r = f->opt("rotational")) mat.rotationalFriction = r->number(0.0, limits::kMaxRotationalFriction, "N m s");
        if (mat.staticFriction > limits::kUnusualFriction)
          assembly_.warnings.push_back({Diagnostic::Severity::Warning, file_, st.path(),
                                        "a friction coefficient up to " + toString(limits::kUnusualFriction) +
                                            " (rubber on dry concrete is about 1)",
                                        toString(mat.staticFriction) + ", used as given"});
      }
      if (auto c = m.opt("color")) mat.color = readColor(*c);
      assembly_.materials.emplace(key, mat);
    }
  }

  void collectParts(const Node& list, const Eigen::Isometry3d& parentPose, TreeNode& parent, int depth) {
    if (depth > limits::kMaxGroupDepth)
      list.failWith("groups nested at most " + std::to_string(limits::kMaxGroupDepth) + " deep", "deeper nesting");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const Node e = list.at(i);
      e.requireObject();
      const Node nameNode = e.get("name");
      const std::string name = nameNode.string();
      if (name.empty()) nameNode.fail("a non-empty name");
      if (e.has("children")) {
        e.allowOnly({"name", "pose", "children"});
        Eigen::Isometry3d pose = parentPose;
        if (auto p = e.opt("pose")) pose = parentPose * readPose(*p, units_.L);
        TreeNode group;
        group.kind = TreeNode::Kind::Group;
        group.name = name;
        parent.children.push_back(std::move(group));
        const Node children = e.get("children");
        children.requireArray();
        collectParts(children, pose, parent.children.back(), depth + 1);
      } else {
        if (!partNames_.insert(name).second) nameNode.fail("a part name not used before in this scene");
        TreeNode leaf;
        leaf.kind = TreeNode::Kind::Part;
        leaf.name = name;
        leaf.index = specs_.size();
        parent.children.push_back(std::move(leaf));
        specs_.push_back({e, parentPose, nullptr});
      }
    }
  }

  // Tree nodes live in vectors that grew while collecting; find the leaf again by id.
  static TreeNode* findLeaf(TreeNode& t, TreeNode::Kind kind, std::size_t index) {
    if (t.kind == kind && t.index == index) return &t;
    for (auto& c : t.children)
      if (TreeNode* f = findLeaf(c, kind, index)) return f;
    return nullptr;
  }

  struct Shape {
    std::shared_ptr<const TriMesh> mesh;
    std::string source;
    std::optional<TreeNode> meshTree;
  };

  Shape readShape(const Node& e, const ProgressFn& progress) {
    const bool hasMesh = e.has("mesh"), hasPrimitive = e.has("primitive");
    if (hasMesh == hasPrimitive) e.failWith("exactly one of \"mesh\" or \"primitive\"", hasMesh ? "both" : "neither");
    Shape s;
    if (hasMesh) {
      const Node m = e.get("mesh");
      const std::filesystem::path file = dir_ / m.string();
      const Imported& im = meshes_.get(file, units_.L, m, progress);
      for (const auto& w : im.warnings) assembly_.warnings.push_back({Diagnostic::Severity::Warning, file.string(), "", "", w});
      s.mesh = im.mesh;
      s.source = m.string();
      // A file whose geometry sits in one node has no hierarchy worth showing.
      if (detail::nodesWithGeometry(im.root) > 1) s.meshTree = detail::meshTree(im.root);
    } else {
      const Node p = e.get("primitive");
      TriMesh mesh;
      if (p.json().is_array()) {
        if (p.size() == 0) p.fail("a primitive or a non-empty array of primitives");
        for (std::size_t i = 0; i < p.size(); ++i) mesh.append(readPrimitive(p.at(i), units_.L));
        s.source = "compound of " + std::to_string(p.size()) + " primitives";
      } else {
        mesh = readPrimitive(p, units_.L);
        s.source = "primitive " + p.get("type").string();
      }
      s.mesh = std::make_shared<const TriMesh>(std::move(mesh));
    }
    return s;
  }

  void readPart(PartSpec& spec, std::size_t index) {
    const Node& e = spec.node;
    e.allowOnly({"name", "mesh", "primitive", "material", "pose", "final_pose", "properties", "density"});
    Part part;
    part.id = index;
    part.name = e.get("name").string();
    const Node matNode = e.get("material");
    part.material = matNode.string();
    auto mat = assembly_.materials.find(part.material);
    if (mat == assembly_.materials.end()) matNode.fail("the name of a material in \"materials\"");

    Shape shape = readShape(e, progress_.sub(0.05 + 0.85 * static_cast<double>(index) / static_cast<double>(specs_.size()),
                                             0.05 + 0.85 * static_cast<double>(index + 1) / static_cast<double>(specs_.size())));
    part.mesh = shape.mesh;
    part.shapeSource = shape.source;
    part.pose = spec.parentPose;
    // Each pose is within the world bound; so must be the pose its groups' poses compose to.
    const auto composed = [&](const char* key) {
      const Node p = e.get(key);
      const Eigen::Isometry3d pose = spec.parentPose * readPose(p, units_.L);
      if (!(pose.translation().cwiseAbs().maxCoeff() <= limits::kMaxCoordinate))
        p.failWith("a pose within " + toString(limits::kMaxCoordinate) + " m of the origin with its groups' poses",
                   "a position " + toString(pose.translation().cwiseAbs().maxCoeff()) + " m out");
      return pose;
    };
    if (e.has("pose")) part.pose = composed("pose");
    if (e.has("final_pose")) part.finalPose = composed("final_pose");

    std::optional<double> density = mat->second.density;
    if (auto d = e.opt("density")) density = readDensity(*d);
    if (density) part.meshMass = massPropertiesFromMesh(*part.mesh, *density);
    if (auto pf = e.opt("properties")) {
      part.propertyFile = dir_ / pf->string();
      if (const std::string problem = fileProblem(part.propertyFile); !problem.empty())
        pf->failWith("an existing, readable property file", "\"" + part.propertyFile.string() + "\": " + problem);
      part.fileMass = readPropertyFile(part.propertyFile).mass;
    }
    if (part.fileMass) {
      part.mass = *part.fileMass;
      part.massSource = MassSource::PropertyFile;
      if (part.meshMass) {
        part.disagreement = compare(*part.fileMass, *part.meshMass, part.mesh->bounds().diagonal().norm());
        if (part.disagreement->worst() > options_.massDisagreementWarning) {
          std::ostringstream s;
          s << "mass " << 100.0 * part.disagreement->massRel << " %, centre of mass " << 1000.0 * part.disagreement->comDistance
            << " mm, inertia " << 100.0 * part.disagreement->inertiaRel << " %";
          assembly_.warnings.push_back({Diagnostic::Severity::Warning, part.propertyFile.string(), "mass properties",
                                        "agreement with the mesh within " + toString(100.0 * options_.massDisagreementWarning) + " %",
                                        s.str()});
        }
      }
    } else if (part.meshMass) {
      part.mass = *part.meshMass;
      part.massSource = MassSource::Mesh;
    } else {
      e.failWith("a density (on the part or its material) or a \"properties\" file", "neither");
    }
    if (const std::string problem = inertiaProblem(part.mass.inertiaCm, 1e-6); !problem.empty())
      e.failWith("mass properties with a physically valid inertia", problem);

    part.principal = principalMoments(part.mass.inertiaCm);
    part.extent = principalExtent(*part.mesh, part.principal.axes);
    part.category = categorize(part.mass.mass, part.extent, options_.categories);

    if (TreeNode* leaf = findLeaf(assembly_.tree, TreeNode::Kind::Part, index); leaf && shape.meshTree)
      leaf->children = std::move(shape.meshTree->children);
    assembly_.parts.push_back(std::move(part));
  }

  void readEnvironment(const Node& list) {
    list.requireArray();
    std::set<std::string> names;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const Node e = list.at(i);
      e.allowOnly({"name", "kind", "mesh", "primitive", "pose", "color"});
      EnvironmentObject obj;
      const Node nameNode = e.get("name");
      obj.name = nameNode.string();
      if (!names.insert(obj.name).second) nameNode.fail("a name not used by another environment object");
      const Node kind = e.get("kind");
      obj.kind = kind.string();
      if (obj.kind != "table" && obj.kind != "floor" && obj.kind != "fixture") kind.fail("\"table\", \"floor\" or \"fixture\"");
      Shape shape = readShape(e, {});
      obj.mesh = shape.mesh;
      obj.shapeSource = shape.source;
      if (auto p = e.opt("pose")) obj.pose = readPose(*p, units_.L);
      if (auto c = e.opt("color")) obj.color = readColor(*c);
      TreeNode leaf;
      leaf.kind = TreeNode::Kind::Environment;
      leaf.name = obj.name;
      leaf.index = assembly_.environment.size();
      assembly_.tree.children.push_back(std::move(leaf));
      assembly_.environment.push_back(std::move(obj));
    }
  }

  Plane readPlane(const Node& n) {
    n.allowOnly({"point", "normal"});
    return {n.get("point").position(units_.L), n.get("normal").direction()};
  }
  Axis readAxis(const Node& n) {
    n.allowOnly({"point", "direction"});
    return {n.get("point").position(units_.L), n.get("direction").direction()};
  }

  // What recognition measured, kept with a saved CAD scene (lengths in the scene's unit, areas in its square).
  Constraint::Found readFound(const Node& n, Constraint::Type type) {
    n.requireObject();
    n.allowOnly({"part_radius", "partner_radius", "clearance", "overlap", "from_spline", "fit", "interference", "thread", "seat",
                 "seat_radius", "seat_angle", "key_width"});
    Constraint::Found f;
    const double L = units_.L;
    if (auto x = n.opt("part_radius")) f.partRadius = x->number(0.0, limits::kMaxCoordinate / L, "") * L;
    if (auto x = n.opt("partner_radius")) f.partnerRadius = x->number(0.0, limits::kMaxCoordinate / L, "") * L;
    if (auto x = n.opt("clearance")) f.clearance = x->number(0.0, limits::kMaxCoordinate / L, "") * L;
    if (auto x = n.opt("overlap"))
      f.overlap = x->number(0.0, 1e12, "") * (type == Constraint::Type::Insert ? L : L * L);
    if (auto x = n.opt("from_spline")) {
      if (!x->json().is_boolean()) x->fail("true or false");
      f.fromSpline = x->json().get<bool>();
    }
    if (auto x = n.opt("fit")) {
      const std::string fit = x->string();
      if (fit == "threaded") f.fit = Constraint::Found::Fit::Threaded;
      else if (fit == "press") f.fit = Constraint::Found::Fit::Press;
      else if (fit != "clearance") x->fail("\"clearance\", \"threaded\" or \"press\"");
    }
    if (auto x = n.opt("interference")) f.interference = x->number(0.0, limits::kMaxCoordinate / L, "") * L;
    if (auto x = n.opt("thread")) f.thread = x->string();
    if (auto x = n.opt("seat")) {
      if (x->string() == "counterbore") f.seat = Constraint::Found::Seat::Counterbore;
      else if (x->string() == "countersink") f.seat = Constraint::Found::Seat::Countersink;
      else if (x->string() != "none") x->fail("\"none\", \"counterbore\" or \"countersink\"");
    }
    if (auto x = n.opt("seat_radius")) f.seatRadius = x->number(0.0, limits::kMaxCoordinate / L, "") * L;
    if (auto x = n.opt("seat_angle")) f.seatAngle = x->number(0.0, 90.0, "degrees") * std::numbers::pi / 180.0;
    if (auto x = n.opt("key_width")) f.keyWidth = x->number(0.0, limits::kMaxCoordinate / L, "") * L;
    return f;
  }

  void readConstraints(const Node& list) {
    list.requireArray();
    for (std::size_t i = 0; i < list.size(); ++i) {
      const Node c = list.at(i);
      c.requireObject();
      const Node typeNode = c.get("type");
      const std::string type = typeNode.string();
      Constraint con;
      if (type == "mate" || type == "align") {
        c.allowOnly({"type", "name", "part", "partner", "part_plane", "base_plane", "offset", "accepted", "home_direction", "found"});
        con.type = type == "mate" ? Constraint::Type::Mate : Constraint::Type::Align;
        con.partPlane = readPlane(c.get("part_plane"));
        con.basePlane = readPlane(c.get("base_plane"));
        if (auto o = c.opt("offset")) {
          con.offset = o->number() * units_.L;
          if (!(std::abs(con.offset) <= limits::kMaxCoordinate)) o->fail("an offset within the world bound of 1000 m");
        }
      } else if (type == "insert") {
        c.allowOnly({"type", "name", "part", "partner", "part_axis", "base_axis", "accepted", "home_direction", "found"});
        con.type = Constraint::Type::Insert;
        con.partAxis = readAxis(c.get("part_axis"));
        con.baseAxis = readAxis(c.get("base_axis"));
      } else {
        typeNode.fail("a constraint type: \"mate\", \"align\" or \"insert\"");
      }
      if (!assembly_.base) c.failWith("a scene with a \"base\" part to constrain against", "no base");
      const Node partNode = c.get("part");
      const auto id = assembly_.findPart(partNode.string());
      if (!id) partNode.fail("the name of a part in this scene");
      if (*id == *assembly_.base) partNode.fail("a part other than the base");
      con.part = *id;
      if (auto pn = c.opt("partner")) {
        const auto partner = assembly_.findPart(pn->string());
        if (!partner) pn->fail("the name of a part in this scene");
        if (*partner == *id) pn->fail("a part other than the constrained part itself");
        if (!assembly_.parts[*partner].finalPose && *partner != *assembly_.base)
          pn->fail("a part with a final_pose (the partner's assembled pose places the constraint)");
        if (*partner != *assembly_.base) con.partner = *partner;
      }
      con.name = c.has("name") ? c.get("name").string() : type + " " + partNode.string();
      if (auto a = c.opt("accepted")) {
        if (!a->json().is_boolean()) a->fail("true or false");
        con.accepted = a->json().get<bool>();
      }
      // Off the partner's face for a plane; along the axis (one way or the other) unless the file says.
      con.homeDirection = con.type == Constraint::Type::Insert ? con.baseAxis.direction : con.basePlane.normal;
      if (auto h = c.opt("home_direction")) con.homeDirection = h->direction();
      if (auto f = c.opt("found")) con.found = readFound(*f, con.type);
      checkAtFinalPose(con, c);
      assembly_.constraints.push_back(con);
    }
  }

  FrictionValues readFriction(const Node& f) {
    f.requireObject();
    f.allowOnly({"static", "kinetic", "rotational"});
    FrictionValues v{f.get("static").number(0.0, limits::kMaxFriction, ""), 0.0, 0.0};
    const Node kin = f.get("kinetic");
    v.kineticFriction = kin.number(0.0, limits::kMaxFriction, "");
    if (v.kineticFriction > v.staticFriction)
      kin.fail("a kinetic coefficient no larger than the static one (" + toString(v.staticFriction) + ")");
    if (auto r = f.opt("rotational")) v.rotationalFriction = r->number(0.0, limits::kMaxRotationalFriction, "N m s");
    return v;
  }

  // The tuning saved with the scene: it replaces the defaults and the materials' friction.
  void readSettings(const Node& n) {
    n.requireObject();
    n.allowOnly({"rate", "gravity_scale", "rotation_method", "friction"});
    SceneSettings& s = assembly_.settings;
    if (auto r = n.opt("rate")) s.rate = r->number(limits::kMinRate, limits::kMaxRate, "Hz");
    if (auto g = n.opt("gravity_scale")) {
      g->requireObject();
      g->allowOnly({"free_flight", "slide", "rotation"});
      const auto scale = [](const Node& x) { return x.number(0.0, limits::kMaxGravityScale, ""); };
      if (auto x = g->opt("free_flight")) s.freeFlightScale = scale(*x);
      if (auto x = g->opt("slide")) s.slideScale = scale(*x);
      if (auto x = g->opt("rotation")) s.rotationScale = scale(*x);
    }
    if (auto m = n.opt("rotation_method")) {
      const std::string method = m->string();
      if (!dyn::parseMethod(method, dyn::Hinge::kMethods))
        m->fail("a method a rotation about an axis supports: " + dyn::describe(dyn::Hinge::kMethods));
      s.rotationMethod = method;
    }
    if (auto f = n.opt("friction")) {
      f->requireObject();
      f->allowOnly({"materials", "parts"});
      if (auto mats = f->opt("materials")) {
        mats->requireObject();
        for (const auto& [key, value] : mats->json().items()) {
          const Node m(value, mats->path() + "." + key, file_);
          const auto it = assembly_.materials.find(key);
          if (it == assembly_.materials.end()) m.fail("the name of a material in this scene");
          const FrictionValues v = readFriction(m);
          it->second.staticFriction = v.staticFriction;
          it->second.kineticFriction = v.kineticFriction;
          it->second.rotationalFriction = v.rotationalFriction;
        }
      }
      if (auto parts = f->opt("parts")) {
        parts->requireObject();
        for (const auto& [key, value] : parts->json().items()) {
          const Node p(value, parts->path() + "." + key, file_);
          const auto id = assembly_.findPart(key);
          if (!id) p.fail("the name of a part in this scene");
          s.partFriction[*id] = readFriction(p);
        }
      }
    }
  }

  void readTools(const Node& list) {
    list.requireArray();
    std::set<std::string> names;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const Node t = list.at(i);
      t.requireObject();
      const Node type = t.get("type");
      if (type.string() != "hoist") type.fail("a tool type: \"hoist\"");
      t.allowOnly({"type", "name", "position", "reach", "travel", "height"});
      Hoist h;
      if (auto n = t.opt("name")) h.name = n->string();
      if (!names.insert(h.name).second) t.get("name").fail("a name not used by another tool");
      const Node pos = t.get("position");
      if (!pos.json().is_array() || pos.size() != 2) pos.fail("[x, y]: where the hoist's vertical line stands");
      h.position = Eigen::Vector2d(pos.at(0).number(), pos.at(1).number()) * units_.L;
      if (auto r = t.opt("reach")) h.reach = r->positive() * units_.L;
      const Node travel = t.get("travel");
      if (!travel.json().is_array() || travel.size() != 2) travel.fail("[lowest, highest]: the hook's height range");
      h.lowest = travel.at(0).number() * units_.L;
      h.highest = travel.at(1).number() * units_.L;
      if (!(h.highest > h.lowest)) travel.at(1).fail("a height above the lowest (" + std::to_string(h.lowest / units_.L) + ")");
      h.height = h.highest;
      if (auto hn = t.opt("height")) {
        h.height = hn->number() * units_.L;
        if (h.height < h.lowest || h.height > h.highest) hn->fail("a height within the travel");
      }
      assembly_.hoists.push_back(std::move(h));
    }
  }

  // A constraint that the part's own assembled pose violates can never be satisfied: reject it.
  void checkAtFinalPose(const Constraint& con, const Node& c) {
    const Part& part = assembly_.parts[con.part];
    if (!part.finalPose) return;
    const Eigen::Isometry3d& P = *part.finalPose;
    const Eigen::Isometry3d& B = con.partner ? *assembly_.parts[*con.partner].finalPose : assembly_.parts[*assembly_.base].pose;
    constexpr double posTol = 1e-6, angTol = 1e-6;
    std::ostringstream why;
    if (con.type == Constraint::Type::Insert) {
      const Eigen::Vector3d dp = P.linear() * con.partAxis.direction, db = B.linear() * con.baseAxis.direction;
      const double angle = std::asin(std::min(1.0, dp.cross(db).norm()));
      const Eigen::Vector3d pp = P * con.partAxis.point, pb = B * con.baseAxis.point;
      const Eigen::Vector3d off = (pp - pb) - db * db.dot(pp - pb);
      if (angle > angTol) why << "axes " << angle * 180.0 / M_PI << " deg apart";
      else if (off.norm() > posTol) why << "axes " << off.norm() * 1000.0 << " mm apart";
    } else {
      const Eigen::Vector3d np = P.linear() * con.partPlane.normal, nb = B.linear() * con.basePlane.normal;
      const double want = con.type == Constraint::Type::Mate ? -1.0 : 1.0;
      const double angle = std::acos(std::clamp(want * np.dot(nb), -1.0, 1.0));
      const double dist = nb.dot(P * con.partPlane.point - B * con.basePlane.point);
      if (angle > angTol)
        why << "plane normals " << angle * 180.0 / M_PI << " deg from " << (want < 0 ? "opposed" : "parallel");
      else if (std::abs(dist - con.offset) > posTol)
        why << "planes " << dist * 1000.0 << " mm apart, offset " << con.offset * 1000.0 << " mm";
    }
    if (!why.str().empty())
      c.failWith("a constraint that holds at the part's final_pose (within 1e-6 m and 1e-6 rad)", why.str());
  }

  std::filesystem::path path_;
  std::string file_;
  std::filesystem::path dir_;
  const LoadOptions& options_;
  Progress progress_;
  const ImporterRegistry& importers_;
  detail::Json json_;
  Assembly assembly_;
  MeshCache meshes_;
  Units units_;
  std::vector<PartSpec> specs_;
  std::set<std::string> partNames_;
};

}  // namespace

Assembly loadScene(const std::filesystem::path& file, const ImporterRegistry& importers, const LoadOptions& options,
                   const ProgressFn& progress) {
  return SceneReader(file, importers, options, progress).read();
}

Assembly loadAny(const std::filesystem::path& file, const ImporterRegistry& importers, const LoadOptions& options,
                 const ProgressFn& progress) {
  if (const std::string problem = fileProblem(file); !problem.empty())
    fail(file.string(), "", "an existing, readable file", problem + " (" + scenePlaces(file) + ")");
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".json" || ext == ".vaw") return loadScene(file, importers, options, progress);
  return loadMeshFile(file, importers, options, progress);
}

}  // namespace vaw
