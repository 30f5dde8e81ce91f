// CPU time per headset frame for each bundled scene under the simulated OpenXR runtime (docs/benchmarks.md,
// "VR mode"): the workbench enters VR, the right hand pinches a part and carries it round a 5 cm circle once
// a second (every step moves a held part: collision checks, the drop line, the frame description), and each
// frame's CPU time is split as XrController measures it: simulate (the steps owed to the frame and the frame
// description), render (both eyes' drawing calls) and the whole frame on the GUI thread (from one shown frame
// to the next: the runtime's calls, the desktop's mirror and panels included).
//
//   xvfb-run -a build/bin/vaw_bench_xr [SECONDS_PER_SCENE]
//
// The runtime's clock is virtual (each xrWaitFrame is one 90 Hz period later, at once), so the loop runs as
// fast as the CPU allows and the numbers are costs, not a frame rate.
#include <time.h>

#include <QApplication>
#include <QDir>
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTimer>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "vaw/paths.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/xr_controller.hpp"

namespace {

double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

// The stage's coordinates of a world point, as the plugin places the table (vaw::xr::Placement's defaults).
QJsonArray stage(const Eigen::Vector3d& w) { return {w.x(), w.z() + 0.90, -w.y() - 0.45}; }

struct Stats {
  double median = 0.0, p95 = 0.0, mean = 0.0;
};
Stats stats(std::vector<double> v) {
  Stats s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  s.median = v[v.size() / 2];
  s.p95 = v[std::min(v.size() - 1, static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(v.size()))) - 1)];
  for (double x : v) s.mean += x;
  s.mean /= static_cast<double>(v.size());
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  if (qEnvironmentVariableIsEmpty("QT3D_RENDERER")) qputenv("QT3D_RENDERER", "opengl");
  if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "xcb");
  if (qEnvironmentVariableIsEmpty("QT_XCB_GL_INTEGRATION")) qputenv("QT_XCB_GL_INTEGRATION", "xcb_glx");
  if (qEnvironmentVariableIsEmpty("XR_RUNTIME_JSON")) qputenv("XR_RUNTIME_JSON", VAW_SIMXR_MANIFEST);
  if (qEnvironmentVariableIsEmpty("VAW_PLUGIN_PATH")) qputenv("VAW_PLUGIN_PATH", VAW_BUILD_PLUGIN_DIR);
  if (qEnvironmentVariableIsEmpty("VAW_RESOURCE_DIR")) qputenv("VAW_RESOURCE_DIR", VAW_BUILD_RESOURCE_DIR);
  QApplication app(argc, argv);
  const double seconds = argc > 1 ? std::atof(argv[1]) : 4.0;
  QTemporaryDir dir;

  vaw::ui::AssemblyController controller;
  vaw::ui::MainWindow window(controller);
  window.resize(1024, 700);
  window.show();
  vaw::ui::SimulationController& sim = window.simulation();
  vaw::ui::XrController& xr = window.xr();

  const std::pair<const char*, const char*> scenes[] = {{"block-on-plate.vaw.json", "block"},
                                                        {"gear-on-shaft.vaw.json", "gear"},
                                                        {"sleeve-on-shaft.vaw.json", "sleeve"},
                                                        {"hoist-demo.vaw.json", "tray"},
                                                        {"large-gearbox.vaw.json", "gear-a1"}};
  std::printf("| scene | parts | frames | simulate median / p95 (ms) | render median / p95 (ms) | whole frame median / p95 (ms) |\n");
  std::printf("|---|---|---|---|---|---|\n");
  int status = 0;
  for (const auto& [scene, partName] : scenes) {
    QSignalSpy loaded(&controller, &vaw::ui::AssemblyController::assemblyLoaded);
    controller.open(QFile::decodeName((vaw::resourceDir() / "scenes").string().c_str()) + QLatin1Char('/') + QLatin1String(scene));
    if (loaded.isEmpty() && !loaded.wait(120000)) {
      std::fprintf(stderr, "vaw_bench_xr: %s did not load\n", scene);
      return 1;
    }
    sim.reset();
    sim.pause();
    const vaw::Assembly& a = *controller.assembly();
    const vaw::PartId part = *a.findPart(partName);
    const Eigen::Vector3d com = a.parts[part].pose * a.parts[part].mass.centerOfMass;
    const Eigen::Vector3d centre = com + Eigen::Vector3d(0.0, 0.0, 0.08);
    // A two-hand part (the hoist demo's tray) is taken by both hands, one either side of its centre; the left
    // closes after the right, which is how it joins the right on the part.
    const bool both = a.parts[part].mass.mass > 5.0;
    QJsonObject script{{"refresh", 90}, {"duration", seconds}};
    for (int hand = both ? 0 : 1; hand < 2; ++hand) {
      const Eigen::Vector3d side(both ? (hand == 0 ? -0.08 : 0.08) : 0.0, 0.0, 0.0);
      QJsonArray keys{QJsonObject{{"t", 0.0}, {"position", stage(com + side)}, {"pinch", 0.08}},
                      QJsonObject{{"t", hand == 0 ? 0.3 : 0.2}, {"position", stage(com + side)}, {"pinch", 0.015}},
                      QJsonObject{{"t", 0.5}, {"position", stage(centre + side + Eigen::Vector3d(0.05, 0.0, 0.0))}}};
      for (double t = 0.55; t < seconds; t += 0.05) {
        const double phase = 2.0 * std::numbers::pi * (t - 0.5);
        keys.append(QJsonObject{{"t", t}, {"position", stage(centre + side + 0.05 * Eigen::Vector3d(std::cos(phase), std::sin(phase), 0.0))}});
      }
      script[hand == 0 ? "left" : "right"] = keys;
    }
    QFile f(dir.filePath(QStringLiteral("bench.json")));
    if (!f.open(QIODevice::WriteOnly)) return 1;
    f.write(QJsonDocument(script).toJson());
    f.close();
    qputenv("VAW_SIMXR_SCRIPT", QFile::encodeName(f.fileName()));

    std::vector<double> simulate, render, whole;
    double last = 0.0;
    const auto connection = QObject::connect(&xr, &vaw::ui::XrController::frameShown, [&] {
      const double now = threadCpuMs();
      // From the moment the part is held and moving (0.6 s of the script on).
      if (xr.lastFrame().rendered && sim.world().time() > 0.6 && sim.world().held(1) == part) {
        simulate.push_back(xr.lastFrame().simulateMs);
        render.push_back(xr.lastFrame().renderMs);
        if (last > 0.0) whole.push_back(now - last);
      }
      last = now;
    });
    QString failure;
    const auto failed = QObject::connect(&xr, &vaw::ui::XrController::failed, [&](vaw::xr::Failure, const QString& t) { failure = t; });
    xr.enter();
    while (xr.inHeadset()) QCoreApplication::processEvents(QEventLoop::AllEvents, 50);
    QObject::disconnect(connection);
    QObject::disconnect(failed);
    if (!failure.isEmpty() || simulate.empty()) {
      std::fprintf(stderr, "vaw_bench_xr: %s: %s\n", scene, failure.isEmpty() ? "the part was never held" : qPrintable(failure));
      status = 1;
      continue;
    }
    const Stats s = stats(simulate), r = stats(render), w = stats(whole);
    std::printf("| %s | %zu | %zu | %.3f / %.3f | %.3f / %.3f | %.3f / %.3f |\n", scene, a.parts.size(), simulate.size(), s.median,
                s.p95, r.median, r.p95, w.median, w.p95);
    std::fflush(stdout);
  }
  return status;
}
