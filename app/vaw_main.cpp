// vaw: the Virtual Assembly Workbench GUI.
//   vaw [SCENE_OR_MESH] [--select PART] [--screenshot FILE] [--size WxH]
// Without a file it opens the bundled default scene (vaw::defaultScenePath()).
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
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/viewport.hpp"

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
  QApplication app(argc, argv);
  QApplication::setApplicationName(QStringLiteral("vaw"));
  QApplication::setApplicationDisplayName(QStringLiteral("Virtual Assembly Workbench"));
  QApplication::setOrganizationName(QStringLiteral("vaw"));
  // Matches packaging/io.github.vaw.Workbench.desktop and its icon.
  QApplication::setDesktopFileName(QStringLiteral("io.github.vaw.Workbench"));
  QApplication::setWindowIcon(QIcon::fromTheme(QStringLiteral("io.github.vaw.Workbench")));

  QCommandLineParser parser;
  parser.setApplicationDescription(QStringLiteral("Virtual Assembly Workbench"));
  parser.addHelpOption();
  parser.addPositionalArgument(QStringLiteral("file"),
                               QStringLiteral("Scene (.vaw.json) or mesh file to open; default: the bundled demo."),
                               QStringLiteral("[SCENE_OR_MESH]"));
  const QCommandLineOption screenshotOption(
      QStringLiteral("screenshot"),
      QStringLiteral("Open the file, wait until the viewport has rendered, save a PNG of the window to FILE and quit."),
      QStringLiteral("FILE"));
  const QCommandLineOption sizeOption(QStringLiteral("size"), QStringLiteral("Window size, e.g. 1280x800."),
                                      QStringLiteral("WxH"));
  const QCommandLineOption selectOption(QStringLiteral("select"),
                                        QStringLiteral("Select the part named PART once the file is open."),
                                        QStringLiteral("PART"));
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

  vaw::ui::AssemblyController controller;
  vaw::ui::MainWindow window(controller);
  window.resize(size);
  window.show();

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
  controller.open(path);
  return QApplication::exec();
}
