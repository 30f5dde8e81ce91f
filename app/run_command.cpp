// `vaw-sim run SCENE --inputs SCRIPT --out DIR` and `vaw-sim run --replay SESSION --out DIR`: runs the
// simulation world headless over scripted (or recorded) inputs and writes DIR/trajectories.csv,
// DIR/transitions.csv and DIR/session.vaw-session.json (which replays bit for bit).
//
// Output integrity: each file is written completely to a temporary file beside it (vaw::AtomicFile, every
// write checked), and the three are renamed into place together only once all are complete, under a
// lock on DIR/.vaw-run.lock: concurrent runs into one DIR leave the three files of one run, and a failed
// or killed run leaves the previous run's files.
#include "run_command.hpp"

#include "directory_lock.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "vaw/atomic_file.hpp"
#include "vaw/error.hpp"
#include "vaw/importer.hpp"
#include "vaw/paths.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/session.hpp"

namespace vaw::app {

int run(const RunArgs& args) {
  const std::string& scene = args.scene;
  const std::string& inputs = args.inputs;
  const std::string& out = args.out;
  const std::string& replayFile = args.replay;
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
    const auto loaded = sim::Scene::build(loadAny(resolveScenePath(session.scene), importers));
    if (replayFile.empty()) session.sceneHash = loaded->contentHash();
    // A CAD assembly's parts are PLACED where they come to rest at home (docs/physics.md, "Parts on parts").
    if (replayFile.empty() && loaded->assembly().settings.placeAtRest) session.settings.placeAtRest = true;
    const Assembly& assembly = loaded->assembly();
    const std::filesystem::path dir(out);
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir, ec))
      throw OutputError("cannot create the output directory " + dir.string() + ": " +
                        (ec ? ec.message() : std::string("something else is there")));
    // The trajectories stream into their temporary file as the world steps: a long run needs no memory
    // for them, and a full disk stops the run at once.
    AtomicFile trajectories(dir / "trajectories.csv");
    trajectories << sim::kTrajectoriesCsvHeader;
    std::vector<sim::TrajectoryRow> rows;
    std::string text;
    const sim::World w = sim::replay(loaded, session, [&](const sim::World& world) {
      rows.clear();
      text.clear();
      sim::appendTrajectory(world, rows);
      for (const auto& row : rows) sim::appendTrajectoryCsv(world, row, text);
      trajectories << text;
    });
    trajectories.finish();
    AtomicFile transitions(dir / "transitions.csv"), sessionFile(dir / "session.vaw-session.json");
    sim::writeTransitionsCsv(w, transitions);
    transitions.finish();
    sim::saveSession(session, sessionFile);
    sessionFile.finish();
    {
      const DirectoryLock lock(dir);
      for (AtomicFile* f : {&trajectories, &transitions, &sessionFile}) f->publish();
    }
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
  } catch (const OutputError& e) {
    std::fprintf(stderr, "vaw-sim: error: %s\n", e.what());
    return 1;
  }
}

}  // namespace vaw::app
