// How long a STEP assembly takes to be ready to assemble (docs/benchmarks.md, "STEP import"): the reader
// process (parse, transfer, tessellation, B-rep mass properties), the whole load (that plus welding,
// checks, constraint recognition and the layout), that plus the collision geometry the world runs on,
// recognition alone, and the assembly sequence found from the geometry; for the bundled sample and for
// 100-part assemblies the fixtures write (shared products, and every part a product of its own).
#include <BRepBndLib.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <Bnd_Box.hxx>
#include <STEPCAFControl_Reader.hxx>
#include <TDF_LabelSequence.hxx>
#include <TDocStd_Document.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "step_first_pass.hpp"
#include "step_fixtures.hpp"
#include "vaw/cad_assembly.hpp"
#include "vaw/collision/interference.hpp"
#include "vaw/constraint_recognition.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/report/report.hpp"
#include "vaw/sim/world.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/scene.hpp"

namespace {

namespace fs = std::filesystem;

const vaw::ImporterRegistry& registry() {
  static vaw::ImporterRegistry r;
  static const bool loaded = [] {
    // Every open is timed from the file, nothing kept from an earlier one, unless VAW_CACHE_DIR says else.
    ::setenv("VAW_CACHE_DIR", "off", 0);
    (void)r.loadPlugins(VAW_BUILD_PLUGIN_DIR);
    return true;
  }();
  (void)loaded;
  return r;
}

fs::path sample() { return fs::path(VAW_BUILD_RESOURCE_DIR) / "step" / "bolted-bracket.stp"; }

fs::path manyParts(bool distinct) {
  const fs::path f = fs::temp_directory_path() / (distinct ? "vaw-bench-100-products.stp" : "vaw-bench-100-parts.stp");
  if (!fs::exists(f)) vaw::steptest::writeManyParts(f, 100, distinct);
  return f;
}

// The bolted rod as CAD systems write it (docs/step.md, "Files as CAD systems write them"): 18 parts with
// headed bolts; `proE` AP203 in inches, Y up, cylinders in halves, else AP214 with every cylinder in
// quarters as B-spline faces.
fs::path boltedRod(bool proE) {
  const fs::path f = fs::temp_directory_path() / (proE ? "vaw-bench-bolted-rod-proe.stp" : "vaw-bench-bolted-rod-split4.stp");
  if (!fs::exists(f))
    vaw::steptest::writeBoltedRod(f, proE ? vaw::steptest::ExportStyle{2, false, false, true, true, "AP203"}
                                          : vaw::steptest::ExportStyle{4, true, true, false, false, "AP214"});
  return f;
}

// The tiled product (writeTiledProduct): 5 x 1 tiles (96 parts) or 9 x 6 (1,027 parts, 540 holes in its base).
fs::path tiled(bool thousand) {
  const fs::path f = fs::temp_directory_path() / (thousand ? "vaw-bench-tiled-9x6.stp" : "vaw-bench-tiled-5x1.stp");
  if (!fs::exists(f)) vaw::steptest::writeTiledProduct(f, thousand ? 9 : 5, thousand ? 6 : 1);
  return f;
}

// The rig (writeRigProduct), a product unlike the tiled one: `tiles` tiles of 35 parts, one row of up to 7,
// 10 as 5 x 2, 28 as 7 x 4.
fs::path rig(int tiles) {
  const int x = tiles == 10 ? 5 : std::min(tiles, 7), y = tiles / x;
  if (x * y != tiles) throw std::invalid_argument("bench: no rig layout for " + std::to_string(tiles) + " tiles");
  const fs::path f = fs::temp_directory_path() / ("vaw-bench-rig-" + std::to_string(x) + "x" + std::to_string(y) + ".stp");
  if (!fs::exists(f)) vaw::steptest::writeRigProduct(f, x, y);
  return f;
}

// 0: the bundled sample; 1: 100 parts, instances of 5 products; 2: 100 parts, each its own product;
// 3: the bolted rod, split B-spline cylinders; 4: the bolted rod as Pro/ENGINEER writes it; 5: the tiled
// product, 96 parts; 6: the tiled product, 1,027 parts; 7: the rig, 7 x 4 tiles, 981 parts.
fs::path fileFor(int which) {
  if (which == 7) return rig(28);
  return which == 0 ? sample() : which <= 2 ? manyParts(which == 2) : which <= 4 ? boltedRod(which == 4) : tiled(which == 6);
}

// The real exports kept beside the project (VAW_CAD_EXPORTS_DIR): 0 the SolidWorks rotary table, 1 the
// Fusion 360 robot arm. Empty when they are not there.
fs::path cadExport(int which) {
  const fs::path f = fs::path(VAW_CAD_EXPORTS_DIR) / (which == 0 ? "Drehtisch.STEP" : "arm.step");
  return fs::exists(f) ? f : fs::path();
}

// What Open CASCADE alone does with the file, the yardstick for vaw's open: the read, the transfer with names
// and colours, and every product's solids meshed at the same relative deflection (a thousandth of its box's
// diagonal) and angle vaw uses, in this process.
void BM_CadExportOpenCascade(benchmark::State& state) {
  const fs::path file = cadExport(static_cast<int>(state.range(0)));
  if (file.empty()) {
    state.SkipWithError("no real CAD exports (VAW_CAD_EXPORTS_DIR)");
    return;
  }
  for (auto _ : state) {
    STEPCAFControl_Reader reader;
    reader.SetNameMode(true);
    reader.SetColorMode(true);
    reader.ReadFile(file.string().c_str());
    Handle(TDocStd_Document) doc;
    XCAFApp_Application::GetApplication()->NewDocument("MDTV-XCAF", doc);
    reader.Transfer(doc);
    const Handle(XCAFDoc_ShapeTool) shapes = XCAFDoc_DocumentTool::ShapeTool(doc->Main());
    TDF_LabelSequence labels;
    shapes->GetShapes(labels);
    for (Standard_Integer i = 1; i <= labels.Length(); ++i) {
      if (XCAFDoc_ShapeTool::IsAssembly(labels.Value(i))) continue;
      const TopoDS_Shape shape = XCAFDoc_ShapeTool::GetShape(labels.Value(i));
      Bnd_Box box;
      BRepBndLib::Add(shape, box);
      if (box.IsVoid()) continue;
      BRepMesh_IncrementalMesh mesh(shape, 1e-3 * std::sqrt(box.SquareExtent()), false, 0.35, true);
      benchmark::DoNotOptimize(mesh.IsDone());
    }
  }
  state.SetLabel(file.filename().string());
}

// vaw's open of the same file, from the file to ready to assemble: the reader process (with its healing),
// units, recognition, the base, who goes first and the layout; nothing kept from an earlier read.
void BM_CadExportReady(benchmark::State& state) {
  const fs::path file = cadExport(static_cast<int>(state.range(0)));
  if (file.empty()) {
    state.SkipWithError("no real CAD exports (VAW_CAD_EXPORTS_DIR)");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(vaw::loadAny(file, registry()));
  state.SetLabel(file.filename().string());
}

// Its order (docs/evaluation.md): ways home, sub-assemblies, clashes passed through.
void BM_CadExportOrder(benchmark::State& state) {
  const fs::path file = cadExport(static_cast<int>(state.range(0)));
  if (file.empty()) {
    state.SkipWithError("no real CAD exports (VAW_CAD_EXPORTS_DIR)");
    return;
  }
  const vaw::Assembly a = vaw::loadAny(file, registry());
  vaw::eval::SequencePlan plan;
  for (auto _ : state) benchmark::DoNotOptimize(plan = vaw::eval::planSequence(a));
  state.counters["parts"] = static_cast<double>(a.parts.size());
  state.counters["ordered"] = static_cast<double>(plan.order.size());
  state.SetLabel(file.filename().string());
}

// What overlaps at rest (docs/evaluation.md, "Interferences"), on a fixture (fileFor's numbering) or a real
// export (10 + cadExport's).
void BM_Interferences(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const fs::path file = which >= 10 ? cadExport(which - 10) : fileFor(which);
  if (file.empty()) {
    state.SkipWithError("no real CAD exports (VAW_CAD_EXPORTS_DIR)");
    return;
  }
  const vaw::Assembly a = vaw::loadAny(file, registry());
  const auto poses = vaw::collision::assembledPoses(a);
  std::size_t pairs = 0;
  for (auto _ : state) pairs = vaw::collision::interferences(a, poses).size();
  state.counters["parts"] = static_cast<double>(a.parts.size());
  state.counters["pairs"] = static_cast<double>(pairs);
  state.SetLabel(file.filename().string());
}

void BM_StepReader(benchmark::State& state) {
  const fs::path file = fileFor(static_cast<int>(state.range(0)));
  const vaw::MeshImporter* importer = registry().find(file);
  if (importer == nullptr) {
    state.SkipWithError("no STEP plugin");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(importer->read(file, {}, {}));
  state.SetLabel(file.filename().string());
}

void BM_StepReadyToAssemble(benchmark::State& state) {
  const fs::path file = fileFor(static_cast<int>(state.range(0)));
  std::size_t parts = 0, constraints = 0, triangles = 0;
  for (auto _ : state) {
    const vaw::Assembly a = vaw::loadAny(file, registry());
    parts = a.parts.size();
    constraints = a.constraints.size();
    triangles = a.totalTriangles();
  }
  state.counters["parts"] = static_cast<double>(parts);
  state.counters["constraints"] = static_cast<double>(constraints);
  state.counters["triangles"] = static_cast<double>(triangles);
  state.SetLabel(file.filename().string());
}

// What the window waits for: the assembly and its collision geometry (the scene the world runs on).
void BM_StepSceneBuilt(benchmark::State& state) {
  const fs::path file = fileFor(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(vaw::sim::Scene::build(vaw::loadAny(file, registry())));
  state.SetLabel(file.filename().string());
}

void BM_Recognition(benchmark::State& state) {
  const vaw::Assembly a = vaw::loadAny(fileFor(static_cast<int>(state.range(0))), registry());
  std::vector<vaw::RecognitionPart> parts;
  for (const auto& p : a.parts) parts.push_back({p.cad, p.finalPose.value_or(p.pose)});
  for (auto _ : state) benchmark::DoNotOptimize(vaw::recognizeConstraints(parts));
  state.counters["parts"] = static_cast<double>(parts.size());
}

// Feasibility and order (docs/evaluation.md): the collision world at the final poses, every part's ways
// home swept against what they reach, and assembly by disassembly.
void BM_PlanSequence(benchmark::State& state) {
  const vaw::Assembly a = vaw::loadAny(fileFor(static_cast<int>(state.range(0))), registry());
  vaw::eval::SequencePlan plan;
  for (auto _ : state) benchmark::DoNotOptimize(plan = vaw::eval::planSequence(a));
  state.counters["parts"] = static_cast<double>(a.parts.size());
  state.counters["sweeps"] = plan.pairChecks;
  state.counters["reused"] = plan.reused;
  state.counters["checks"] = plan.evaluations;
  state.counters["ordered"] = static_cast<double>(plan.order.size());
}

// How each stage of an open and the order grow with a product's size (docs/benchmarks.md, "A product's
// size"): the rig of 1, 2, 5 and 10 tiles (36 to 351 parts) and 7 x 4 (981), nothing kept from an earlier
// read; a counter per stage in seconds (vaw-sim inspect --timings names them), the last run's.
void BM_RigGrowth(benchmark::State& state) {
  const fs::path file = rig(static_cast<int>(state.range(0)));
  std::vector<std::pair<std::string, double>> timings;
  std::size_t parts = 0;
  double order = 0.0;
  for (auto _ : state) {
    timings.clear();
    vaw::LoadOptions options;
    options.timings = &timings;
    const vaw::Assembly a = vaw::loadAny(file, registry(), options);
    parts = a.parts.size();
    const auto started = std::chrono::steady_clock::now();
    const vaw::eval::SequencePlan plan = vaw::eval::planSequence(a);
    order = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    if (!plan.complete()) state.SkipWithError("the rig has parts no order places");
  }
  for (const auto& [stage, seconds] : timings) state.counters[stage] = seconds;
  state.counters["order"] = order;
  state.counters["parts"] = static_cast<double>(parts);
  state.SetLabel(file.filename().string());
}

// The report of an ordered assembly (docs/evaluation.md, "The report"): the summary, the pictures, the
// tables and the files, written into a temporary folder.
void BM_Report(benchmark::State& state) {
  const vaw::Assembly a = vaw::loadAny(fileFor(static_cast<int>(state.range(0))), registry());
  const vaw::eval::SequencePlan plan = vaw::eval::planSequence(a);
  const fs::path dir = fs::temp_directory_path() / ("vaw-bench-report-" + std::to_string(state.range(0)));
  vaw::report::ReportFiles files;
  for (auto _ : state) files = vaw::report::writeReport(a, plan, {}, dir);
  state.counters["html_bytes"] = static_cast<double>(fs::file_size(files.html));
  state.counters["parts"] = static_cast<double>(a.parts.size());
  fs::remove_all(dir);
}

// The world's step on a loaded product (docs/benchmarks.md, "A product's size"): every part at rest where
// the layout put it (arg 1 = 0), or the first nut held and carried round a 5 cm circle (arg 1 = 1).
void BM_WorldStep(benchmark::State& state) {
  const vaw::Assembly a = vaw::loadAny(fileFor(static_cast<int>(state.range(0))), registry());
  vaw::sim::World w(a, vaw::sim::settingsFor(a));
  vaw::sim::Input in;
  const bool carry = state.range(1) == 1;
  const auto nut = a.findPart("nut-1");
  if (carry && !nut) throw std::runtime_error("no nut-1 to carry");
  const Eigen::Isometry3d start = carry ? w.part(*nut).pose : Eigen::Isometry3d::Identity();
  const Eigen::Vector3d from = start.translation();
  const Eigen::Matrix3d turn = start.linear();
  const auto hand = [&](double phase) {
    Eigen::Isometry3d h = Eigen::Isometry3d::Identity();
    h.linear() = turn;
    h.translation() = from + Eigen::Vector3d(0.05 * (std::cos(phase) - 1.0), 0.05 * std::sin(phase), 0.1 * std::min(1.0, phase));
    return h;
  };
  if (carry) {
    in.left = {hand(0.0), true, *nut, std::nullopt};
    w.step(in);
    if (w.part(*nut).state != vaw::interact::PartState::InHand) throw std::runtime_error("the nut was not grabbed");
  }
  long k = 0;
  for (auto _ : state) {
    if (carry) in.left.pose = hand(0.01 * static_cast<double>(++k));
    w.step(in);
  }
  state.counters["parts"] = static_cast<double>(a.parts.size());
  state.counters["active"] = static_cast<double>(w.activeParts());
}

// Who goes first from the geometry (docs/step.md, "Who goes first"): part of every load, measured alone.
void BM_GeometricPrecedence(benchmark::State& state) {
  const vaw::Assembly a = vaw::loadAny(fileFor(static_cast<int>(state.range(0))), registry());
  std::vector<Eigen::Isometry3d> home;
  for (const auto& p : a.parts) home.push_back(p.finalPose.value_or(p.pose));
  int sweeps = 0;
  std::size_t decided = 0;
  for (auto _ : state) decided = vaw::eval::geometricPrecedence(a, home, {}, &sweeps).size();
  state.counters["sweeps"] = sweeps;
  state.counters["decided"] = static_cast<double>(decided);
}

}  // namespace

std::string readText(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::ostringstream all;
  all << in.rdbuf();
  return all.str();
}

// The reader's first pass over a file's text (plugins/step/step_first_pass.hpp): 0 the sample, 1 the
// 100-product assembly, 2 the sample with its first NEXT_ASSEMBLY_USAGE_OCCURRENCE 20,000 times over
// (refused).
void BM_StepFirstPass(benchmark::State& state) {
  std::string text = readText(state.range(0) == 1 ? manyParts(true) : sample());
  if (state.range(0) == 2) text = vaw::steptest::withMoreUses(text, 20000);
  for (auto _ : state) {
    try {
      benchmark::DoNotOptimize(vaw::step::firstPass(text));
    } catch (const vaw::step::FirstPassRefusal&) {
    }
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(text.size()));
}

BENCHMARK(BM_StepFirstPass)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CadExportOpenCascade)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CadExportReady)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CadExportOrder)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Interferences)->Arg(6)->Arg(7)->Arg(10)->Arg(11)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_StepReader)->Arg(0)->Arg(1)->Arg(2)->Arg(5)->Arg(6)->Arg(7)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_StepReadyToAssemble)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Arg(4)->Arg(5)->Arg(6)->Arg(7)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_StepSceneBuilt)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Recognition)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlanSequence)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Arg(4)->Arg(5)->Arg(6)->Arg(7)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Report)->Arg(0)->Arg(5)->Arg(6)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_WorldStep)->Args({0, 0})->Args({0, 1})->Args({6, 0})->Args({6, 1})->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_GeometricPrecedence)->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Arg(4)->Arg(5)->Arg(6)->Arg(7)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RigGrowth)->Arg(1)->Arg(2)->Arg(5)->Arg(10)->Arg(28)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
