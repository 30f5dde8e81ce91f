#include "gui_test_support.hpp"

#include <Qt3DExtras/Qt3DWindow>
#include <Qt3DRender/QRenderCapture>
#include <QRegularExpression>
#include <QApplication>
#include <QLineEdit>
#include <QMainWindow>
#include <QPixmap>
#include <QScreen>
#include <QStatusBar>
#include <QSignalSpy>
#include <QTest>
#include <memory>

#include "vaw/ui/viewport.hpp"

namespace vaw::guitest {

namespace {

// Warnings that say nothing about vaw. Each needs a reason.
const QRegularExpression kAllowedWarnings[] = {
    // xvfb-run starts no login session, so there is no runtime directory; Qt falls back to /tmp.
    QRegularExpression(QStringLiteral("^QStandardPaths: XDG_RUNTIME_DIR not set")),
    QRegularExpression(QStringLiteral("^QStandardPaths: runtime directory .* permissions")),
};

QStringList g_warnings;
QtMessageHandler g_previous = nullptr;

void handler(QtMsgType type, const QMessageLogContext& context, const QString& message) {
  if (type == QtWarningMsg || type == QtCriticalMsg) {
    bool allowed = false;
    for (const auto& re : kAllowedWarnings) allowed = allowed || re.match(message).hasMatch();
    if (!allowed) g_warnings << message;
  }
  if (g_previous != nullptr) g_previous(type, context, message);
}

}  // namespace

void failOnWarnings() { g_previous = qInstallMessageHandler(handler); }
void restoreMessageHandler() { qInstallMessageHandler(g_previous); }

QStringList takeWarnings() {
  QStringList w = g_warnings;
  g_warnings.clear();
  return w;
}

QImage capture(ui::Viewport* viewport) {
  std::unique_ptr<Qt3DRender::QRenderCaptureReply> reply(viewport->renderCapture()->requestCapture());
  if (!reply->isComplete()) {
    QSignalSpy completed(reply.get(), &Qt3DRender::QRenderCaptureReply::completed);
    if (!completed.wait(20000) && !reply->isComplete()) return {};
  }
  return reply->image();
}

bool differs(QRgb a, QRgb b, int tolerance) {
  return std::abs(qRed(a) - qRed(b)) + std::abs(qGreen(a) - qGreen(b)) + std::abs(qBlue(a) - qBlue(b)) > tolerance;
}

double nonBackgroundFraction(const ui::Viewport* viewport, const QImage& image) {
  const QRgb background = viewport->clearColor().rgb();
  qsizetype different = 0;
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) different += differs(image.pixel(x, y), background, 6) ? 1 : 0;
  }
  return image.isNull() ? 0.0 : static_cast<double>(different) / (static_cast<double>(image.width()) * image.height());
}

void pressAndDrag(QWindow* window, const QPoint& from, const QPoint& to, int steps, int msPerStep,
                  Qt::KeyboardModifiers modifiers) {
  QTest::mousePress(window, Qt::LeftButton, modifiers, from);
  for (int i = 1; i <= steps; ++i) {
    QTest::mouseMove(window, from + (to - from) * i / steps);
    QTest::qWait(msPerStep);
  }
}

void typeInto(QAbstractSpinBox* box, const QString& text) {
  box->setFocus();
  QLineEdit* edit = box->findChild<QLineEdit*>();
  if (edit == nullptr) return;
  QTest::keyClick(edit, Qt::Key_A, Qt::ControlModifier);
  QTest::keyClicks(edit, text);
  QTest::keyClick(edit, Qt::Key_Return);
}

QPoint pointOnPart(ui::Viewport* viewport, const Assembly& assembly, PartId id, const Eigen::Isometry3d& pose) {
  // The ray caster works on Qt3D's backend copy of the camera and the transforms: let a frame render so
  // that it has caught up with the latest change.
  if (capture(viewport).isNull()) return {-1, -1};
  const Part& part = assembly.parts[id];
  Eigen::AlignedBox3d box;
  const Eigen::AlignedBox3d local = part.mesh->bounds();
  for (int c = 0; c < 8; ++c) box.extend(pose * local.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
  const QRect area(QPoint(0, 0), viewport->view3d()->size());
  const QPoint centre = viewport->projectToWindow(box.center()).toPoint();
  if (area.contains(centre) && viewport->partAt(centre) == id) return centre;
  QPoint best(-1, -1);
  for (int i = 1; i < 8; ++i) {
    for (int j = 1; j < 8; ++j) {
      for (int k = 1; k < 8; ++k) {
        const Eigen::Vector3d f(i / 8.0, j / 8.0, k / 8.0);
        const QPoint p = viewport->projectToWindow(box.min() + f.cwiseProduct(box.sizes())).toPoint();
        if (!area.contains(p) || viewport->partAt(p) != id) continue;
        if (best.x() < 0 || (p - centre).manhattanLength() < (best - centre).manhattanLength()) best = p;
      }
    }
  }
  return best;
}

void verifyNoWarnings() {
  const QStringList warnings = takeWarnings();
  QVERIFY2(warnings.isEmpty(), qPrintable(QStringLiteral("unexpected Qt warnings:\n") + warnings.join(QLatin1Char('\n'))));
}

QString shotPath(const QString& name) { return QStringLiteral(VAW_GUI_SHOT_DIR "/") + name; }

void pressKey(QMainWindow* window, int key, Qt::KeyboardModifiers modifiers) {
  if (QApplication::activeWindow() != window || QGuiApplication::focusWindow() != window->windowHandle()) {
    QTest::mouseClick(window->statusBar(), Qt::LeftButton);
    window->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(window));
  }
  QWidget* target = QApplication::focusWidget() != nullptr ? QApplication::focusWidget() : window;
  QTest::keyClick(target, static_cast<Qt::Key>(key), modifiers);
}

void shot(QMainWindow* window, QWidget* widget, const QString& name) {
  QTest::qWait(150);
  const QPixmap p = widget == window ? window->screen()->grabWindow(window->winId()) : widget->grab();
  QVERIFY(p.save(shotPath(name)));
}

}  // namespace vaw::guitest
