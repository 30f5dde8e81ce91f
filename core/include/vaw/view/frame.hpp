#pragma once
// What a renderer draws, without any renderer (docs/architecture.md, "The live loop"): a SceneDescription
// built once from the assembly (what to draw: flat-shaded GPU-ready meshes shared between drawables, the
// resolved colour of each, the hoists) and a Frame produced from the world each step (where and how:
// poses, states, holders, highlights, the hands, the hoists, the drop lines under lifted parts). The Qt3D
// viewport and the OpenXR headset are two consumers of the same description and frames; neither holds
// a colour rule, a normal computation or a highlight rule of its own.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/interaction/states.hpp"
#include "vaw/sim/world.hpp"

namespace vaw::view {

struct Rgb {
  float r = 0.0f, g = 0.0f, b = 0.0f;
  friend bool operator==(const Rgb&, const Rgb&) = default;
};

// Flat-shaded triangles: three vertices per triangle, each position xyz then face normal xyz (floats, in the
// object's own frame, metres). Invalid triangles are left out.
struct MeshBuffer {
  std::vector<float> vertices;
  std::size_t vertexCount = 0;
  Eigen::AlignedBox3d bounds;
};
inline constexpr int kFloatsPerVertex = 6;
std::shared_ptr<const MeshBuffer> flatShaded(const TriMesh& mesh);

enum class DrawableKind : std::uint8_t { Part, Base, Environment };

struct Drawable {
  DrawableKind kind = DrawableKind::Part;
  std::size_t index = 0;  // PartId (Part, Base) or index into Assembly::environment
  std::string name;
  std::shared_ptr<const MeshBuffer> mesh;  // one buffer per distinct TriMesh
  Rgb color;                               // the material's (parts) or the object's (environment)
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // at load; a frame moves parts
  // The default floor: drawn, but only the height of its top counts in the scene's bounds, so that the
  // view frames the table and not 20 m of floor.
  bool backdrop = false;
};
// What a drawable adds to the scene's bounds.
Eigen::AlignedBox3d boundsOf(const Drawable& d);

struct SceneDescription {
  std::vector<Drawable> drawables;                   // parts with a mesh in id order, then the environment
  std::vector<std::optional<std::size_t>> partDrawable;  // per PartId: its drawable, if it has a mesh
  std::vector<Hoist> hoists;
  Eigen::AlignedBox3d partsBounds, allBounds;        // world, at load
};
SceneDescription describe(const Assembly& assembly);

// The colour of each part state (the viewport's tint and the timeline's segments and legend).
Rgb stateColor(interact::PartState s);
// The selection highlight.
inline constexpr Rgb kHighlight{1.0f, 0.549f, 0.102f};
// How a swept volume looks wherever it is drawn (the viewport, the headset, a video): translucent blue.
inline constexpr Rgb kSweptColor{70.0f / 255.0f, 140.0f / 255.0f, 230.0f / 255.0f};
inline constexpr float kSweptAlpha = 0.3f;

// A part's colour on screen: its own, tinted by its state while it moves (held, on a tool, sliding or
// turning, flying), and highlighted when selected.
Rgb displayColor(const Rgb& own, interact::PartState state, bool selected);

struct PartFrame {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // world
  interact::PartState state = interact::PartState::Static;
  sim::Holder holder = sim::Holder::None;
  bool selected = false;
  Rgb color;  // displayColor of its drawable
  bool shown = true;  // false: not drawn (a video of the order hides the parts whose step has not come)
};

struct HandFrame {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // world
  bool grab = false;
  std::optional<PartId> holding;
};

struct HoistFrame {
  Eigen::Isometry3d hook = Eigen::Isometry3d::Identity();  // world
  double top = 2.0;  // m, world z where the cable hangs from
  bool engaged = false;
  std::optional<PartId> load;
};

// A vertical line from a lifted part's centre of mass down to the surface below it, and the point it meets.
struct DropLine {
  PartId part = 0;
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();  // world
};

struct Frame {
  std::uint64_t step = 0;
  double t = 0.0;
  Eigen::Isometry3d basePose = Eigen::Isometry3d::Identity();
  std::vector<PartFrame> parts;  // per PartId
  std::array<HandFrame, 2> hands;  // left, right
  std::vector<HoistFrame> hoists;
  std::vector<DropLine> drops;
};

struct FrameOptions {
  std::optional<PartId> selected;
  bool drops = true;  // find the surface below held, hoisted and flying parts
};

// Fills `out` (reusing its storage) from the world after its last step.
void makeFrame(const sim::World& world, const SceneDescription& scene, const FrameOptions& options, Frame& out);

}  // namespace vaw::view
