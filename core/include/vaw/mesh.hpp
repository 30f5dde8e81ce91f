#pragma once
// An indexed triangle mesh in SI units, in the frame of the part it belongs to. Meshes are rigid and
// immutable once loaded; parts share them through shared_ptr<const TriMesh>.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace vaw {

struct TriMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;  // counter-clockwise seen from outside

  [[nodiscard]] std::size_t triangleCount() const { return triangles.size(); }
  [[nodiscard]] Eigen::AlignedBox3d bounds() const;
  void append(const TriMesh& other, const Eigen::Isometry3d& transform = Eigen::Isometry3d::Identity());
  void scale(double factor);
  void transform(const Eigen::Isometry3d& t);
};

// What is wrong with a mesh as a solid. Counts, so a message can say how bad it is.
struct MeshCheck {
  std::size_t nonFiniteVertices = 0;
  std::size_t badIndices = 0;
  std::size_t degenerateTriangles = 0;    // zero area (repeated index or collinear corners)
  std::size_t boundaryEdges = 0;          // edges used by one triangle only: the mesh is open
  std::size_t nonManifoldEdges = 0;       // edges used by more than two triangles
  std::size_t inconsistentEdges = 0;      // a directed edge used twice: neighbours disagree on orientation
  std::size_t duplicateVertices = 0;      // distinct indices at the same position (welded before checks)

  [[nodiscard]] bool closed() const { return boundaryEdges == 0 && nonManifoldEdges == 0; }
  [[nodiscard]] bool consistentlyOriented() const { return inconsistentEdges == 0; }
  [[nodiscard]] bool valid() const {
    return nonFiniteVertices == 0 && badIndices == 0 && closed() && consistentlyOriented();
  }
  [[nodiscard]] std::string summary() const;
};

// Merges vertices closer than `tolerance` (metres) so that meshes written as triangle soup (STL)
// have shared edges. Returns the number of vertices removed.
std::size_t weldVertices(TriMesh& mesh, double tolerance);

// What repairMesh changed, and the mesh's check after it.
struct MeshRepair {
  std::size_t welded = 0;   // vertices merged into another within the tolerance
  std::size_t mended = 0;   // slivers removed by splitting their neighbour (the mesh stays closed)
  std::size_t removed = 0;  // triangles whose corners welded together, and slivers with no neighbour to split
  MeshCheck check;
};
// Makes a tessellation as closed as its source: welds vertices within `weldTolerance`, removes triangles
// whose corners weld together, and takes out every zero-area triangle with three distinct corners (a
// sliver: one corner lies on the opposite edge, as meshers leave along an edge from a cone's apex) by
// splitting the neighbour across its long edge at that corner. Deleting a sliver by its area would open
// the mesh along all three of its edges.
MeshRepair repairMesh(TriMesh& mesh, double weldTolerance, double areaTolerance);

MeshCheck checkMesh(const TriMesh& mesh, double areaTolerance = 0.0);

}  // namespace vaw
