// `vaw-sim run SCENE --inputs SCRIPT --out DIR` and `vaw-sim run --replay SESSION --out DIR`: runs the
// simulation world headless over scripted (or recorded) inputs and writes DIR/trajectories.csv,
// DIR/transitions.csv and DIR/session.vaw-session.json (which replays bit for bit).
#include "run_command.hpp"

#include <cstdio>
#include <filesystem>
#include <string>

#include "vaw/importer.hpp"
#include "vaw/paths.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/session.hpp"

namespace vaw::app {

namespace {

std::filesystem::path resolveScene(const std::string& scene) {
  const std::filesystem::path p(scene);
  if (std::filesystem::exists(p)) return p;
  const std::filesystem::path bundled = resourceDir() / "scenes" / p;
  return std::filesystem::exists(bundled) ? bundled : p;
}

}  // namespace

int run(const std::vector<std::string>& args) {
  std::string scene, inputs, out, replayFile;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const bool hasValue = i + 1 < args.size();
    if (args[i] == "--inputs" && hasValue) inputs = args[++i];
    else if (args[i] == "--out" && hasValue) out = args[++i];
    else if (args[i] == "--replay" && hasValue) replayFile = args[++i];
    else if (!args[i].empty() && args[i][0] == '-') {
      std::fprintf(stderr, "vaw-sim run: unknown option or missing value: %s\n", args[i].c_str());
      return 2;
    } else if (scene.empty()) scene = args[i];
    else {
      std::fprintf(stderr, "vaw-sim run: one scene at a time\n");
      return 2;
    }
  }
  if (out.empty() || (replayFile.empty() && (scene.empty() || inputs.empty())) || (!replayFile.empty() && !inputs.empty())) {
    std::fprintf(stderr, "usage: vaw-sim run SCENE --inputs SCRIPT --out DIR\n       vaw-sim run --replay SESSION --out DIR\n");
    return 2;
  }
  ImporterRegistry importers;
  for (const auto& dir : ImporterRegistry::defaultPluginDirs())
    for (const auto& problem : importers.loadPlugins(dir)) std::fprintf(stderr, "vaw-sim: plugin: %s\n", problem.c_str());
  try {
    sim::Session session;
    if (!replayFile.empty()) {
      session = sim::loadSession(replayFile);
      if (!scene.empty()) session.scene = scene;  // a scene given on the command line overrides the recorded one
    } else {
      session.scene = scene;
      session.inputs = sim::loadInputScript(inputs, session.settings);
    }
    const auto loaded = sim::Scene::build(loadAny(resolveScene(session.scene), importers));
    if (replayFile.empty()) session.sceneHash = loaded->contentHash();
    const Assembly& assembly = loaded->assembly();
    std::vector<sim::TrajectoryRow> rows;
    rows.reserve(session.inputs.size() * assembly.parts.size());
    const sim::World w = sim::replay(loaded, session, [&rows](const sim::World& world) { sim::appendTrajectory(world, rows); });
    std::filesystem::create_directories(out);
    const std::filesystem::path dir(out);
    sim::writeTrajectoriesCsv(w, rows, dir / "trajectories.csv");
    sim::writeTransitionsCsv(w, dir / "transitions.csv");
    sim::saveSession(session, dir / "session.vaw-session.json");
    std::printf("%zu steps at %g Hz (%.4f s), %zu parts, %zu transitions, %zu refusals, %zu edits, state hash %016llx\n",
                session.inputs.size(), session.settings.rate, w.time(), assembly.parts.size(), w.transitions().size(),
                w.refusals().size(), w.edits().size(), static_cast<unsigned long long>(w.stateHash()));
    for (const auto& e : w.edits())
      std::printf("  t=%8.4f  edit: %s\n", e.t, sim::describe(e.edit, assembly).c_str());
    for (const auto& t : w.transitions())
      std::printf("  t=%8.4f  %-10s %-12s -> %-12s %-24s %s\n", t.t, assembly.parts[t.part].name.c_str(),
                  std::string(interact::name(t.from)).c_str(), std::string(interact::name(t.to)).c_str(),
                  std::string(interact::name(t.event)).c_str(), t.cause.c_str());
    for (const auto& r : w.refusals())
      std::printf("  t=%8.4f  %-10s refused %s in %s: %s\n", r.t, assembly.parts[r.part].name.c_str(),
                  std::string(interact::name(r.event)).c_str(), std::string(interact::name(r.state)).c_str(), r.reason.c_str());
    std::printf("wrote %s, %s, %s\n", (dir / "trajectories.csv").c_str(), (dir / "transitions.csv").c_str(),
                (dir / "session.vaw-session.json").c_str());
    return 0;
  } catch (const InputError& e) {
    std::fprintf(stderr, "vaw-sim: error: %s\n", e.what());
    return 1;
  }
}

}  // namespace vaw::app
