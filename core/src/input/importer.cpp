#include "vaw/importer.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <sstream>

#include "vaw/paths.hpp"

namespace vaw {

std::size_t ImportedNode::subtreeTriangles() const {
  std::size_t n = mesh.triangleCount();
  for (const auto& c : children) n += c.subtreeTriangles();
  return n;
}

namespace {
void countInto(const ImportedNode& n, std::size_t& vertices, std::size_t& triangles) {
  vertices += n.mesh.vertices.size();
  triangles += n.mesh.triangles.size();
  for (const auto& c : n.children) countInto(c, vertices, triangles);
}
void appendInto(const ImportedNode& n, TriMesh& out) {
  out.append(n.mesh);
  for (const auto& c : n.children) appendInto(c, out);
}
}  // namespace

bool ImportedMesh::isCad() const {
  const auto any = [](const auto& self, const ImportedNode& n) -> bool {
    if (n.solid) return true;
    for (const auto& c : n.children)
      if (self(self, c)) return true;
    return false;
  };
  return any(any, root);
}

TriMesh ImportedNode::merged() const {
  // One copy into storage sized once: a 5-million-triangle file is 15 million vertices before welding.
  std::size_t vertices = 0, triangles = 0;
  countInto(*this, vertices, triangles);
  TriMesh out;
  out.vertices.reserve(vertices);
  out.triangles.reserve(triangles);
  appendInto(*this, out);
  return out;
}

struct ImporterRegistry::Library {
  void* handle = nullptr;
  ~Library() {
    if (handle) dlclose(handle);
  }
};

ImporterRegistry::ImporterRegistry() = default;

// Importers are destroyed before the libraries holding their code are unloaded.
ImporterRegistry::~ImporterRegistry() {
  importers_.clear();
  exporters_.clear();
  libraries_.clear();
}

void ImporterRegistry::add(std::unique_ptr<MeshImporter> importer) { importers_.push_back(std::move(importer)); }

std::vector<std::string> ImporterRegistry::loadPlugins(const std::filesystem::path& dir) {
  std::vector<std::string> problems;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return problems;
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const auto fname = e.path().filename().string();
    if (fname.rfind("libvaw_import_", 0) == 0 && e.path().extension() == ".so") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    auto lib = std::make_unique<Library>();
    lib->handle = dlopen(f.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!lib->handle) {
      problems.push_back(f.string() + ": cannot load: " + dlerror());
      continue;
    }
    auto abi = reinterpret_cast<VawPluginAbiFn>(dlsym(lib->handle, "vaw_plugin_abi_version"));
    auto create = reinterpret_cast<VawCreateImporterFn>(dlsym(lib->handle, "vaw_create_mesh_importer"));
    if (!abi || !create) {
      problems.push_back(f.string() + ": not a vaw importer plugin (missing vaw_plugin_abi_version or vaw_create_mesh_importer)");
      continue;
    }
    if (abi() != kImporterAbiVersion) {
      problems.push_back(f.string() + ": built for importer ABI " + std::to_string(abi()) + ", this vaw needs " +
                         std::to_string(kImporterAbiVersion));
      continue;
    }
    std::unique_ptr<MeshImporter> imp(create());
    if (!imp) {
      problems.push_back(f.string() + ": plugin returned no importer");
      continue;
    }
    if (auto exporter = reinterpret_cast<VawCreateExporterFn>(dlsym(lib->handle, "vaw_create_solid_exporter")))
      if (std::unique_ptr<SolidExporter> e(exporter()); e) exporters_.push_back(std::move(e));
    libraries_.push_back(std::move(lib));
    importers_.push_back(std::move(imp));
  }
  return problems;
}

namespace {
// Whether `file`'s extension, in lower case, is one of `extensions`.
bool takes(const std::vector<std::string>& extensions, const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  if (!ext.empty()) ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return std::find(extensions.begin(), extensions.end(), ext) != extensions.end();
}
}  // namespace

const SolidExporter* ImporterRegistry::exporterFor(const std::filesystem::path& file) const {
  for (const auto& e : exporters_)
    if (takes(e->extensions(), file)) return e.get();
  return nullptr;
}

const MeshImporter* ImporterRegistry::find(const std::filesystem::path& file) const {
  for (const auto& imp : importers_)
    if (takes(imp->extensions(), file) && imp->canRead(file)) return imp.get();
  return nullptr;
}

std::vector<std::string> ImporterRegistry::extensions() const {
  std::vector<std::string> out;
  for (const auto& imp : importers_)
    for (auto& e : imp->extensions()) out.push_back(std::move(e));
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<std::string> ImporterRegistry::importerNames() const {
  std::vector<std::string> out;
  for (const auto& imp : importers_) out.push_back(imp->name());
  return out;
}

std::vector<std::filesystem::path> ImporterRegistry::defaultPluginDirs() {
  std::vector<std::filesystem::path> dirs;
  if (const char* env = std::getenv("VAW_PLUGIN_PATH"); env && *env) {
    std::stringstream ss(env);
    std::string item;
    while (std::getline(ss, item, ':'))
      if (!item.empty()) dirs.emplace_back(item);
  }
  dirs.push_back((executableDir() / ".." / "lib" / "vaw" / "plugins").lexically_normal());
  return dirs;
}

}  // namespace vaw
