#pragma once
// Mesh files as a scene's parts use them, shared by the scene loader and the mesh-file loader (private to
// the core's sources).
#include <cstddef>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "../base/json_node.hpp"
#include "vaw/assembly.hpp"
#include "vaw/importer.hpp"
#include "vaw/mesh.hpp"

namespace vaw::detail {

// Before a mesh file is read whole into memory; the error names `field` when a scene referenced it.
void checkMeshFileSize(const std::filesystem::path& file, const std::optional<Node>& field);

struct Imported {
  std::shared_ptr<const TriMesh> mesh;  // merged, SI, welded, checked; shared by every part using the file
  ImportedNode root;
  std::vector<std::string> warnings;
};

// Loads, converts and validates a mesh file; problems name the scene field that referenced it.
class MeshCache {
 public:
  MeshCache(const ImporterRegistry& importers, ImportOptions options) : importers_(importers), options_(options) {}

  const Imported& get(const std::filesystem::path& file, double L, const Node& field, const ProgressFn& progress);

 private:
  const ImporterRegistry& importers_;
  ImportOptions options_;
  std::map<std::string, Imported> cache_;
};

// How many nodes of an imported tree carry triangles, and the tree as the scene tree shows it.
std::size_t nodesWithGeometry(const ImportedNode& n);
TreeNode meshTree(const ImportedNode& n);

}  // namespace vaw::detail
