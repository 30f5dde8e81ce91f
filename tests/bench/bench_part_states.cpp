// The world step through the public API, per part state, on the bundled scenes: what one step of
// World::step costs while the part slides, swings, rests, flies or is held, at 90 Hz and 1000 Hz.
// One world per benchmark; each iteration is one episode: the hand brings the part into the state (not
// timed), then the steps in that state are timed with the thread's CPU clock, and the reported time is
// the mean per step over the episode (docs/benchmarks.md, "World: the step per part state"). The world
// is kept from one episode to the next, as in a session: the first episode's first touches of memory
// (page faults, lazy binding) are not what a step costs.
//   build/bin/vaw_bench_part_states --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <ctime>
#include <filesystem>
#include <functional>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>

#include "vaw/scene_loader.hpp"
#include "vaw/sim/world.hpp"
#include "vaw/units.hpp"

namespace {

using vaw::interact::PartState;
using vaw::sim::Input;
using vaw::sim::World;

using vaw::kDeg;

const vaw::Assembly& bundled(const std::string& name) {
  static vaw::ImporterRegistry importers;
  static const bool loaded = [] {
    (void)importers.loadPlugins(VAW_BUILD_PLUGIN_DIR);
    return true;
  }();
  (void)loaded;
  static std::map<std::string, vaw::Assembly> cache;
  auto it = cache.find(name);
  if (it == cache.end())
    it = cache.emplace(name, vaw::loadScene(std::filesystem::path(VAW_BUILD_RESOURCE_DIR) / "scenes" / name, importers)).first;
  return it->second;
}

Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = Eigen::Vector3d(x, y, z);
  return p;
}

// The base turned by `deg` about world x through a point 0.3 m up (its block stays above the table).
Eigen::Isometry3d tilted(const vaw::Assembly& a, double deg) {
  Eigen::Isometry3d r = Eigen::Isometry3d::Identity();
  r.linear() = Eigen::AngleAxisd(deg * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Vector3d pivot(0, 0, 0.3);
  r.translation() = pivot - r.linear() * pivot;
  return r * a.parts[*a.base].pose;
}

double threadSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Grabs `part` where it is, carries it to `target`, holds it still there for 0.1 s (longer than the
// release velocity's window, so that it is let go at rest) and lets go.
void placeByHand(World& w, vaw::PartId part, const Eigen::Isometry3d& target, Input& in) {
  in.left = vaw::sim::HandInput{w.part(part).pose, true, std::nullopt, std::nullopt};
  w.step(in);
  in.left = vaw::sim::HandInput{target, true, std::nullopt, std::nullopt};
  for (int i = 0; i < static_cast<int>(0.1 * w.settings().rate); ++i) w.step(in);
  in.left.grab = false;
  w.step(in);
}

struct Episode {
  std::function<void(World&, Input&)> setup;  // brings the part into the state, not timed
  PartState state;                            // timed while the part is in it
  int maxSteps;                               // at most this many steps
};

void runEpisodes(benchmark::State& st, const std::string& scene, const std::string& partName, const Episode& e) {
  const vaw::Assembly& a = bundled(scene);
  const vaw::PartId part = *a.findPart(partName);
  vaw::sim::Settings settings;
  settings.rate = static_cast<double>(st.range(0));
  double steps = 0.0;
  World w(a, settings);
  Input in;
  // One episode first, not timed: the world's memory is then touched as in the timed ones.
  e.setup(w, in);
  for (int n = 0; n < e.maxSteps && w.part(part).state == e.state; ++n) w.step(in);
  for (auto _ : st) {
    e.setup(w, in);
    if (w.part(part).state != e.state) throw std::runtime_error(scene + ": the part is not in the state to time");
    int n = 0;
    const double t0 = threadSeconds();
    while (n < e.maxSteps && w.part(part).state == e.state) {
      w.step(in);
      ++n;
    }
    const double t1 = threadSeconds();
    st.SetIterationTime((t1 - t0) / n);
    steps = n;
  }
  st.counters["steps"] = steps;
}

// The sleeve released on its shaft tilted 30 degrees, its bottom 80 mm above the block, slides down
// until the block stops it.
void BM_SleeveSlidingDownTheTiltedShaft(benchmark::State& st) {
  const vaw::Assembly& a = bundled("sleeve-on-shaft.vaw.json");
  const Eigen::Isometry3d B = tilted(a, 30.0);
  const vaw::PartId sleeve = *a.findPart("sleeve");
  runEpisodes(st, "sleeve-on-shaft.vaw.json", "sleeve",
              {[B, sleeve](World& w, Input& in) {
                 in.base = B;
                 placeByHand(w, sleeve, B * at(0, 0, 0.12), in);
                 while (w.part(sleeve).state == PartState::OnBaseStatic) w.step(in);
               },
               PartState::OnBaseSlide, 1000000});
}

// The block at its final place on the plate tilted 30 degrees (past the 16.7 degree friction angle)
// slides downhill until it goes over the plate's edge.
void BM_BlockSlidingDownTheTiltedPlate(benchmark::State& st) {
  const vaw::Assembly& a = bundled("block-on-plate.vaw.json");
  const Eigen::Isometry3d B = tilted(a, 30.0);
  const vaw::PartId block = *a.findPart("block");
  const Eigen::Isometry3d inBase = a.parts[*a.base].pose.inverse() * *a.parts[block].finalPose * at(0, 0, 0);
  runEpisodes(st, "block-on-plate.vaw.json", "block",
              {[B, block, inBase](World& w, Input& in) {
                 in.base = B;
                 // 5 mm off its final pose, so that it is put on the plate, not placed.
                 placeByHand(w, block, B * at(0.005, 0, 0) * inBase, in);
                 while (w.part(block).state == PartState::OnBaseStatic) w.step(in);
               },
               PartState::OnBaseSlide, 1000000});
}

// The gear put on its horizontal shaft 30 mm from its final place, its centre of mass turned 90 degrees
// from the bottom, swings for 2 s.
void BM_GearSwingingOnItsShaft(benchmark::State& st) {
  const vaw::Assembly& a = bundled("gear-on-shaft.vaw.json");
  const vaw::PartId gear = *a.findPart("gear");
  Eigen::Isometry3d target = *a.parts[gear].finalPose;
  target.pretranslate(Eigen::Vector3d(0.03, 0, 0));
  Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
  turn.linear() = Eigen::AngleAxisd(90.0 * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Vector3d onAxis(target.translation());
  turn.translation() = onAxis - turn.linear() * onAxis;
  target = turn * target;
  runEpisodes(st, "gear-on-shaft.vaw.json", "gear",
              {[target, gear](World& w, Input& in) {
                 placeByHand(w, gear, target, in);
                 while (w.part(gear).state == PartState::OnBaseStatic) w.step(in);
               },
               PartState::OnBaseSlide, static_cast<int>(2.0 * static_cast<double>(st.range(0)))});
}

// The sleeve resting on the block after a 5 mm slide: 1 s of the static check.
void BM_SleeveRestingOnTheBase(benchmark::State& st) {
  const vaw::Assembly& a = bundled("sleeve-on-shaft.vaw.json");
  const vaw::PartId sleeve = *a.findPart("sleeve");
  runEpisodes(st, "sleeve-on-shaft.vaw.json", "sleeve",
              {[sleeve](World& w, Input& in) {
                 placeByHand(w, sleeve, at(0, 0, 0.045), in);
                 while (w.part(sleeve).state == PartState::OnBaseSlide) w.step(in);
               },
               PartState::OnBaseStatic, static_cast<int>(st.range(0))});
}

// The block dropped from 0.5 m over the table, in flight until it lands.
void BM_BlockInFlight(benchmark::State& st) {
  const vaw::Assembly& a = bundled("block-on-plate.vaw.json");
  const vaw::PartId block = *a.findPart("block");
  runEpisodes(st, "block-on-plate.vaw.json", "block",
              {[block](World& w, Input& in) { placeByHand(w, block, at(0.4, 0.2, 0.5), in); }, PartState::InSpace, 10000});
}

// The block held in the hand: 1 s.
void BM_BlockInHand(benchmark::State& st) {
  const vaw::Assembly& a = bundled("block-on-plate.vaw.json");
  const vaw::PartId block = *a.findPart("block");
  runEpisodes(st, "block-on-plate.vaw.json", "block",
              {[block](World& w, Input& in) {
                 in.left = vaw::sim::HandInput{w.part(block).pose, false, std::nullopt, std::nullopt};
                 w.step(in);  // let go, after the last episode
                 in.left = vaw::sim::HandInput{w.part(block).pose, true, std::nullopt, std::nullopt};
                 w.step(in);
               },
               PartState::InHand, static_cast<int>(st.range(0))});
}

#define VAW_STATE_BENCHMARK(fn) BENCHMARK(fn)->Arg(90)->Arg(1000)->Iterations(10)->UseManualTime()->Unit(benchmark::kMicrosecond)
VAW_STATE_BENCHMARK(BM_SleeveSlidingDownTheTiltedShaft);
VAW_STATE_BENCHMARK(BM_BlockSlidingDownTheTiltedPlate);
VAW_STATE_BENCHMARK(BM_GearSwingingOnItsShaft);
VAW_STATE_BENCHMARK(BM_SleeveRestingOnTheBase);
VAW_STATE_BENCHMARK(BM_BlockInFlight);
VAW_STATE_BENCHMARK(BM_BlockInHand);

}  // namespace

BENCHMARK_MAIN();
