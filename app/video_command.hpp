#pragma once
#include <optional>
#include <string>
#include <vector>

namespace vaw::app {
// `vaw-sim video SESSION --out FILE.mp4` (or a scene with --order): the recording or the planned order as
// an H.264 video (docs/sharing.md). The options as parsed in vaw_sim.cpp.
struct VideoArgs {
  std::string input, out;
  std::string size = "1280x720";
  int fps = 30;
  std::optional<double> from, to;
  double speed = 1.0;
  std::vector<std::string> camera = {"auto"};  // "follow PART" may come as two words
  bool order = false;
  double stepSeconds = 2.0;
  bool sweeps = false;   // with order: each way's swept volume and nearest pass shown
  double voxelMm = 2.0;  // their voxel edge
};
int video(const VideoArgs& args);
}  // namespace vaw::app
