// The workbench's cost per simulation step on the 97-part gearbox, on the GUI thread, with a 0.42 kg gear
// held in the right hand and moving (so every step changes a pose, the drop line and the inspector):
//   BM_FrameDescription  the core's view::makeFrame (poses, colours, hands, the drop line's ray cast)
//   BM_ViewportFrame     Viewport::applyFrame (Qt3D property updates of what moved; rendering is Qt3D's
//                        own thread and is not counted)
//   BM_Inspector         sim::report, the part panel's in-place update and the table's repaint (the window
//                        does this at most
//                        every 100 ms while running: the per-step share is a ninth of it at 90 Hz)
//   BM_Timeline          the timeline's playhead update and a full repaint (also at most every 100 ms)
//   BM_Tree...           the scene tree: expand every row, click a part's row, Page Down (see below)
//   BM_WholeStep         SimulationController::stepOnce: the world's step, the frame, the viewport and, since
//                        a paused window refreshes its panels at once, the inspector and timeline too: an
//                        upper bound of the GUI-side cost of one step
// Needs a display (Qt3D): xvfb-run -a -s '-screen 0 1280x800x24' build/bin/vaw_bench_gui [FILE PART]
// FILE PART: another scene or CAD file (VAW_PLUGIN_PATH for STEP) and the part to hold, instead of the
// gearbox's gear (the thousand-part product: vaw_write_step_fixture tiled-9x6 t.stp, then t.stp nut-1).
#include <benchmark/benchmark.h>

#include <QApplication>
#include <QElapsedTimer>
#include <QScrollBar>
#include <QTableView>
#include <QTest>
#include <QTreeView>
#include <QSignalSpy>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>

#include "vaw/sim/report.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/part_properties_model.hpp"
#include "vaw/ui/scene_tree_model.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/timeline.hpp"
#include "vaw/ui/viewport.hpp"

namespace {

vaw::ui::MainWindow* g_window = nullptr;
vaw::ui::AssemblyController* g_controller = nullptr;
vaw::PartId g_gear = 0;
int g_tick = 0;

// The held gear goes one step round a 5 cm circle.
void moveHand() {
  vaw::ui::SimulationController& sim = g_window->simulation();
  const double a = 2.0 * std::numbers::pi * (g_tick++ % 90) / 90.0;
  static const Eigen::Vector3d centre = sim.handPosition();
  sim.moveHand(centre + Eigen::Vector3d(0.05 * std::cos(a), 0.05 * std::sin(a), 0.0));
}

void stepWorld() {
  moveHand();
  g_window->simulation().stepOnce();
}

void BM_FrameDescription(benchmark::State& state) {
  vaw::ui::SimulationController& sim = g_window->simulation();
  vaw::view::Frame frame;
  vaw::view::FrameOptions options;
  options.selected = g_gear;
  for (auto _ : state) {
    state.PauseTiming();
    stepWorld();
    state.ResumeTiming();
    vaw::view::makeFrame(sim.world(), sim.description(), options, frame);
    benchmark::DoNotOptimize(frame.parts.data());
  }
  state.counters["drops"] = static_cast<double>(frame.drops.size());
}

void BM_ViewportFrame(benchmark::State& state) {
  vaw::ui::SimulationController& sim = g_window->simulation();
  vaw::view::Frame frame;
  vaw::view::FrameOptions options;
  options.selected = g_gear;
  std::size_t touched = 0;
  for (auto _ : state) {
    state.PauseTiming();
    stepWorld();
    vaw::view::makeFrame(sim.world(), sim.description(), options, frame);
    state.ResumeTiming();
    g_window->viewport()->applyFrame(frame);
    touched += g_window->viewport()->lastFrameUpdates();
  }
  state.counters["touched_per_frame"] = static_cast<double>(touched) / static_cast<double>(state.iterations());
}

void BM_Inspector(benchmark::State& state) {
  vaw::ui::SimulationController& sim = g_window->simulation();
  for (auto _ : state) {
    state.PauseTiming();
    stepWorld();
    state.ResumeTiming();
    g_window->partDock()->model()->updateLive(vaw::sim::report(sim.world(), g_gear));
    g_window->partDock()->view()->viewport()->repaint();  // the table as it shows the changed cells
  }
}

void BM_Timeline(benchmark::State& state) {
  vaw::ui::SimulationController& sim = g_window->simulation();
  vaw::ui::TimelineView* view = g_window->timelineDock()->view();
  for (auto _ : state) {
    state.PauseTiming();
    stepWorld();
    state.ResumeTiming();
    view->setTimes(sim.world().time(), sim.recorder().endTime(), false);
    view->repaint();
  }
}

void BM_WholeStep(benchmark::State& state) {
  for (auto _ : state) {
    moveHand();
    g_window->simulation().stepOnce();
  }
  state.counters["active"] = static_cast<double>(g_window->simulation().world().activeParts());
}

// The scene tree with every part of the assembly in it (1,027 rows on the product), used as a person uses
// it: every row expanded and the view repainted; a click on a part's row far down the tree (the selection,
// the viewport's highlight and the part panel follow it) and the repaint; Page Down and the repaint.
QTreeView* sceneTree() { return g_window->sceneDock()->view(); }

void BM_TreeExpandAll(benchmark::State& state) {
  QTreeView* tree = sceneTree();
  for (auto _ : state) {
    tree->expandAll();
    tree->repaint();
    state.PauseTiming();
    tree->collapseAll();
    tree->repaint();
    state.ResumeTiming();
  }
  tree->expandToDepth(1);
  state.counters["rows"] = static_cast<double>(g_controller->assembly()->parts.size());
}

void BM_TreeClickPart(benchmark::State& state) {
  QTreeView* tree = sceneTree();
  tree->expandAll();
  const auto* model = g_window->sceneDock()->model();
  const std::size_t n = g_controller->assembly()->parts.size();
  std::size_t k = 0;
  for (auto _ : state) {
    state.PauseTiming();
    const QModelIndex index = model->indexOfPart(static_cast<vaw::PartId>(n - 1 - (k++ % 2) * 30));
    tree->scrollTo(index);
    tree->repaint();
    QCoreApplication::processEvents();
    const QPoint at = tree->visualRect(index).center();
    state.ResumeTiming();
    QTest::mouseClick(tree->viewport(), Qt::LeftButton, {}, at);
    QCoreApplication::processEvents();
    tree->repaint();
    g_window->partDock()->repaint();
  }
}

void BM_TreePageDown(benchmark::State& state) {
  QTreeView* tree = sceneTree();
  tree->expandAll();
  tree->setFocus();
  for (auto _ : state) {
    QTest::keyClick(tree, Qt::Key_PageDown);
    tree->repaint();
    if (tree->verticalScrollBar()->value() == tree->verticalScrollBar()->maximum()) {
      state.PauseTiming();
      QTest::keyClick(tree, Qt::Key_Home);
      state.ResumeTiming();
    }
  }
}

BENCHMARK(BM_FrameDescription)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ViewportFrame)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Inspector)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Timeline)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_WholeStep)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TreeExpandAll)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TreeClickPart)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TreePageDown)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  qputenv("QT3D_RENDERER", "opengl");
  QApplication app(argc, argv);
  benchmark::Initialize(&argc, argv);
  vaw::ui::AssemblyController controller;
  vaw::ui::MainWindow window(controller);
  window.setAutoPlay(false);
  window.resize(1280, 800);
  window.show();
  g_window = &window;
  g_controller = &controller;
  QSignalSpy loaded(&controller, &vaw::ui::AssemblyController::assemblyLoaded);
  const bool other = argc == 3;
  QElapsedTimer opening;
  opening.start();
  controller.open(other ? QString::fromLocal8Bit(argv[1]) : QStringLiteral(VAW_BUILD_RESOURCE_DIR "/scenes/large-gearbox.vaw.json"));
  if (!loaded.wait(300000)) {
    std::fprintf(stderr, "bench_gui: the file did not load\n");
    return 1;
  }
  // From File > Open to the assembly in the window: read, recognised, ordered who goes first, laid out.
  std::fprintf(stderr, "bench_gui: opened in %.2f s\n", static_cast<double>(opening.elapsed()) / 1000.0);
  vaw::ui::SimulationController& sim = window.simulation();
  const auto held = controller.assembly()->findPart(other ? argv[2] : "gear-a1");
  if (!held) {
    std::fprintf(stderr, "bench_gui: no part %s\n", other ? argv[2] : "gear-a1");
    return 1;
  }
  g_gear = *held;
  window.viewport()->selectPart(g_gear);
  // The right hand closes on the gear and lifts it 0.1 m.
  const Eigen::Vector3d at = sim.world().part(g_gear).pose * controller.assembly()->parts[g_gear].mass.centerOfMass;
  sim.grab(g_gear, at, false);
  sim.stepOnce();
  for (int i = 1; i <= 10; ++i) {
    sim.moveHand(at + Eigen::Vector3d(0, 0, 0.01 * i));
    sim.stepOnce();
  }
  if (sim.world().part(g_gear).state != vaw::interact::PartState::InHand) {
    std::fprintf(stderr, "bench_gui: the part is not held\n");
    return 1;
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
