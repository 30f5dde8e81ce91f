// Reading mesh files: a scene's mesh shapes (through MeshCache) and a bare mesh file opened as an
// assembly. What the scene file says about them is scene_loader.cpp's.
#include "mesh_import.hpp"

#include <algorithm>
#include <chrono>
#include <cctype>

#include "load_detail.hpp"
#include "vaw/cad_assembly.hpp"
#include "vaw/limits.hpp"
#include "vaw/paths.hpp"
#include "vaw/scene_loader.hpp"

namespace vaw {

using detail::Progress;
using detail::toString;
using detail::validateSolid;

MeshCheck detail::validateSolid(TriMesh& mesh, const std::string& file, const ProgressFn& progressFn, OpenMesh open) {
  const Progress progress(progressFn);
  if (mesh.triangles.empty()) vaw::fail(file, "mesh", "a mesh with triangles", "no triangles");
  if (mesh.triangles.size() > limits::kMaxTriangles)
    vaw::fail(file, "triangles", "at most " + std::to_string(limits::kMaxTriangles) + " triangles in one mesh",
              std::to_string(mesh.triangles.size()));
  progress.report(0.0, "welding vertices");
  // Before welding only what would poison the weld matters; the edge checks run once, after it.
  const auto nonFinite = std::count_if(mesh.vertices.begin(), mesh.vertices.end(), [](const Eigen::Vector3d& v) { return !v.allFinite(); });
  if (nonFinite > 0)
    vaw::fail(file, "vertices", "finite vertex coordinates", std::to_string(nonFinite) + " NaN or infinite vertices");
  const auto far = std::find_if(mesh.vertices.begin(), mesh.vertices.end(),
                                [](const Eigen::Vector3d& v) { return v.cwiseAbs().maxCoeff() > limits::kMaxCoordinate; });
  if (far != mesh.vertices.end()) {
    std::ostringstream where;
    where << "a vertex at (" << far->x() << ", " << far->y() << ", " << far->z() << ") m";
    vaw::fail(file, "vertices", "coordinates within " + toString(limits::kMaxCoordinate) + " m of the origin (the world bound)",
              where.str());
  }
  const auto n = static_cast<int>(mesh.vertices.size());
  const auto badIndices = std::count_if(mesh.triangles.begin(), mesh.triangles.end(),
                                        [n](const Eigen::Vector3i& t) { return t.minCoeff() < 0 || t.maxCoeff() >= n; });
  if (badIndices > 0)
    vaw::fail(file, "triangles", "vertex indices within range", std::to_string(badIndices) + " triangles out of range");
  const double diag = mesh.bounds().diagonal().norm();
  // STL stores every corner separately, and slivers are mended without a hole: both routine, no warning.
  const MeshRepair repair = repairMesh(mesh, 1e-9 * diag, 1e-14 * diag * diag);
  progress.report(0.5, "checking edges");
  const MeshCheck& c = repair.check;
  if (open == OpenMesh::Refuse) {
    if (!c.closed()) vaw::fail(file, "mesh", "a closed mesh (every edge shared by exactly two triangles)", c.summary());
    if (!c.consistentlyOriented())
      vaw::fail(file, "mesh", "consistently oriented triangles (every edge traversed once each way)", c.summary());
  }
  progress.report(0.9, "volume");
  const double volume = integrateVolume(mesh).volume;
  if (open == OpenMesh::Refuse && !(volume > 0.0))
    vaw::fail(file, "mesh", "outward-facing triangles enclosing a positive volume",
              volume < 0.0 ? "volume " + toString(volume) + " m^3: the normals point inward (inverted)" : "zero volume");
  return c;
}

const detail::SolidMeshes::Checked& detail::SolidMeshes::of(const std::shared_ptr<const CadSolid>& solid) {
  if (const auto it = done_.find(solid.get()); it != done_.end()) return it->second.second;
  TriMesh mesh = solid->mesh;
  Checked c;
  c.check = validateSolid(mesh, file_ + " (product " + solid->product + ")", {}, OpenMesh::Keep);
  c.mesh = std::make_shared<const TriMesh>(std::move(mesh));
  return done_.emplace(solid.get(), std::pair{solid, std::move(c)}).first->second.second;
}

namespace detail {

void checkMeshFileSize(const std::filesystem::path& file, const std::optional<Node>& field) {
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(file, ec);
  if (ec || bytes <= limits::kMaxMeshFileBytes) return;
  const std::string expected = "a mesh file of at most 2 GiB", found = std::to_string(bytes) + " bytes";
  if (field) field->failWith(expected, "\"" + file.string() + "\": " + found);
  vaw::fail(file.string(), "", expected, found);
}

const Imported& MeshCache::get(const std::filesystem::path& file, double L, const Node& field, const ProgressFn& progress) {
  if (const std::string problem = fileProblem(file); !problem.empty())
    field.failWith("an existing, readable mesh file", "\"" + file.string() + "\": " + problem);
  std::error_code ec;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(file, ec);
  const std::string key = (ec ? file.lexically_normal() : canonical).string() + "|" + toString(L);
  if (auto it = cache_.find(key); it != cache_.end()) return it->second;
  const MeshImporter* importer = importers_.find(file);
  if (!importer) {
    std::string exts;
    for (const auto& e : importers_.extensions()) exts += (exts.empty() ? "" : " ") + e;
    field.failWith("a mesh format an importer plugin reads (" + (exts.empty() ? std::string("no importer plugins loaded") : exts) + ")",
                   "\"" + file.extension().string() + "\"");
  }
  checkMeshFileSize(file, field);
  const Progress scaled(progress);
  ImportedMesh im = importer->read(file, options_, scaled.sub(0.0, 0.6));
  Imported out;
  out.root = std::move(im.root);
  out.warnings = std::move(im.warnings);
  TriMesh mesh = out.root.merged();
  mesh.scale(L);
  validateSolid(mesh, file.string(), scaled.sub(0.6, 1.0));
  out.mesh = std::make_shared<const TriMesh>(std::move(mesh));
  return cache_.emplace(key, std::move(out)).first->second;
}
std::size_t nodesWithGeometry(const ImportedNode& n) {
  std::size_t count = n.mesh.triangleCount() > 0 ? 1 : 0;
  for (const auto& c : n.children) count += nodesWithGeometry(c);
  return count;
}

TreeNode meshTree(const ImportedNode& n) {
  TreeNode t;
  t.kind = TreeNode::Kind::MeshNode;
  t.name = n.name.empty() ? std::string("(unnamed)") : n.name;
  for (const auto& c : n.children) t.children.push_back(meshTree(c));
  return t;
}
}  // namespace detail

Assembly loadMeshFile(const std::filesystem::path& file, const ImporterRegistry& importers, const LoadOptions& options,
                      const ProgressFn& progressFn) {
  Progress progress(progressFn);
  Assembly a;
  a.source = file;
  a.name = file.filename().string();
  a.categorySettings = options.categories;
  if (const std::string problem = fileProblem(file); !problem.empty())
    fail(file.string(), "", "an existing, readable file", problem);
  const MeshImporter* importer = importers.find(file);
  if (!importer) fail(file.string(), "", "a mesh format an importer plugin reads", "\"" + file.extension().string() + "\"");
  detail::checkMeshFileSize(file, std::nullopt);
  const auto started = std::chrono::steady_clock::now();
  ImportedMesh im = importer->read(file, options.import, progress.sub(0.0, 0.6));
  if (options.timings) options.timings->emplace_back("reading the file", std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  if (im.isCad()) return assemblyFromCad(std::move(im), file, options, progress.sub(0.6, 1.0));
  for (const auto& w : im.warnings) a.warnings.push_back({Diagnostic::Severity::Warning, file.string(), "", "", w});

  // glTF is metres by its specification; the other formats carry no unit.
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  a.units = (ext == ".gltf" || ext == ".glb") ? LengthUnit::Metre : options.bareMeshUnits;
  const double L = toMetres(a.units);
  a.warnings.push_back({Diagnostic::Severity::Warning, file.string(), "units", "a scene file to state units and materials",
                        "assumed " + std::string(name(a.units)) + " and density " + toString(options.bareMeshDensity) + " kg/m^3"});
  Material mat;
  mat.name = "default";
  mat.density = options.bareMeshDensity;
  a.materials.emplace(mat.name, mat);

  // One part per top-level node that has geometry; a flat file is one part.
  std::vector<const ImportedNode*> roots;
  if (im.root.mesh.triangleCount() > 0 || im.root.children.empty()) roots.push_back(&im.root);
  else
    for (const auto& c : im.root.children)
      if (c.subtreeTriangles() > 0) roots.push_back(&c);

  const std::string fileStr = file.string();
  if (roots.size() >= 2) {
    // An assembly of several parts: laid out and its constraints found from the surface patches, like a
    // STEP file's (docs/step.md, "Mesh files").
    ImportedMesh solids;
    solids.root.name = file.stem().string();
    for (std::size_t i = 0; i < roots.size(); ++i) {
      const ImportedNode& n = *roots[i];
      const std::string name = n.name.empty() ? file.stem().string() + "-" + std::to_string(i + 1) : n.name;
      progress.report(0.6 + 0.2 * static_cast<double>(i) / static_cast<double>(roots.size()), "part " + name);
      TriMesh mesh = n.merged();
      mesh.scale(L);
      validateSolid(mesh, fileStr + " (node " + name + ")", {});
      ImportedNode node;
      node.name = name;
      Eigen::Vector3d centroid;
      node.solid = cadSolidFromMesh(mesh, name, centroid);
      node.location.translation() = centroid;
      solids.root.children.push_back(std::move(node));
    }
    Assembly cad = assemblyFromCad(std::move(solids), file, options, progress.sub(0.8, 1.0), MassSource::Mesh);
    cad.units = a.units;
    cad.warnings.insert(cad.warnings.begin(), a.warnings.begin(), a.warnings.end());
    return cad;
  }

  a.tree.kind = TreeNode::Kind::Assembly;
  a.tree.name = a.name;
  for (std::size_t i = 0; i < roots.size(); ++i) {
    const double from = 0.6 + 0.4 * static_cast<double>(i) / static_cast<double>(roots.size());
    const double to = 0.6 + 0.4 * static_cast<double>(i + 1) / static_cast<double>(roots.size());
    progress.report(from, "part " + std::to_string(i + 1));
    const ImportedNode& n = *roots[i];
    TriMesh mesh = n.merged();
    mesh.scale(L);
    validateSolid(mesh, fileStr + (n.name.empty() ? "" : " (node " + n.name + ")"), progress.sub(from, to));
    Part p;
    p.id = i;
    p.name = n.name.empty() || roots.size() == 1 ? file.stem().string() : n.name;
    p.material = mat.name;
    p.shapeSource = file.filename().string();
    p.mesh = std::make_shared<const TriMesh>(std::move(mesh));
    p.meshMass = massPropertiesFromMesh(*p.mesh, options.bareMeshDensity);
    p.mass = *p.meshMass;
    p.principal = principalMoments(p.mass.inertiaCm);
    p.extent = principalExtent(*p.mesh, p.principal.axes);
    p.category = categorize(p.mass.mass, p.extent, options.categories);
    TreeNode leaf = detail::nodesWithGeometry(n) > 1 ? detail::meshTree(n) : TreeNode{};
    leaf.kind = TreeNode::Kind::Part;
    leaf.name = p.name;
    leaf.index = i;
    a.tree.children.push_back(std::move(leaf));
    a.parts.push_back(std::move(p));
  }
  progress.report(1.0, "done");
  return a;
}

}  // namespace vaw
