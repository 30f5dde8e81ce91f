// What a video costs (docs/benchmarks.md, "Videos"): a minute of the large gearbox, the 0.42 kg gear lifted
// 0.1 m and carried round a 5 cm circle the whole time, replayed, drawn, captioned and encoded at
// range(0) x range(1) pixels and 30 frames a second. "x_real_time": the time it took over the video's
// length (over 1: slower than real time).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "bundled.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/sim/session.hpp"
#include "vaw/video/video.hpp"

namespace {

vaw::sim::Session carriedGear(const vaw::sim::Scene& scene, vaw::PartId gear, double seconds) {
  vaw::sim::Session session;
  session.scene = "large-gearbox.vaw.json";
  const double rate = session.settings.rate;
  const Eigen::Vector3d start = scene.assembly().parts[gear].pose * scene.assembly().parts[gear].mass.centerOfMass;
  const auto at = [](double x, double y, double z) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation() = Eigen::Vector3d(x, y, z);
    return p;
  };
  vaw::sim::Input in;
  in.right = {at(start.x(), start.y(), start.z()), true, gear};
  session.inputs.push_back(in);
  for (int k = 1; k <= static_cast<int>(seconds * rate); ++k) {
    const double t = k / rate;
    const double a = 2.0 * std::numbers::pi * 0.1 * t;
    in.right.pose = at(start.x() + 0.05 * (1.0 - std::cos(a)), start.y() + 0.05 * std::sin(a), start.z() + std::min(t, 1.0) * 0.1);
    session.inputs.push_back(in);
  }
  return session;
}

void BM_VideoOfAMinuteLargeGearbox(benchmark::State& state) {
  const auto scene = vaw::sim::Scene::build(vaw::test::loadBundled("large-gearbox.vaw.json"));
  const vaw::PartId gear = *scene->assembly().findPart("gear-a1");
  const vaw::sim::Session session = carriedGear(*scene, gear, 60.0);
  vaw::video::VideoOptions o;
  o.width = static_cast<int>(state.range(0));
  o.height = static_cast<int>(state.range(1));
  o.fps = 30;
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "vaw-bench-video.mp4";
  vaw::video::VideoResult r;
  double took = 0.0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    r = vaw::video::writeSessionVideo(scene, session, file, o);
    took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  state.counters["frames"] = static_cast<double>(r.frames);
  state.counters["file_MB"] = static_cast<double>(std::filesystem::file_size(file)) / 1e6;
  state.counters["x_real_time"] = took / r.seconds;
  std::filesystem::remove(file);
}
BENCHMARK(BM_VideoOfAMinuteLargeGearbox)->Args({1280, 720})->Args({640, 360})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
