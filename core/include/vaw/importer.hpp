#pragma once
// Mesh importers are plugins (shared libraries) behind this interface, so backends such as assimp or
// Open CASCADE stay out of the core and can be added without rebuilding it.
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "vaw/mesh.hpp"

namespace vaw {

// Called with a fraction in [0, 1] and a stage description; return false to cancel.
using ProgressFn = std::function<bool(double fraction, const std::string& stage)>;

// One node of a mesh file's own hierarchy (glTF nodes, OBJ groups, ...), names as in the file.
struct ImportedNode {
  std::string name;
  TriMesh mesh;  // this node's own meshes, node transforms applied, file frame and units
  std::vector<ImportedNode> children;

  [[nodiscard]] std::size_t subtreeTriangles() const;
  // This node's and all descendants' geometry in one mesh.
  [[nodiscard]] TriMesh merged() const;
};

struct ImportedMesh {
  ImportedNode root;  // the file's hierarchy and names
  std::vector<std::string> warnings;
};

class MeshImporter {
 public:
  virtual ~MeshImporter() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  // Lower-case extensions without the dot.
  [[nodiscard]] virtual std::vector<std::string> extensions() const = 0;
  [[nodiscard]] virtual bool canRead(const std::filesystem::path& file) const = 0;
  // Throws vaw::InputError naming the file on anything it cannot read.
  [[nodiscard]] virtual ImportedMesh read(const std::filesystem::path& file, const ProgressFn& progress) const = 0;
};

// A plugin exports these two C symbols. The ABI version guards against loading a plugin built
// against a different interface.
inline constexpr int kImporterAbiVersion = 1;
extern "C" {
using VawPluginAbiFn = int (*)();
using VawCreateImporterFn = vaw::MeshImporter* (*)();
}

class ImporterRegistry {
 public:
  ImporterRegistry();
  ~ImporterRegistry();
  ImporterRegistry(const ImporterRegistry&) = delete;
  ImporterRegistry& operator=(const ImporterRegistry&) = delete;

  // Loads every plugin in `dir` (files named libvaw_import_*.so). Returns messages for plugins that
  // failed to load; a missing directory is not an error (returns nothing).
  std::vector<std::string> loadPlugins(const std::filesystem::path& dir);
  void add(std::unique_ptr<MeshImporter> importer);

  [[nodiscard]] const MeshImporter* find(const std::filesystem::path& file) const;
  [[nodiscard]] std::vector<std::string> extensions() const;
  [[nodiscard]] std::vector<std::string> importerNames() const;

  // Default plugin search path: $VAW_PLUGIN_PATH (colon separated), then <exe>/../lib/vaw/plugins.
  static std::vector<std::filesystem::path> defaultPluginDirs();

 private:
  struct Library;
  std::vector<std::unique_ptr<Library>> libraries_;
  std::vector<std::unique_ptr<MeshImporter>> importers_;
};

}  // namespace vaw
