#pragma once
// The script the simulated OpenXR runtime plays back (a JSON file named by VAW_SIMXR_SCRIPT), shared with the
// tests so they can say what the runtime showed at any moment. Times are seconds of display time from the
// session's first frame; poses are in the STAGE space (metres, y up, the user looks along -z).
//
// {
//   "refresh": 90,               display rate (Hz)
//   "duration": 3.0,             then the runtime ends the session (STOPPING, EXITING) as a user leaving would
//   "realtime": false,           true: xrWaitFrame blocks until the frame is due on the wall clock (a demo);
//                                false: each frame is one period of the runtime's clock later, at once (tests)
//   "eye_size": [320, 288],      the recommended swapchain size per eye
//   "headset": true,             false: xrGetSystem answers XR_ERROR_FORM_FACTOR_UNAVAILABLE
//   "stage": true,               false: only VIEW and LOCAL spaces
//   "hand_tracking": true,       false: XR_EXT_hand_tracking is not offered
//   "joint_velocities": true,    false: joint velocities are never flagged valid
//   "local_origin": {...},       the LOCAL space's origin in STAGE (a pose; default: 1.6 m above the floor)
//   "head": [keyframe...],       {"t", "position", "rotation"}
//   "left", "right": [keyframe...]   a tracked hand: {"t", "position", "rotation", "pinch", "grip", "tracked",
//                                "joints"}: the pose is the point between the thumb and index tips with the palm's
//                                orientation, "pinch" the gap between those tips (m), "grip" the fingers' curl
//                                (0 open, 1 a fist); or "joints": 26 [x, y, z, qw, qx, qy, qz] given outright
//   "left_controller", "right_controller": [keyframe...]  {"t", "position", "rotation", "select", "active"}
//   "events": [{"t", "lose_session": true} | {"t", "lose_instance": true}]
//   "capture_at": [t...]         the submitted images of the first frame at or after each time are kept
// }
// A keyframe leaves out what does not change: fields carry over from the previous keyframe of the channel.
// Positions and pinch/grip interpolate linearly, rotations by slerp; booleans hold from their keyframe on.
#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <string>
#include <vector>

namespace vaw::simxr {

inline constexpr int kJoints = 26;

struct HandKey {
  double t = 0.0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  double pinch = 0.08, grip = 0.0;
  bool tracked = true;
  std::optional<std::array<Eigen::Isometry3d, kJoints>> joints;
};

struct ControllerKey {
  double t = 0.0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  bool select = false, active = true;
};

struct PoseKey {
  double t = 0.0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
};

// A hand at a moment: where its pinch point is, how it is shaped, and all of its joints.
struct HandPose {
  bool tracked = false;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  double pinch = 0.0, grip = 0.0;
  std::array<Eigen::Isometry3d, kJoints> joints{};
  std::array<float, kJoints> radii{};
};

struct ControllerPose {
  bool active = false, select = false;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

struct Script {
  double refresh = 90.0, duration = 3.0;
  int eyeWidth = 320, eyeHeight = 288;
  bool headset = true, stage = true, handTracking = true, jointVelocities = true, realtime = false;
  Eigen::Isometry3d localOrigin = Eigen::Isometry3d::Identity();
  std::vector<PoseKey> head;
  std::array<std::vector<HandKey>, 2> hands;
  std::array<std::vector<ControllerKey>, 2> controllers;
  std::optional<double> loseSessionAt, loseInstanceAt;
  std::vector<double> captureAt;

  // Throws std::runtime_error naming the file and the field.
  static Script load(const std::string& file);

  [[nodiscard]] Eigen::Isometry3d headAt(double t) const;
  [[nodiscard]] HandPose handAt(int hand, double t) const;  // 0 left, 1 right
  [[nodiscard]] ControllerPose controllerAt(int hand, double t) const;
};

// The runtime's hand: the 26 joints of a hand whose pinch point is `pose` (thumb and index tips `pinch` apart
// along its x axis, centred on it) with the fingers curled by `grip`; every joint has the palm's orientation.
std::array<Eigen::Isometry3d, kJoints> handJoints(int hand, const Eigen::Isometry3d& pose, double pinch, double grip);

}  // namespace vaw::simxr
