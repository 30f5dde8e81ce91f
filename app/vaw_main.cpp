// vaw: the Virtual Assembly Workbench GUI.
//   vaw [SCENE_OR_MESH_OR_SESSION] [--select PART] [--at SECONDS] [--screenshot FILE] [--size WxH] [--vr]
// Without a file it opens the bundled default scene (vaw::defaultScenePath()). A session
// (*.vaw-session.json) opens paused at its start, or at --at SECONDS, ready to play back.
#include <Qt3DRender/QRenderCapture>
#include <QApplication>
#include <QCommandLineParser>
#include <QFile>
#include <QIcon>
#include <QImage>
#include <QPixmap>
#include <QRegularExpression>
#include <QScreen>
#include <QTimer>
#include <cstdio>
#include <string>

#include "vaw/paths.hpp"
#include "vaw/version.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/viewport.hpp"
#include "vaw/ui/xr_controller.hpp"

namespace {

// Waits for two rendered frames of the viewport (the second one shows everything the first one
// uploaded), lets the window system present it, then saves the whole window.
void screenshotWhenRendered(vaw::ui::MainWindow& window, const QString& file) {
  auto* capture = window.viewport()->renderCapture();
  auto* first = capture->requestCapture();
  QObject::connect(first, &Qt3DRender::QRenderCaptureReply::completed, &window, [&window, capture, first, file] {
    first->deleteLater();
    auto* second = capture->requestCapture();
    QObject::connect(second, &Qt3DRender::QRenderCaptureReply::completed, &window, [&window, second, file] {
      second->deleteLater();
      QTimer::singleShot(300, &window, [&window, file] {
        QScreen* screen = window.screen();
        const QPixmap shot = screen != nullptr ? screen->grabWindow(window.winId()) : QPixmap();
        if (shot.isNull() || !shot.save(file, "PNG")) {
          std::fprintf(stderr, "vaw: cannot write screenshot %s\n", qPrintable(file));
          QCoreApplication::exit(1);
          return;
        }
        std::printf("vaw: wrote %s (%dx%d)\n", qPrintable(file), shot.width(), shot.height());
        QCoreApplication::exit(0);
      });
    });
  });
}

}  // namespace

int main(int argc, char** argv) {
  // Qt3D's OpenGL renderer: captures come out the right way up, and it runs on Mesa's llvmpipe.
  if (qEnvironmentVariableIsEmpty("QT3D_RENDERER")) qputenv("QT3D_RENDERER", "opengl");
  // --help and --version print and exit: they must work without a display (a terminal over ssh, CI).
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h" || a == "--help-all" || a == "--version" || a == "-v") qputenv("QT_QPA_PLATFORM", "offscreen");
  }
  // The headset's OpenGL binding is GLX (docs/vr.md): Qt's contexts on X11 are to be GLX ones (its default,
  // said here so an EGL default cannot creep in), and under Wayland --vr runs the window through XWayland.
  if (qEnvironmentVariableIsEmpty("QT_XCB_GL_INTEGRATION")) qputenv("QT_XCB_GL_INTEGRATION", "xcb_glx");
  bool vr = false;
  for (int i = 1; i < argc; ++i) vr = vr || std::string(argv[i]) == "--vr";
  if (vr && qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "xcb");
  QApplication app(argc, argv);
  QApplication::setApplicationName(QStringLiteral("vaw"));
  QApplication::setApplicationVersion(QString::fromLatin1(vaw::kVersion));
  QApplication::setApplicationDisplayName(QStringLiteral("Virtual Assembly Workbench"));
  QApplication::setOrganizationName(QStringLiteral("vaw"));
  // Matches packaging/io.github.vaw.Workbench.desktop and its icon.
  QApplication::setDesktopFileName(QStringLiteral("io.github.vaw.Workbench"));
  QApplication::setWindowIcon(QIcon::fromTheme(QStringLiteral("io.github.vaw.Workbench")));

  QCommandLineParser parser;
  parser.setApplicationDescription(QStringLiteral("Virtual Assembly Workbench"));
  parser.addHelpOption();
  parser.addVersionOption();
  parser.addPositionalArgument(QStringLiteral("file"),
                               QStringLiteral("Scene (.vaw.json), mesh or recorded session (.vaw-session.json) to open; "
                                              "default: the bundled demo."),
                               QStringLiteral("[SCENE_OR_MESH_OR_SESSION]"));
  const QCommandLineOption screenshotOption(
      QStringLiteral("screenshot"),
      QStringLiteral("Open the file, wait until the viewport has rendered, save a PNG of the window to FILE and quit."),
      QStringLiteral("FILE"));
  const QCommandLineOption sizeOption(QStringLiteral("size"), QStringLiteral("Window size, e.g. 1280x800."),
                                      QStringLiteral("WxH"));
  const QCommandLineOption selectOption(QStringLiteral("select"),
                                        QStringLiteral("Select the part named PART once the file is open."),
                                        QStringLiteral("PART"));
  const QCommandLineOption atOption(
      QStringLiteral("at"), QStringLiteral("Show a recorded session at this time (s) instead of its start."),
      QStringLiteral("SECONDS"));
  const QCommandLineOption vrOption(QStringLiteral("vr"),
                                    QStringLiteral("Start in the OpenXR headset (VR mode) once the file is open."));
  parser.addOption(vrOption);
  parser.addOption(atOption);
  parser.addOption(screenshotOption);
  parser.addOption(sizeOption);
  parser.addOption(selectOption);
  parser.process(app);

  const QStringList files = parser.positionalArguments();
  if (files.size() > 1) {  // the desktop entry passes %F; one assembly is open at a time
    std::fprintf(stderr, "vaw: opening %s only; one file at a time\n", qPrintable(files.first()));
  }
  const QString path = QFile::decodeName((files.isEmpty() ? vaw::defaultScenePath() : vaw::resolveScenePath(QFile::encodeName(files.first()).toStdString())).c_str());

  QSize size(1280, 800);
  if (parser.isSet(sizeOption)) {
    const auto match = QRegularExpression(QStringLiteral("^(\\d+)x(\\d+)$")).match(parser.value(sizeOption));
    if (!match.hasMatch()) {
      std::fprintf(stderr, "vaw: --size expects WxH, e.g. 1280x800\n");
      return 2;
    }
    size = QSize(match.captured(1).toInt(), match.captured(2).toInt());
  }

  double at = -1.0;
  if (parser.isSet(atOption)) {
    bool ok = false;
    at = parser.value(atOption).toDouble(&ok);
    if (!ok || !(at >= 0.0)) {
      std::fprintf(stderr, "vaw: --at expects a time in seconds, 0 or more\n");
      return 2;
    }
  }

  vaw::ui::AssemblyController controller;
  vaw::ui::MainWindow window(controller);
  // A screenshot shows the scene as opened (or the session at --at), not whatever ran in between.
  if (parser.isSet(screenshotOption)) window.setAutoPlay(false);
  window.resize(size);
  window.show();

  if (at >= 0.0) {
    QObject::connect(&controller, &vaw::ui::AssemblyController::assemblyLoaded, &window, [&window, at] {
      vaw::ui::SimulationController& sim = window.simulation();
      if (!sim.isPlayback() && sim.recorder().length() == 0)
        std::fprintf(stderr, "vaw: --at applies to a recorded session; showing the scene as loaded\n");
      sim.seek(sim.recorder().stepAt(at));
      window.viewport()->resetView();  // frame the parts where they are then
    });
  }
  if (parser.isSet(selectOption)) {
    const std::string part = parser.value(selectOption).toStdString();
    QObject::connect(&controller, &vaw::ui::AssemblyController::assemblyLoaded, &window, [&controller, &window, part] {
      const auto id = controller.assembly()->findPart(part);
      if (!id) std::fprintf(stderr, "vaw: no part named \"%s\"\n", part.c_str());
      window.viewport()->selectPart(id);
    });
  }
  if (parser.isSet(screenshotOption)) {
    const QString file = parser.value(screenshotOption);
    QObject::connect(&controller, &vaw::ui::AssemblyController::assemblyLoaded, &window,
                     [&window, file] { screenshotWhenRendered(window, file); });
    QObject::connect(&controller, &vaw::ui::AssemblyController::loadFailed, &window,
                     [](const vaw::ui::LoadFailure& failure) {
                       std::fprintf(stderr, "vaw: %s\n", qPrintable(failure.message));
                       QCoreApplication::exit(1);
                     });
    QTimer::singleShot(120000, &app, [] {
      std::fprintf(stderr, "vaw: timed out waiting for the viewport to render\n");
      QCoreApplication::exit(3);
    });
  }
  if (parser.isSet(vrOption)) {
    QObject::connect(&window.xr(), &vaw::ui::XrController::failed, &window, [](vaw::xr::Failure, const QString& text) {
      std::fprintf(stderr, "vaw: %s\n", qPrintable(text));
    });
    // The first file opened goes into the headset; later ones open wherever the workbench is then.
    QObject::connect(
        &controller, &vaw::ui::AssemblyController::assemblyLoaded, &window,
        [&window] {
          if (!window.xr().inHeadset()) window.xr().enter();
        },
        Qt::SingleShotConnection);
  }
  controller.open(path);
  return QApplication::exec();
}
