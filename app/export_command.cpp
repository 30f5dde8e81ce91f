// `vaw-sim export`: a recorded session replayed, or a scene's planned order, or a scene at rest, written as
// one glTF 2.0 binary (docs/sharing.md).
#include "export_command.hpp"

#include <cstdio>
#include <filesystem>
#include <system_error>

#include "session_scene.hpp"
#include "vaw/error.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/importer.hpp"
#include "vaw/paths.hpp"
#include "vaw/report/gltf.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/sim/session.hpp"

namespace vaw::app {

int exportGltf(const ExportArgs& args) {
  ImporterRegistry importers;
  for (const auto& dir : ImporterRegistry::defaultPluginDirs())
    for (const auto& problem : importers.loadPlugins(dir)) std::fprintf(stderr, "vaw-sim: plugin: %s\n", problem.c_str());
  report::GltfOptions options;
  options.positionTolerance = 1e-3 * args.toleranceMm;
  // The same tolerance at the end of an arm of 100 mm.
  options.angleTolerance = options.positionTolerance / 0.1;
  std::shared_ptr<const sim::Scene> scene;
  report::Motion motion;
  const std::string& in = args.input;
  if (in.ends_with(".vaw-session.json")) {
    if (args.order) fail(in, "--order", "a scene, STEP or mesh file (a session plays what was recorded)", "a session");
    const sim::Session session = sim::loadSession(in);
    scene = sim::Scene::build(loadAny(sessionSceneFile(session, in), importers));
    sim::checkScene(session, *scene);
    motion = report::sessionMotion(scene, session, args.rate);
  } else {
    scene = sim::Scene::build(loadAny(resolveScenePath(in), importers));
    if (args.order) {
      const eval::SequencePlan plan = eval::planSequence(scene->assembly());
      motion = report::orderMotion(scene->assembly(), plan, args.stepSeconds, args.rate);
    }
  }
  report::writeGlb(args.out, scene->assembly(), motion, options);
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(args.out, ec);
  char what[96] = "at rest";
  if (!motion.parts.empty()) std::snprintf(what, sizeof what, "%s of %.1f s", motion.name.c_str(), motion.duration);
  std::printf("wrote %s (%zu parts, %s, %.1f kB)\n", args.out.c_str(), scene->assembly().parts.size(), what,
              ec ? 0.0 : static_cast<double>(bytes) / 1e3);
  return 0;
}

}  // namespace vaw::app
