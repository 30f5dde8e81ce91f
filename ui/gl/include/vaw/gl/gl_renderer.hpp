#pragma once
// A small OpenGL 3.3 renderer of the workbench's renderer-neutral picture (view::SceneDescription once,
// view::Frame per frame) into the headset's swapchain images. Qt 6.4 has no XR rendering, and Qt3D cannot
// draw into textures the runtime owns, so the headset gets its own renderer; it holds no colour, normal or
// highlight rule of its own: those come with the frame.
//
// Meshes are uploaded once per distinct MeshBuffer (parts that share a mesh share its buffer), every
// drawable is one draw call, lighting is two directional lights fixed to the world plus ambient, and the
// tracked hands are drawn as a small sphere per joint (a box for a controller's grip).
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "vaw/ui/xr.hpp"
#include "vaw/view/frame.hpp"

namespace vaw::xr {

// One eye: where it is and what it sees (OpenXR's field of view angles, radians).
struct EyeView {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // world; looks along its -z with y up
  double angleLeft = 0.0, angleRight = 0.0, angleUp = 0.0, angleDown = 0.0;
};

// The matrix OpenXR's asymmetric field of view gives, for OpenGL's clip space (z in [-1, 1]).
Eigen::Matrix4f projection(const EyeView& eye, float nearZ, float farZ);

class GlRenderer {
 public:
  // Compiles the shaders and builds the joint and line shapes; needs a current OpenGL 3.3 core context.
  GlRenderer();
  ~GlRenderer();
  GlRenderer(const GlRenderer&) = delete;
  GlRenderer& operator=(const GlRenderer&) = delete;

  // Uploads each distinct mesh of `scene` once and keeps a copy of what to draw.
  void setScene(const view::SceneDescription& scene);
  // A world mesh drawn translucent after everything else (its back faces culled: it is closed and
  // outward); null removes it.
  void setOverlay(std::shared_ptr<const view::MeshBuffer> mesh, const view::Rgb& color, float alpha);
  // World segments drawn unlit with the parts, as beams `width` across (a video's nearest pass); empty: none.
  struct Line {
    Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
    double width = 0.001;  // m
    view::Rgb color;
  };
  void setLines(std::vector<Line> lines) { lines_ = std::move(lines); }
  // For a camera that holds still (a video's): what has not moved since the frame before is drawn once
  // into a layer of its own, colour and depth, and copied under each frame, so that a frame costs only
  // what moves. A layer is made when the eye is the last frame's and made again when a part in it moves
  // or the eye moves. Off unless asked: a headset's eyes move every frame.
  void keepStillLayer(bool on);
  struct LayerUse {
    std::int64_t made = 0;   // layers drawn
    std::int64_t drawnOver = 0;  // frames drawn over a layer
  };
  [[nodiscard]] const LayerUse& stillLayerUse() const { return use_; }
  // Draws into `colorTexture` (a 2D texture, e.g. a swapchain image) of `width` x `height` pixels.
  void render(std::uint32_t colorTexture, int width, int height, const EyeView& eye, const view::Frame* frame,
              const HandsSample& hands);

 private:
  struct GpuMesh {
    std::uint32_t vao = 0, vbo = 0;
    std::int32_t count = 0;
  };
  struct Item {
    view::DrawableKind kind = view::DrawableKind::Part;
    std::size_t index = 0;
    const GpuMesh* mesh = nullptr;
    Eigen::Matrix4f pose = Eigen::Matrix4f::Identity();
    view::Rgb color;
  };
  // What an item looks like in one frame: compared exactly to tell what moved.
  struct Look {
    Eigen::Matrix4f pose = Eigen::Matrix4f::Identity();
    view::Rgb color;
    bool shown = true;
    bool operator==(const Look&) const = default;
  };
  struct StillLayer {
    bool on = false, valid = false;
    std::uint32_t fbo = 0, color = 0, depth = 0;
    int width = 0, height = 0;
    EyeView eye;                  // the eye it was drawn for
    std::vector<char> in;         // per item: drawn in the layer
    std::vector<Look> drawn;      // per item: as the layer has it
  };
  GpuMesh upload(const std::vector<float>& vertices, std::size_t count);
  [[nodiscard]] Look lookOf(const Item& item, const view::Frame& frame) const;
  // True when `layer_` holds what `looks` and `eye` show (made again here when it can be).
  bool useStillLayer(const std::vector<Look>& looks, const EyeView& eye, int width, int height, const Eigen::Matrix4f& viewProj);
  void draw(const GpuMesh& mesh, const Eigen::Matrix4f& model, const view::Rgb& color, bool lit, float alpha = 1.0f);
  void drawSegment(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double width, const view::Rgb& color);
  void ensureTargets(int width, int height);

  std::uint32_t program_ = 0;
  std::int32_t uModel_ = -1, uViewProj_ = -1, uColor_ = -1, uLit_ = -1, uAlpha_ = -1;
  std::uint32_t fbo_ = 0, depth_ = 0;
  int depthWidth_ = 0, depthHeight_ = 0;
  GpuMesh sphere_, cube_;
  std::unordered_map<const view::MeshBuffer*, GpuMesh> meshes_;
  std::vector<Item> items_;
  struct Overlay {
    std::shared_ptr<const view::MeshBuffer> mesh;  // kept while its upload is drawn
    GpuMesh gpu;
    view::Rgb color;
    float alpha = 1.0f;
  };
  std::optional<Overlay> overlay_;
  std::vector<Line> lines_;
  StillLayer layer_;
  LayerUse use_;
  std::vector<Look> last_;   // the last frame's looks, per item
  std::vector<Look> looks_;  // this frame's, swapped with last_ so that no frame allocates
  std::optional<EyeView> lastEye_;
};

}  // namespace vaw::xr
