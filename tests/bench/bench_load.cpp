// Loading the large assembly: mesh import, mass properties, and the whole load.
//   build/bin/vaw_bench_load [--benchmark_repetitions=5]
#include <benchmark/benchmark.h>

#include <map>

#include "vaw/mass_properties.hpp"
#include "vaw/primitives.hpp"
#include "vaw/scene_loader.hpp"

namespace {

const std::filesystem::path kScene = std::filesystem::path(VAW_BUILD_RESOURCE_DIR) / "scenes" / "large-gearbox.vaw.json";

const vaw::ImporterRegistry& importers() {
  static vaw::ImporterRegistry r;
  static bool loaded = [] {
    (void)r.loadPlugins(VAW_BUILD_PLUGIN_DIR);
    return true;
  }();
  (void)loaded;
  return r;
}

const vaw::Assembly& large() {
  static const vaw::Assembly a = vaw::loadScene(kScene, importers());
  return a;
}

// Import alone: every distinct mesh file of the large assembly through the assimp plugin.
void BM_ImportLargeMeshes(benchmark::State& state) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(kScene.parent_path().parent_path() / "meshes"))
    if (importers().find(e.path())) files.push_back(e.path());
  std::size_t triangles = 0;
  for (auto _ : state) {
    triangles = 0;
    for (const auto& f : files) {
      const vaw::ImportedMesh m = importers().find(f)->read(f, {});
      triangles += m.root.subtreeTriangles();
    }
  }
  state.counters["files"] = static_cast<double>(files.size());
  state.counters["triangles"] = static_cast<double>(triangles);
}
BENCHMARK(BM_ImportLargeMeshes)->Unit(benchmark::kMillisecond);

// Mass properties of every part of the large assembly from its (already loaded) mesh.
void BM_MassPropertiesLarge(benchmark::State& state) {
  const vaw::Assembly& a = large();
  for (auto _ : state)
    for (const auto& p : a.parts) benchmark::DoNotOptimize(vaw::massPropertiesFromMesh(*p.mesh, 7850.0));
  std::size_t triangles = 0;
  for (const auto& p : a.parts) triangles += p.mesh->triangleCount();
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["tri/s"] = benchmark::Counter(static_cast<double>(triangles), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_MassPropertiesLarge)->Unit(benchmark::kMillisecond);

// Mesh validation (weld + closedness + orientation) of the large assembly's meshes.
void BM_MeshCheckLarge(benchmark::State& state) {
  const vaw::Assembly& a = large();
  for (auto _ : state)
    for (const auto& p : a.parts) benchmark::DoNotOptimize(vaw::checkMesh(*p.mesh));
}
BENCHMARK(BM_MeshCheckLarge)->Unit(benchmark::kMillisecond);

// The whole load as the workbench does it: parse, import, weld, check, mass properties, categories.
void BM_LoadLargeTotal(benchmark::State& state) {
  std::size_t parts = 0, triangles = 0;
  for (auto _ : state) {
    const vaw::Assembly a = vaw::loadScene(kScene, importers());
    parts = a.parts.size();
    triangles = a.totalTriangles();
  }
  state.counters["parts"] = static_cast<double>(parts);
  state.counters["triangles"] = static_cast<double>(triangles);
}
BENCHMARK(BM_LoadLargeTotal)->Unit(benchmark::kMillisecond);

// Mass properties scale linearly in triangles.
void BM_MassPropertiesCylinder(benchmark::State& state) {
  const vaw::TriMesh m = vaw::primitives::cylinder(0.05, 0.1, static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(vaw::massPropertiesFromMesh(m, 7850.0));
  state.counters["triangles"] = static_cast<double>(m.triangleCount());
}
BENCHMARK(BM_MassPropertiesCylinder)->RangeMultiplier(10)->Range(25, 25000);

}  // namespace

BENCHMARK_MAIN();
