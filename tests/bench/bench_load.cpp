// Loading the large assembly: mesh import, mass properties, and the whole load.
//   build/bin/vaw_bench_load [--benchmark_repetitions=5]
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <fstream>
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
      const vaw::ImportedMesh m = importers().find(f)->read(f, {}, {});
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

// A valid 5-million-triangle mesh opened on its own, as `vaw-sim inspect FILE.stl` does: a closed sphere
// (2500 segments, 1001 rings) written as binary STL, i.e. 15 million corners to weld.
void BM_LoadHugeMesh(benchmark::State& state) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "vaw-bench-5m-triangles.stl";
  {
    const vaw::TriMesh m = vaw::primitives::sphere(50.0, 2500, 1001);
    std::ofstream out(file, std::ios::binary);
    const std::array<char, 80> header{};
    out.write(header.data(), header.size());
    const auto count = static_cast<std::uint32_t>(m.triangles.size());
    out.write(reinterpret_cast<const char*>(&count), 4);
    for (const auto& t : m.triangles) {
      std::array<float, 12> record{};  // normal (left zero), three corners
      for (int k = 0; k < 3; ++k)
        for (int a = 0; a < 3; ++a) record[static_cast<std::size_t>(3 + 3 * k + a)] = static_cast<float>(m.vertices[static_cast<std::size_t>(t[k])][a]);
      out.write(reinterpret_cast<const char*>(record.data()), sizeof record);
      out.write("\0\0", 2);
    }
  }
  for (auto _ : state) benchmark::DoNotOptimize(vaw::loadMeshFile(file, importers()));
  std::filesystem::remove(file);
  state.SetLabel("5,000,000 triangles");
}
BENCHMARK(BM_LoadHugeMesh)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
