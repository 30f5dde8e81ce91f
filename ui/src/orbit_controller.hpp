#pragma once
// Orbit, pan and zoom for a z-up world. Qt3DExtras::QOrbitCameraController orbits about the world
// y axis (hard-coded), which tumbles a z-up scene; this one keeps the horizon level.
//   left drag: orbit about the view centre (yaw about world z, pitch clamped short of the poles)
//   right or middle drag, or shift + left drag: pan
//   wheel, PageUp/PageDown: zoom towards the view centre
//   arrow keys: orbit (not with Shift held: Shift+arrows drive the hoist)
#include <Qt3DExtras/QAbstractCameraController>

namespace vaw::ui {

class OrbitController : public Qt3DExtras::QAbstractCameraController {
  Q_OBJECT
 public:
  explicit OrbitController(Qt3DCore::QNode* parent = nullptr);
  // Closest and farthest the camera may come to the view centre (m).
  void setDistanceLimits(float closest, float farthest);
  // While the mouse holds a part the camera stays put: Qt3D's input sees the mouse whatever the viewport
  // does with it, so the controller itself must ignore it.
  void setSuspended(bool suspended) { suspended_ = suspended; }
  [[nodiscard]] bool suspended() const { return suspended_; }

 private:
  void moveCamera(const InputState& state, float dt) override;

  bool suspended_ = false;
  float closest_ = 1e-3f;
  float farthest_ = 1e3f;
};

}  // namespace vaw::ui
