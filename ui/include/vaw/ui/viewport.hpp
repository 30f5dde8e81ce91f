#pragma once
// The 3D view. Built once per scene from the core's renderer-neutral description (view::SceneDescription:
// GPU-ready meshes, colours, hoists) and then moved by frames (view::Frame: poses, display colours, hands,
// hoists, drop lines), touching only what changed. Orbit/pan/zoom camera with z up; picking by ray cast.
//
// The mouse is the right hand: dragging a part grabs it (with Ctrl: both hands); it follows the pointer on
// a camera-facing plane through the grab point, the wheel moves it in depth, Q/E turn it about the
// vertical, Z/X about the view's horizontal axis and C/V about the view's axis, releasing the button lets
// it go. Dragging the
// background (or anything with Alt held) orbits. The keys I/K, J/L, U/O tilt and turn the base (the left
// hand); H engages the hoist, Shift+Up/Down raises and lowers it, Shift+Left/Right turns it. The viewport
// only reports these as signals; the SimulationController turns them into the world's input.
#include <Eigen/Geometry>
#include <QColor>
#include <QKeySequence>
#include <QPoint>
#include <QPointF>
#include <QSet>
#include <QWidget>
#include <memory>
#include <optional>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/view/frame.hpp"

namespace Qt3DCore {
class QEntity;
class QTransform;
}  // namespace Qt3DCore
namespace Qt3DRender {
class QCamera;
class QRenderCapture;
class QScreenRayCaster;
class QGeometryRenderer;
}  // namespace Qt3DRender
namespace Qt3DExtras {
class Qt3DWindow;
class QPhongMaterial;
}  // namespace Qt3DExtras

namespace vaw::ui {

class OrbitController;

class Viewport : public QWidget {
  Q_OBJECT
 public:
  explicit Viewport(QWidget* parent = nullptr);
  ~Viewport() override;
  Viewport(const Viewport&) = delete;
  Viewport& operator=(const Viewport&) = delete;

  // Rebuilds the scene from `scene` (null: empty) and frames it from the default direction. Copies what it
  // draws; shares the mesh buffers' bytes with Qt3D.
  void setScene(const vaw::view::SceneDescription* scene);
  // Moves and colours what the frame says; only entities whose pose or colour changed are touched.
  void applyFrame(const vaw::view::Frame& frame);

  [[nodiscard]] std::optional<vaw::PartId> selectedPart() const { return selected_; }
  [[nodiscard]] std::size_t partCount() const { return parts_.size(); }

  // The part under a point of the 3D window (window coordinates), by a synchronous ray cast, and where the
  // ray meets it (world, m).
  struct Pick {
    vaw::PartId part = 0;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
  };
  [[nodiscard]] std::optional<Pick> pick(const QPoint& windowPos) const;
  [[nodiscard]] std::optional<vaw::PartId> partAt(const QPoint& windowPos) const;
  // A point of the 3D window on the screen (for a menu at the pointer).
  [[nodiscard]] QPoint windowToGlobal(const QPoint& windowPos) const;
  // Where a world point (metres) appears in the 3D window (window coordinates).
  [[nodiscard]] QPointF projectToWindow(const Eigen::Vector3d& world) const;
  // The world ray through a window point: origin (on the near plane) and unit direction.
  [[nodiscard]] std::pair<Eigen::Vector3d, Eigen::Vector3d> rayThrough(const QPointF& windowPos) const;
  // World bounds of the parts (m) where the last frame put them.
  [[nodiscard]] Eigen::AlignedBox3d partsBounds() const;
  // Where the last frame put `part` (its frame -> world); none for a part not drawn.
  [[nodiscard]] std::optional<Eigen::Isometry3d> partPose(vaw::PartId part) const;
  // Face picking (the Constraints panel's "Add from faces"): while on, a click on a part emits facePicked
  // instead of only selecting it, a drag turns the view instead of grabbing, and Esc emits
  // facePickCancelled.
  void setPickingFaces(bool on);
  [[nodiscard]] bool pickingFaces() const { return pickingFaces_; }
  // The part being dragged, if any.
  [[nodiscard]] std::optional<vaw::PartId> dragging() const { return grabbing_ ? std::optional(candidate_->part) : std::nullopt; }

  // Draws the principal axes of `part` (centre of mass and axes in its own frame, half-lengths in m) with
  // it, following its pose; none: hides them.
  struct Axes {
    vaw::PartId part = 0;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // columns
    Eigen::Vector3d halfLengths = Eigen::Vector3d::Constant(0.05);
  };
  void showAxes(const std::optional<Axes>& axes);

  // A constraint's geometry on its partner (the Constraints panel's selected row), drawn where the last
  // frame put the partner: an axis as a line of `size` through `point`, a plane as a square of side `size`
  // round `point` with its normal as a line. Given in the partner's frame; a new scene hides it.
  struct ConstraintGeometry {
    enum class Kind { Axis, Plane };
    Kind kind = Kind::Axis;
    vaw::PartId partner = 0;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // the axis's direction, the plane's normal; unit
    double size = 0.1;                                     // m
  };
  // Where a carried part must be let go to go onto its mate (vaw::sim::CaptureHint), in the world: a ring of
  // the capture distance round the mate's axis (or in a plane parallel to its face) centred on `point`, and
  // the axis (or normal) on from it. Green when a release now would put the part on, red when not.
  struct CaptureZone {
    bool axis = true;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // unit
    double reach = 0.01;                                   // m, the capture distance
    bool captures = false;
  };
  void showCaptureZone(const std::optional<CaptureZone>& zone);
  // The volume a part's path swept (the Path panel), in the world, drawn translucent so the parts show
  // through; null hides it. A new scene hides it. Not picked: a click goes through it to the parts.
  void showSweptVolume(std::shared_ptr<const vaw::view::MeshBuffer> mesh);
  [[nodiscard]] bool sweptVolumeShown() const { return sweptMesh_ != nullptr; }
  [[nodiscard]] const std::shared_ptr<const vaw::view::MeshBuffer>& sweptVolume() const { return sweptMesh_; }
  [[nodiscard]] const std::optional<CaptureZone>& captureZone() const { return captureShown_; }

  void showConstraintGeometry(const ConstraintGeometry& geometry);
  void hideConstraintGeometry();
  [[nodiscard]] const std::optional<ConstraintGeometry>& constraintGeometry() const { return constraintShown_; }
  // The world segments the constraint's overlay is drawn as now (none while hidden).
  [[nodiscard]] const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& constraintSegments() const {
    return constraintSegments_;
  }

  [[nodiscard]] Qt3DExtras::Qt3DWindow* view3d() const { return view_; }
  [[nodiscard]] Qt3DRender::QCamera* camera() const;
  // The root of the frame graph: request captures from it (tests, screenshots).
  [[nodiscard]] Qt3DRender::QRenderCapture* renderCapture() const { return capture_; }
  [[nodiscard]] QColor clearColor() const;
  // Entities touched by the last applyFrame (parts moved or recoloured, overlays), for the benchmark.
  [[nodiscard]] std::size_t lastFrameUpdates() const { return lastUpdates_; }

  static QColor highlightColor();

 public slots:
  // Selects `part` (nothing: clears). Emits partSelected when the selection changes; the highlight comes
  // with the next frame (the core's colour rule).
  void selectPart(std::optional<vaw::PartId> part);
  // Frames the parts where they are now, keeping the current view direction.
  void fitToView();
  // Frames the parts where they are now from the default direction (front, right, above; z up).
  void resetView();
  // Looks from `eye` at `centre` (world, m; z up) and keeps that view when the window resizes.
  void lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& centre);

 signals:
  void partSelected(std::optional<vaw::PartId> part);
  // showSweptVolume was called (the headset shows the same).
  void sweptVolumeChanged();
  void grabStarted(vaw::PartId part, const Eigen::Vector3d& at, bool bothHands);
  void handMoved(const Eigen::Vector3d& at);
  void grabEnded();
  // Held keys: the held part's angular velocity (rad/s, world) from Q/E (about the vertical), Z/X (about
  // the view's horizontal axis) and C/V (about the view's axis); zero when released.
  void handTurn(const Eigen::Vector3d& angularVelocity);
  // Held keys: rates in rad/s (m/s for the hoist's height); zero when released.
  void baseRates(double tiltX, double tiltY, double turn);
  void hoistRates(double up, double yaw);
  void hoistToggled();
  // A key the viewport does not use, pressed while its 3D window has focus: the window's shortcuts do not
  // see it there (the 3D view is a native window of its own), so the main window matches it to its actions.
  void shortcutKey(const QKeySequence& key);
  // A click on `part` while picking faces, and where it met the part (world, m).
  void facePicked(vaw::PartId part, const Eigen::Vector3d& at);
  void facePickCancelled();
  // A right click (no drag) at a point of the 3D window: the window offers what can be done there.
  void contextMenuRequested(const QPoint& windowPos);

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  struct PartVisual {
    vaw::PartId id = 0;
    bool base = false;
    Qt3DCore::QEntity* entity = nullptr;
    Qt3DCore::QTransform* transform = nullptr;
    Qt3DExtras::QPhongMaterial* material = nullptr;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    vaw::view::Rgb color;
    Eigen::AlignedBox3d local;  // mesh bounds, own frame
  };
  // A thin cylinder between two points (lines: drop lines, cable, axes) or a marker.
  struct Overlay {
    Qt3DCore::QEntity* entity = nullptr;
    Qt3DCore::QTransform* transform = nullptr;
    Qt3DExtras::QPhongMaterial* material = nullptr;
  };
  void createScene();
  void frame(const Eigen::Vector3d& direction);
  void onClick(const QPoint& windowPos);
  Overlay makeOverlay(Qt3DRender::QGeometryRenderer* mesh, const QColor& color);
  void placeLine(Overlay& o, const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius);
  void placeAt(Overlay& o, const Eigen::Isometry3d& pose, const Eigen::Vector3d& scale);
  // Overlays are hidden by collapsing them to nothing, never by disabling their entity: in Qt 6.4 an entity
  // that was disabled and is enabled again is not drawn any more.
  static void hide(Overlay& o);
  [[nodiscard]] Eigen::Vector3d handOnPlane(const QPointF& windowPos) const;
  void keyRates();
  [[nodiscard]] double lineRadius() const;
  void placeConstraint();

  Qt3DExtras::Qt3DWindow* view_ = nullptr;
  QWidget* container_ = nullptr;
  Qt3DCore::QEntity* root_ = nullptr;
  Qt3DCore::QEntity* sceneRoot_ = nullptr;  // parts, environment and overlays; rebuilt per scene
  Qt3DRender::QRenderCapture* capture_ = nullptr;
  Qt3DRender::QScreenRayCaster* rayCaster_ = nullptr;
  OrbitController* cameraController_ = nullptr;
  std::vector<PartVisual> parts_;
  std::vector<std::optional<std::size_t>> visualOfPart_;
  std::vector<Qt3DCore::QEntity*> environment_;
  // Overlays: the two hands, each hoist's cable and hook, a pool of drop lines and their markers, the axes.
  Qt3DRender::QGeometryRenderer* cylinder_ = nullptr;
  Qt3DRender::QGeometryRenderer* sphere_ = nullptr;
  Qt3DRender::QGeometryRenderer* torus_ = nullptr;
  Overlay hands_[2];
  std::vector<Overlay> cables_, hooks_;
  std::vector<Overlay> drops_, marks_;
  Overlay axes_[3];
  std::optional<Axes> axesShown_;
  static constexpr std::size_t kConstraintLines = 5;  // a square's four sides and its normal; an axis uses one
  Overlay constraintLines_[kConstraintLines];
  Overlay captureRing_, captureLine_;
  std::optional<CaptureZone> captureShown_;
  Qt3DCore::QEntity* swept_ = nullptr;                         // under sceneRoot_
  std::shared_ptr<const vaw::view::MeshBuffer> sweptMesh_;  // Qt3D reads its bytes
  std::optional<ConstraintGeometry> constraintShown_;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> constraintSegments_;
  std::size_t lastUpdates_ = 0;
  std::optional<vaw::PartId> selected_;
  Eigen::AlignedBox3d partsBounds_;  // at load: the size of things (line widths)
  Eigen::AlignedBox3d allBounds_;
  QPoint pressPos_;
  bool dragged_ = false;
  bool autoFit_ = true;  // refit on resize until the user moves the camera
  bool pickingFaces_ = false;
  // Dragging a part: what the press hit, whether the drag has begun, the plane the hand moves on.
  std::optional<Pick> candidate_;
  bool grabbing_ = false;
  bool bothHands_ = false;
  Eigen::Vector3d planePoint_ = Eigen::Vector3d::Zero(), planeNormal_ = Eigen::Vector3d::UnitZ();
  QPointF lastPointer_;
  QSet<int> keysDown_;
};

}  // namespace vaw::ui
