// `vaw-sim video`: a recorded session replayed, or a scene's planned order played, rendered with no
// display and encoded as an MP4 file (docs/sharing.md).
#include "video_command.hpp"

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "session_scene.hpp"
#include "vaw/error.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/importer.hpp"
#include "vaw/paths.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/sim/session.hpp"
#include "vaw/video/video.hpp"

namespace vaw::app {

int video(const VideoArgs& args) {
  video::VideoOptions options;
  const std::string& in = args.input;
  // WxH, as people type it.
  const std::size_t x = args.size.find('x');
  const char* s = args.size.data();
  if (x == std::string::npos || std::from_chars(s, s + x, options.width).ptr != s + x ||
      std::from_chars(s + x + 1, s + args.size.size(), options.height).ptr != s + args.size.size())
    fail(args.out, "--size", "WIDTHxHEIGHT in pixels (1280x720)", "\"" + args.size + "\"");
  options.fps = args.fps;
  options.from = args.from;
  options.to = args.to;
  options.speed = args.speed;
  options.stepSeconds = args.stepSeconds;
  if (args.sweeps) {
    if (!args.order) fail(args.out, "--sweeps", "--order as well (a session's video shows what was recorded)", "--sweeps alone");
    options.sweepVoxel = args.voxelMm * 1e-3;
  }
  std::string cameraText;
  for (const std::string& word : args.camera) cameraText += (cameraText.empty() ? "" : " ") + word;
  const auto camera = video::parseCamera(cameraText);
  if (!camera) fail(args.out, "--camera", video::kCameraChoices, "\"" + cameraText + "\"");
  options.camera = *camera;

  ImporterRegistry importers;
  for (const auto& dir : ImporterRegistry::defaultPluginDirs())
    for (const auto& problem : importers.loadPlugins(dir)) std::fprintf(stderr, "vaw-sim: plugin: %s\n", problem.c_str());
  // The fraction done on one line of stderr, rewritten, for a person watching a long video being made.
  int shown = -1;
  const ProgressFn progress = [&](double f, const std::string&) {
    const int percent = static_cast<int>(100.0 * f);
    if (percent / 10 != shown / 10) std::fprintf(stderr, "vaw-sim video: %d %%\n", percent);
    shown = percent;
    return true;
  };
  video::VideoResult result;
  std::string what;
  if (in.ends_with(".vaw-session.json")) {
    if (args.order) fail(in, "--order", "a scene, STEP or mesh file (a session plays what was recorded)", "a session");
    const sim::Session session = sim::loadSession(in);
    const auto scene = sim::Scene::build(loadAny(sessionSceneFile(session, in), importers));
    sim::checkScene(session, *scene);
    result = video::writeSessionVideo(scene, session, args.out, options, progress);
    what = "the session";
  } else {
    if (!args.order) fail(in, "--order", "a recorded session (.vaw-session.json), or --order to play a scene's planned order", "a scene without --order");
    const auto scene = sim::Scene::build(loadAny(resolveScenePath(in), importers));
    const eval::SequencePlan plan = eval::planSequence(scene->assembly());
    result = video::writeOrderVideo(scene, plan, args.out, options, progress);
    what = "the order of " + std::to_string(plan.order.size()) + " parts";
    if (args.sweeps) what += ", the swept volume and nearest pass of " + std::to_string(result.sweeps) + (result.sweeps == 1 ? " way" : " ways");
  }
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(args.out, ec);
  std::printf("wrote %s: %s, %lld frames at %d x %d, %d fps (%.1f s of video, %s, %.1f MB); drawn by %s\n", args.out.c_str(), what.c_str(),
              static_cast<long long>(result.frames), options.width, options.height, options.fps, result.seconds, result.encoder.c_str(),
              ec ? 0.0 : static_cast<double>(bytes) / 1e6, result.gl.c_str());
  return 0;
}

}  // namespace vaw::app
