#pragma once
// Mesh importers are plugins (shared libraries) behind this interface, so backends such as assimp or
// Open CASCADE stay out of the core and can be added without rebuilding it.
#include <filesystem>
#include <exception>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vaw/mesh.hpp"
#include "vaw/units.hpp"

namespace vaw {

// Thrown when the progress callback asked to stop; nothing was loaded.
class LoadCancelled : public std::exception {
 public:
  [[nodiscard]] const char* what() const noexcept override { return "loading cancelled"; }
};

// Called with a fraction in [0, 1] and a stage description; return false to cancel.
using ProgressFn = std::function<bool(double fraction, const std::string& stage)>;
// Work over pairs of parts (recognition, who goes first): the fraction done and the pair at hand, by
// index, which the caller names; return false to cancel.
using PairProgress = std::function<bool(double fraction, std::size_t a, std::size_t b)>;

// What the importer is asked for besides the file. Mesh formats ignore it; CAD formats tessellate with it.
struct ImportOptions {
  // Chordal deflection of the tessellation as a fraction of each part's bounding-box diagonal, and the
  // angular deflection in radians (docs/step.md).
  double relativeDeflection = 0.001;
  double angularDeflection = 0.35;
  // A CAD reader runs in a child process; past this it is ended and the file named as too slow.
  double timeoutSeconds = 300.0;
  // A CAD reader's address-space limit, MB; past it the reader ends with a named error. 0: half the
  // machine's memory.
  double readerMemoryMB = 0.0;
  // Part instances a CAD file may declare (its assembly tree expanded); more is refused before reading.
  double maxInstances = 10000;
  // Where a CAD reader keeps its results, so that an unchanged file reopens without being read again
  // (docs/step.md, "Reopening a file"); empty: nothing is kept. The applications set it to
  // vaw::userCacheDir(); library callers and tests choose.
  std::filesystem::path resultCache;
  double resultCacheMB = 512.0;  // the folder's size limit
};

// The exact geometry a CAD importer knows about one face of a solid, in the solid's own frame, metres.
// Constraint recognition (vaw/constraint_recognition.hpp) works on these.
struct CadFace {
  enum class Surface { Plane, Cylinder, Other, Cone };
  Surface surface = Surface::Other;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();       // plane: a point on it; cylinder: a point on its axis;
                                                         // cone: its apex
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // plane: unit normal pointing out of the material;
                                                         // cylinder: unit axis direction; cone: unit axis
                                                         // direction from the apex, the way it widens
  double radius = 0.0;                                   // cylinder, m; cone: the face's largest radius
  double halfAngle = 0.0;                                // cone, rad: between its axis and its surface
  bool convex = true;  // cylinder, cone: material inside (a shaft, a countersunk head); false: a hole, a countersink
  double axialMin = 0.0, axialMax = 0.0;  // cylinder, cone: the face's extent along the axis, from `point`
  double area = 0.0;              // m^2
  bool fromSpline = false;        // a B-spline or other free-form surface recognised as this within tolerance
  std::size_t firstTriangle = 0;  // this face's triangles are CadSolid::mesh.triangles[first, first + count)
  std::size_t triangleCount = 0;
};

// One product's solid, shared by every instance of it. Geometry in the product's own frame, metres.
struct CadSolid {
  std::string product;  // the product's own name
  TriMesh mesh;         // tessellation, outward oriented, faces' triangles contiguous
  std::vector<CadFace> faces;
  double volume = 0.0;                                    // m^3, from the boundary representation
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();     // m
  Eigen::Matrix3d inertiaUnitDensity = Eigen::Matrix3d::Zero();  // m^5, about the centroid, density 1
  double surfaceArea = 0.0;                               // m^2
  std::optional<Eigen::Vector3f> color;                   // from the file, linear RGB in [0, 1]
  double deflection = 0.0;                                // m, the chordal deflection used
};

// One node of a mesh file's own hierarchy (glTF nodes, OBJ groups, ...), names as in the file. For a
// CAD assembly: an assembly node (children, no solid) or a part instance (a solid), placed by `location`.
struct ImportedNode {
  std::string name;
  TriMesh mesh;  // this node's own meshes, node transforms applied, file frame and units
  std::vector<ImportedNode> children;
  // CAD files only: the node's placement relative to its parent node (metres), the instance's solid
  // (shared between instances of one product) and an instance colour that overrides the solid's.
  Eigen::Isometry3d location = Eigen::Isometry3d::Identity();
  std::shared_ptr<const CadSolid> solid;
  std::optional<Eigen::Vector3f> color;

  [[nodiscard]] std::size_t subtreeTriangles() const;
  // This node's and all descendants' geometry in one mesh.
  [[nodiscard]] TriMesh merged() const;
};

struct ImportedMesh {
  ImportedNode root;  // the file's hierarchy and names
  std::vector<std::string> warnings;
  // Set by importers of formats that declare their unit (STEP): the unit the file declared, e.g.
  // "inch". The geometry is then already converted to metres.
  std::optional<std::string> declaredUnit;
  std::string format;  // e.g. "STEP AP214", for the part panel and notes
  // The file's bytes hashed (vaw::fileContentHash), when the importer read them all anyway: the file is
  // then not hashed a second time for the scene that refers to it.
  std::string contentHash;
  // True when the nodes are a CAD assembly (solids and locations), not meshes.
  [[nodiscard]] bool isCad() const;
};

class MeshImporter {
 public:
  virtual ~MeshImporter() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  // Lower-case extensions without the dot.
  [[nodiscard]] virtual std::vector<std::string> extensions() const = 0;
  [[nodiscard]] virtual bool canRead(const std::filesystem::path& file) const = 0;
  // Throws vaw::InputError naming the file on anything it cannot read.
  // Throws vaw::LoadCancelled when `progress` returned false.
  [[nodiscard]] virtual ImportedMesh read(const std::filesystem::path& file, const ImportOptions& options,
                                          const ProgressFn& progress) const = 0;
};

// What a solid's writer may take: a plugin that writes through a child process (the STEP writer) holds it
// to these, as the reader is held to ImportOptions'.
struct ExportOptions {
  double timeoutSeconds = 300.0;  // the write is stopped past this, with a named error
  double memoryMB = 0.0;          // the writer's memory limit; 0: half the machine's memory
  // A faceted B-rep (faces bounded by loops of points) rather than an advanced one (loops of edges): about
  // a third the size for a voxel surface, though some CAD systems take it as a faceted body.
  bool faceted = false;
};

// Writes a closed mesh as a solid in a format only a plugin can write (STEP, through the STEP plugin): the
// swept volume of a path for a CAD system (docs/swept-volume.md).
class SolidExporter {
 public:
  virtual ~SolidExporter() = default;
  [[nodiscard]] virtual std::string name() const = 0;
  // Lower-case extensions without the dot.
  [[nodiscard]] virtual std::vector<std::string> extensions() const = 0;
  // Writes `mesh` (metres; a closed, outward-facing manifold) as one solid named `solidName` to `file`,
  // lengths in `unit`, within `options`' limits. `progress`, when given, hears how far it is and stops it by
  // returning false. Throws vaw::OutputError saying why when it cannot (stopped, past a limit, refused);
  // whatever was at `file` before is then left as it was.
  virtual void write(const TriMesh& mesh, const std::string& solidName, LengthUnit unit, const std::filesystem::path& file,
                     const ExportOptions& options, const ProgressFn& progress) const = 0;
};

// A plugin exports these two C symbols. The ABI version guards against loading a plugin built
// against a different interface.
// 2: ImportOptions and CAD assemblies; 3: the reader's memory limit; 4: the instance limit; 5: the results kept;
// 6: the solid writer's limits and progress
inline constexpr int kImporterAbiVersion = 7;
extern "C" {
using VawPluginAbiFn = int (*)();
using VawCreateImporterFn = vaw::MeshImporter* (*)();
// Optional: a plugin that also writes exports vaw_create_solid_exporter.
using VawCreateExporterFn = vaw::SolidExporter* (*)();
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
  // The exporter that writes `file`'s extension, or null.
  [[nodiscard]] const SolidExporter* exporterFor(const std::filesystem::path& file) const;
  [[nodiscard]] std::vector<std::string> extensions() const;
  [[nodiscard]] std::vector<std::string> importerNames() const;

  // Default plugin search path: $VAW_PLUGIN_PATH (colon separated), then <exe>/../lib/vaw/plugins.
  static std::vector<std::filesystem::path> defaultPluginDirs();

 private:
  struct Library;
  std::vector<std::unique_ptr<Library>> libraries_;
  std::vector<std::unique_ptr<MeshImporter>> importers_;
  std::vector<std::unique_ptr<SolidExporter>> exporters_;
};

}  // namespace vaw
