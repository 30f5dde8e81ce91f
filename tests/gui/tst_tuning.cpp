// The tuning panels driven as a person drives them: keys typed into the gravity and method spin boxes, cells
// of the friction table edited with F2 and Return, Ctrl+Z, the File menu's Save As dialog, a dock closed by
// its close button. Each test asserts on the running world, and on what the panels, the inspector and the
// status bar show. Screenshots of every panel go to the build tree (tests/gui/tuning-*.png).
//
// Runs under Xvfb (Qt3D needs GL); any Qt warning fails the test. QSettings live in the test's own
// XDG_CONFIG_HOME (tests/gui/CMakeLists.txt), cleared at the start.
#include <Qt3DExtras/Qt3DWindow>
#include <Qt3DRender/QCamera>
#include <QAbstractButton>
#include <QComboBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QLabel>
#include <QLineEdit>
#include <QMenu>
#include <QMessageBox>
#include <QPushButton>
#include <QRegularExpression>
#include <QScreen>
#include <QSettings>
#include <QSignalSpy>
#include <QSpinBox>
#include <QStatusBar>
#include <QTableView>
#include <QTreeView>
#include <QTemporaryDir>
#include <QUndoStack>
#include <QtCharts/QChart>
#include <QtCharts/QChartView>
#include <QtCharts/QScatterSeries>
#include <QProgressBar>
#include <QtTest>
#include <cmath>
#include <functional>
#include <memory>
#include <numbers>

#include "gui_test_support.hpp"
#include "vaw/dynamics/hinge.hpp"
#include "vaw/human/head_demand.hpp"
#include "vaw/paths.hpp"
#include "vaw/sim/report.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/motion_chart.hpp"
#include "vaw/ui/part_properties_model.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/tuning.hpp"
#include "vaw/ui/viewport.hpp"
#include "vaw/ui/work_precision_dock.hpp"
#include "vaw/peers/peers.hpp"
#include "vaw/units.hpp"

using vaw::PartId;
using vaw::ui::AssemblyController;
using vaw::ui::MainWindow;

namespace {

// How long a condition may take to come true. A full `ctest -j2` runs two GUI tests at once on two cores
// with software OpenGL, and a reload or a recognition then takes several times its time alone; the
// tests wait for the condition, so a generous cap costs nothing when it comes at once.
constexpr int kSettle = 30000;

using vaw::kDeg;

QString stateOf(const vaw::sim::World& w, PartId p) { return QString::fromStdString(std::string(vaw::interact::name(w.part(p).state))); }

QString bundled(const QString& scene) {
  return QFile::decodeName((vaw::resourceDir() / "scenes").string().c_str()) + QLatin1Char('/') + scene;
}

void clickButton(QWidget* box, QMessageBox::StandardButton which) {
  auto* mb = qobject_cast<QMessageBox*>(box);
  QVERIFY(mb != nullptr);
  QTest::mouseClick(mb->button(which), Qt::LeftButton);
}

}  // namespace

class TestTuning : public QObject {
  Q_OBJECT

 public:
  static void initMain() {
    if (qEnvironmentVariableIsEmpty("QT3D_RENDERER")) qputenv("QT3D_RENDERER", "opengl");
  }

 private slots:
  void initTestCase();
  void cleanup();
  void cleanupTestCase();

  void quarterFreeFlightScaleDoublesTheDropTime();
  void headDemandCalculatorAppliesItsScale();
  void staticFrictionMovesTheTiltWhereTheBlockStarts();
  void invalidFrictionIsRefusedAndUndoRestores();
  void unstableMethodWarnsBeforeTheGearGainsEnergy();
  void workPrecisionChartOfTheSelectedGear();
  void motionChartOfALongSessionStaysBounded();
  void savedSettingsReopenAndOldFilesOpen();
  void failedWritesAreReportedNotFatal();
  void unsavedTuningIsAskedAbout();
  void dockLayoutSurvivesARestart();

 private:
  [[nodiscard]] vaw::ui::Viewport* viewport() const { return window_->viewport(); }
  [[nodiscard]] vaw::ui::SimulationController& sim() const { return window_->simulation(); }
  [[nodiscard]] const vaw::Assembly& assembly() const { return *controller_->assembly(); }
  [[nodiscard]] const vaw::sim::World& world() const { return sim().world(); }
  void makeWindow();
  void open(const QString& path);
  void show(QDockWidget* dock);
  void setSpin(QAbstractSpinBox* box, const QString& text);
  void editCell(QTableView* view, int row, int column, const QString& text);
  void pressAndDrag(const QPoint& from, const QPoint& to, int steps, int msPerStep);
  // Lets `seconds` of simulated time pass with the mouse where it is.
  void holdStill(double seconds);
  QPoint onPart(PartId part) { return vaw::guitest::pointOnPart(viewport(), assembly(), part, world().part(part).pose); }
  void shot(QWidget* widget, const QString& name);
  // A key press where the keyboard focus is (shortcuts of the window's menus included).
  void press(int key, Qt::KeyboardModifiers modifiers);
  // Lifts the sleeve about 1 m with the mouse, holds it still, lets go and returns the fall time (from the
  // release to the impact time the world found inside its step) and the height its centre fell.
  std::pair<double, double> dropSleeve();
  void putBlockOnPlate();
  // Selects the part with a click on its row in the scene tree.
  void selectInTree(const QString& name);

  vaw::guitest::Workbench bench_;
  std::unique_ptr<AssemblyController>& controller_ = bench_.controller;
  std::unique_ptr<MainWindow>& window_ = bench_.window;
  QTemporaryDir dir_;
};

void TestTuning::initTestCase() {
  QVERIFY(dir_.isValid());
  QVERIFY(bench_.start({.autoPlay = true}));
}

void TestTuning::makeWindow() { QVERIFY(bench_.restart()); }

void TestTuning::press(int key, Qt::KeyboardModifiers modifiers) { vaw::guitest::pressKey(window_.get(), key, modifiers); }

void TestTuning::cleanup() {
  if (window_) {
    sim().setExternalPacing(false);  // a test that failed while it paced the world itself
    sim().pause();
  }
  vaw::guitest::verifyNoWarnings();
}

void TestTuning::cleanupTestCase() {
  bench_.stop();
}

void TestTuning::open(const QString& path) {
  // Whatever the previous test tuned is dropped without a question.
  QVERIFY(bench_.open(path));
  sim().setSpeed(1.0);
}

void TestTuning::show(QDockWidget* dock) {
  dock->show();
  dock->raise();
  QTest::qWait(50);
  QVERIFY(dock->isVisible());
}

void TestTuning::setSpin(QAbstractSpinBox* box, const QString& text) { vaw::guitest::typeInto(box, text); }

void TestTuning::editCell(QTableView* view, int row, int column, const QString& text) {
  const QModelIndex index = view->model()->index(row, column);
  view->scrollTo(index);
  QTest::mouseClick(view->viewport(), Qt::LeftButton, {}, view->visualRect(index).center());
  QCOMPARE(view->currentIndex(), index);
  QTest::keyClick(view, Qt::Key_F2);
  QLineEdit* editor = view->findChild<QLineEdit*>();
  QVERIFY2(editor != nullptr && editor->isVisible(), "F2 opens the cell's editor");
  QTest::keyClick(editor, Qt::Key_A, Qt::ControlModifier);
  QTest::keyClicks(editor, text);
  QTest::keyClick(editor, Qt::Key_Return);
  QTest::qWait(30);
}

void TestTuning::pressAndDrag(const QPoint& from, const QPoint& to, int steps, int msPerStep) {
  vaw::guitest::pressAndDrag(viewport()->view3d(), from, to, steps, msPerStep);
}

void TestTuning::holdStill(double seconds) {
  const double until = world().time() + seconds;
  QVERIFY2(QTest::qWaitFor([&] { return world().time() >= until; }, kSettle), "the simulation stood still");
}

void TestTuning::shot(QWidget* widget, const QString& name) { vaw::guitest::shot(window_.get(), widget, name); }

std::pair<double, double> TestTuning::dropSleeve() {
  const PartId sleeve = *assembly().findPart("sleeve");
  // From the side and far enough back to see a metre above the table.
  Qt3DRender::QCamera* cam = viewport()->camera();
  cam->setViewCenter(QVector3D(0.25f, 0.0f, 0.6f));
  cam->setPosition(QVector3D(0.25f, -3.2f, 0.6f));
  cam->setUpVector(QVector3D(0, 0, 1));
  if (vaw::guitest::capture(viewport()).isNull()) return {-1.0, 0.0};
  const QPoint from = onPart(sleeve);
  if (from.x() < 0) return {-1.0, 0.0};
  // The point a metre above the grab point, on screen.
  const QPoint up = viewport()->projectToWindow(world().part(sleeve).pose.translation() + Eigen::Vector3d(0, 0, 1.0)).toPoint() -
                    viewport()->projectToWindow(world().part(sleeve).pose.translation()).toPoint();
  pressAndDrag(from, from + up, 16, 30);
  // Held still longer than the release estimator's window (80 ms of simulated time, however slowly the
  // loaded machine simulates it): it lets go with no velocity.
  holdStill(0.3);
  const double zHeld = world().part(sleeve).pose.translation().z();
  QTest::mouseRelease(viewport()->view3d(), Qt::LeftButton, {}, from + up);
  const auto landed = [&] { return stateOf(world(), sleeve) == QStringLiteral("STATIC") && world().transitions().back().part == sleeve; };
  if (!QTest::qWaitFor(landed, 8000)) return {-1.0, 0.0};
  const auto& log = world().transitions();
  const auto& hit = log.back();
  const auto& release = log[log.size() - 2];
  const auto m = QRegularExpression(QStringLiteral("at t=([0-9.]+) s")).match(QString::fromStdString(hit.cause));
  if (!m.hasMatch() || release.event != vaw::interact::Event::Release) return {-1.0, 0.0};
  // The part leaves the hand at the start of the step in which the hand opens; the log stamps the release
  // with that step's end.
  return {m.captured(1).toDouble() - (release.t - world().settings().step()), zHeld - world().part(sleeve).pose.translation().z()};
}

// A 1 m drop at the free-flight scale set in the Gravity panel: 1.0 (typed into its spin box) and then 0.25
// (the paper's preset button). The same mouse path from the same start (Simulation > Reset keeps the
// tuning) gives the same height, so the times are in the ratio 1 / sqrt(0.25) = 2; each is also checked
// against sqrt(2 h / (g s)) for the height it fell.
void TestTuning::quarterFreeFlightScaleDoublesTheDropTime() {
  open(bundled(QStringLiteral("sleeve-on-shaft.vaw.json")));
  auto* gravity = window_->gravityDock();
  show(gravity);
  auto* factor = gravity->findChild<QDoubleSpinBox*>(QStringLiteral("gravityFreeFlight"));
  QVERIFY(factor != nullptr);
  setSpin(factor, QStringLiteral("1"));
  QTRY_COMPARE_WITH_TIMEOUT(world().settings().gravity.freeFlight, 1.0, kSettle);
  QCOMPARE(gravity->findChild<QDoubleSpinBox*>(QStringLiteral("gravityFreeFlightMs2"))->value(),
           std::round(vaw::kStandardGravity * 1000.0) / 1000.0);
  const PartId sleeve = *assembly().findPart("sleeve");
  const double start = world().part(sleeve).pose.translation().z();
  const auto [tFull, hFull] = dropSleeve();
  QVERIFY2(tFull > 0.0, "the sleeve fell and landed");
  shot(gravity, QStringLiteral("tuning-gravity.png"));

  press(Qt::Key_R, Qt::ControlModifier);  // Simulation > Reset
  QTRY_VERIFY_WITH_TIMEOUT(std::abs(world().part(sleeve).pose.translation().z() - start) < 1e-12, kSettle);
  QCOMPARE(world().settings().gravity.freeFlight, 1.0);  // Reset keeps the tuning
  QTest::mouseClick(gravity->findChild<QPushButton*>(QStringLiteral("gravityPresetPaper")), Qt::LeftButton);
  QTRY_COMPARE_WITH_TIMEOUT(world().settings().gravity.freeFlight, 0.25, kSettle);
  QCOMPARE(factor->value(), 0.25);
  const auto [tQuarter, hQuarter] = dropSleeve();
  QVERIFY2(tQuarter > 0.0, "the sleeve fell and landed");
  QVERIFY2(std::abs(hQuarter - hFull) < 1e-4, qPrintable(QStringLiteral("fell %1 m and %2 m").arg(hFull).arg(hQuarter)));
  QVERIFY2(hFull > 0.8 && hFull < 1.3, qPrintable(QStringLiteral("fell %1 m").arg(hFull)));
  const double ratio = tQuarter / tFull;
  QVERIFY2(std::abs(ratio - 2.0) < 0.02, qPrintable(QStringLiteral("fall times %1 s and %2 s: ratio %3").arg(tFull).arg(tQuarter).arg(ratio)));
  // And each against the closed form for the height it fell, released at rest (the centre falls straight).
  const double expectFull = std::sqrt(2.0 * hFull / vaw::kStandardGravity);
  QVERIFY2(std::abs(tFull - expectFull) < 0.01 * expectFull, qPrintable(QStringLiteral("%1 s, expected %2 s").arg(tFull).arg(expectFull)));
  QVERIFY(std::abs(tQuarter - 2.0 * expectFull) < 0.02 * expectFull);
}

// The demand calculator: distance and height typed in, its recommendation against the core's formula, and
// Apply sets the free-flight scale.
void TestTuning::headDemandCalculatorAppliesItsScale() {
  open(bundled(QStringLiteral("sleeve-on-shaft.vaw.json")));
  auto* gravity = window_->gravityDock();
  show(gravity);
  setSpin(gravity->findChild<QDoubleSpinBox*>(QStringLiteral("headDistance")), QStringLiteral("0.5"));
  setSpin(gravity->findChild<QDoubleSpinBox*>(QStringLiteral("headFallHeight")), QStringLiteral("1"));
  setSpin(gravity->findChild<QDoubleSpinBox*>(QStringLiteral("headPitchLimit")), QStringLiteral("150"));
  vaw::human::HeadLimits limits;
  limits.pitchRate_deg_s = 150.0;
  const auto r = vaw::human::recommendScale({0.5, 1.0}, limits);
  QVERIFY2(r.recommendedScale < 1.0, "a slow head needs a lower scale here");
  auto* apply = gravity->findChild<QPushButton*>(QStringLiteral("headApply"));
  QVERIFY(apply->text().contains(QString::number(r.recommendedScale, 'g', 3)));
  QTest::mouseClick(apply, Qt::LeftButton);
  QTRY_VERIFY_WITH_TIMEOUT(std::abs(world().settings().gravity.freeFlight - r.recommendedScale) < 1e-12, kSettle);
  shot(gravity, QStringLiteral("tuning-head-demand.png"));
}

void TestTuning::putBlockOnPlate() {
  const PartId block = *assembly().findPart("block");
  Qt3DRender::QCamera* cam = viewport()->camera();
  cam->setViewCenter(QVector3D(0.15f, 0.0f, 0.0f));
  cam->setPosition(QVector3D(0.15f, -0.03f, 1.2f));
  cam->setUpVector(QVector3D(0, 0, 1));
  QVERIFY(!vaw::guitest::capture(viewport()).isNull());
  const QPoint from = onPart(block);
  QVERIFY(from.x() >= 0);
  const Eigen::Vector3d grabbed = world().part(block).pose.translation();
  const QPoint to = viewport()->projectToWindow(Eigen::Vector3d(0.0, 0.0, grabbed.z())).toPoint() +
                    (from - viewport()->projectToWindow(grabbed).toPoint());
  pressAndDrag(from, to, 10, 25);
  holdStill(0.15);
  QTest::mouseRelease(viewport()->view3d(), Qt::LeftButton, {}, to);
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), block), QStringLiteral("STATIC"), 5000);
  const QPoint at = onPart(block);
  pressAndDrag(at, at + QPoint(14, 0), 4, 25);
  holdStill(0.15);
  QTest::mouseRelease(viewport()->view3d(), Qt::LeftButton, {}, at + QPoint(14, 0));
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), block), QStringLiteral("ONBASESTATIC"), 5000);
}

// The block's material's static friction raised from 0.3 to 0.5 in the Friction panel: the block on the
// tilted plate stays at 26.50 degrees and starts past atan(0.5) = 26.565 degrees, within 0.1 degree.
void TestTuning::staticFrictionMovesTheTiltWhereTheBlockStarts() {
  open(bundled(QStringLiteral("block-on-plate.vaw.json")));
  const PartId block = *assembly().findPart("block");
  putBlockOnPlate();
  auto* friction = window_->frictionDock();
  show(friction);
  auto* model = friction->model();
  const int row = model->materialRow("aluminium");
  QVERIFY(row >= 0);
  editCell(friction->view(), row, vaw::ui::FrictionModel::StaticColumn, QStringLiteral("0.5"));
  QTRY_COMPARE_WITH_TIMEOUT(world().friction(block).staticFriction, 0.5, kSettle);
  QCOMPARE(model->index(row, vaw::ui::FrictionModel::StaticAngleColumn).data().toString(), QStringLiteral("26.57°"));
  shot(friction, QStringLiteral("tuning-friction.png"));

  auto* tilt = window_->controlsDock()->tiltX();
  show(window_->controlsDock());
  setSpin(tilt, QStringLiteral("26.5"));
  QTRY_VERIFY_WITH_TIMEOUT(std::abs(sim().baseAngles().tiltX - 26.5 * kDeg) < 1e-9, kSettle);
  holdStill(0.5);  // half a second of simulated time at 26.5 degrees
  QCOMPARE(stateOf(world(), block), QStringLiteral("ONBASESTATIC"));
  setSpin(tilt, QStringLiteral("26.65"));
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), block), QStringLiteral("ONBASESLIDE"), 3000);
  const auto& started = world().transitions().back();
  const auto m = QRegularExpression(QStringLiteral("surface slope=([0-9.]+) deg")).match(QString::fromStdString(started.cause));
  QVERIFY2(m.hasMatch(), started.cause.c_str());
  const double slope = m.captured(1).toDouble();
  const double angle = std::atan(0.5) / kDeg;
  QVERIFY2(slope >= angle - 1e-9 && slope < angle + 0.1, qPrintable(QStringLiteral("started at %1 deg").arg(slope)));
}

// Negative, not a number, kinetic above static: each refused with the cell marked and the rule said, the
// value kept; a good value is taken, Ctrl+Z restores the one before and Ctrl+Shift+Z the new one again.
void TestTuning::invalidFrictionIsRefusedAndUndoRestores() {
  open(bundled(QStringLiteral("sleeve-on-shaft.vaw.json")));
  auto* friction = window_->frictionDock();
  show(friction);
  auto* model = friction->model();
  const int row = model->materialRow("brass");
  QVERIFY(row >= 0);
  const vaw::FrictionValues before = world().materialFriction("brass");
  QCOMPARE(before.staticFriction, 0.25);
  using Col = vaw::ui::FrictionModel::Column;

  editCell(friction->view(), row, Col::StaticColumn, QStringLiteral("-0.1"));
  QVERIFY2(friction->problemLabel()->text().contains(QStringLiteral("0 or more")) ||
               friction->problemLabel()->text().contains(QStringLiteral("negative")),
           qPrintable(friction->problemLabel()->text()));
  QVERIFY(!model->problem(row, Col::StaticColumn).isEmpty());
  QVERIFY(model->index(row, Col::StaticColumn).data(Qt::BackgroundRole).isValid());  // marked
  QCOMPARE(world().materialFriction("brass"), before);
  shot(friction, QStringLiteral("tuning-friction-refused.png"));

  editCell(friction->view(), row, Col::KineticColumn, QStringLiteral("abc"));
  QVERIFY2(friction->problemLabel()->text().contains(QStringLiteral("not a number")), qPrintable(friction->problemLabel()->text()));
  editCell(friction->view(), row, Col::KineticColumn, QStringLiteral("0.3"));  // above static 0.25
  QVERIFY2(friction->problemLabel()->text().contains(QStringLiteral("kinetic")), qPrintable(friction->problemLabel()->text()));
  QCOMPARE(world().materialFriction("brass"), before);
  QVERIFY(window_->statusBar()->currentMessage().startsWith(QStringLiteral("Refused")));

  editCell(friction->view(), row, Col::StaticColumn, QStringLiteral("0.42"));
  QTRY_COMPARE_WITH_TIMEOUT(world().materialFriction("brass").staticFriction, 0.42, kSettle);
  QVERIFY(model->problem(row, Col::StaticColumn).isEmpty());
  QVERIFY(window_->hasUnsavedChanges());
  QVERIFY(window_->windowTitle().contains(QStringLiteral("*")) || window_->isWindowModified());
  press(Qt::Key_Z, Qt::ControlModifier);
  QTRY_COMPARE_WITH_TIMEOUT(world().materialFriction("brass"), before, kSettle);
  QCOMPARE(model->index(row, Col::StaticColumn).data(Qt::EditRole).toString(), QStringLiteral("0.25"));
  press(Qt::Key_Z, Qt::ControlModifier | Qt::ShiftModifier);
  QTRY_COMPARE_WITH_TIMEOUT(world().materialFriction("brass").staticFriction, 0.42, kSettle);
  // Every one of these was recorded in the session as an edit with its step.
  QVERIFY(world().edits().size() >= 3);

  // A part's own friction: checking its row gives it its material's values, to edit on their own.
  const PartId sleeve = *assembly().findPart("sleeve");
  viewport()->selectPart(sleeve);
  QTRY_VERIFY_WITH_TIMEOUT(model->partRow() >= 0, kSettle);
  const int prow = model->partRow();
  const QRect box = friction->view()->visualRect(model->index(prow, Col::NameColumn));
  QTest::mouseClick(friction->view()->viewport(), Qt::LeftButton, {}, QPoint(box.left() + 10, box.center().y()));
  QTRY_COMPARE_WITH_TIMEOUT(model->index(prow, Col::NameColumn).data(Qt::CheckStateRole).toInt(), static_cast<int>(Qt::Checked), kSettle);
  editCell(friction->view(), prow, Col::KineticColumn, QStringLiteral("0.1"));
  QTRY_COMPARE_WITH_TIMEOUT(world().friction(sleeve).kineticFriction, 0.1, kSettle);
  QCOMPARE(world().materialFriction("brass").kineticFriction, before.kineticFriction);
}

// The gear swinging on its shaft (a session recorded by vaw-sim, paused at 2.5 s): choosing the paper's
// explicit method at 30 Hz in the Methods panel warns at once, in the panel, the inspector and the status
// bar, with a suggestion, while the swing's energy is what it was; played on, the swing gains energy as
// warned. The suggestion, applied with its button, makes it stable again.
void TestTuning::unstableMethodWarnsBeforeTheGearGainsEnergy() {
  const QString session = QStringLiteral(VAW_GEAR_SESSION);
  QVERIFY2(QFile::exists(session), qPrintable(session));
  open(session);
  QVERIFY(sim().isPlayback());
  sim().seek(sim().recorder().stepAt(2.5));
  const PartId gear = *assembly().findPart("gear");
  QCOMPARE(stateOf(world(), gear), QStringLiteral("ONBASESLIDE"));
  selectInTree(QStringLiteral("gear"));
  QTRY_COMPARE_WITH_TIMEOUT(sim().selected(), std::optional<PartId>(gear), kSettle);
  QVERIFY(window_->stabilityWarning().isEmpty());  // rk4 at 90 Hz

  // The swing's energy above hanging still: the hinge's kinetic and potential energy.
  const auto swing = [&] {
    const vaw::sim::PartReport r = vaw::sim::report(world(), gear);
    return r.kineticEnergy + r.potentialEnergy;
  };
  const double e0 = swing();
  auto* methods = window_->methodsDock();
  show(methods);
  auto* combo = methods->findChild<QComboBox*>(QStringLiteral("rotationMethod"));
  auto* rate = methods->findChild<QSpinBox*>(QStringLiteral("stepRate"));
  QVERIFY(combo != nullptr && rate != nullptr);
  QCOMPARE(combo->findText(QStringLiteral("exact")), -1);  // a method rotation cannot use is not offered
  setSpin(rate, QStringLiteral("30"));
  QTRY_COMPARE_WITH_TIMEOUT(world().settings().rate, 30.0, kSettle);
  combo->setFocus();
  const int paper = combo->findText(QStringLiteral("paper-explicit"));
  QVERIFY(paper >= 0);
  while (combo->currentIndex() > paper) QTest::keyClick(combo, Qt::Key_Up);
  QTRY_COMPARE_WITH_TIMEOUT(world().settings().rotationMethod, vaw::dyn::Method::PaperExplicit, kSettle);
  const double tWarned = world().time();
  QTRY_VERIFY_WITH_TIMEOUT(!window_->stabilityWarning().isEmpty(), kSettle);
  QVERIFY2(window_->stabilityWarning().contains(QStringLiteral("unstable (use rk4")), qPrintable(window_->stabilityWarning()));
  QVERIFY(methods->stabilityLabel()->text().contains(QStringLiteral("UNSTABLE")));
  QVERIFY(window_->partDock()->model()->value(QStringLiteral("Stability")).contains(QStringLiteral("UNSTABLE")));
  QCOMPARE(world().time(), tWarned);
  QCOMPARE(swing(), e0);  // warned before anything moved under the new method
  shot(window_.get(), QStringLiteral("tuning-unstable-warning.png"));
  shot(methods, QStringLiteral("tuning-methods.png"));

  show(window_->motionDock());
  sim().play();
  QTRY_VERIFY_WITH_TIMEOUT(swing() > e0 + 0.01, 6000);
  sim().pause();
  // The motion chart shows it: the recorded past replayed (from 0 s) and the growth sampled live.
  QTRY_VERIFY_WITH_TIMEOUT(!window_->motionDock()->samples().empty(), kSettle);
  const auto& samples = window_->motionDock()->samples();
  QCOMPARE(samples.begin()->second.t, 0.0);
  double after = -1e300;
  for (const auto& [step, x] : samples)
    if (x.t > tWarned) after = std::max(after, x.energy);
  QVERIFY2(after > e0 + 0.005, qPrintable(QStringLiteral("energy %1 J when warned, peak %2 J after").arg(e0).arg(after)));
  QCOMPARE(vaw::ui::MotionChartDock::sample(world(), gear).energy, swing());
  shot(window_.get(), QStringLiteral("tuning-motion-chart.png"));
  auto* suggestion = methods->findChild<QPushButton*>(QStringLiteral("applyStabilitySuggestion"));
  QVERIFY(suggestion->isVisible());
  QTest::mouseClick(suggestion, Qt::LeftButton);
  QTRY_VERIFY_WITH_TIMEOUT(window_->stabilityWarning().isEmpty(), kSettle);
  QCOMPARE(world().settings().rotationMethod, vaw::dyn::Method::RK4);
}

void TestTuning::selectInTree(const QString& name) {
  auto* tree = window_->sceneDock()->view();
  QModelIndex found;
  const std::function<void(const QModelIndex&)> find = [&](const QModelIndex& parent) {
    for (int r = 0; r < tree->model()->rowCount(parent); ++r) {
      const QModelIndex i = tree->model()->index(r, 0, parent);
      if (i.data().toString() == name) found = i;
      find(i);
    }
  };
  find({});
  QVERIFY2(found.isValid(), qPrintable(name));
  tree->scrollTo(found);
  QTest::mouseClick(tree->viewport(), Qt::LeftButton, {}, tree->visualRect(found).center());
}

// The Motion chart of a long session keeps a bounded number of samples, evenly spread over the whole
// recording, and still ends where the playhead is: an hour's session must not cost the window more than a
// minute's (it used to keep one sample per frame for ever).
void TestTuning::motionChartOfALongSessionStaysBounded() {
  open(bundled(QStringLiteral("gear-on-shaft.vaw.json")));
  const PartId gear = *assembly().findPart("gear");
  selectInTree(QStringLiteral("gear"));
  QTRY_COMPARE_WITH_TIMEOUT(sim().selected(), std::optional<PartId>(gear), kSettle);
  // 150 s of session at once, paced here rather than by the clock.
  sim().setExternalPacing(true);
  sim().play();
  const std::uint64_t before = world().stepCount();
  const auto steps = static_cast<int>(150.0 * world().settings().rate);
  sim().advance(steps);
  QCOMPARE(world().stepCount() - before, static_cast<std::uint64_t>(steps));
  // A chart that comes to the session now fills in its past from a replay, then follows it live.
  vaw::ui::MotionChartDock chart;
  chart.follow(sim(), true, false);
  const auto check = [&](const char* when) {
    const auto& samples = chart.samples();
    QVERIFY2(samples.size() <= vaw::ui::MotionChartDock::kMaxSamples && samples.size() > vaw::ui::MotionChartDock::kMaxSamples / 4,
             qPrintable(QStringLiteral("%1: %2 samples").arg(QLatin1String(when)).arg(samples.size())));
    QCOMPARE(samples.begin()->first, std::uint64_t{0});
    std::uint64_t gap = 0;
    for (auto it = std::next(samples.begin()); it != samples.end(); ++it) gap = std::max(gap, it->first - std::prev(it)->first);
    QVERIFY2(gap <= 2 * chart.spacing(), qPrintable(QStringLiteral("%1: a gap of %2 steps, spacing %3").arg(QLatin1String(when)).arg(gap).arg(chart.spacing())));
    QVERIFY2(world().stepCount() - samples.rbegin()->first <= 2 * chart.spacing(), when);
  };
  check("replayed");
  for (int i = 0; i < 3000; ++i) {
    sim().advance(3);
    chart.follow(sim(), false, false);
  }
  check("live");
  sim().setExternalPacing(false);
  sim().pause();
}

// The work-precision chart of the selected gear, computed in the background from the dock's button: every
// method the hinge offers at every rate, the peers where built, the method and rate the world uses ringed;
// choosing another method moves the ring without measuring again; Cancel stops a measurement.
void TestTuning::workPrecisionChartOfTheSelectedGear() {
  open(QStringLiteral(VAW_GEAR_SESSION));
  sim().seek(sim().recorder().stepAt(2.5));
  const PartId gear = *assembly().findPart("gear");
  selectInTree(QStringLiteral("gear"));
  QTRY_COMPARE_WITH_TIMEOUT(sim().selected(), std::optional<PartId>(gear), kSettle);
  auto* dock = window_->workPrecisionDock();
  show(dock);
  const std::string scenario = vaw::ui::WorkPrecisionDock::scenarioFor(world(), gear);
  QVERIFY(scenario == "gear-pendulum" || scenario == "gear-pendulum-damped");
  QCOMPARE(dock->scenario(), scenario);  // picked from the gear's model on its shaft
  QCOMPARE(world().settings().rotationMethod, vaw::dyn::Method::RK4);
  QCOMPARE(world().settings().rate, 90.0);

  QSignalSpy finished(dock, &vaw::ui::WorkPrecisionDock::finished);
  auto* compute = dock->findChild<QPushButton*>(QStringLiteral("workPrecisionCompute"));
  auto* progress = dock->findChild<QProgressBar*>(QStringLiteral("workPrecisionProgress"));
  QVERIFY(compute != nullptr && progress != nullptr);
  QTest::mouseClick(compute, Qt::LeftButton);
  QVERIFY(dock->busy());
  QVERIFY(!compute->isEnabled());
  QVERIFY(finished.wait(180000));
  QVERIFY(!dock->busy());
  QCOMPARE(progress->value(), progress->maximum());

  // Every method the hinge offers at every standard rate, and each peer engine built in.
  for (const vaw::dyn::Method m : vaw::dyn::Hinge::kMethods)
    for (const int rate : vaw::dyn::kStepRates) {
      const auto& rs = dock->records();
      const bool found = std::any_of(rs.begin(), rs.end(), [&](const vaw::dyn::Record& r) {
        return r.scenario == scenario && r.method == vaw::dyn::name(m) && r.stepRate == rate && std::isfinite(r.error);
      });
      QVERIFY2(found, qPrintable(QStringLiteral("%1 at %2 Hz").arg(QString::fromLatin1(vaw::dyn::name(m).data())).arg(rate)));
    }
  for (const auto& peer : vaw::peers::availablePeers()) {
    const auto& rs = dock->records();
    QVERIFY2(std::any_of(rs.begin(), rs.end(), [&](const vaw::dyn::Record& r) { return r.method == peer.name; }), peer.name.c_str());
  }
  const auto at = [&](const char* method, double rate) {
    for (const auto& r : dock->records())
      if (r.scenario == scenario && r.method == method && r.stepRate == rate) return r;
    return vaw::dyn::Record{};
  };
  // Fourth order against the paper's first-order explicit step: far smaller error at the same rate.
  QVERIFY(at("rk4", 90).error < 0.01 * at("paper-explicit", 90).error);

  // The ring: rk4 at 90 Hz, drawn at that record's point.
  auto highlight = dock->highlighted();
  QVERIFY(highlight.has_value());
  QCOMPARE(QString::fromStdString(highlight->method), QStringLiteral("rk4"));
  QCOMPARE(highlight->stepRate, 90.0);
  const auto ring = [&]() -> QScatterSeries* {
    for (QAbstractSeries* s : dock->chart()->series())
      if (s->name().startsWith(QStringLiteral("now: "))) return qobject_cast<QScatterSeries*>(s);
    return nullptr;
  };
  QVERIFY(ring() != nullptr);
  QCOMPARE(ring()->name(), QStringLiteral("now: rk4 at 90 Hz"));
  QCOMPARE(ring()->count(), 1);
  QCOMPARE(ring()->at(0).x(), highlight->cpuPerSimSecond);
  shot(dock, QStringLiteral("tuning-work-precision.png"));
  shot(window_.get(), QStringLiteral("tuning-work-precision-window.png"));

  // Another method in the Methods panel: the ring follows, nothing is measured again.
  auto* methods = window_->methodsDock();
  show(methods);
  auto* combo = methods->findChild<QComboBox*>(QStringLiteral("rotationMethod"));
  combo->setFocus();
  const int verlet = combo->findText(QStringLiteral("velocity-verlet"));
  QVERIFY(verlet >= 0);
  while (combo->currentIndex() > verlet) QTest::keyClick(combo, Qt::Key_Up);
  while (combo->currentIndex() < verlet) QTest::keyClick(combo, Qt::Key_Down);
  QTRY_COMPARE_WITH_TIMEOUT(world().settings().rotationMethod, vaw::dyn::Method::VelocityVerlet, kSettle);
  QTRY_COMPARE_WITH_TIMEOUT(ring() ? ring()->name() : QString(), QStringLiteral("now: velocity-verlet at 90 Hz"), kSettle);
  QCOMPARE(finished.count(), 1);

  // Cancel: the measurement stops, the chart keeps what it had.
  show(dock);
  const std::size_t before = dock->records().size();
  QTest::mouseClick(compute, Qt::LeftButton);
  QVERIFY(dock->busy());
  QTest::mouseClick(dock->findChild<QPushButton*>(QStringLiteral("workPrecisionCancel")), Qt::LeftButton);
  QVERIFY(!dock->busy());
  QVERIFY(compute->isEnabled());
  QCOMPARE(dock->records().size(), before);
  QTest::qWait(100);  // its queued last report arrives and is ignored
  QCOMPARE(finished.count(), 1);
}

// Every write the window makes (scene, session, timeline exports) into a folder that is not there fails with
// a message, and the window, the world and the unsaved tuning stay as they were; nothing is left behind.
void TestTuning::failedWritesAreReportedNotFatal() {
  open(bundled(QStringLiteral("gear-on-shaft.vaw.json")));
  auto* methods = window_->methodsDock();
  show(methods);
  setSpin(methods->findChild<QSpinBox*>(QStringLiteral("stepRate")), QStringLiteral("120"));
  QTRY_COMPARE_WITH_TIMEOUT(world().settings().rate, 120.0, kSettle);
  QVERIFY(window_->hasUnsavedChanges());
  const QString missing = dir_.filePath(QStringLiteral("no-such-folder"));
  QVERIFY(!window_->saveScene(missing + QStringLiteral("/tuned.vaw.json")));
  QVERIFY(!window_->saveSession(missing + QStringLiteral("/s.vaw-session.json")));
  QVERIFY(!window_->exportTimelineCsv(missing + QStringLiteral("/timeline.csv")));
  QVERIFY(!window_->exportTimelinePng(missing + QStringLiteral("/timeline.png")));
  QVERIFY(!QDir(missing).exists());
  QVERIFY(window_->isVisible());
  QVERIFY(window_->hasUnsavedChanges());
  QCOMPARE(world().settings().rate, 120.0);
}

// Save As writes the scene with the tuning; opened again (File > Open Recent) it starts with it. A file
// without a settings block (a bundled scene) still opens, with the defaults.
void TestTuning::savedSettingsReopenAndOldFilesOpen() {
  open(bundled(QStringLiteral("sleeve-on-shaft.vaw.json")));
  show(window_->gravityDock());
  setSpin(window_->gravityDock()->findChild<QDoubleSpinBox*>(QStringLiteral("gravitySlide")), QStringLiteral("0.5"));
  QTRY_COMPARE_WITH_TIMEOUT(world().settings().gravity.slide, 0.5, kSettle);
  show(window_->frictionDock());
  editCell(window_->frictionDock()->view(), window_->frictionDock()->model()->materialRow("brass"),
           vaw::ui::FrictionModel::KineticColumn, QStringLiteral("0.11"));
  QTRY_COMPARE_WITH_TIMEOUT(world().materialFriction("brass").kineticFriction, 0.11, kSettle);
  show(window_->methodsDock());
  setSpin(window_->methodsDock()->findChild<QSpinBox*>(QStringLiteral("stepRate")), QStringLiteral("120"));
  QTRY_COMPARE_WITH_TIMEOUT(world().settings().rate, 120.0, kSettle);
  QVERIFY(window_->hasUnsavedChanges());

  const QString target = dir_.filePath(QStringLiteral("tuned.vaw.json"));
  vaw::guitest::whenModal([target](QWidget* w) { vaw::guitest::answerFileDialog(w, target); });
  press(Qt::Key_S, Qt::ControlModifier | Qt::AltModifier);  // File > Save As
  QTRY_VERIFY_WITH_TIMEOUT(QFile::exists(target), kSettle);
  QVERIFY(!window_->hasUnsavedChanges());

  // The bundled original has no settings block: it opens with the defaults.
  open(bundled(QStringLiteral("sleeve-on-shaft.vaw.json")));
  QCOMPARE(world().settings().gravity.slide, 1.0);
  QCOMPARE(world().settings().rate, 90.0);
  QCOMPARE(world().materialFriction("brass").kineticFriction, 0.18);

  // File > Open Recent: the saved scene is the second entry (the bundled one, opened last, the first).
  auto* recent = window_->findChild<QMenu*>(QStringLiteral("recentMenu"));
  QVERIFY(recent != nullptr);
  QAction* entry = nullptr;
  for (QAction* a : recent->actions())
    if (a->toolTip() == QFileInfo(target).absoluteFilePath()) entry = a;
  QVERIFY(entry != nullptr);
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  entry->trigger();
  QVERIFY(loaded.wait(60000) || !loaded.isEmpty());
  QCOMPARE(controller_->currentPath(), target);
  QCOMPARE(world().settings().gravity.slide, 0.5);
  QCOMPARE(world().settings().rate, 120.0);
  QCOMPARE(world().materialFriction("brass").kineticFriction, 0.11);
  QCOMPARE(window_->gravityDock()->findChild<QDoubleSpinBox*>(QStringLiteral("gravitySlide"))->value(), 0.5);
  QCOMPARE(window_->methodsDock()->findChild<QSpinBox*>(QStringLiteral("stepRate"))->value(), 120);
}

// Tuning not saved: opening another file asks; Cancel keeps everything, Discard opens the other file.
void TestTuning::unsavedTuningIsAskedAbout() {
  open(bundled(QStringLiteral("sleeve-on-shaft.vaw.json")));
  show(window_->gravityDock());
  QTest::mouseClick(window_->gravityDock()->findChild<QPushButton*>(QStringLiteral("gravityPresetReal")), Qt::LeftButton);
  QTRY_COMPARE_WITH_TIMEOUT(world().settings().gravity.freeFlight, 1.0, kSettle);
  QVERIFY(window_->hasUnsavedChanges());
  const QString current = controller_->currentPath();
  bool asked = false;
  vaw::guitest::whenModal([&asked](QWidget* w) {
    asked = w->objectName() == QStringLiteral("unsavedChangesBox");
    clickButton(w, QMessageBox::Cancel);
  });
  window_->openFile(bundled(QStringLiteral("block-on-plate.vaw.json")));
  QVERIFY(asked);
  QCOMPARE(controller_->currentPath(), current);
  QCOMPARE(world().settings().gravity.freeFlight, 1.0);

  asked = false;
  vaw::guitest::whenModal([&asked](QWidget* w) {
    asked = w->objectName() == QStringLiteral("unsavedChangesBox");
    clickButton(w, QMessageBox::Discard);
  });
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  window_->openFile(bundled(QStringLiteral("block-on-plate.vaw.json")));
  QVERIFY(asked);
  QVERIFY(loaded.wait(60000) || !loaded.isEmpty());
  QVERIFY(controller_->currentPath().endsWith(QStringLiteral("block-on-plate.vaw.json")));
  QVERIFY(!window_->hasUnsavedChanges());
}

// The Friction dock closed with its close button and the Methods dock shown: a new window (a restart)
// has them so.
void TestTuning::dockLayoutSurvivesARestart() {
  open(bundled(QStringLiteral("sleeve-on-shaft.vaw.json")));
  show(window_->frictionDock());
  auto* close = window_->frictionDock()->findChild<QAbstractButton*>(QStringLiteral("qt_dockwidget_closebutton"));
  QVERIFY(close != nullptr);
  QTest::mouseClick(close, Qt::LeftButton);
  QVERIFY(!window_->frictionDock()->isVisible());
  show(window_->methodsDock());
  QVERIFY(window_->close());
  window_.reset();
  controller_.reset();
  makeWindow();
  QVERIFY(!window_->frictionDock()->isVisible());
  QVERIFY(window_->methodsDock()->isVisible());
  QVERIFY(!window_->frictionDock()->toggleViewAction()->isChecked());
}

QTEST_MAIN(TestTuning)
#include "tst_tuning.moc"
