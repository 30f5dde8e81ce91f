// `vaw-sim clearance SESSION --part NAME --out DIR`: replays a recorded session and writes how close the
// part's path came to everything else (docs/clearance.md): DIR/clearance.csv, the nearest object at every
// step of the span, and DIR/summary.json, each object's least clearance and the spans of near misses,
// contacts and interference. `vaw-sim sweep` writes the same and the volume the path swept
// (docs/swept-volume.md): DIR/swept.stl and, through the STEP plugin, DIR/swept.step; given a scene rather
// than a session, it sweeps the part's way home from the order search instead. All are written
// whole beside their targets and renamed into place together under the output folder's lock, as
// `vaw-sim run` does.
#include "clearance_command.hpp"

#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include "directory_lock.hpp"
#include "session_scene.hpp"
#include "vaw/atomic_file.hpp"
#include "vaw/error.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/evaluation/way_clearance.hpp"
#include "vaw/importer.hpp"
#include "vaw/mesh_export.hpp"
#include "vaw/paths.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/clearance.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/sim/session.hpp"
#include "vaw/sim/swept_volume.hpp"

namespace vaw::app {

namespace {

std::string mm(double metres) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6f", 1e3 * metres);
  return buf;
}

nlohmann::json pointMm(const Eigen::Vector3d& p) { return {1e3 * p.x(), 1e3 * p.y(), 1e3 * p.z()}; }

// The session and the scene it was recorded on, the part named, and the options as the core takes them.
struct Recorded {
  sim::Session session;
  std::filesystem::path sceneFile;
  std::shared_ptr<const sim::Scene> scene;
  PartId part = 0;
  sim::ClearanceOptions options;
};

Recorded load(const ClearanceArgs& args, const ImporterRegistry& importers) {
  Recorded r;
  r.session = sim::loadSession(args.session);
  r.sceneFile = sessionSceneFile(r.session, args.session);
  r.scene = sim::Scene::build(loadAny(r.sceneFile, importers));
  sim::checkScene(r.session, *r.scene);
  const auto part = r.scene->assembly().findPart(args.part);
  if (!part) fail(args.session, "part", "the name of a part of " + r.sceneFile.string(), "\"" + args.part + "\"");
  r.part = *part;
  r.options.threshold = 1e-3 * args.thresholdMm;
  r.options.reach = 1e-3 * args.reachMm;
  r.options.from = args.from;
  r.options.to = args.to;
  return r;
}

std::filesystem::path outputDir(const std::string& out) {
  const std::filesystem::path dir(out);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir, ec))
    throw OutputError("cannot create the output directory " + dir.string() + ": " + (ec ? ec.message() : std::string("something else is there")));
  return dir;
}

// clearance.csv: the nearest object at every step.
void writeSteps(AtomicFile& csv, const sim::ClearanceReport& r, const sim::Scene& scene) {
  csv << "t,nearest,distance_mm,interfering,part_x_mm,part_y_mm,part_z_mm,other_x_mm,other_y_mm,other_z_mm\n";
  for (const auto& s : r.steps) {
    char t[32];
    std::snprintf(t, sizeof t, "%.6f", s.t);
    csv << t << "," << scene.collision().info(s.nearest).name << "," << mm(s.distance) << (s.interfering ? ",1" : ",0");
    for (const Eigen::Vector3d* p : {&s.onPart, &s.onOther})
      for (int i = 0; i < 3; ++i) csv << "," << mm((*p)[i]);
    csv << "\n";
  }
  csv.finish();
}

// The summary's clearance: each object's least clearance and the spans.
void addClearance(nlohmann::json& j, const sim::ClearanceReport& r, const ClearanceArgs& args) {
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
}

void printClearance(const sim::ClearanceReport& r, const std::string& part, const ClearanceArgs& args) {
  std::printf("%s over %zu steps (t %.4f to %.4f s):", part.c_str(), r.steps.size(), r.steps.front().t, r.steps.back().t);
  if (r.objects.empty()) std::printf(" nothing within %g mm\n", args.reachMm);
  else std::printf(" nearest %s, %.3f mm at t = %.4f s\n", r.objects.front().name.c_str(), 1e3 * r.objects.front().least, r.objects.front().t);
  for (const auto& s : r.spans) std::printf("  %-12s %-16s t %.4f to %.4f s\n", std::string(sim::name(s.kind)).c_str(), s.name.c_str(), s.from, s.to);
}

// Runs a command body, reporting bad input and unwritable output as `run` does.
template <typename Body>
int reporting(Body&& body) {
  try {
    return body();
  } catch (const InputError& e) {
    std::fprintf(stderr, "vaw-sim: error: %s\n", e.what());
    return 1;
  } catch (const OutputError& e) {
    std::fprintf(stderr, "vaw-sim: error: %s\n", e.what());
    return 1;
  }
}

void loadPlugins(ImporterRegistry& importers) {
  for (const auto& dir : ImporterRegistry::defaultPluginDirs())
    for (const auto& problem : importers.loadPlugins(dir)) std::fprintf(stderr, "vaw-sim: plugin: %s\n", problem.c_str());
}

}  // namespace

int clearance(const ClearanceArgs& args) {
  ImporterRegistry importers;
  loadPlugins(importers);
  return reporting([&] {
    const Recorded rec = load(args, importers);
    const sim::ClearanceReport r = sim::clearanceAlong(rec.scene, rec.session, rec.part, rec.options);
    const std::string& partName = rec.scene->assembly().parts[rec.part].name;
    const std::filesystem::path dir = outputDir(args.out);
    AtomicFile csv(dir / "clearance.csv");
    writeSteps(csv, r, *rec.scene);
    nlohmann::json j;
    j["part"] = partName;
    addClearance(j, r, args);
    AtomicFile summary(dir / "summary.json");
    summary << j.dump(2) << "\n";
    summary.finish();
    {
      const DirectoryLock lock(dir);
      csv.publish();
      summary.publish();
    }
    printClearance(r, partName, args);
    std::printf("wrote %s, %s\n", (dir / "clearance.csv").c_str(), (dir / "summary.json").c_str());
    return 0;
  });
}

namespace {

// swept.stl and, through the STEP plugin when it is installed, swept.step (written beside its target, put
// in place by publish): the volume in the assembly's own unit and frame, so that a CAD system places it
// where it belongs.
class SweptFiles {
 public:
  SweptFiles(const std::filesystem::path& dir, const TriMesh& mesh, const std::string& partName, const Assembly& a,
             const ImporterRegistry& importers, const ExportOptions& limits)
      : dir_(dir), stl_(dir / "swept.stl"), step_(importers.exporterFor("swept.step")) {
    stl_ << binaryStl(mesh, 1.0 / toMetres(a.units), "vaw swept volume of " + partName + ", " + std::string(name(a.units)));
    stl_.finish();
    if (step_ != nullptr) step_->write(mesh, partName + " swept", a.units, dir / ".swept.step.new", limits, {});
    else std::fprintf(stderr, "vaw-sim: no swept.step: no STEP writer (the STEP plugin is not installed)\n");
  }
  [[nodiscard]] bool step() const { return step_ != nullptr; }
  // Under the folder's lock, with the other files.
  void publish() {
    stl_.publish();
    if (step_ == nullptr) return;
    std::error_code ec;
    std::filesystem::rename(dir_ / ".swept.step.new", dir_ / "swept.step", ec);
    if (ec) throw OutputError((dir_ / "swept.step").string() + ": cannot put the written file in place: " + ec.message());
  }
  [[nodiscard]] std::string written() const {
    return (dir_ / "swept.stl").string() + (step_ != nullptr ? ", " + (dir_ / "swept.step").string() : std::string());
  }

 private:
  std::filesystem::path dir_;
  AtomicFile stl_;
  const SolidExporter* step_;
};

nlohmann::json sweptJson(const SweptVolume& sv, double voxelMm, const Assembly& a, bool step) {
  const Eigen::AlignedBox3d bounds = sv.mesh.bounds();
  return {{"voxel_mm", voxelMm},
          {"relative_to_base", sv.relativeToBase},
          {"base", sv.relativeToBase ? a.parts[*a.base].name : std::string()},
          {"from", sv.from},
          {"to", sv.to},
          {"moves", sv.moves},
          {"voxels", sv.voxels},
          {"volume_mm3", 1e9 * sv.volume},
          {"triangles", sv.mesh.triangles.size()},
          {"min_mm", pointMm(bounds.min())},
          {"max_mm", pointMm(bounds.max())},
          {"unit", std::string(name(a.units))},
          {"step", step}};
}

// summary.json written, then everything put in place together under the folder's lock.
void publishSweep(const std::filesystem::path& dir, SweptFiles& swept, AtomicFile& csv, const nlohmann::json& j) {
  AtomicFile summary(dir / "summary.json");
  summary << j.dump(2) << "\n";
  summary.finish();
  const DirectoryLock lock(dir);
  swept.publish();
  csv.publish();
  summary.publish();
}

bool isSession(const std::string& file) {
  const std::string suffix = ".vaw-session.json";
  return file.size() >= suffix.size() && file.compare(file.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A scene rather than a session: the part's way home, as the order search finds it, swept and walked past
// the parts already in (docs/evaluation.md, "Ways home: clearance and space").
int sweepWayHome(const SweepArgs& args, const ImporterRegistry& importers) {
  const ClearanceArgs& c = args.clearance;
  const std::string& file = c.session;
  if (args.relativeToBase || c.from || c.to)
    fail(file, args.relativeToBase ? "--relative-to-base" : "--from/--to", "a recorded session (a scene's way home is swept with the assembly at rest)",
         "a scene");
  const Assembly a = loadAny(resolveScenePath(file), importers);
  const auto part = a.findPart(c.part);
  if (!part) fail(file, "part", "the name of a part of the assembly", "\"" + c.part + "\"");
  const eval::SequencePlan plan = eval::planSequence(a);
  const eval::Direction* way = plan.wayOf(*part);
  if (way == nullptr)
    fail(file, "part", "a part the order puts in place along a way home",
         a.base && *a.base == *part ? c.part + " is the base" : c.part + ": no order puts it in place (vaw-sim evaluate names what blocks it)");
  eval::WayClearanceOptions o;
  o.threshold = 1e-3 * c.thresholdMm;
  o.reach = 1e-3 * c.reachMm;
  o.voxel = 1e-3 * args.voxelMm;
  o.only = *part;
  const std::vector<eval::WayClearance> ways = eval::wayClearances(a, plan, o);
  if (ways.size() != 1 || !ways.front().swept) fail(file, "part", "a way home to sweep", "none for " + c.part);
  const eval::WayClearance& w = ways.front();
  const std::filesystem::path dir = outputDir(c.out);

  SweptFiles swept(dir, w.swept->surface(), c.part, a, importers, args.step);
  // clearance.csv: each part already in within reach, nearest first.
  AtomicFile csv(dir / "clearance.csv");
  csv << "part,least_mm,at_mm_out,part_x_mm,part_y_mm,part_z_mm,other_x_mm,other_y_mm,other_z_mm\n";
  for (const eval::WayObject& ob : w.objects) {
    csv << a.parts[ob.part].name << "," << mm(ob.least) << "," << mm(ob.at);
    for (const Eigen::Vector3d* p : {&ob.onPart, &ob.onOther})
      for (int i = 0; i < 3; ++i) csv << "," << mm((*p)[i]);
    csv << "\n";
  }
  csv.finish();
  const auto names = [&](const std::vector<PartId>& parts) {
    nlohmann::json out = nlohmann::json::array();
    for (const PartId p : parts) out.push_back(a.parts[p].name);
    return out;
  };
  nlohmann::json j;
  j["part"] = c.part;
  j["way_home"] = {{"comes_home", eval::travelText(w.out) + ": " + way->from}, {"out", {w.out.x(), w.out.y(), w.out.z()}}, {"length_mm", 1e3 * w.length}};
  j["swept"] = sweptJson(*w.swept, args.voxelMm, a, swept.step());
  nlohmann::json objects = nlohmann::json::array();
  for (const eval::WayObject& ob : w.objects)
    objects.push_back({{"name", a.parts[ob.part].name}, {"least_mm", 1e3 * ob.least}, {"at_mm_out", 1e3 * ob.at},
                       {"on_part_mm", pointMm(ob.onPart)}, {"on_other_mm", pointMm(ob.onOther)}});
  j["clearance"] = {{"threshold_mm", c.thresholdMm}, {"reach_mm", c.reachMm}, {"near_miss", w.nearMiss(o.threshold)},
                    {"slides_on", names(w.guides)}, {"rests_on", names(w.seatedOn)}, {"objects", objects}};
  publishSweep(dir, swept, csv, j);
  std::printf("%s's way home (%s, %.1f mm) swept %.1f cm^3 (%zu voxels of %g mm)\n", c.part.c_str(), j["way_home"]["comes_home"].get<std::string>().c_str(),
              1e3 * w.length, 1e6 * w.swept->volume, w.swept->voxels, args.voxelMm);
  if (const eval::WayObject* n = w.nearest())
    std::printf("  nearest %s, %.3f mm at %.3f mm out%s\n", a.parts[n->part].name.c_str(), 1e3 * n->least, 1e3 * n->at,
                w.nearMiss(o.threshold) ? ": a near miss" : "");
  else
    std::printf("  nothing already in within %g mm\n", c.reachMm);
  std::printf("wrote %s, %s, %s\n", swept.written().c_str(), (dir / "clearance.csv").c_str(), (dir / "summary.json").c_str());
  return 0;
}

}  // namespace

int sweep(const SweepArgs& args) {
  ImporterRegistry importers;
  loadPlugins(importers);
  return reporting([&] {
    if (!isSession(args.clearance.session)) return sweepWayHome(args, importers);
    const Recorded rec = load(args.clearance, importers);
    const Assembly& a = rec.scene->assembly();
    sim::SweptVolumeOptions so;
    so.voxel = 1e-3 * args.voxelMm;
    so.relativeToBase = args.relativeToBase;
    so.from = args.clearance.from;
    so.to = args.clearance.to;
    const auto [sv, r] = sim::sweptVolumeAndClearance(rec.scene, rec.session, rec.part, so, rec.options);
    const std::string& partName = a.parts[rec.part].name;
    const std::filesystem::path dir = outputDir(args.clearance.out);

    SweptFiles swept(dir, sv.mesh, partName, a, importers, args.step);
    AtomicFile csv(dir / "clearance.csv");
    writeSteps(csv, r, *rec.scene);
    nlohmann::json j;
    j["part"] = partName;
    j["swept"] = sweptJson(sv, args.voxelMm, a, swept.step());
    nlohmann::json c;
    addClearance(c, r, args.clearance);
    j["clearance"] = c;
    publishSweep(dir, swept, csv, j);
    std::printf("%s swept %.1f cm^3 (%zu voxels of %g mm, %zu moves, t %.4f to %.4f s)%s\n", partName.c_str(), 1e6 * sv.volume,
                sv.voxels, args.voxelMm, sv.moves, sv.from, sv.to, sv.relativeToBase ? (", on " + a.parts[*a.base].name).c_str() : "");
    printClearance(r, partName, args.clearance);
    std::printf("wrote %s, %s, %s\n", swept.written().c_str(), (dir / "clearance.csv").c_str(), (dir / "summary.json").c_str());
    return 0;
  });
}

}  // namespace vaw::app
