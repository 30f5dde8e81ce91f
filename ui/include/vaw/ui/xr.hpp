#pragma once
// The headset behind an interface (docs/vr.md). The OpenXR plugin (plugins/openxr/, libvaw_xr_openxr.so)
// implements vaw::xr::Backend; the workbench's XrController loads it with dlopen, so the workbench builds and
// runs without OpenXR and no OpenXR header is included outside the plugin and its tests. Plain C++ (no Qt):
// the plugin takes the OpenGL context that is current on the calling thread (a GLX context) and reads the
// X display, drawable and context it hands to the runtime from GLX itself.
//
// Coordinates: everything here is in the world's frame (metres, z up, the table top at z = 0); the plugin
// places the world in the runtime's reference space (Placement) and converts both ways.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "vaw/view/frame.hpp"

namespace vaw::xr {

inline constexpr int kAbiVersion = 3;  // 2: Backend::recenter; 3: Backend::setOverlay
inline constexpr const char* kPluginFile = "libvaw_xr_openxr.so";

// The 26 joints of XR_EXT_hand_tracking, in its order.
inline constexpr int kJointCount = 26;
enum Joint : int {
  kPalm = 0,
  kWrist = 1,
  kThumbTip = 5,
  kIndexTip = 10,
  kMiddleTip = 15,
  kRingTip = 20,
  kLittleTip = 25,
};

// XrSessionState, named for messages and tests.
enum class SessionState { Unknown, Idle, Ready, Synchronized, Visible, Focused, Stopping, LossPending, Exiting };
constexpr std::string_view name(SessionState s) {
  switch (s) {
    case SessionState::Idle: return "IDLE";
    case SessionState::Ready: return "READY";
    case SessionState::Synchronized: return "SYNCHRONIZED";
    case SessionState::Visible: return "VISIBLE";
    case SessionState::Focused: return "FOCUSED";
    case SessionState::Stopping: return "STOPPING";
    case SessionState::LossPending: return "LOSS_PENDING";
    case SessionState::Exiting: return "EXITING";
    case SessionState::Unknown: break;
  }
  return "UNKNOWN";
}

// Why the headset could not start or stopped without being asked to.
enum class Failure {
  None,
  NotInstalled,    // this vaw was built or installed without the OpenXR plugin
  NoRuntime,       // no OpenXR runtime installed or selected
  NoHeadset,       // the runtime sees no head-mounted display
  NoOpenGL,        // the runtime does not offer XR_KHR_opengl_enable
  OpenGLContext,   // the OpenGL context does not suit the runtime (not GLX, version out of its range)
  SessionLost,     // the runtime lost the session (headset unplugged, compositor restarted)
  RuntimeLost,     // the runtime itself went away (crashed or quit): the instance is lost
  RuntimeError,    // any other error the runtime returned
};

// Where the world sits in the runtime's space.
struct Placement {
  double tableHeight = 0.90;     // m, the table top above the floor when the runtime offers a STAGE space
  double tableBelowEyes = 0.45;  // m, the table top below the head's starting height (LOCAL space)
  double tableDistance = 0.45;   // m, the table's centre in front of the space's origin
};

struct StartOptions {
  Placement placement;
};

struct RuntimeInfo {
  std::string name;     // XrInstanceProperties::runtimeName
  std::string version;  // "major.minor.patch"
  std::string system;   // XrSystemProperties::systemName
  bool handTracking = false;  // XR_EXT_hand_tracking offered and the system tracks hands
  bool stage = false;         // a STAGE space (else LOCAL)
  int eyeWidth = 0, eyeHeight = 0;  // swapchain image size per eye
};

// One hand at a moment: its tracked joints, or its controller.
struct HandSample {
  enum class Source { None, Joints, Controller };
  Source source = Source::None;
  // Joints: every joint's pose and radius; Controller: kPalm holds the grip pose.
  std::array<Eigen::Isometry3d, kJointCount> joints{};
  std::array<float, kJointCount> radii{};
  // Joint velocities (m/s, rad/s, world) where the runtime flags them valid; for a controller, kPalm's.
  std::array<Eigen::Vector3d, kJointCount> linear{}, angular{};
  std::array<bool, kJointCount> linearValid{}, angularValid{};
  bool select = false;  // Controller: the select (or trigger) click
};
struct HandsSample {
  std::array<HandSample, 2> hands;  // left, right
};

struct FrameTiming {
  std::int64_t displayTime = 0;  // ns, the runtime's clock (XrTime): when this frame will be shown
  bool shouldRender = false;
};

// What was shown, for the desktop's mirror and the benchmark.
struct FrameResult {
  bool submitted = false;  // xrEndFrame accepted the frame
  bool rendered = false;   // with the scene drawn into both eyes
  Eigen::Isometry3d head = Eigen::Isometry3d::Identity();  // world, the mean of the eyes
  double fovUp = 0.0, fovDown = 0.0;  // rad, the eyes' vertical field of view (up > 0 > down)
  double simulateMs = 0.0;  // CPU time inside the simulate callback
  double renderMs = 0.0;    // CPU time issuing both eyes' drawing (the driver's work included)
};

struct Event {
  enum class Kind { State, Failure, Message };
  Kind kind = Kind::Message;
  SessionState state = SessionState::Unknown;  // State
  Failure failure = Failure::None;             // Failure
  bool warning = false;                        // Message: a warning (validation errors are) rather than a note
  std::string text;                            // Failure and Message
};

// Every call expects the OpenGL context given to start() to be current on the calling thread.
class Backend {
 public:
  virtual ~Backend() = default;
  // Creates the instance, the session (XR_KHR_opengl_enable with the Xlib/GLX binding), the reference space,
  // the swapchains, the hand trackers and the controller actions. On failure returns an event of kind
  // Failure that says which, and nothing is left behind.
  [[nodiscard]] virtual Event start(const StartOptions& options) = 0;
  [[nodiscard]] virtual const RuntimeInfo& runtime() const = 0;
  // What to draw from now on: uploads the meshes once.
  virtual void setScene(const view::SceneDescription& scene) = 0;
  // A mesh in the world drawn translucent over the scene (a path's swept volume), `alpha` its opacity;
  // null removes it. Kept across setScene.
  virtual void setOverlay(std::shared_ptr<const view::MeshBuffer> mesh, const view::Rgb& color, float alpha) = 0;
  // The runtime's events since the last call, with any messages from the validation layer; begins and ends
  // the session as the states ask.
  [[nodiscard]] virtual std::vector<Event> poll() = 0;
  // The session is running: frame() should be called in a loop.
  [[nodiscard]] virtual bool running() const = 0;
  // One frame, paced by the runtime (xrWaitFrame blocks until it is time): `simulate` runs with the frame's
  // timing and returns what to draw (nothing: the previous frame), then both eyes are rendered and submitted.
  using Simulate = std::function<const view::Frame*(const FrameTiming&)>;
  virtual FrameResult frame(const Simulate& simulate) = 0;
  // The hands at `time` (the runtime's clock, ns): tracked joints where the runtime tracks them, else the
  // controller; Source::None while the session has no input focus.
  [[nodiscard]] virtual HandsSample sampleHands(std::int64_t time) = 0;
  // Places the world again from where the head is and looks now (the last frame's): the table's centre
  // Placement::tableDistance ahead along the gaze's horizontal direction and its top
  // Placement::tableBelowEyes below the eyes, the world's +y ahead. From the next frame on.
  virtual void recenter() = 0;
  // Asks the runtime to end the session (xrRequestExitSession); poll() then reports STOPPING and EXITING.
  virtual void requestExit() = 0;
  // The session reached EXITING or was lost: nothing more to do but destroy the backend.
  [[nodiscard]] virtual bool finished() const = 0;
};

}  // namespace vaw::xr

extern "C" {
using VawXrAbiFn = int (*)();
using VawXrCreateFn = vaw::xr::Backend* (*)();
}
