#pragma once
// A recorded session or an assembly's planned order as a video (docs/sharing.md): every frame the
// renderer-neutral picture of the world at that time (view::Frame, drawn by the OpenGL renderer the headset
// uses, in a context with no display), a caption line under it (the time, what is in hand, each state
// change as it happens, the scene's name), encoded as H.264 in an MP4 file. No display and no GPU are
// needed; a GPU's driver is used where EGL offers one.
#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "vaw/evaluation/sequence.hpp"
#include "vaw/importer.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/sim/session.hpp"

class QImage;

namespace vaw::video {

// Where the camera looks from. Auto: from the window's home view, every part drawn in the picture where it
// is now (as the window's F frames them), the camera easing to each new framing so that a carried part, a
// lifted base or a dropped part stays in view. Follow: close on one part, easing after it. View: as Auto
// from a fixed side ("iso", the home view; "front", "back", "left", "right", "top"). Eye: still, from a
// given eye (the window's viewport as it looks when the video is asked for).
struct Camera {
  enum class Kind : std::uint8_t { Auto, Follow, View, Eye };
  Kind kind = Kind::Auto;
  std::string part;  // Follow
  std::string view;  // View
  // Eye: where it is, what it looks at, which way is up (m, the scene's frame), and the picture's vertical
  // field of view (degrees); the horizontal follows from the video's size.
  Eigen::Vector3d position = Eigen::Vector3d::Zero(), target = Eigen::Vector3d::Zero(), up = Eigen::Vector3d::UnitZ();
  double verticalFovDeg = 35.0;
};

// "auto", "follow PART", or a view's name: the camera, or std::nullopt when `text` is none of them.
std::optional<Camera> parseCamera(const std::string& text);
inline constexpr const char* kCameraChoices = "auto, follow PART, iso, front, back, left, right or top";

struct VideoOptions {
  int width = 1280, height = 720;  // pixels, both even
  int fps = 30;
  std::optional<double> from, to;  // s of the recording (or of the order played); unset: its start, its end
  double speed = 1.0;              // seconds of recording per second of video
  Camera camera;
  double stepSeconds = 2.0;        // an order's: the time each step takes
  // An order's: each way's swept volume at this voxel edge (m), drawn translucent while its part comes
  // home, and the nearest pass (a line between the two nearest points, the part and the distance in the
  // caption); 0 shows neither.
  double sweepVoxel = 0.0;
};

struct VideoResult {
  std::int64_t frames = 0;
  double seconds = 0.0;  // of video
  std::string encoder;   // FFmpeg's name for it ("libx264")
  std::string gl;        // the OpenGL renderer and EGL's platform it drew with
  std::int64_t sweeps = 0;  // an order's ways whose swept volume was shown
};

// `progress` is told the fraction done after each frame and stops the video by returning false (nothing
// is written then: LoadCancelled). Throws vaw::OutputError naming the file for a video that cannot be
// written, and vaw::InputError for options that do not fit (an odd size, a span outside the recording,
// a part the scene lacks). The file appears whole or not at all.
VideoResult writeSessionVideo(const std::shared_ptr<const sim::Scene>& scene, const sim::Session& session, const std::filesystem::path& file,
                              const VideoOptions& options, const ProgressFn& progress = {});
// The planned order played (as the report's 3D view and `vaw-sim export --order` play it): the base in
// place, then each part in its step's turn flying home along its way, lit, with the step's number and name.
// With a sweepVoxel the ways' swept volumes and clearances are worked out first (progress says so).
VideoResult writeOrderVideo(const std::shared_ptr<const sim::Scene>& scene, const eval::SequencePlan& plan, const std::filesystem::path& file,
                            const VideoOptions& options, const ProgressFn& progress = {});

// Frame `index` of the session's video exactly as writeSessionVideo encodes it (caption and camera
// included), before encoding: what the tests compare the decoded video with.
QImage sessionPicture(const std::shared_ptr<const sim::Scene>& scene, const sim::Session& session, const VideoOptions& options,
                      std::int64_t index);

}  // namespace vaw::video
