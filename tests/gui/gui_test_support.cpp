#include "gui_test_support.hpp"

#include <Qt3DExtras/Qt3DWindow>
#include <Qt3DRender/QCamera>
#include <Qt3DRender/QRenderCapture>
#include <QRegularExpression>
#include <QApplication>
#include <QComboBox>
#include <QDialogButtonBox>
#include <QFileDialog>
#include <QMessageBox>
#include <QPointer>
#include <QPushButton>
#include <QScopeGuard>
#include <QTimer>
#include <QLineEdit>
#include <QLocale>
#include <QMainWindow>
#include <QMenu>
#include <QSettings>
#include <QUndoStack>
#include <QTreeView>
#include <QPixmap>
#include <QScreen>
#include <QStatusBar>
#include <QSignalSpy>
#include <QTest>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "vaw/constraint_recognition.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/scene_tree_model.hpp"
#include "vaw/ui/simulation_controller.hpp"
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
  QTest::keyClicks(edit, inLocale(text));
  QTest::keyClick(edit, Qt::Key_Return);
}

QString inLocale(QString number) { return number.replace(QLatin1Char('.'), QLocale().decimalPoint()); }

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

QMenu* openSceneTreeMenu(ui::MainWindow& window, PartId part) {
  QTreeView* tree = window.sceneDock()->view();
  const QModelIndex item = window.sceneDock()->model()->indexOfPart(part);
  if (!item.isValid()) return nullptr;
  tree->scrollTo(item);
  const QPoint at = tree->viewport()->mapTo(&window, tree->visualRect(item).center());
  QTest::mouseClick(window.windowHandle(), Qt::RightButton, {}, at);
  QMenu* menu = nullptr;
  const bool shown = QTest::qWaitFor([&] {
    menu = tree->findChild<QMenu*>(QStringLiteral("sceneTreeMenu"));
    return menu != nullptr && menu->isVisible();
  }, 5000);
  return shown ? menu : nullptr;
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

void answerFileDialog(QWidget* modal, const QString& path, const QString& fileType) {
  // Whatever fails here, the dialog must not stay open: its exec() would hold the test until ctest's time
  // limit (a run under load once waited 300 s on it) instead of failing at once.
  const QPointer<QDialog> open = qobject_cast<QDialog*>(modal);
  const auto rejectIfStillOpen = qScopeGuard([open] {
    if (open && open->isVisible()) open->reject();
  });
  auto* dialog = qobject_cast<QFileDialog*>(modal);
  QVERIFY2(dialog != nullptr, "the modal dialog is a file dialog");
  auto* name = dialog->findChild<QLineEdit*>(QStringLiteral("fileNameEdit"));
  QVERIFY(name != nullptr);
  name->setCompleter(nullptr);
  // The dialog lists its folder on a thread; when the listing arrives it selects the suggested file and, in a
  // name field without focus, puts that name back over what was typed (seen in a loaded CI run: Save then
  // went nowhere). So the field gets focus the way a person gives it, and what was typed is checked and
  // typed again if the listing overwrote it, as a person would.
  QVERIFY(QTest::qWaitForWindowActive(dialog));
  if (!fileType.isEmpty()) {
    auto* types = dialog->findChild<QComboBox*>(QStringLiteral("fileTypeCombo"));
    QVERIFY(types != nullptr);
    types->setFocus();
    QTest::keyClick(types, Qt::Key_Home);
    for (int i = 0; i < types->count() && !types->currentText().startsWith(fileType); ++i) QTest::keyClick(types, Qt::Key_Down);
    QVERIFY2(types->currentText().startsWith(fileType), qPrintable(fileType + QStringLiteral(" is not among the file types")));
  }
  QTest::mouseClick(name, Qt::LeftButton);
  QTRY_VERIFY_WITH_TIMEOUT(name->hasFocus(), 5000);
  for (int attempt = 0; attempt < 3 && name->text() != path; ++attempt) {
    QTest::keyClick(name, Qt::Key_A, Qt::ControlModifier);
    QTest::keyClicks(name, path);
    QTest::qWait(200);
  }
  QCOMPARE(name->text(), path);
  auto* buttons = dialog->findChild<QDialogButtonBox*>(QStringLiteral("buttonBox"));
  QVERIFY(buttons != nullptr);
  QPushButton* accept = nullptr;
  for (QAbstractButton* b : buttons->buttons())
    if (buttons->buttonRole(b) == QDialogButtonBox::AcceptRole) accept = qobject_cast<QPushButton*>(b);
  QVERIFY2(accept != nullptr, "the dialog has a Save or Open button");
  QTRY_VERIFY2_WITH_TIMEOUT(accept->isEnabled(), "the dialog's Save or Open button can be clicked", 5000);
  QTest::mouseClick(accept, Qt::LeftButton);
  QTRY_VERIFY2_WITH_TIMEOUT(!dialog->isVisible(),
                            qPrintable(QStringLiteral("the dialog closed on its Save or Open button with \"%1\" in %2")
                                           .arg(name->text(), dialog->directory().absolutePath())),
                            5000);
}

void whenModal(std::function<void(QWidget*)> act) {
  auto* timer = new QTimer;
  timer->setInterval(50);
  QObject::connect(timer, &QTimer::timeout, [timer, act = std::move(act)] {
    if (QWidget* modal = QApplication::activeModalWidget()) {
      timer->stop();
      timer->deleteLater();
      act(modal);
    }
  });
  timer->start();
}

void shot(QMainWindow* window, QWidget* widget, const QString& name) {
  QTest::qWait(150);
  const QPixmap p = widget == window ? window->screen()->grabWindow(window->winId()) : widget->grab();
  QVERIFY(p.save(shotPath(name)));
}

QPoint aimAtFace(ui::Viewport& viewport, const Part& p, PartId part, std::size_t face) {
  const auto pose = viewport.partPose(part);
  if (!pose || !p.cad) return {-1, -1};
  const CadSolid& s = *p.cad;
  const CadFace& f = s.faces[face];
  std::vector<Eigen::Vector3d> centroids;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (std::size_t t = f.firstTriangle; t < f.firstTriangle + f.triangleCount; ++t) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) c += s.mesh.vertices[static_cast<std::size_t>(s.mesh.triangles[t][k])] / 3.0;
    centroids.push_back(c);
    centre += *pose * c;
  }
  if (centroids.empty()) return {-1, -1};
  centre /= static_cast<double>(centroids.size());
  Eigen::AlignedBox3d bounds;
  for (const auto& v : s.mesh.vertices) bounds.extend(v);
  const double tolerance = 0.01 * bounds.diagonal().norm();
  const double distance = std::max(0.15, 6.0 * bounds.diagonal().norm());
  Eigen::Vector3d axis = (pose->linear() * f.direction).normalized();
  if (axis.z() < 0.0) axis = -axis;
  const Eigen::Vector3d side =
      std::abs(axis.z()) > 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d(axis.cross(Eigen::Vector3d::UnitZ()).normalized());
  std::vector<Eigen::Vector3d> directions;
  if (f.surface == CadFace::Surface::Cylinder && f.convex) {
    for (double turn : {0.0, 1.0, 2.0, 3.0})
      directions.push_back(Eigen::AngleAxisd(turn * std::numbers::pi / 2.0, axis) * side + 0.4 * Eigen::Vector3d::UnitZ());
  } else if (f.surface == CadFace::Surface::Cylinder) {
    // Into the bore along its axis, tilted so that the far wall shows.
    for (double turn : {0.0, 1.0, 2.0, 3.0})
      directions.push_back(axis + 0.35 * (Eigen::AngleAxisd(turn * std::numbers::pi / 2.0, axis) * side));
  } else {
    const Eigen::Vector3d n = pose->linear() * f.direction;
    directions = {n + 0.3 * side, n - 0.3 * side, n + 0.3 * Eigen::Vector3d::UnitZ()};
  }
  for (const Eigen::Vector3d& d : directions) {
    viewport.lookAt(centre + distance * d.normalized(), centre);
    if (capture(&viewport).isNull()) return {-1, -1};
    const QSize size = viewport.view3d()->size();
    for (const Eigen::Vector3d& c : centroids) {
      const Eigen::Vector3d world = *pose * c;
      const QPoint at = viewport.projectToWindow(world).toPoint();
      if (at.x() < 2 || at.y() < 2 || at.x() > size.width() - 3 || at.y() > size.height() - 3) continue;
      const auto hit = viewport.pick(at);
      if (!hit || hit->part != part) continue;
      if (faceAt(s, pose->inverse() * hit->point, tolerance) == face) return at;
    }
  }
  return {-1, -1};
}

Eigen::Vector3d topFaceCentre(const TriMesh& m, const Eigen::Isometry3d& pose) {
  Eigen::Vector3d best = pose.translation();
  double bestZ = -1e300, bestArea = 0.0;
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d a = pose * m.vertices[static_cast<std::size_t>(t[0])], b = pose * m.vertices[static_cast<std::size_t>(t[1])],
                          c = pose * m.vertices[static_cast<std::size_t>(t[2])];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.z() < 0.9 * n.norm()) continue;
    const Eigen::Vector3d centre = (a + b + c) / 3.0;
    const double area = 0.5 * n.norm();
    if (centre.z() > bestZ + 1e-6 || (centre.z() > bestZ - 1e-6 && area > bestArea)) {
      best = centre;
      bestZ = centre.z();
      bestArea = area;
    }
  }
  return best;
}

namespace {
QVector3D toQt(const Eigen::Vector3d& v) { return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())}; }
}  // namespace

void carryWithMouse(ui::MainWindow& window, PartId id, const Eigen::Isometry3d& target, const char* name, bool letGo) {
  ui::Viewport* viewport = window.viewport();
  ui::SimulationController& sim = window.simulation();
  // A steep view from above that holds the part and its place, so that the parts waiting in a column do not
  // hide each other: the hand moves on a plane facing it. Where the part shows: its top face's centre, or
  // else the upward face of it nearest the top that no other part hides; from another side, or from
  // straight above, where a taller part hides it (a spacer behind a motor).
  const Eigen::Vector3d from = sim.world().part(id).pose.translation();
  const Eigen::Vector3d centre = 0.5 * (from + target.translation());
  const double distance = 0.2 + 2.0 * (target.translation() - from).norm();
  Qt3DRender::QCamera* cam = viewport->camera();
  const TriMesh& mesh = *sim.recorder().scene().assembly().parts[id].mesh;
  const Eigen::Isometry3d pose = sim.world().part(id).pose;
  std::vector<Eigen::Vector3d> spots{topFaceCentre(mesh, pose)};
  std::vector<std::pair<double, Eigen::Vector3d>> upward;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = pose * mesh.vertices[static_cast<std::size_t>(t[0])], b = pose * mesh.vertices[static_cast<std::size_t>(t[1])],
                          c = pose * mesh.vertices[static_cast<std::size_t>(t[2])];
    if ((b - a).cross(c - a).z() > 0.0) upward.emplace_back(-(a + b + c).z(), (a + b + c) / 3.0);
  }
  std::sort(upward.begin(), upward.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  for (const auto& u : upward) spots.push_back(u.second);
  QPoint p(-1, -1);
  for (const Eigen::Vector3d& side : {Eigen::Vector3d(0.25, -0.6, 1.0), Eigen::Vector3d(0.0, -0.05, 1.0), Eigen::Vector3d(-0.25, 0.6, 1.0)}) {
    cam->setViewCenter(toQt(centre));
    cam->setPosition(toQt(centre + distance * side.normalized()));
    cam->setUpVector(QVector3D(0, 0, 1));
    QVERIFY(!capture(viewport).isNull());
    for (const Eigen::Vector3d& spot : spots) {
      const QPoint at = viewport->projectToWindow(spot).toPoint();
      if (!viewport->rect().contains(at)) continue;
      const auto hit = viewport->pick(at);
      if (hit && hit->part == id) {
        p = at;
        break;
      }
    }
    if (viewport->rect().contains(p)) break;
  }
  QVERIFY2(viewport->rect().contains(p), qPrintable(QStringLiteral("%1 shows nowhere in the viewport").arg(QLatin1String(name))));
  pressAndDrag(viewport->view3d(), p, p + QPoint(0, -20), 4, 30);  // past the drag distance
  QTRY_COMPARE_WITH_TIMEOUT(sim.world().part(id).state, interact::PartState::InHand, 3000);
  QTest::qWait(100);
  moveCarriedWithMouse(window, id, target, name);
  if (letGo) releaseWithMouse(window);
}

void moveCarriedWithMouse(ui::MainWindow& window, PartId id, const Eigen::Isometry3d& target, const char* name) {
  ui::Viewport* viewport = window.viewport();
  ui::SimulationController& sim = window.simulation();
  Qt3DRender::QCamera* cam = viewport->camera();
  // The hand carries the part rigidly: it must go where the part's move takes the hand.
  const Eigen::Vector3d hand = sim.handPosition();
  const Eigen::Vector3d wanted = hand + (target.translation() - sim.world().part(id).pose.translation());
  const Eigen::Vector3d eye(cam->position().x(), cam->position().y(), cam->position().z());
  const Eigen::Vector3d centre(cam->viewCenter().x(), cam->viewCenter().y(), cam->viewCenter().z());
  const Eigen::Vector3d view = (centre - eye).normalized();
  // The wheel moves the hand's plane along the view by 5 % of its distance a notch.
  const double notches = view.dot(wanted - hand) / (0.05 * view.dot(hand - eye));
  const QPoint pointer = viewport->projectToWindow(hand).toPoint();
  QWheelEvent wheel(QPointF(pointer), viewport->view3d()->mapToGlobal(QPointF(pointer)), QPoint(),
                    QPoint(0, static_cast<int>(std::lround(notches * 120.0))), Qt::LeftButton, Qt::NoModifier,
                    Qt::NoScrollPhase, false);
  QCoreApplication::sendEvent(viewport->view3d(), &wheel);
  QTest::qWait(50);
  const QPoint to = viewport->projectToWindow(wanted).toPoint();
  for (int i = 1; i <= 10; ++i) {
    QTest::mouseMove(viewport->view3d(), pointer + (to - pointer) * i / 10);
    QTest::qWait(25);
  }
  // Held still before the release, so it leaves with no speed.
  QTest::qWait(300);
  const double off = (sim.world().part(id).pose.translation() - target.translation()).norm();
  QVERIFY2(off < 0.003, qPrintable(QStringLiteral("%1 carried to %2 mm from its target").arg(QLatin1String(name)).arg(off * 1e3)));
}

void releaseWithMouse(ui::MainWindow& window) {
  const QPoint at = window.viewport()->projectToWindow(window.simulation().handPosition()).toPoint();
  QTest::mouseRelease(window.viewport()->view3d(), Qt::LeftButton, {}, at);
}


Workbench::Workbench() = default;
Workbench::~Workbench() = default;

bool Workbench::start(const WorkbenchOptions& options, const std::function<void(ui::MainWindow&)>& beforeShow) {
  options_ = options;
  failOnWarnings();
  modalWatch_ = std::make_unique<QTimer>();
  modalWatch_->setInterval(1000);
  QObject::connect(modalWatch_.get(), &QTimer::timeout, [since = std::make_shared<std::pair<QPointer<QWidget>, int>>()] {
    QWidget* modal = QApplication::activeModalWidget();
    if (modal == nullptr || modal != since->first) {
      *since = {modal, 0};
      return;
    }
    if (++since->second < 30) return;
    const auto* box = qobject_cast<QMessageBox*>(modal);
    const QString what = QStringLiteral("a modal dialog (%1 \"%2\"%3) stayed open 30 s with nobody to answer it")
                             .arg(QString::fromLatin1(modal->metaObject()->className()), modal->windowTitle(),
                                  box ? QStringLiteral(": ") + box->text() : QString());
    *since = {nullptr, 0};
    if (auto* dialog = qobject_cast<QDialog*>(modal)) dialog->reject();
    QTest::qFail(qPrintable(what), __FILE__, __LINE__);
  });
  modalWatch_->start();
  if (options.clearSettings) QSettings().clear();
  controller = std::make_unique<ui::AssemblyController>();
  window = std::make_unique<ui::MainWindow>(*controller);
  if (beforeShow) beforeShow(*window);
  return restart();
}

bool Workbench::restart() {
  if (!controller) controller = std::make_unique<ui::AssemblyController>();
  if (!window) window = std::make_unique<ui::MainWindow>(*controller);
  if (options_.autoPlay) window->setAutoPlay(*options_.autoPlay);
  window->resize(options_.size);
  window->show();
  if (!QTest::qWaitForWindowExposed(window.get()) || !QTest::qWaitForWindowExposed(window->viewport()->view3d())) {
    QTest::qFail("the workbench's window was not exposed", __FILE__, __LINE__);
    return false;
  }
  if (options_.activate) {
    window->activateWindow();
    if (!QTest::qWaitForWindowActive(window.get())) {
      QTest::qFail("the workbench's window did not become active", __FILE__, __LINE__);
      return false;
    }
  }
  return true;
}

void Workbench::stop() {
  modalWatch_.reset();
  window.reset();
  controller.reset();
  restoreMessageHandler();
}

bool Workbench::open(const QString& path) {
  window->undoStack()->setClean();
  QSignalSpy loaded(controller.get(), &ui::AssemblyController::assemblyLoaded);
  window->openFile(path);
  if (!loaded.wait(60000) && loaded.isEmpty()) {
    QTest::qFail(qPrintable(QStringLiteral("%1 did not load within a minute").arg(path)), __FILE__, __LINE__);
    return false;
  }
  if (!window->simulation().hasWorld() || capture(window->viewport()).isNull()) {
    QTest::qFail(qPrintable(QStringLiteral("%1 loaded, but the viewport shows no world").arg(path)), __FILE__, __LINE__);
    return false;
  }
  return true;
}

}  // namespace vaw::guitest
