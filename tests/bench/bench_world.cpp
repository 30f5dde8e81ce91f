// The simulation world's step cost against the number of parts that are not active (the goal: the step cost
// grows with the active parts only). One active part, a 50 mm steel cube in free flight (free-flight gravity
// scale 0, drifting at 0.1 mm/s, 0.3 m from the nearest other part) runs its time-of-impact query every step;
// every other part is STATIC. Assemblies: a grid of N resting cubes on a table (N = 10, 100, 1000) and the
// bundled large gearbox (large meshes) with the cube added.
//   build/bin/vaw_bench_world [--benchmark_repetitions=5 --benchmark_report_aggregates_only=true]
#include <benchmark/benchmark.h>

#include <malloc.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>

#include "vaw/primitives.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/clearance.hpp"
#include "vaw/sim/recorder.hpp"
#include "vaw/sim/swept_volume.hpp"
#include "vaw/sim/world.hpp"

namespace {

const vaw::ImporterRegistry& importers() {
  static vaw::ImporterRegistry r;
  static bool loaded = [] {
    (void)r.loadPlugins(VAW_BUILD_PLUGIN_DIR);
    return true;
  }();
  (void)loaded;
  return r;
}

Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = Eigen::Vector3d(x, y, z);
  return p;
}

vaw::PartId addCube(vaw::Assembly& a, const std::string& name, const Eigen::Isometry3d& pose) {
  vaw::Part p;
  p.id = a.parts.size();
  p.name = name;
  p.pose = pose;
  vaw::TriMesh mesh = vaw::primitives::box({0.05, 0.05, 0.05});
  p.mass = vaw::massPropertiesFromMesh(mesh, 7850.0);
  p.mesh = std::make_shared<const vaw::TriMesh>(std::move(mesh));
  p.shapeSource = "box 50 mm";
  p.extent = 0.05;
  p.category = vaw::categorize(p.mass.mass, p.extent, vaw::CategorySettings::defaults());
  a.parts.push_back(std::move(p));
  return a.parts.size() - 1;
}

// N cubes on a 0.1 m grid on a table; the flying cube 0.3 m beyond the grid's -x edge.
vaw::Assembly grid(int n, Eigen::Vector3d& flyAt) {
  vaw::Assembly a;
  a.name = "grid";
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  for (int i = 0; i < n; ++i) addCube(a, "cube" + std::to_string(i), at(0.1 * (i % side), 0.1 * (i / side), 0.025));
  vaw::EnvironmentObject table;
  table.name = "table";
  table.kind = "table";
  table.mesh = std::make_shared<const vaw::TriMesh>(vaw::primitives::box({8.0, 8.0, 0.04}));
  table.shapeSource = "box";
  table.pose = at(0, 0, -0.02);
  a.environment.push_back(table);
  flyAt = Eigen::Vector3d(-0.3, 0.0, 0.1);
  return a;
}

vaw::Assembly gearbox(Eigen::Vector3d& flyAt) {
  vaw::Assembly a = vaw::loadScene(std::filesystem::path(VAW_BUILD_RESOURCE_DIR) / "scenes" / "large-gearbox.vaw.json", importers());
  const Eigen::AlignedBox3d b = a.worldBounds();
  flyAt = Eigen::Vector3d(b.min().x() - 0.3, b.center().y(), b.center().z());
  return a;
}

// Builds the world and puts the extra cube in flight: held for 10 steps while moving at 0.1 mm/s, released.
std::unique_ptr<vaw::sim::World> flying(vaw::Assembly a, const Eigen::Vector3d& flyAt) {
  const vaw::PartId cube = addCube(a, "flyer", at(flyAt.x(), flyAt.y(), flyAt.z()));
  vaw::sim::Settings s;
  s.gravity.freeFlight = 0.0;
  auto w = std::make_unique<vaw::sim::World>(a, s);
  vaw::sim::Input in;
  for (int k = 0; k < 10; ++k) {
    in.left = {at(flyAt.x() - 0.0001 / 90.0 * k, flyAt.y(), flyAt.z()), true, std::nullopt};
    w->step(in);
  }
  in.left.grab = false;
  w->step(in);
  if (w->part(cube).state != vaw::interact::PartState::InSpace) throw std::runtime_error("the cube is not in flight");
  return w;
}

void run(benchmark::State& state, const vaw::Assembly& a, const Eigen::Vector3d& flyAt) {
  auto w = flying(a, flyAt);
  int steps = 0;
  const vaw::sim::Input idle;
  for (auto _ : state) {
    if (++steps == 90000) {  // 1000 s of flight (10 cm): start again so the situation stays the same
      state.PauseTiming();
      w = flying(a, flyAt);
      steps = 0;
      state.ResumeTiming();
    }
    w->step(idle);
    benchmark::DoNotOptimize(w->time());
  }
  state.counters["parts"] = static_cast<double>(a.parts.size() + 1);
  state.counters["active"] = static_cast<double>(w->activeParts());
}

void BM_WorldStepOneFlyingPartGrid(benchmark::State& state) {
  Eigen::Vector3d flyAt;
  const vaw::Assembly a = grid(static_cast<int>(state.range(0)), flyAt);
  run(state, a, flyAt);
}
BENCHMARK(BM_WorldStepOneFlyingPartGrid)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

void BM_WorldStepOneFlyingPartLargeGearbox(benchmark::State& state) {
  Eigen::Vector3d flyAt;
  const vaw::Assembly a = gearbox(flyAt);
  run(state, a, flyAt);
}
BENCHMARK(BM_WorldStepOneFlyingPartLargeGearbox)->Unit(benchmark::kMicrosecond);

// The 0.42 kg gear closed on where it lies in the large gearbox, lifted 0.1 m and carried round a 5 cm
// circle for 10 s (900 steps at 90 Hz): the carry both path benchmarks below measure.
vaw::sim::Session carriedGear(const vaw::sim::Scene& scene, vaw::PartId gear) {
  vaw::sim::Session session;
  session.scene = "large-gearbox.vaw.json";
  const double rate = session.settings.rate;
  const Eigen::Vector3d start = scene.assembly().parts[gear].pose * scene.assembly().parts[gear].mass.centerOfMass;
  vaw::sim::Input in;
  in.right = {at(start.x(), start.y(), start.z()), true, gear};
  session.inputs.push_back(in);
  for (int k = 1; k <= static_cast<int>(10.0 * rate); ++k) {
    const double t = k / rate;
    const double a = 2.0 * std::numbers::pi * 0.5 * t;
    in.right.pose = at(start.x() + 0.05 * (1.0 - std::cos(a)), start.y() + 0.05 * std::sin(a), start.z() + std::min(t, 1.0) * 0.1);
    session.inputs.push_back(in);
  }
  return session;
}

// Clearance along a carried path (docs/clearance.md): the gear's carry measured against the other 96
// parts, the table and the floor at every step (the replay included).
void BM_ClearanceTenSecondsLargeGearbox(benchmark::State& state) {
  Eigen::Vector3d unused;
  const auto scene = vaw::sim::Scene::build(gearbox(unused));
  const vaw::PartId gear = *scene->assembly().findPart("gear-a1");
  const vaw::sim::Session session = carriedGear(*scene, gear);
  std::size_t steps = 0;
  for (auto _ : state) {
    const vaw::sim::ClearanceReport r = vaw::sim::clearanceAlong(scene, session, gear);
    steps = r.steps.size();
    benchmark::DoNotOptimize(r.objects.size());
  }
  state.counters["steps"] = static_cast<double>(steps);  // the time per step: the iteration's over this
}
BENCHMARK(BM_ClearanceTenSecondsLargeGearbox)->Unit(benchmark::kMillisecond)->UseRealTime();

// The swept volume of the same carry (docs/swept-volume.md) at a voxel of range(0) micrometres, the
// replay included. Reported: the moves swept, occupied voxels, the surface's triangles and the grid's
// bytes (two bit grids of the path's box).
void BM_SweptVolumeTenSecondsLargeGearbox(benchmark::State& state) {
  Eigen::Vector3d unused;
  const auto scene = vaw::sim::Scene::build(gearbox(unused));
  const vaw::PartId gear = *scene->assembly().findPart("gear-a1");
  const vaw::sim::Session session = carriedGear(*scene, gear);
  vaw::sim::SweptVolumeOptions options;
  options.voxel = 1e-6 * static_cast<double>(state.range(0));
  vaw::SweptVolume sv;
  for (auto _ : state) {
    sv = vaw::sim::sweptVolume(scene, session, gear, options);
    benchmark::DoNotOptimize(sv.volume);
  }
  state.counters["moves"] = static_cast<double>(sv.moves);
  state.counters["voxels"] = static_cast<double>(sv.voxels);
  state.counters["triangles"] = static_cast<double>(sv.mesh.triangles.size());
  state.counters["grid_MB"] = 2.0 * 8.0 * static_cast<double>(sv.occupied.size()) / 1e6;
  state.counters["volume_cm3"] = sv.volume * 1e6;
}
BENCHMARK(BM_SweptVolumeTenSecondsLargeGearbox)->Arg(1000)->Arg(500)->Unit(benchmark::kMillisecond)->UseRealTime();

// The 1 mm swept volume of that carry written as a STEP solid through the STEP plugin (vaw-step-write: the
// voxel faces merged into plane polygons), the file's size reported. Argument 0: an advanced B-rep (the
// default), 1: a faceted one.
void BM_SweptVolumeAsStepLargeGearbox(benchmark::State& state) {
  Eigen::Vector3d unused;
  const auto scene = vaw::sim::Scene::build(gearbox(unused));
  const vaw::PartId gear = *scene->assembly().findPart("gear-a1");
  const vaw::SweptVolume sv = vaw::sim::sweptVolume(scene, carriedGear(*scene, gear), gear);
  const vaw::SolidExporter* step = importers().exporterFor("swept.step");
  if (step == nullptr) {
    state.SkipWithError("no STEP plugin in " VAW_BUILD_PLUGIN_DIR);
    return;
  }
  const std::filesystem::path out = std::filesystem::temp_directory_path() / "vaw-bench-swept.step";
  vaw::ExportOptions form;
  form.faceted = state.range(0) == 1;
  for (auto _ : state) step->write(sv.mesh, "gear-a1 swept", vaw::LengthUnit::Millimetre, out, form, {});
  state.counters["triangles"] = static_cast<double>(sv.mesh.triangles.size());
  state.counters["file_MB"] = static_cast<double>(std::filesystem::file_size(out)) / 1e6;
  std::filesystem::remove(out);
}
BENCHMARK(BM_SweptVolumeAsStepLargeGearbox)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// Seeking in a recording (the timeline's scrubbing): a 10-minute session on the large gearbox in which the
// right hand picks up a 0.42 kg gear every 20 s, lifts it 0.1 m, carries it round a 5 cm circle for 15 s
// and drops it into the housing. Each iteration seeks to a step in the middle of the recording that is 89
// steps past a snapshot, coming from a later step: the worst case (a restore and 89 steps replayed).
void BM_SeekMiddleOfTenMinutesLargeGearbox(benchmark::State& state) {
  Eigen::Vector3d unused;
  const auto scene = vaw::sim::Scene::build(gearbox(unused));
  const vaw::PartId gear = *scene->assembly().findPart("gear-a1");
  vaw::sim::Recorder rec(scene, vaw::sim::Settings{}, "large-gearbox.vaw.json");
  const double rate = rec.world().settings().rate;
  const auto steps = static_cast<std::uint64_t>(600.0 * rate);
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  vaw::sim::Input in;
  for (std::uint64_t k = 0; k < steps; ++k) {
    const double t = static_cast<double>(k) / rate;
    const double phase = std::fmod(t, 20.0);
    if (phase < 1.0 / rate) {  // close on the gear where it lies
      start = rec.world().part(gear).pose * scene->assembly().parts[gear].mass.centerOfMass;
      in.right = {at(start.x(), start.y(), start.z()), true, gear};
    } else if (phase < 15.0) {
      const double a = 2.0 * std::numbers::pi * 0.5 * phase;
      const double lift = std::min(phase, 1.0) * 0.1;
      in.right.pose = at(start.x() + 0.05 * (1.0 - std::cos(a)), start.y() + 0.05 * std::sin(a), start.z() + lift);
    } else {
      in.right.grab = false;
    }
    rec.record(in);
  }
  const std::uint64_t interval = rec.snapshotInterval();
  const std::uint64_t mid = steps / 2 / interval * interval;
  const std::uint64_t a = mid + interval - 1, b = mid - 1;  // each 89 steps past its snapshot
  bool toA = true;
  for (auto _ : state) {
    rec.seek(toA ? a : b);
    toA = !toA;
    benchmark::DoNotOptimize(rec.world().stateHash());
  }
  state.counters["recorded_s"] = rec.endTime();
  state.counters["snapshots"] = static_cast<double>(rec.snapshotCount());
  state.counters["transitions"] = static_cast<double>(rec.transitions().size());
}
BENCHMARK(BM_SeekMiddleOfTenMinutesLargeGearbox)->Unit(benchmark::kMillisecond)->Iterations(200);

// An hour at the workbench (docs/benchmarks.md, "Recording an hour"): one simulated hour of the large gearbox
// recorded as the workbench records it, with parts handled as a person would: every 16 s the right hand
// closes on the next bolt or washer, lifts it 0.1 m over half a second, carries it 0.2 m sideways over a
// second and lets go while still moving at 0.2 m/s; every 5 minutes the
// base tilts by 10 degrees for 30 s. Reported: the heap the recording holds per hour (measured by malloc's
// own count before and after, and the recorder's estimate), the snapshots and input runs it keeps, and the
// time of a seek to the start, into the middle and to the end, each the worst of its kind (the most steps
// to replay) and each from far away, timed over 20 seeks.
void BM_RecordAnHourLargeGearbox(benchmark::State& state) {
  Eigen::Vector3d unused;
  const auto scene = vaw::sim::Scene::build(gearbox(unused));
  const vaw::Assembly& a = scene->assembly();
  std::vector<vaw::PartId> handled;
  for (const char* kind : {"bolt-", "washer-"})
    for (int k = 1; k <= 24; ++k) {
      char name[32];
      std::snprintf(name, sizeof name, "%s%02d", kind, k);
      if (const auto id = a.findPart(name)) handled.push_back(*id);
    }
  for (auto _ : state) {
    const std::size_t heapBefore = mallinfo2().uordblks;
    auto rec = std::make_unique<vaw::sim::Recorder>(scene, vaw::sim::Settings{}, "large-gearbox.vaw.json");
    const double rate = rec->world().settings().rate;
    const auto steps = static_cast<std::uint64_t>(3600.0 * rate);
    const Eigen::Isometry3d base0 = rec->world().basePose();
    Eigen::Vector3d start = Eigen::Vector3d::Zero();
    vaw::sim::Input in;
    std::size_t next = 0;
    for (std::uint64_t k = 0; k < steps; ++k) {
      const double t = static_cast<double>(k) / rate;
      const double phase = std::fmod(t, 16.0);
      if (phase < 1.0 / rate) {  // close on the next part where it lies
        const vaw::PartId id = handled[next++ % handled.size()];
        start = rec->world().part(id).pose * a.parts[id].mass.centerOfMass;
        in.right = {at(start.x(), start.y(), start.z()), true, id};
      } else if (phase < 0.5) {
        in.right.pose = at(start.x(), start.y(), start.z() + 0.2 * phase);
      } else if (phase < 1.5) {
        in.right.pose = at(start.x() + 0.2 * (phase - 0.5), start.y(), start.z() + 0.1);
        if (phase > 1.5 - 2.0 / rate) in.right.grab = false;  // let go while moving
      }
      const double cycle = std::fmod(t, 300.0);
      Eigen::Isometry3d base = base0;
      if (cycle > 240.0 && cycle < 270.0)
        base.linear() = Eigen::AngleAxisd(10.0 * std::numbers::pi / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix() * base0.linear();
      in.base = base;
      rec->record(in);
    }
    const std::size_t heapAfter = mallinfo2().uordblks;
    const double hours = rec->endTime() / 3600.0;
    state.counters["recording_MB_per_h"] = static_cast<double>(rec->memoryBytes()) / 1e6 / hours;
    state.counters["heap_MB_per_h"] = static_cast<double>(heapAfter - heapBefore) / 1e6 / hours;
    state.counters["snapshots"] = static_cast<double>(rec->snapshotCount());
    state.counters["input_runs"] = static_cast<double>(rec->session().inputs.runs());
    state.counters["transitions"] = static_cast<double>(rec->transitions().size());
    // The worst seek of each kind: the step before a snapshot, so the most steps are replayed.
    const std::uint64_t interval = rec->snapshotInterval();
    const std::uint64_t sparse = interval * vaw::sim::Recorder::kSparseEvery;
    const std::uint64_t targets[3] = {interval - 1, steps / 2 / sparse * sparse - 1, steps - 1};
    const char* names[3] = {"seek_start_ms", "seek_middle_ms", "seek_end_ms"};
    for (int k = 0; k < 3; ++k) {
      double worst = 0.0;
      for (int r = 0; r < 20; ++r) {
        rec->seek(targets[k] > steps / 2 ? 0 : steps);  // from far away
        const auto t0 = std::chrono::steady_clock::now();
        rec->seek(targets[k]);
        const std::chrono::duration<double, std::milli> took = std::chrono::steady_clock::now() - t0;
        worst = std::max(worst, took.count());
        benchmark::DoNotOptimize(rec->world().stateHash());
      }
      state.counters[names[k]] = worst;
    }
  }
}
BENCHMARK(BM_RecordAnHourLargeGearbox)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
