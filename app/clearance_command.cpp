// `vaw-sim clearance SESSION --part NAME --out DIR`: replays a recorded session and writes how close the
// part's path came to everything else (docs/clearance.md): DIR/clearance.csv, the nearest object at every
// step of the span, and DIR/summary.json, each object's least clearance and the spans of near misses,
// contacts and interference. Both are written whole beside their targets and renamed into place together
// under the output folder's lock, as `vaw-sim run` does.
#include "clearance_command.hpp"

#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include "directory_lock.hpp"
#include "vaw/atomic_file.hpp"
#include "vaw/error.hpp"
#include "vaw/importer.hpp"
#include "vaw/paths.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/clearance.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/sim/session.hpp"

namespace vaw::app {

namespace {

std::string mm(double metres) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6f", 1e3 * metres);
  return buf;
}

nlohmann::json pointMm(const Eigen::Vector3d& p) { return {1e3 * p.x(), 1e3 * p.y(), 1e3 * p.z()}; }

}  // namespace

int clearance(const ClearanceArgs& args) {
  ImporterRegistry importers;
  for (const auto& dir : ImporterRegistry::defaultPluginDirs())
    for (const auto& problem : importers.loadPlugins(dir)) std::fprintf(stderr, "vaw-sim: plugin: %s\n", problem.c_str());
  try {
    const sim::Session session = sim::loadSession(args.session);
    // The scene as recorded: as given, else beside the session file.
    std::filesystem::path sceneFile = resolveScenePath(session.scene);
    std::error_code ec;
    if (!std::filesystem::exists(sceneFile, ec) && std::filesystem::path(session.scene).is_relative())
      sceneFile = std::filesystem::path(args.session).parent_path() / session.scene;
    const auto scene = sim::Scene::build(loadAny(sceneFile, importers));
    sim::checkScene(session, *scene);
    const auto part = scene->assembly().findPart(args.part);
    if (!part) fail(args.session, "part", "the name of a part of " + sceneFile.string(), "\"" + args.part + "\"");
    sim::ClearanceOptions options;
    options.threshold = 1e-3 * args.thresholdMm;
    options.reach = 1e-3 * args.reachMm;
    options.from = args.from;
    options.to = args.to;
    const sim::ClearanceReport r = sim::clearanceAlong(scene, session, *part, options);
    const Assembly& a = scene->assembly();
    const auto objectName = [&](const collision::ObjectId& id) {
      return scene->collision().info(id).name;
    };

    const std::filesystem::path dir(args.out);
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir, ec))
      throw OutputError("cannot create the output directory " + dir.string() + ": " + (ec ? ec.message() : std::string("something else is there")));
    AtomicFile csv(dir / "clearance.csv");
    csv << "t,nearest,distance_mm,interfering,part_x_mm,part_y_mm,part_z_mm,other_x_mm,other_y_mm,other_z_mm\n";
    for (const auto& s : r.steps) {
      char t[32];
      std::snprintf(t, sizeof t, "%.6f", s.t);
      csv << t << "," << objectName(s.nearest) << "," << mm(s.distance) << (s.interfering ? ",1" : ",0");
      for (const Eigen::Vector3d* p : {&s.onPart, &s.onOther})
        for (int i = 0; i < 3; ++i) csv << "," << mm((*p)[i]);
      csv << "\n";
    }
    csv.finish();
    nlohmann::json j;
    j["part"] = a.parts[*part].name;
    j["threshold_mm"] = args.thresholdMm;
    j["reach_mm"] = args.reachMm;
    j["steps"] = r.steps.size();
    j["from"] = r.steps.front().t;
    j["to"] = r.steps.back().t;
    j["objects"] = nlohmann::json::array();
    for (const auto& o : r.objects)
      j["objects"].push_back({{"name", o.name}, {"least_mm", 1e3 * o.least}, {"t", o.t}, {"on_part_mm", pointMm(o.onPart)}, {"on_other_mm", pointMm(o.onOther)}});
    j["spans"] = nlohmann::json::array();
    for (const auto& s : r.spans)
      j["spans"].push_back({{"kind", std::string(sim::name(s.kind))}, {"object", s.name}, {"from", s.from}, {"to", s.to}});
    AtomicFile summary(dir / "summary.json");
    summary << j.dump(2) << "\n";
    summary.finish();
    {
      const DirectoryLock lock(dir);
      csv.publish();
      summary.publish();
    }
    std::printf("%s over %zu steps (t %.4f to %.4f s):", a.parts[*part].name.c_str(), r.steps.size(), r.steps.front().t, r.steps.back().t);
    if (r.objects.empty()) std::printf(" nothing within %g mm\n", args.reachMm);
    else std::printf(" nearest %s, %.3f mm at t = %.4f s\n", r.objects.front().name.c_str(), 1e3 * r.objects.front().least, r.objects.front().t);
    for (const auto& s : r.spans) std::printf("  %-12s %-16s t %.4f to %.4f s\n", std::string(sim::name(s.kind)).c_str(), s.name.c_str(), s.from, s.to);
    std::printf("wrote %s, %s\n", (dir / "clearance.csv").c_str(), (dir / "summary.json").c_str());
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
