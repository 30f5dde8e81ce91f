#include "orbit_controller.hpp"

#include <Qt3DRender/QCamera>
#include <QVector3D>
#include <algorithm>
#include <cmath>

namespace vaw::ui {

namespace {
const QVector3D kUp(0.0f, 0.0f, 1.0f);
constexpr float kMaxElevationSin = 0.995f;  // stop ~6 degrees short of straight up or down
constexpr float kZoomPerUnit = 0.15f;
}  // namespace

OrbitController::OrbitController(Qt3DCore::QNode* parent) : QAbstractCameraController(parent) {}

void OrbitController::setDistanceLimits(float closest, float farthest) {
  closest_ = closest;
  farthest_ = std::max(farthest, closest);
}

void OrbitController::moveCamera(const InputState& state, float dt) {
  Qt3DRender::QCamera* cam = camera();
  if (cam == nullptr || suspended_) return;
  // Mouse axis values are the pointer's movement since the last frame times the mouse device's
  // sensitivity (0.1 per pixel); they are not rates, so they are not multiplied by dt (keys are).
  constexpr float kPixelsPerUnit = 10.0f;
  const bool pan = state.rightMouseButtonActive || state.middleMouseButtonActive ||
                   (state.leftMouseButtonActive && state.shiftKeyActive);
  const bool orbit = state.leftMouseButtonActive && !pan;

  if (pan) {
    // About the distance covered by one pixel at the view centre, so the scene follows the pointer.
    const float distance = (cam->position() - cam->viewCenter()).length();
    const float perPixel = 2.0f * distance * std::tan(cam->fieldOfView() * 0.5f * 3.14159265f / 180.0f) / 700.0f;
    cam->translate(QVector3D(-state.rxAxisValue, -state.ryAxisValue, 0.0f) * kPixelsPerUnit * perPixel);
  }

  const float keys = state.shiftKeyActive ? 0.0f : 1.0f;
  float yaw = keys * state.txAxisValue * lookSpeed() * dt;  // arrow keys
  float pitch = keys * state.tyAxisValue * lookSpeed() * dt;
  if (orbit) {
    constexpr float kDegreesPerPixel = 0.4f;
    yaw -= state.rxAxisValue * kPixelsPerUnit * kDegreesPerPixel;
    pitch -= state.ryAxisValue * kPixelsPerUnit * kDegreesPerPixel;
  }
  if (yaw != 0.0f) cam->panAboutViewCenter(yaw, kUp);
  if (pitch != 0.0f) {
    const QVector3D before = cam->position();
    cam->tiltAboutViewCenter(pitch);
    const QVector3D view = (cam->viewCenter() - cam->position()).normalized();
    if (std::abs(QVector3D::dotProduct(view, kUp)) > kMaxElevationSin) cam->setPosition(before);
  }
  cam->setUpVector(kUp);

  if (state.tzAxisValue != 0.0f) {
    const QVector3D offset = cam->position() - cam->viewCenter();
    const float distance = offset.length();
    const float factor = std::exp(-state.tzAxisValue * kZoomPerUnit);
    const float wanted = std::clamp(distance * factor, closest_, farthest_);
    if (distance > 0.0f) cam->setPosition(cam->viewCenter() + offset * (wanted / distance));
  }
}

}  // namespace vaw::ui
