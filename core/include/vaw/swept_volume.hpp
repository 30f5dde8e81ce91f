#pragma once
// The space a moving mesh needs (docs/swept-volume.md): the union of its poses along runs of poses,
// voxelised so that the result contains the whole way (every pose between the given ones too), with a
// closed surface mesh for display and export. The voxels are the answer; the mesh is their outer surface,
// so its volume is exactly theirs. vaw/sim/swept_volume.hpp takes the poses from a recorded session.
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "vaw/mesh.hpp"

namespace vaw {

struct SweptVolume {
  TriMesh mesh;             // the outer surface of the voxels, in the assembly frame (m), closed, outward
  double voxel = 0.0;       // m, the voxels' edge
  double volume = 0.0;      // m^3, the voxels' (and the mesh's)
  std::size_t voxels = 0;   // occupied
  std::size_t moves = 0;    // swept whole: from pose to pose, split where the part turns far
  bool relativeToBase = false;
  double from = 0.0, to = 0.0;  // s: the first and last step swept (0 for a path given as poses)

  // Is `p` (assembly frame, m) in an occupied voxel.
  [[nodiscard]] bool contains(const Eigen::Vector3d& p) const;
  // The occupied voxels' outer surface, made again from the grid: what `mesh` holds, for a volume kept
  // without it (the ways home keep none: a thousand of them took 410 MB, docs/swept-volume.md).
  [[nodiscard]] TriMesh surface() const;

  // The grid: voxel (i, j, k) spans frame * (origin + voxel * [i, i+1] x [j, j+1] x [k, k+1]). Rows along
  // i are padded to whole 64-bit words.
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3i dims = Eigen::Vector3i::Zero();
  std::vector<std::uint64_t> occupied;
};

// The most voxels a grid may hold (its bounding box's); more is an error that asks for a larger voxel.
inline constexpr std::uint64_t kMaxSweepVoxels = std::uint64_t{1} << 32;
// The most moves a path may be swept in (a move per recorded step, more where the part turns fast).
inline constexpr std::uint64_t kMaxSweepMoves = 20'000'000;

// Sweeps `mesh` (a closed mesh in its own frame) through each run of poses (mesh frame -> the result's
// frame); within a run the part moves from pose to pose with its centre on a straight line and its
// rotation turning the shortest way, and every pose in between is in the result. Throws std::invalid_argument for a voxel that is
// not a positive finite length, no poses, a non-finite pose, or a grid over `maxVoxels` (at most
// kMaxSweepVoxels) or a path of more than kMaxSweepMoves moves, naming the voxel that would fit.
// `margin` (m) grows the volume all round: how far the true surface may lie outside `mesh` (a CAD part's
// tessellation, whose facets lie up to its chordal deflection inside its curved faces: tessellationSag).
SweptVolume sweep(const TriMesh& mesh, const std::vector<std::vector<Eigen::Isometry3d>>& runs, double voxel,
                  std::uint64_t maxVoxels = kMaxSweepVoxels, double margin = 0.0);

// The most voxels a grid may hold in `memoryMB` (0: half the machine's memory): three bits a voxel while
// the sweep works (the marks, the outside, the result), and never more than kMaxSweepVoxels.
std::uint64_t sweepVoxelsInMemory(double memoryMB);

}  // namespace vaw
