// Mesh import through assimp: STL, OBJ, PLY, glTF 2.0 and the many other formats assimp reads.
#include <assimp/Importer.hpp>
#include <assimp/ProgressHandler.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <sstream>

#include "vaw/error.hpp"
#include "vaw/importer.hpp"

namespace {

class Progress final : public Assimp::ProgressHandler {
 public:
  explicit Progress(const vaw::ProgressFn& fn) : fn_(fn) {}
  bool Update(float percentage) override {
    if (!fn_) return true;
    const double f = percentage < 0.0f ? 0.0 : static_cast<double>(percentage);
    return fn_(std::min(1.0, f), "importing mesh");
  }

 private:
  const vaw::ProgressFn& fn_;
};

Eigen::Matrix4d toEigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  for (unsigned r = 0; r < 4; ++r)
    for (unsigned c = 0; c < 4; ++c) e(r, c) = static_cast<double>(m[r][c]);
  return e;
}

// Copies the node's own meshes (transformed to the file frame) and recurses into its children, so
// the scene tree can show the file's own hierarchy and names.
vaw::ImportedNode convert(const aiScene& scene, const aiNode& node, const Eigen::Matrix4d& parent, std::size_t& skippedFaces) {
  vaw::ImportedNode out;
  out.name = node.mName.C_Str();
  const Eigen::Matrix4d world = parent * toEigen(node.mTransformation);
  const Eigen::Matrix3d linear = world.topLeftCorner<3, 3>();
  const Eigen::Vector3d translation = world.topRightCorner<3, 1>();
  std::size_t vertices = out.mesh.vertices.size(), triangles = out.mesh.triangles.size();
  for (unsigned i = 0; i < node.mNumMeshes; ++i) {
    vertices += scene.mMeshes[node.mMeshes[i]]->mNumVertices;
    triangles += scene.mMeshes[node.mMeshes[i]]->mNumFaces;
  }
  out.mesh.vertices.reserve(vertices);
  out.mesh.triangles.reserve(triangles);
  for (unsigned i = 0; i < node.mNumMeshes; ++i) {
    const aiMesh& m = *scene.mMeshes[node.mMeshes[i]];
    const int offset = static_cast<int>(out.mesh.vertices.size());
    for (unsigned v = 0; v < m.mNumVertices; ++v)
      out.mesh.vertices.push_back(linear * Eigen::Vector3d(m.mVertices[v].x, m.mVertices[v].y, m.mVertices[v].z) + translation);
    for (unsigned f = 0; f < m.mNumFaces; ++f) {
      const aiFace& face = m.mFaces[f];
      if (face.mNumIndices != 3) { ++skippedFaces; continue; }
      out.mesh.triangles.emplace_back(offset + static_cast<int>(face.mIndices[0]), offset + static_cast<int>(face.mIndices[1]),
                                      offset + static_cast<int>(face.mIndices[2]));
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) out.children.push_back(convert(scene, *node.mChildren[c], world, skippedFaces));
  return out;
}

// JSON is vaw's own scene format (assimp's "json" is an export format); .stp and .step are STEP, which
// assimp reads only as IFC and the Open CASCADE plugin reads as CAD assemblies (docs/step.md).
bool claimedElsewhere(const std::string& ext) { return ext == "json" || ext == "stp" || ext == "step"; }

class AssimpImporter final : public vaw::MeshImporter {
 public:
  [[nodiscard]] std::string name() const override { return "assimp"; }

  [[nodiscard]] std::vector<std::string> extensions() const override {
    Assimp::Importer imp;
    std::string list;
    imp.GetExtensionList(list);  // "*.3ds;*.obj;..."
    std::vector<std::string> out;
    std::stringstream ss(list);
    std::string item;
    while (std::getline(ss, item, ';')) {
      if (item.rfind("*.", 0) == 0) item.erase(0, 2);
      std::transform(item.begin(), item.end(), item.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      if (!item.empty() && !claimedElsewhere(item)) out.push_back(item);
    }
    return out;
  }

  [[nodiscard]] bool canRead(const std::filesystem::path& file) const override {
    std::string ext = file.extension().string();
    if (!ext.empty()) ext.erase(0, 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (claimedElsewhere(ext)) return false;
    Assimp::Importer imp;
    return imp.IsExtensionSupported(file.extension().string());
  }

  [[nodiscard]] vaw::ImportedMesh read(const std::filesystem::path& file, const vaw::ImportOptions& /*options*/,
                                  const vaw::ProgressFn& progress) const override {
    Assimp::Importer imp;
    imp.SetProgressHandler(new Progress(progress));  // the importer owns and deletes it
    // Lines and points carry no volume; drop them rather than fail on mixed files.
    imp.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    // No aiProcess_JoinIdenticalVertices: vaw welds every mesh itself (within 1e-9 of its size), and
    // assimp's join took 11 of the 13 s of reading a 5-million-triangle STL.
    const aiScene* scene =
        imp.ReadFile(file.string(), aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure);
    if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode) {
      const std::string why = imp.GetErrorString();
      vaw::fail(file.string(), "", "a readable " + file.extension().string() + " mesh file", why.empty() ? "nothing assimp could read" : why);
    }
    std::size_t skipped = 0;
    vaw::ImportedMesh out;
    out.root = convert(*scene, *scene->mRootNode, Eigen::Matrix4d::Identity(), skipped);
    if (skipped > 0) out.warnings.push_back(std::to_string(skipped) + " non-triangle faces ignored");
    return out;
  }
};

}  // namespace

extern "C" __attribute__((visibility("default"))) int vaw_plugin_abi_version() { return vaw::kImporterAbiVersion; }
extern "C" __attribute__((visibility("default"))) vaw::MeshImporter* vaw_create_mesh_importer() { return new AssimpImporter(); }
