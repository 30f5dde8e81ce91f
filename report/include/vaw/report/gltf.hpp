#pragma once
// A scene and how its parts moved as one glTF 2.0 binary (.glb), for people who were not at the workbench:
// Blender, three.js and the common viewers open it and play its one animation (docs/sharing.md).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "vaw/assembly.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/sim/session.hpp"

namespace vaw::report {

// Where each part is over time, a track per part: its world poses at rising times (s, from 0), kept only
// where it moves (a part at rest for a while has a key where the rest begins and one where it ends), and
// from when it is drawn (the order's parts appear at their step; none: always).
struct Track {
  std::vector<double> times;
  std::vector<Eigen::Isometry3d> poses;
  std::optional<double> shown;
};
struct Motion {
  std::string name;  // the animation's
  double duration = 0.0;
  std::vector<Track> parts;  // by PartId; empty: the scene at rest
};

// A recorded session replayed on its scene, every part's pose sampled `rate` times a second (and at the
// session's end), a part's samples where it stands still left out but for the first and last.
Motion sessionMotion(const std::shared_ptr<const sim::Scene>& scene, const sim::Session& session, double rate);

// The planned order played: the base in place, then each part in its step's turn flying home along its way
// over the first four fifths of `stepSeconds`, from a little more than its own size out; parts no order
// inserts appear at home at the end. Sampled `rate` times a second.
Motion orderMotion(const Assembly& assembly, const eval::SequencePlan& plan, double stepSeconds, double rate);

// Where the order has a part come in from: the offset from its home (world, m) along its way out, one and a
// half times its own size and 20 mm; zero for the base and for parts no order inserts.
Eigen::Vector3d orderApproach(const Assembly& assembly, const eval::SequencePlan& plan, PartId part);

struct GltfOptions {
  // A part's keys are thinned where the linear interpolation between the keys kept stays within these of
  // every sample dropped (m, rad); zero keeps every sample.
  double positionTolerance = 1e-4;
  double angleTolerance = 1e-3;
};

// The glTF 2.0 binary: a mesh per distinct part and environment mesh (instances share it), a material per
// colour (the scene's, in linear light), a node per part and environment object named as in the scene, in
// metres, under one root node that turns the scene's z-up into glTF's y-up; one animation with a
// translation and a rotation channel (and a stepped scale for parts that appear) per part that moves.
// Normals are left to the viewer, which the format has shade such triangles flat. The room's default floor
// is left out.
std::vector<std::uint8_t> glb(const Assembly& assembly, const Motion& motion, const GltfOptions& options = {});

// glb() written atomically to `file`: all of it or nothing (vaw::OutputError naming the file).
void writeGlb(const std::filesystem::path& file, const Assembly& assembly, const Motion& motion, const GltfOptions& options = {});

}  // namespace vaw::report
