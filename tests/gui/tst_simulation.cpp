// The workbench running the simulation, driven as a person drives it: real mouse presses, moves, wheel
// turns and key presses in the 3D view and the panels. Each test opens a bundled scene, lets the
// simulation run in real time and asserts on the world (through the window's SimulationController), the
// inspector, the timeline and the viewport. Screenshots go to the build tree (tests/gui/*.png).
//
// Runs under Xvfb (Qt3D needs GL); any Qt warning fails the test.
#include <Qt3DExtras/Qt3DWindow>
#include <Qt3DRender/QCamera>
#include <QCheckBox>
#include <QComboBox>
#include <QDialogButtonBox>
#include <QMenuBar>
#include <QProgressDialog>
#include <QDoubleSpinBox>
#include <QLineEdit>
#include <QProcess>
#include <QRegularExpression>
#include <QScreen>
#include <QSignalSpy>
#include <QSpinBox>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QWheelEvent>
#include <QtTest>
#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>

#include "gui_test_support.hpp"
#include "vaw/ui/path_dock.hpp"
#include <QLabel>
#include <QPushButton>
#include <QTableView>
#include <QtCharts/QChartView>
#include <QtCharts/QLineSeries>
#include <QtCharts/QScatterSeries>
#include "vaw/hash.hpp"
#include "vaw/paths.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/report.hpp"
#include "vaw/sim/session.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/message_log_model.hpp"
#include "vaw/ui/part_properties_model.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/timeline.hpp"
#include "vaw/ui/tuning.hpp"
#include "vaw/ui/viewport.hpp"
#include "vaw/units.hpp"

using vaw::PartId;
using vaw::interact::Event;
using vaw::interact::PartState;
using vaw::ui::AssemblyController;
using vaw::ui::MainWindow;

namespace {

using vaw::kDeg;

QString stateOf(const vaw::sim::World& w, PartId p) { return QString::fromStdString(std::string(vaw::interact::name(w.part(p).state))); }

// The events of one part, e.g. "grab:INHAND release:INSPACE hit-environment:STATIC".
QString eventsOf(const std::vector<vaw::sim::TransitionRecord>& log, PartId part) {
  QStringList out;
  for (const auto& t : log)
    if (t.part == part)
      out << QString::fromStdString(std::string(vaw::interact::name(t.event)) + ":" + std::string(vaw::interact::name(t.to)));
  return out.join(QLatin1Char(' '));
}

QColor colorOf(PartState s) {
  const auto c = vaw::view::stateColor(s);
  return QColor::fromRgbF(c.r, c.g, c.b);
}

}  // namespace

class TestSimulation : public QObject {
  Q_OBJECT

 public:
  static void initMain() {
    if (qEnvironmentVariableIsEmpty("QT3D_RENDERER")) qputenv("QT3D_RENDERER", "opengl");
  }

 private slots:
  void initTestCase();
  void cleanup();
  void cleanupTestCase();

  void grabMoveReleaseDropsAndRests();
  void playheadDragShowsTheRecordedPast();
  void sessionSavedInTheWindowReplaysBitForBit();
  void sessionOpensAndPlaysBack();
  void flickThrowsThePart();
  void twoHandPartRefusesAOneHandGrab();
  void tiltingTheBaseStartsTheBlockOnlyPastTheFrictionAngle();
  void gearReleasedOnItsShaftSwingsWithThePendulumPeriod();
  void pauseSingleStepAndSpeed();
  void hoistLiftsTheToolPart();
  void principalAxesAreDrawnOnRequest();
  void partOnTheFloorIsPickedUpAndPutBackOnTheTable();
  void shortMemoryGivesUpTheOldestSnapshotsNotTheProcess();
  void carriedNearItsMateThePartShowsTheCaptureZone();
  void fallingBehindIsShownWithTheRealRate();
  void carriedPathShowsItsSweptVolumeAndClearance();
  void theRecordingExportsAsAVideo();
  void aVideoFromTheViewportsEyeShowsWhatTheWindowShowed();
  void theRecordingExportsAsGltf();

 private:
  [[nodiscard]] vaw::ui::Viewport* viewport() const { return window_->viewport(); }
  [[nodiscard]] vaw::ui::SimulationController& sim() const { return window_->simulation(); }
  [[nodiscard]] const vaw::Assembly& assembly() const { return *controller_->assembly(); }
  [[nodiscard]] const vaw::sim::World& world() const { return sim().world(); }
  void open(const QString& scene);
  QPoint onPart(PartId part) {
    return vaw::guitest::pointOnPart(viewport(), assembly(), part, world().part(part).pose);
  }
  // A press at `from`, a move in `steps` to `to` (each after `msPerStep`), no release.
  void pressAndDrag(const QPoint& from, const QPoint& to, int steps, int msPerStep, Qt::KeyboardModifiers mods = {});
  void lookFrom(const Eigen::Vector3d& eye, const Eigen::Vector3d& centre);
  void screenshot(const QString& name);
  void setSpin(QDoubleSpinBox* box, double value);
  // As a person picks it: File clicked in the menu bar, then the item whose action is named `action`.
  void clickFileMenuItem(const QString& action);
  // In the sleeve-on-shaft scene, the sleeve carried with the mouse from where it waits, 130 mm over the
  // table, aside and down to 20 mm over it, and let go there; the sleeve's id.
  PartId carryTheSleeveAside();
  // File > Export Video: the size picked in the dialog by `sizeKey` (Home: the largest, End: the smallest),
  // the frame rate typed, the camera (the last entry, which must read `camera`) when given, `file` named in
  // the file dialog; returns once the export runs.
  void exportVideoThroughTheMenu(const QString& file, int sizeKey, const QString& fps, const QString& camera = {});

  vaw::guitest::Workbench bench_;
  std::unique_ptr<AssemblyController>& controller_ = bench_.controller;
  std::unique_ptr<MainWindow>& window_ = bench_.window;
  QTemporaryDir keep_;
  QString savedSession_;  // a session saved by one test for the next to open
};

void TestSimulation::initTestCase() {
  QVERIFY(bench_.start({.clearSettings = false, .autoPlay = std::nullopt, .size = {1280, 800}, .activate = false}));
}

void TestSimulation::cleanup() {
  if (window_) sim().pause();
  vaw::guitest::verifyNoWarnings();
}

void TestSimulation::cleanupTestCase() {
  bench_.stop();
}

void TestSimulation::open(const QString& scene) {
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  controller_->open(QFile::decodeName((vaw::resourceDir() / "scenes").string().c_str()) + QLatin1Char('/') + scene);
  QVERIFY(loaded.wait(60000) || !loaded.isEmpty());
  QVERIFY(sim().hasWorld());
  QVERIFY2(sim().isPlaying(), "the workbench runs the simulation as soon as a scene is open");
  sim().setSpeed(1.0);
  QVERIFY(!vaw::guitest::capture(viewport()).isNull());
}

void TestSimulation::pressAndDrag(const QPoint& from, const QPoint& to, int steps, int msPerStep,
                                  Qt::KeyboardModifiers mods) {
  vaw::guitest::pressAndDrag(viewport()->view3d(), from, to, steps, msPerStep, mods);
}

void TestSimulation::lookFrom(const Eigen::Vector3d& eye, const Eigen::Vector3d& centre) {
  Qt3DRender::QCamera* cam = viewport()->camera();
  cam->setViewCenter(QVector3D(static_cast<float>(centre.x()), static_cast<float>(centre.y()), static_cast<float>(centre.z())));
  cam->setPosition(QVector3D(static_cast<float>(eye.x()), static_cast<float>(eye.y()), static_cast<float>(eye.z())));
  cam->setUpVector(QVector3D(0, 0, 1));
  QVERIFY(!vaw::guitest::capture(viewport()).isNull());
}

void TestSimulation::screenshot(const QString& name) {
  QVERIFY(!vaw::guitest::capture(viewport()).isNull());
  QTest::qWait(200);
  const QPixmap shot = window_->screen()->grabWindow(window_->winId());
  QVERIFY(shot.save(vaw::guitest::shotPath(name)));
}

void TestSimulation::setSpin(QDoubleSpinBox* box, double value) {
  vaw::guitest::typeInto(box, QString::number(value));
  QCOMPARE(box->value(), value);
}

// Grab the sleeve with the mouse, lift it well above the table (the drop line and marker show its height),
// let go: INHAND -> INSPACE -> STATIC, and the timeline shows those three segments in the sleeve's lane.
void TestSimulation::grabMoveReleaseDropsAndRests() {
  open(QStringLiteral("sleeve-on-shaft.vaw.json"));
  const PartId sleeve = *assembly().findPart("sleeve");
  const QPoint p0 = onPart(sleeve);
  QVERIFY2(p0.x() >= 0, "the sleeve is visible");
  const double z0 = world().part(sleeve).pose.translation().z();
  pressAndDrag(p0, p0 + QPoint(0, -90), 12, 25);
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), sleeve), QStringLiteral("INHAND"), 5000);
  QTRY_VERIFY_WITH_TIMEOUT(world().part(sleeve).pose.translation().z() > z0 + 0.03, 3000);
  QVERIFY(viewport()->dragging() == sleeve);
  // While held: the inspector follows it and the frame carries a drop line to the table below.
  QTRY_COMPARE_WITH_TIMEOUT(window_->partDock()->model()->value(QStringLiteral("State")), QStringLiteral("INHAND"), 3000);
  QCOMPARE(window_->partDock()->model()->value(QStringLiteral("Holder")), QStringLiteral("right hand"));
  const auto& frame = sim().frame();
  QCOMPARE(frame.drops.size(), std::size_t{1});
  QCOMPARE(frame.drops[0].part, sleeve);
  QVERIFY2(frame.drops[0].from.z() - frame.drops[0].to.z() > 0.15, "held well above what is below it");
  QVERIFY(frame.hands[1].grab && frame.hands[1].holding == sleeve);
  screenshot(QStringLiteral("held-part.png"));
  vaw::guitest::capture(viewport()).save(vaw::guitest::shotPath(QStringLiteral("held-3d.png")));
  // Hold still, then let go: a slow release drops it.
  QTest::qWait(250);
  QTest::mouseRelease(viewport()->view3d(), Qt::LeftButton, {}, p0 + QPoint(0, -90));
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), sleeve), QStringLiteral("STATIC"), 8000);
  QCOMPARE(eventsOf(world().transitions(), sleeve), QStringLiteral("grab:INHAND release:INSPACE hit-environment:STATIC"));
  QVERIFY(std::abs(world().part(sleeve).pose.translation().z()) < 1e-3);  // on the table (its frame is at its bottom)
  QVERIFY(sim().frame().drops.empty());
  // The timeline: the sleeve's lane with its segments in the state colours.
  QTest::qWait(600);
  vaw::ui::TimelineView* timeline = window_->timelineDock()->view();
  QCOMPARE(timeline->lanes(), std::vector<PartId>{sleeve});
  const auto& log = window_->timelineDock()->model()->transitions();
  QCOMPARE(log.size(), std::size_t{3});
  const QImage image = timeline->render(1.0);
  const QRect lane = timeline->laneRect(0);
  const auto colourAt = [&](double t) { return image.pixelColor(static_cast<int>(std::lround(timeline->xOf(t))), lane.center().y()); };
  const auto close = [](const QColor& a, const QColor& b) {
    return std::abs(a.red() - b.red()) + std::abs(a.green() - b.green()) + std::abs(a.blue() - b.blue()) < 20;
  };
  QVERIFY(close(colourAt(0.5 * (log[0].t + log[1].t)), colorOf(PartState::InHand)));
  QVERIFY(close(colourAt(0.5 * (log[1].t + log[2].t)), colorOf(PartState::InSpace)));
  QVERIFY(close(colourAt(log[2].t + 0.2), colorOf(PartState::Static)));
  QVERIFY(image.save(vaw::guitest::shotPath(QStringLiteral("timeline.png"))));
  screenshot(QStringLiteral("after-drop.png"));
}

// Dragging the timeline's playhead back to the middle of the flight puts the sleeve where the recording
// had it at that step (compared with a headless replay of the recorded session, bit for bit), and the
// inspector shows that past.
void TestSimulation::playheadDragShowsTheRecordedPast() {
  const PartId sleeve = *assembly().findPart("sleeve");
  QVERIFY(sim().recorder().length() > 0);
  const auto& log = sim().recorder().transitions();
  QVERIFY(log.size() >= 3);
  const double mid = 0.5 * (log[1].t + log[2].t);  // in flight
  vaw::ui::TimelineView* timeline = window_->timelineDock()->view();
  timeline->setVisibleRange(0.0, std::max(5.0, sim().recorder().endTime()));
  const int y = timeline->axisHeight() - 4;
  const QPoint start(static_cast<int>(timeline->xOf(sim().recorder().endTime())), y);
  const QPoint target(static_cast<int>(std::lround(timeline->xOf(mid))), y);
  QTest::mousePress(timeline, Qt::LeftButton, {}, start);
  for (int i = 1; i <= 6; ++i) {
    QTest::mouseMove(timeline, start + (target - start) * i / 6);
    QTest::qWait(20);
  }
  QTest::mouseRelease(timeline, Qt::LeftButton, {}, target);
  QVERIFY(!sim().isPlaying());
  QVERIFY(sim().inPast());
  const std::uint64_t step = sim().recorder().step();
  QVERIFY2(step > log[1].step && step <= log[2].step, qPrintable(QString::number(step)));
  QCOMPARE(stateOf(world(), sleeve), QStringLiteral("INSPACE"));
  // The recorded pose at that step, from a headless replay of the session.
  Eigen::Isometry3d recorded = Eigen::Isometry3d::Identity();
  std::uint64_t n = 0;
  (void)vaw::sim::replay(sim().recorder().scenePtr(), sim().recorder().session(), [&](const vaw::sim::World& w) {
    if (++n == step) recorded = w.part(sleeve).pose;
  });
  QVERIFY(sim().frame().parts[sleeve].pose.matrix() == recorded.matrix());
  QTRY_COMPARE(window_->partDock()->model()->value(QStringLiteral("State")), QStringLiteral("INSPACE"));
  QVERIFY(window_->statusText().contains(QStringLiteral("in the past")));
  screenshot(QStringLiteral("scrubbed.png"));
  // Back to the end: the recording is whole again.
  QTest::keyClick(viewport()->view3d(), Qt::Key_End);
  QTRY_VERIFY(!sim().inPast());
  QCOMPARE(stateOf(world(), sleeve), QStringLiteral("STATIC"));
}

// File > Save Session writes what `vaw-sim run --replay` reads, and that replay ends in the same state
// hash as the window's world.
void TestSimulation::sessionSavedInTheWindowReplaysBitForBit() {
  QVERIFY(!sim().inPast());
  // An edit recorded with the inputs.
  sim().requestEdit(vaw::sim::MaterialFrictionEdit{"brass", {0.2, 0.15, 0.0005}});
  QTest::qWait(100);
  sim().pause();
  QTemporaryDir dir;
  QVERIFY(dir.isValid());
  const QString file = dir.filePath(QStringLiteral("gui.vaw-session.json"));
  QVERIFY(window_->saveSession(file));
  const std::string expected = vaw::hashText(world().stateHash());
  QVERIFY(!sim().recorder().session().edits.empty());
  QProcess run;
  run.start(QStringLiteral(VAW_SIM_EXE),
            {QStringLiteral("run"), QStringLiteral("--replay"), file, QStringLiteral("--out"), dir.filePath(QStringLiteral("out"))});
  QVERIFY(run.waitForFinished(60000));
  const QString out = QString::fromUtf8(run.readAllStandardOutput());
  QVERIFY2(run.exitCode() == 0, qPrintable(out + QString::fromUtf8(run.readAllStandardError())));
  QVERIFY2(out.contains(QStringLiteral("state hash ") + QString::fromStdString(expected)), qPrintable(out));
  QVERIFY2(out.contains(QStringLiteral("1 edits")), qPrintable(out));
  // The timeline's exports: the CSV has transitions.csv's columns and rows, the PNG is a picture of it.
  const QString csv = dir.filePath(QStringLiteral("timeline.csv"));
  QVERIFY(window_->exportTimelineCsv(csv));
  QFile exported(csv), reference(QDir(dir.filePath(QStringLiteral("out"))).filePath(QStringLiteral("transitions.csv")));
  QVERIFY(exported.open(QIODevice::ReadOnly) && reference.open(QIODevice::ReadOnly));
  QCOMPARE(exported.readAll(), reference.readAll());
  const QString png = dir.filePath(QStringLiteral("timeline.png"));
  QVERIFY(window_->exportTimelinePng(png));
  QVERIFY(QImage(png).width() > 500);
  savedSession_ = keep_.filePath(QStringLiteral("kept.vaw-session.json"));
  QFile::remove(savedSession_);
  QVERIFY(QFile::copy(file, savedSession_));
}

// Opening the saved session plays it back: paused at its start, Space plays the recorded inputs to the
// end (the view follows the recording, not the mouse) and stops there, in the state the recording ended.
void TestSimulation::sessionOpensAndPlaysBack() {
  QVERIFY(!savedSession_.isEmpty());
  const auto session = vaw::sim::loadSession(std::filesystem::path(QFile::encodeName(savedSession_).toStdString()));
  const std::string expected = vaw::hashText(vaw::sim::replay(sim().recorder().scenePtr(), session).stateHash());
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  controller_->open(savedSession_);
  QVERIFY(loaded.wait(60000) || !loaded.isEmpty());
  QVERIFY(sim().isPlayback());
  QVERIFY(!sim().isPlaying());
  QCOMPARE(world().stepCount(), std::uint64_t{0});
  QCOMPARE(sim().recorder().length(), session.inputs.size());
  QVERIFY(window_->timelineDock()->model()->rowCount() > 0);
  sim().setSpeed(2.0);
  QWindow* view = viewport()->view3d();
  view->requestActivate();
  QTRY_VERIFY(QGuiApplication::focusWindow() == view);
  QTest::keyClick(view, Qt::Key_Space);
  QVERIFY(sim().isPlaying());
  QTRY_VERIFY_WITH_TIMEOUT(!sim().isPlaying(), 30000);
  QVERIFY(sim().recorder().atEnd());
  QVERIFY(!sim().isPlayback());  // from here the desktop's hands drive it
  QCOMPARE(vaw::hashText(world().stateHash()), expected);
  QCOMPARE(sim().recorder().length(), session.inputs.size());
}

// A quick drag released while the mouse still moves throws the part: it leaves the hand with the velocity
// the world's windowed estimate gives and lands well away from where it was let go.
void TestSimulation::flickThrowsThePart() {
  open(QStringLiteral("sleeve-on-shaft.vaw.json"));
  const PartId sleeve = *assembly().findPart("sleeve");
  const QPoint p0 = onPart(sleeve);
  QVERIFY(p0.x() >= 0);
  pressAndDrag(p0, p0 + QPoint(0, -40), 4, 40);  // picked up, held a moment
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), sleeve), QStringLiteral("INHAND"), 3000);
  QTest::qWait(200);
  QWindow* w = viewport()->view3d();
  const QPoint from = p0 + QPoint(0, -40);
  // A fast move, let go while the world sees the hand moving: on a loaded machine the event loop may run
  // the moves before any step sees them, so it moves on until the release estimate is a throw.
  QPoint at = from;
  for (int i = 1; i <= 24; ++i) {
    at += QPoint(-15, 0);
    QTest::mouseMove(w, at);
    QTest::qWait(12);
    const auto tw = world().releaseVelocity(sleeve);
    if (i >= 8 && tw && tw->linear.head<2>().norm() > 0.3) break;
  }
  const Eigen::Vector3d released = world().part(sleeve).pose.translation();
  QTest::mouseRelease(w, Qt::LeftButton, {}, at);
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), sleeve), QStringLiteral("INSPACE"), 3000);
  const auto& release = world().transitions().back();
  QCOMPARE(release.event, Event::Release);
  const double speed = world().part(sleeve).velocity.head<2>().norm();
  QVERIFY2(speed > 0.2, qPrintable(QString::number(speed)));
  QTRY_VERIFY_WITH_TIMEOUT(world().part(sleeve).state != PartState::InSpace, 8000);
  const double carried = (world().part(sleeve).pose.translation() - released).head<2>().norm();
  QVERIFY2(carried > 0.02, qPrintable(QString::number(carried)));
}

// The tray of the hoist demo needs both hands: dragging it with one is refused, with the reason in the
// status bar, the messages and the inspector; it stays where it is. With Ctrl (both hands) it comes.
void TestSimulation::twoHandPartRefusesAOneHandGrab() {
  open(QStringLiteral("hoist-demo.vaw.json"));
  const PartId tray = *assembly().findPart("tray");
  QCOMPARE(assembly().parts[tray].category.category, vaw::Category::TwoHand);
  const Eigen::Isometry3d before = world().part(tray).pose;
  viewport()->selectPart(tray);
  const QPoint p = onPart(tray);
  QVERIFY(p.x() >= 0);
  // The hand closes when the drag starts, and the world reads the grab on its next step with the hand where
  // it is then: the rest of the drag waits for that step (on a loaded machine the moves could otherwise
  // come first and carry the hand out of reach before the world ever sees it close on the tray).
  QTest::mousePress(viewport()->view3d(), Qt::LeftButton, {}, p);
  for (int i = 1; i <= 12; ++i) {
    QTest::mouseMove(viewport()->view3d(), p + QPoint(0, -60) * i / 12);
    // Past the drag distance (10 px) the hand closes, a few millimetres above the tray.
    if (i * 5 > QApplication::startDragDistance() && !world().lastInput().right.grab)
      QTRY_VERIFY_WITH_TIMEOUT(world().lastInput().right.grab, 3000);
    QTest::qWait(12);
  }
  QTRY_VERIFY_WITH_TIMEOUT(!world().refusals().empty(), 3000);
  QTest::mouseRelease(viewport()->view3d(), Qt::LeftButton, {}, p + QPoint(0, -60));
  const auto& r = world().refusals().back();
  QCOMPARE(r.part, tray);
  QCOMPARE(r.event, Event::Grab);
  QVERIFY2(window_->statusBar()->currentMessage().contains(QStringLiteral("a two-hand part needs both hands")),
           qPrintable(window_->statusBar()->currentMessage()));
  auto* messages = window_->messagesDock()->model();
  QVERIFY(messages->text(messages->rowCount() - 1).contains(QStringLiteral("two-hand")));
  QTRY_VERIFY(window_->partDock()->model()->value(QStringLiteral("Last refusal")).contains(QStringLiteral("both hands")));
  QTest::qWait(200);
  QCOMPARE(stateOf(world(), tray), QStringLiteral("STATIC"));
  QVERIFY(world().part(tray).pose.matrix() == before.matrix());
  screenshot(QStringLiteral("refused.png"));
  // Both hands (Ctrl held while dragging) take it.
  pressAndDrag(p, p + QPoint(0, -40), 6, 25, Qt::ControlModifier);
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), tray), QStringLiteral("INHAND"), 3000);
  QCOMPARE(world().part(tray).holder, vaw::sim::Holder::Both);
  QTest::mouseRelease(viewport()->view3d(), Qt::LeftButton, Qt::ControlModifier, p + QPoint(0, -40));
  QTRY_VERIFY_WITH_TIMEOUT(world().part(tray).state != PartState::InHand, 3000);
}

// The block on the plate: the user puts it on the plate (a drag from above, a drop, a nudge), then tilts
// the base in the Base panel. At 16 degrees (below atan(0.30) = 16.70) it stays put, exactly; at 18 it
// starts to slide.
void TestSimulation::tiltingTheBaseStartsTheBlockOnlyPastTheFrictionAngle() {
  open(QStringLiteral("block-on-plate.vaw.json"));
  const PartId block = *assembly().findPart("block");
  const PartId plate = *assembly().base;
  // From straight above (almost: the orbit keeps the horizon), the hand moves the block horizontally.
  lookFrom({0.15, -0.03, 1.2}, {0.15, 0.0, 0.0});
  const QPoint from = onPart(block);
  QVERIFY(from.x() >= 0);
  // Over the plate's centre, at the height it was grabbed at: the drop lands it on the plate's face.
  const Eigen::Vector3d grabbed = world().part(block).pose.translation();
  const QPoint to = viewport()->projectToWindow(Eigen::Vector3d(0.0, 0.0, grabbed.z())).toPoint() +
                    (from - viewport()->projectToWindow(grabbed).toPoint());
  pressAndDrag(from, to, 10, 25);
  QTest::qWait(250);
  QTest::mouseRelease(viewport()->view3d(), Qt::LeftButton, {}, to);
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), block), QStringLiteral("STATIC"), 5000);
  QVERIFY2(eventsOf(world().transitions(), block).endsWith(QStringLiteral("hit-environment:STATIC")),
           qPrintable(eventsOf(world().transitions(), block)));
  // A nudge of the resting block: released on its mate, it goes onto the base.
  const QPoint at = onPart(block);
  pressAndDrag(at, at + QPoint(14, 0), 4, 25);
  QTest::qWait(150);
  QTest::mouseRelease(viewport()->view3d(), Qt::LeftButton, {}, at + QPoint(14, 0));
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), block), QStringLiteral("ONBASESTATIC"), 5000);
  // Below the static friction angle: it rides with the plate and does not move on it.
  auto* controls = window_->controlsDock();
  const Eigen::Isometry3d onPlate = world().basePose().inverse() * world().part(block).pose;
  setSpin(controls->tiltX(), 16.0);
  QTRY_VERIFY_WITH_TIMEOUT(std::abs(window_->simulation().baseAngles().tiltX - 16.0 * kDeg) < 1e-9, 3000);
  QTest::qWait(600);
  QCOMPARE(stateOf(world(), block), QStringLiteral("ONBASESTATIC"));
  const Eigen::Isometry3d stillOnPlate = world().basePose().inverse() * world().part(block).pose;
  QVERIFY2((stillOnPlate.translation() - onPlate.translation()).norm() < 1e-12, "0 m on the plate");
  QVERIFY(world().part(plate).pose.isApprox(world().basePose(), 0.0));
  screenshot(QStringLiteral("tilted-16.png"));
  // Past it: the block starts to slide down the plate.
  setSpin(controls->tiltX(), 18.0);
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), block), QStringLiteral("ONBASESLIDE"), 3000);
  const auto& started = world().transitions().back();
  QCOMPARE(started.event, Event::StaticFrictionOvercome);
  // It started on the way from 16 to 18 degrees, past the friction angle atan(0.30) = 16.70 degrees.
  const auto match = QRegularExpression(QStringLiteral("surface slope=([0-9.]+) deg")).match(QString::fromStdString(started.cause));
  QVERIFY2(match.hasMatch(), started.cause.c_str());
  const double slope = match.captured(1).toDouble();
  QVERIFY2(slope > std::atan(0.30) / kDeg && slope <= 18.0 + 1e-9, started.cause.c_str());
  QTest::qWait(150);
  screenshot(QStringLiteral("sliding.png"));
}

// The gear: brought to its shaft (turned a quarter about y with Z held, moved onto the axis, rolled about it
// with C so that it hangs off-centre) and released,
// it swings as a damped pendulum; each period, taken from a headless replay of what the window recorded,
// is within 1 % of the large-amplitude pendulum's 4 sqrt(J / (m g d)) K(sin(a / 2)).
void TestSimulation::gearReleasedOnItsShaftSwingsWithThePendulumPeriod() {
  open(QStringLiteral("gear-on-shaft.vaw.json"));
  const PartId gear = *assembly().findPart("gear");
  const vaw::Part& g = assembly().parts[gear];
  // Looking along -x: the hand moves in the y-z plane, Z turns about the view's horizontal axis (y).
  lookFrom({0.9, 0.25, 0.1}, {0.0, 0.25, 0.1});
  const QPoint p = onPart(g.id);
  QVERIFY(p.x() >= 0);
  pressAndDrag(p, p + QPoint(0, -12), 3, 30);
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), gear), QStringLiteral("INHAND"), 3000);
  QTest::keyPress(viewport()->view3d(), Qt::Key_Z);
  const Eigen::Vector3d u = Eigen::Vector3d::UnitX();
  // Stopped once the gear's axis is within 10 degrees of the shaft's (recognition snaps the rest): a
  // narrower window could be passed between two looks under load and end a half turn later.
  const auto alignment = [&] { return std::abs((world().part(gear).pose.linear() * Eigen::Vector3d::UnitZ()).dot(u)); };
  QTRY_VERIFY_WITH_TIMEOUT(alignment() > std::cos(8.0 * kDeg), 5000);
  QTest::keyRelease(viewport()->view3d(), Qt::Key_Z);
  QTest::qWait(100);
  QVERIFY2(alignment() > std::cos(10.0 * kDeg), qPrintable(QString::number(std::acos(alignment()) / kDeg)));
  // Rolled about the view's axis (C; the turn is about the hand, so the bore moves, and is put back below)
  // until its centre of mass, which now hangs straight below the bore, is 22-40 degrees out.
  const auto offHanging = [&] {  // the angle of the centre of mass from straight below the bore, about x
    const Eigen::Vector3d r = world().part(gear).pose * g.mass.centerOfMass - world().part(gear).pose.translation();
    return std::abs(std::atan2(r.y(), -r.z()));
  };
  QTest::keyPress(viewport()->view3d(), Qt::Key_C);
  QTRY_VERIFY_WITH_TIMEOUT(offHanging() > 22.0 * kDeg, 5000);
  QTest::keyRelease(viewport()->view3d(), Qt::Key_C);
  QTest::qWait(100);
  QVERIFY2(offHanging() < 40.0 * kDeg, qPrintable(QString::number(offHanging() / kDeg)));
  // Away from the camera (along the view, -x) with the wheel to x = 0, on the shaft (its assembled place is
  // at x = 60 mm: released there it would be PLACED): 5 % of the distance along the view a notch.
  const Eigen::Vector3d eye(0.9, 0.25, 0.1);
  const double distance = eye.x() - sim().handPosition().x();
  const double notches = world().part(gear).pose.translation().x() / (0.05 * distance);
  const QPoint pointer = viewport()->projectToWindow(sim().handPosition()).toPoint();
  QWheelEvent wheel(QPointF(pointer), viewport()->view3d()->mapToGlobal(QPointF(pointer)), QPoint(),
                    QPoint(0, static_cast<int>(std::lround(notches * 120.0))), Qt::LeftButton, Qt::NoModifier,
                    Qt::NoScrollPhase, false);
  QCoreApplication::sendEvent(viewport()->view3d(), &wheel);
  QTest::qWait(150);
  QVERIFY2(std::abs(world().part(gear).pose.translation().x()) < 0.01,
           qPrintable(QString::number(world().part(gear).pose.translation().x())));
  // Its bore's centre onto the shaft's axis (y = 0, z = 150 mm): the hand moves by the difference.
  const Eigen::Vector3d bore = world().part(gear).pose.translation();
  const Eigen::Vector3d hand = sim().handPosition();
  const Eigen::Vector3d wanted = hand + Eigen::Vector3d(0.0, -bore.y(), 0.15 - bore.z());
  const QPoint target = viewport()->projectToWindow(wanted).toPoint();
  const QPoint now = viewport()->projectToWindow(hand).toPoint();
  for (int i = 1; i <= 10; ++i) {
    QTest::mouseMove(viewport()->view3d(), now + (target - now) * i / 10);
    QTest::qWait(25);
  }
  QTest::qWait(300);
  QTest::mouseRelease(viewport()->view3d(), Qt::LeftButton, {}, target);  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), gear), QStringLiteral("ONBASESLIDE"), 3000);
  QVERIFY2(eventsOf(world().transitions(), gear).endsWith(QStringLiteral("constraint-recognized:ONBASESTATIC static-friction-overcome:ONBASESLIDE")),
           qPrintable(eventsOf(world().transitions(), gear)));
  QTest::qWait(3500);
  screenshot(QStringLiteral("gear-swinging.png"));
  sim().pause();
  // Every step of the swing, from a replay of the recording.
  const std::uint64_t swingFrom = world().transitions().back().step;
  std::vector<double> phis, ts;
  const Eigen::Vector3d axisPoint(0, 0, 0.15);
  (void)vaw::sim::replay(sim().recorder().scenePtr(), sim().recorder().session(), [&](const vaw::sim::World& w) {
    if (w.stepCount() <= swingFrom) return;
    const Eigen::Vector3d com = w.part(gear).pose * g.mass.centerOfMass - axisPoint;
    phis.push_back(std::atan2(com.y(), -com.z()));  // from hanging straight down, about +x
    ts.push_back(w.time());
  });
  std::vector<double> crossings, peaks;
  double peak = 0.0;
  for (std::size_t i = 1; i < phis.size(); ++i) {
    peak = std::max(peak, std::abs(phis[i]));
    if (phis[i - 1] > 0.0 && phis[i] <= 0.0) {
      crossings.push_back(ts[i - 1] + (ts[i] - ts[i - 1]) * phis[i - 1] / (phis[i - 1] - phis[i]));
      peaks.push_back(peak);
      peak = 0.0;
    }
  }
  QVERIFY2(crossings.size() >= 3, qPrintable(QString::number(crossings.size())));
  const Eigen::Isometry3d atRest = world().part(gear).pose;
  const Eigen::Vector3d uPart = atRest.linear().transpose() * u;
  const Eigen::Vector3d r = atRest * g.mass.centerOfMass - axisPoint;
  const double d = (r - u * u.dot(r)).norm();
  const double J = uPart.dot(g.mass.inertiaCm * uPart) + g.mass.mass * d * d;
  const double w0 = std::sqrt(g.mass.mass * vaw::kStandardGravity * d / J);
  const double zeta = assembly().materials.at(g.material).rotationalFriction / (2.0 * J * w0);
  double worst = 0.0;
  for (std::size_t k = 1; k < crossings.size(); ++k) {
    const double expected = 4.0 / w0 * std::comp_ellint_1(std::sin(peaks[k] / 2.0)) / std::sqrt(1.0 - zeta * zeta);
    worst = std::max(worst, std::abs((crossings[k] - crossings[k - 1]) / expected - 1.0));
  }
  QStringList detail;
  for (std::size_t k = 0; k < crossings.size(); ++k)
    detail << QStringLiteral("%1 s (peak %2 deg)").arg(crossings[k], 0, 'f', 4).arg(peaks[k] / kDeg, 0, 'f', 2);
  QVERIFY2(worst < 0.01, qPrintable(QStringLiteral("worst period error %1; crossings %2; events %3")
                                        .arg(worst)
                                        .arg(detail.join(QStringLiteral(", ")))
                                        .arg(eventsOf(world().transitions(), gear))));
}

// Space pauses and plays, "." steps exactly one step, "[" and "]" change the speed, and the simulated time
// follows the wall clock times the speed.
void TestSimulation::pauseSingleStepAndSpeed() {
  QWindow* view = viewport()->view3d();
  view->requestActivate();
  QTRY_VERIFY(QGuiApplication::focusWindow() == view);
  if (sim().isPlaying()) QTest::keyClick(view, Qt::Key_Space);
  QVERIFY(!sim().isPlaying());
  const std::uint64_t n = world().stepCount();
  QTest::qWait(300);
  QCOMPARE(world().stepCount(), n);
  QTest::keyClick(view, Qt::Key_Period);
  QCOMPARE(world().stepCount(), n + 1);
  QTest::keyClick(view, Qt::Key_Period);
  QCOMPARE(world().stepCount(), n + 2);
  QTest::keyClick(view, Qt::Key_BracketLeft);
  QCOMPARE(sim().speed(), 0.5);
  QTest::keyClick(view, Qt::Key_BracketLeft);
  QCOMPARE(sim().speed(), 0.25);
  QTest::keyClick(view, Qt::Key_Space);
  QVERIFY(sim().isPlaying());
  QElapsedTimer wall;
  wall.start();
  const double t0 = world().time();
  QTest::qWait(1500);
  const double ratio = (world().time() - t0) / (static_cast<double>(wall.elapsed()) * 1e-3);
  QVERIFY2(ratio > 0.15 && ratio < 0.3, qPrintable(QString::number(ratio)));  // 0.25 within a step either way
  for (int i = 0; i < 2; ++i) QTest::keyClick(view, Qt::Key_BracketRight);
  QCOMPARE(sim().speed(), 1.0);
  QTest::keyClick(view, Qt::Key_BracketRight);
  QTest::keyClick(view, Qt::Key_BracketRight);
  QCOMPARE(sim().speed(), 2.0);
  QTest::keyClick(view, Qt::Key_BracketRight);
  QCOMPARE(sim().speed(), 2.0);
  QTest::keyClick(view, Qt::Key_Space);
  QVERIFY(!sim().isPlaying());
  QVERIFY(window_->statusText().contains(QStringLiteral("paused")));
}

// The hoist demo's 40 kg block: the hook is lowered in the panel, H closes it on the block (ONTOOL),
// Shift+Up raises it, H again sets the block down where it hangs (a tool part does not fly).
void TestSimulation::hoistLiftsTheToolPart() {
  open(QStringLiteral("hoist-demo.vaw.json"));
  const PartId block = *assembly().findPart("block");
  auto* controls = window_->controlsDock();
  QVERIFY(controls->hoistEngaged()->isVisibleTo(window_.get()));
  setSpin(controls->hoistHeight(), 150.0);
  QWindow* view = viewport()->view3d();
  view->requestActivate();
  QTRY_VERIFY(QGuiApplication::focusWindow() == view);
  QTest::qWait(100);
  QTest::keyClick(view, Qt::Key_H);
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), block), QStringLiteral("ONTOOL"), 3000);
  QVERIFY(controls->hoistEngaged()->isChecked());
  // QTest's key functions let the event loop run, so a step or two may pass around each key: the lift is
  // bracketed by the simulated time from the press to just before and to just after the release.
  QTest::keyPress(view, Qt::Key_Shift);
  QTest::keyPress(view, Qt::Key_Up, Qt::ShiftModifier);
  const double z0 = world().part(block).pose.translation().z();
  const double t0 = world().time();
  QTest::qWait(600);
  const double t1 = world().time();
  QTest::keyRelease(view, Qt::Key_Up, Qt::ShiftModifier);
  const double t2 = world().time();
  QTest::keyRelease(view, Qt::Key_Shift);
  const double lifted = world().part(block).pose.translation().z() - z0;
  const double h = world().settings().step();
  QVERIFY2(lifted > 0.03 && lifted >= 0.15 * (t1 - t0) - 1e-9 && lifted <= 0.15 * (t2 - t0 + h) + 1e-9,
           qPrintable(QStringLiteral("%1 m in %2-%3 s").arg(lifted).arg(t1 - t0).arg(t2 - t0)));
  // Along the hoist's vertical line only.
  QVERIFY(std::abs(world().part(block).pose.translation().x() - 0.5) < 1e-9);
  QTRY_VERIFY(std::abs(controls->hoistHeight()->value() - sim().hoist().height * 1e3) < 0.5);
  QVERIFY(sim().frame().hoists.size() == 1 && sim().frame().hoists[0].load == block);
  screenshot(QStringLiteral("hoist.png"));
  QTest::keyClick(view, Qt::Key_H);
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), block), QStringLiteral("STATIC"), 3000);
  QCOMPARE(world().transitions().back().event, Event::ToolDetach);
}

// Ticking "Show principal axes" draws three lines through the selected part's centre of mass.
void TestSimulation::principalAxesAreDrawnOnRequest() {
  const PartId block = *assembly().findPart("block");
  viewport()->selectPart(block);
  const QImage before = vaw::guitest::capture(viewport());
  QCheckBox* box = window_->partDock()->axesBox();
  QTest::mouseClick(box, Qt::LeftButton);
  QVERIFY(box->isChecked());
  QImage after;
  int changed = 0;
  for (int attempt = 0; attempt < 3 && changed < 100; ++attempt) {
    after = vaw::guitest::capture(viewport());
    changed = 0;
    for (int y = 0; y < after.height(); ++y)
      for (int x = 0; x < after.width(); ++x) changed += vaw::guitest::differs(before.pixel(x, y), after.pixel(x, y), 40) ? 1 : 0;
  }
  QVERIFY2(changed >= 100, qPrintable(QString::number(changed)));
  screenshot(QStringLiteral("principal-axes.png"));
  QTest::mouseClick(box, Qt::LeftButton);
  QVERIFY(!box->isChecked());
}

// A part carried off the table and let go falls to the room's default floor, 0.72 m below the table's top,
// and rests there STATIC "on the floor" (the scene tree lists the floor); taken from the floor with the
// mouse and let go over the table, it lands on the table again.
void TestSimulation::partOnTheFloorIsPickedUpAndPutBackOnTheTable() {
  open(QStringLiteral("sleeve-on-shaft.vaw.json"));
  const PartId sleeve = *assembly().findPart("sleeve");
  Eigen::AlignedBox3d table;
  std::optional<double> floorTop;
  for (const auto& e : assembly().environment) {
    const Eigen::AlignedBox3d b(e.pose * e.mesh->bounds().min(), e.pose * e.mesh->bounds().max());
    if (e.kind == "table") table = b;
    if (e.kind == "floor") floorTop = b.max().z();
  }
  QVERIFY2(floorTop.has_value(), "the scene declares none: the default floor");
  QCOMPARE(*floorTop, table.max().z() - 0.72);
  const auto lowest = [&] {
    double low = 1e9;
    for (const auto& v : assembly().parts[sleeve].mesh->vertices) low = std::min(low, (world().part(sleeve).pose * v).z());
    return low;
  };
  // Off the table's far edge, 5 cm above its top: let go, it falls to the floor.
  Eigen::Isometry3d beside = world().part(sleeve).pose;
  beside.translation() += Eigen::Vector3d(table.max().x() + 0.12 - world().part(sleeve).pose.translation().x(), 0.0, 0.05);
  vaw::guitest::carryWithMouse(*window_, sleeve, beside, "sleeve");
  if (QTest::currentTestFailed()) return;
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), sleeve), QStringLiteral("STATIC"), 8000);
  QVERIFY2(std::abs(lowest() - *floorTop) < 1e-3, qPrintable(QString::number(lowest())));
  QVERIFY(QString::fromStdString(world().transitions().back().cause).startsWith(QStringLiteral("on the floor")));
  lookFrom(Eigen::Vector3d(table.max().x() + 1.2, -1.6, table.max().z() + 0.6), Eigen::Vector3d(table.max().x(), 0.0, *floorTop + 0.2));
  screenshot(QStringLiteral("part-on-the-floor.png"));
  // Back from the floor onto the table, 2 cm above it near its corner.
  Eigen::Isometry3d back = world().part(sleeve).pose;
  back.translation() += Eigen::Vector3d(table.max().x() - 0.15 - back.translation().x(), 0.0, table.max().z() + 0.02 - lowest());
  vaw::guitest::carryWithMouse(*window_, sleeve, back, "sleeve");
  if (QTest::currentTestFailed()) return;
  QTRY_COMPARE_WITH_TIMEOUT(stateOf(world(), sleeve), QStringLiteral("STATIC"), 8000);
  QVERIFY2(std::abs(lowest() - table.max().z()) < 1e-3, qPrintable(QString::number(lowest())));
  QVERIFY(QString::fromStdString(world().transitions().back().cause).startsWith(QStringLiteral("hit table")));
}

// When the machine runs short of memory the recording gives up its oldest snapshots, says so in Messages and
// the status bar, and goes on: the session is whole and seeking into the given-up past still works.
void TestSimulation::shortMemoryGivesUpTheOldestSnapshotsNotTheProcess() {
  open(QStringLiteral("sleeve-on-shaft.vaw.json"));
  QTRY_VERIFY_WITH_TIMEOUT(sim().recorder().snapshotCount() >= 4, 15000);
  QSignalSpy given(&sim(), &vaw::ui::SimulationController::pastGivenUp);
  sim().setMemoryProbe([] { return std::optional<std::size_t>(std::size_t{100} << 20); }, 100);
  QVERIFY(given.wait(5000));
  sim().setMemoryProbe(&vaw::ui::SimulationController::availableMemory);
  const double before = given.first().first().toDouble();
  QVERIFY(before > 0.0);
  QCOMPARE(sim().recorder().snapshotSteps().front(), std::uint64_t{0});
  const auto* messages = window_->messagesDock()->model();
  bool said = false;
  for (int row = 0; row < messages->rowCount(); ++row) said = said || messages->text(row).contains(QStringLiteral("Memory is short"));
  QVERIFY2(said, "Messages says the past was given up");
  QVERIFY(window_->statusBar()->currentMessage().contains(QStringLiteral("Memory is short")));
  // Seeking into the given-up past replays from the start and lands where a fresh replay does.
  sim().pause();
  const std::uint64_t step = sim().recorder().stepAt(0.5 * before);
  sim().seek(step);
  QCOMPARE(sim().recorder().step(), step);
  vaw::sim::Session upTo = sim().recorder().session();
  upTo.inputs.resize(step);
  QCOMPARE(vaw::sim::replay(sim().recorder().scenePtr(), upTo).stateHash(), sim().world().stateHash());
}

// Carried near its shaft, the sleeve shows where it must be let go: the capture zone round the shaft's axis
// in the viewport (red while a release would not take, green when it would) and, in the status bar, how
// far off it is and how near it must be. Let go where it is green, it goes onto the shaft.
void TestSimulation::carriedNearItsMateThePartShowsTheCaptureZone() {
  open(QStringLiteral("sleeve-on-shaft.vaw.json"));
  const PartId sleeve = *assembly().findPart("sleeve");
  Eigen::Isometry3d off = *assembly().parts[sleeve].finalPose;
  off.translation() += Eigen::Vector3d(0.025, 0.0, 0.01);
  vaw::guitest::carryWithMouse(*window_, sleeve, off, "sleeve", false);
  if (QTest::currentTestFailed()) return;
  QTRY_VERIFY_WITH_TIMEOUT(viewport()->captureZone().has_value(), 2000);
  QVERIFY(!viewport()->captureZone()->captures);
  QVERIFY2((viewport()->captureZone()->direction.cross(Eigen::Vector3d::UnitZ())).norm() < 1e-9, "the shaft's axis is vertical");
  const auto statusText = [&] { return window_->statusText(); };
  QVERIFY2(statusText().contains(QStringLiteral("let go within 10 mm")), qPrintable(statusText()));
  QVERIFY2(statusText().contains(QRegularExpression(QStringLiteral("sleeve is 2[2-8](\\.\\d)? mm"))), qPrintable(statusText()));
  screenshot(QStringLiteral("capture-zone-red.png"));
  Eigen::Isometry3d on = *assembly().parts[sleeve].finalPose;
  on.translation() += Eigen::Vector3d(0.003, 0.0, 0.01);
  vaw::guitest::moveCarriedWithMouse(*window_, sleeve, on, "sleeve");
  if (QTest::currentTestFailed()) return;
  QTRY_VERIFY_WITH_TIMEOUT(viewport()->captureZone() && viewport()->captureZone()->captures, 2000);
  QVERIFY2(statusText().contains(QStringLiteral("let go now and sleeve goes onto base")), qPrintable(statusText()));
  screenshot(QStringLiteral("capture-zone-green.png"));
  vaw::guitest::releaseWithMouse(*window_);
  QTRY_VERIFY_WITH_TIMEOUT(world().part(sleeve).state != PartState::InHand, 3000);
  const PartState s = world().part(sleeve).state;
  QVERIFY2(s == PartState::OnBaseSlide || s == PartState::OnBaseStatic || s == PartState::Placed, qPrintable(stateOf(world(), sleeve)));
  QTRY_VERIFY_WITH_TIMEOUT(!viewport()->captureZone().has_value(), 2000);
}

// A world the timer cannot keep up with (5000 steps a second: each 4 ms tick owes 20 steps and may run 5)
// runs slower than real time: the status bar gives the real rate instead of "1×", and Messages says so
// once. Back at 90 Hz it catches up and the status bar shows the speed again.
void TestSimulation::fallingBehindIsShownWithTheRealRate() {
  open(QStringLiteral("sleeve-on-shaft.vaw.json"));
  QTest::qWait(2500);  // two seconds of play at 90 Hz: the meter's window
  QVERIFY2(!sim().isBehind(), qPrintable(window_->statusText()));
  QVERIFY2(window_->statusText().contains(QStringLiteral(" 1.0× ")), qPrintable(window_->statusText()));
  auto* methods = window_->methodsDock();
  methods->show();
  methods->raise();
  auto* rate = methods->findChild<QSpinBox*>(QStringLiteral("stepRate"));
  QVERIFY(rate != nullptr);
  vaw::guitest::typeInto(rate, QStringLiteral("5000"));
  QTRY_COMPARE_WITH_TIMEOUT(world().settings().rate, 5000.0, 3000);
  QTRY_VERIFY_WITH_TIMEOUT(sim().isBehind(), 6000);
  const QString status = window_->statusText();
  QVERIFY2(status.contains(QRegularExpression(QStringLiteral("0\\.\\d\\d× of real time, "))), qPrintable(status));
  QVERIFY(sim().realRate() && sim().realRate()->rate < 0.95);
  const auto* messages = window_->messagesDock()->model();
  bool said = false;
  for (int row = 0; row < messages->rowCount(); ++row) said = said || messages->text(row).contains(QStringLiteral("cannot keep up with real time"));
  QVERIFY2(said, "Messages says the simulation falls behind");
  screenshot(QStringLiteral("falling-behind.png"));
  vaw::guitest::typeInto(rate, QStringLiteral("90"));
  QTRY_VERIFY_WITH_TIMEOUT(!sim().isBehind(), 8000);
  QVERIFY2(window_->statusText().contains(QStringLiteral(" 1.0× ")), qPrintable(window_->statusText()));
}

// A carry recorded with the mouse, then in the Path panel as a person uses it: the voxel typed in, Sweep
// clicked; the swept volume shows translucent in the viewport and holds the part where it started and
// where it was let go; the clearance chart has a point per carried step, the table an object per row; a
// larger near-miss threshold marks more steps; Export writes the STL through the file dialog.
void TestSimulation::carriedPathShowsItsSweptVolumeAndClearance() {
  open(QStringLiteral("sleeve-on-shaft.vaw.json"));
  const Eigen::Isometry3d start = world().part(*assembly().findPart("sleeve")).pose;
  const PartId sleeve = carryTheSleeveAside();
  if (QTest::currentTestFailed()) return;
  QTRY_VERIFY_WITH_TIMEOUT(world().part(sleeve).state != PartState::InHand, 3000);
  sim().pause();

  vaw::ui::PathDock* path = window_->pathDock();
  path->show();
  path->raise();
  viewport()->selectPart(sleeve);
  QTRY_VERIFY_WITH_TIMEOUT(path->sweepButton()->isEnabled(), 2000);
  vaw::guitest::typeInto(path->voxelBox(), QStringLiteral("2"));
  QCOMPARE(path->voxelBox()->value(), 2.0);
  QSignalSpy done(path, &vaw::ui::PathDock::finishedSweep);
  QTest::mouseClick(path->sweepButton(), Qt::LeftButton);
  QVERIFY(path->working());
  QVERIFY(done.wait(60000));
  QVERIFY2(path->swept() != nullptr, qPrintable(path->summary()->text()));
  const vaw::SweptVolume& sv = *path->swept();
  const vaw::sim::ClearanceReport& cr = *path->clearance();
  // It holds the sleeve's own volume, and the points of its mesh where the carry began.
  QVERIFY(sv.volume > vaw::massPropertiesFromMesh(*assembly().parts[sleeve].mesh, 1.0).mass);
  for (const Eigen::Vector3d& v : assembly().parts[sleeve].mesh->vertices) QVERIFY(sv.contains(start * v));
  QVERIFY(viewport()->sweptVolumeShown());
  QVERIFY2(path->summary()->text().contains(QStringLiteral("sleeve swept")), qPrintable(path->summary()->text()));
  // The part panel has it too, with the voxel.
  const QString row = window_->partDock()->model()->value(QStringLiteral("Swept volume"));
  QVERIFY2(row.contains(QStringLiteral("cm³, voxel 2 mm")), qPrintable(row));
  QCOMPARE(path->distanceSeries()->count(), static_cast<int>(cr.steps.size()));
  QVERIFY(cr.steps.size() > 10);
  QCOMPARE(path->table()->model()->rowCount(), static_cast<int>(cr.objects.size()));
  QVERIFY2(!cr.objects.empty() && cr.objects.front().name == "table", "the carry ended close over the table");
  const int nearAt5 = path->nearSeries()->count();
  vaw::guitest::typeInto(path->thresholdBox(), QStringLiteral("60"));
  QTRY_VERIFY_WITH_TIMEOUT(path->nearSeries()->count() > nearAt5, 2000);
  lookFrom(start.translation() + Eigen::Vector3d(0.35, -0.45, 0.3), start.translation() + Eigen::Vector3d(-0.03, 0.02, 0.03));
  screenshot(QStringLiteral("path-swept-volume.png"));
  vaw::guitest::shot(window_.get(), path->chartView(), QStringLiteral("path-clearance-chart.png"));

  // Export, as a person does: the button, the file dialog; an STL, then a STEP solid (through the STEP
  // plugin, in the background) that the workbench reads back with the voxels' volume.
  QSignalSpy exported(path, &vaw::ui::PathDock::exported);
  const QString target = keep_.filePath(QStringLiteral("sleeve-swept.stl"));
  vaw::guitest::whenModal([target](QWidget* w) { vaw::guitest::answerFileDialog(w, target); });
  QTest::mouseClick(path->exportButton(), Qt::LeftButton);
  QVERIFY(exported.wait(30000));
  QCOMPARE(exported.last().at(1).toString(), QString());
  QCOMPARE(QFileInfo(target).size(), static_cast<qint64>(84 + 50 * sv.mesh.triangles.size()));
  const QString step = keep_.filePath(QStringLiteral("sleeve-swept.step"));
  // A STEP write stopped with the panel's Stop: said, and no file.
  QTRY_VERIFY_WITH_TIMEOUT(path->exportButton()->isEnabled(), 5000);
  vaw::guitest::whenModal([step](QWidget* w) { vaw::guitest::answerFileDialog(w, step); });
  QTest::mouseClick(path->exportButton(), Qt::LeftButton);
  QVERIFY(path->exporting());
  QVERIFY(path->stopExportButton()->isVisible());
  QTest::mouseClick(path->stopExportButton(), Qt::LeftButton);
  QVERIFY(exported.wait(30000));
  QVERIFY2(exported.last().at(1).toString().contains(QStringLiteral("not written: stopped while")), qPrintable(exported.last().at(1).toString()));
  QVERIFY(!path->stopExportButton()->isVisible());
  QVERIFY(!QFileInfo::exists(step));
  // Written to the end, its stages in the status bar as it goes.
  QTRY_VERIFY_WITH_TIMEOUT(path->exportButton()->isEnabled(), 5000);
  QStringList stages;
  const auto heard = connect(path, &vaw::ui::PathDock::statusMessage, this, [&stages](const QString& m) { stages << m; });
  vaw::guitest::whenModal([step](QWidget* w) { vaw::guitest::answerFileDialog(w, step); });
  QTest::mouseClick(path->exportButton(), Qt::LeftButton);
  QVERIFY(exported.wait(60000));
  disconnect(heard);
  QCOMPARE(exported.last().at(1).toString(), QString());
  QVERIFY2(!stages.filter(QStringLiteral("merging coplanar triangles")).isEmpty(), qPrintable(stages.join(QStringLiteral(" | "))));
  const vaw::Assembly back = vaw::loadAny(step.toStdString(), controller_->importers());
  QCOMPARE(back.parts.size(), std::size_t{1});
  QVERIFY(std::abs(vaw::massPropertiesFromMesh(*back.parts[0].mesh, 1.0).mass - sv.volume) < 1e-6 * sv.volume);
  // The faceted form, picked among the dialog's file types: a smaller file, the same solid.
  QTRY_VERIFY_WITH_TIMEOUT(path->exportButton()->isEnabled(), 5000);
  const QString facetedStep = keep_.filePath(QStringLiteral("sleeve-swept-faceted.step"));
  vaw::guitest::whenModal([facetedStep](QWidget* w) { vaw::guitest::answerFileDialog(w, facetedStep, QStringLiteral("STEP faceted")); });
  QTest::mouseClick(path->exportButton(), Qt::LeftButton);
  QVERIFY(exported.wait(60000));
  QCOMPARE(exported.last().at(1).toString(), QString());
  QVERIFY2(QFileInfo(facetedStep).size() < QFileInfo(step).size() / 2,
           qPrintable(QStringLiteral("%1 bytes faceted, %2 not").arg(QFileInfo(facetedStep).size()).arg(QFileInfo(step).size())));
  const vaw::Assembly facetedBack = vaw::loadAny(facetedStep.toStdString(), controller_->importers());
  QCOMPARE(facetedBack.parts.size(), std::size_t{1});
  QVERIFY(std::abs(vaw::massPropertiesFromMesh(*facetedBack.parts[0].mesh, 1.0).mass - sv.volume) < 1e-6 * sv.volume);

  // The box off: the volume goes from the viewport; a new world clears the panel.
  QTest::mouseClick(path->showBox(), Qt::LeftButton);
  QVERIFY(!viewport()->sweptVolumeShown());
  sim().reset();
  QTRY_VERIFY_WITH_TIMEOUT(path->swept() == nullptr, 2000);
  QVERIFY(window_->partDock()->model()->value(QStringLiteral("Swept volume")).isEmpty());
}

void TestSimulation::clickFileMenuItem(const QString& action) {
  QMenuBar* bar = window_->menuBar();
  QAction* fileMenu = bar->actions().front();
  QTest::mouseClick(bar, Qt::LeftButton, {}, bar->actionGeometry(fileMenu).center());
  QMenu* menu = fileMenu->menu();
  QTRY_VERIFY_WITH_TIMEOUT(menu->isVisible(), 3000);
  QAction* item = nullptr;
  for (QAction* a : menu->actions())
    if (a->objectName() == action) item = a;
  QVERIFY2(item != nullptr, qPrintable(action));
  QTest::mouseClick(menu, Qt::LeftButton, {}, menu->actionGeometry(item).center());
}

PartId TestSimulation::carryTheSleeveAside() {
  const PartId sleeve = *assembly().findPart("sleeve");
  Eigen::Isometry3d lifted = world().part(sleeve).pose;
  lifted.translation() += Eigen::Vector3d(-0.06, 0.04, -0.11);
  vaw::guitest::carryWithMouse(*window_, sleeve, lifted, "sleeve");
  return sleeve;
}

void TestSimulation::exportVideoThroughTheMenu(const QString& file, int sizeKey, const QString& fps, const QString& camera) {
  vaw::guitest::whenModal([file, sizeKey, fps, camera](QWidget* dialog) {
    QCOMPARE(dialog->objectName(), QStringLiteral("videoDialog"));
    if (!camera.isEmpty()) {
      auto* cameras = dialog->findChild<QComboBox*>(QStringLiteral("videoCamera"));
      cameras->setFocus();
      QTest::keyClick(cameras, Qt::Key_End);
      QCOMPARE(cameras->currentText(), camera);
    }
    auto* size = dialog->findChild<QComboBox*>(QStringLiteral("videoSize"));
    size->setFocus();
    QTest::keyClick(size, static_cast<Qt::Key>(sizeKey));
    vaw::guitest::typeInto(dialog->findChild<QSpinBox*>(QStringLiteral("videoFps")), fps);
    vaw::guitest::whenModal([file](QWidget* w) { vaw::guitest::answerFileDialog(w, file); });
    QTest::mouseClick(dialog->findChild<QDialogButtonBox*>()->button(QDialogButtonBox::Ok), Qt::LeftButton);
  });
  clickFileMenuItem(QStringLiteral("exportVideoAction"));
  QTRY_VERIFY_WITH_TIMEOUT(window_->exportingVideo(), 10000);
}

// File > Export Video as a person uses it: the menu clicked, the size and frame rate chosen in the dialog,
// the file named in the file dialog. A first export at the largest size is stopped from its progress window
// (said, no file); a small one is written while the simulation goes on, and ffprobe reads it back as H.264
// with a frame for every tenth of a second recorded.
void TestSimulation::theRecordingExportsAsAVideo() {
  open(QStringLiteral("sleeve-on-shaft.vaw.json"));
  QTRY_VERIFY_WITH_TIMEOUT(sim().recorder().endTime() >= 3.0, 20000);
  sim().pause();
  const double recorded = sim().recorder().endTime();

  // The largest size, stopped from its progress window.
  const QString big = keep_.filePath(QStringLiteral("stopped.mp4"));
  exportVideoThroughTheMenu(big, Qt::Key_Home, QStringLiteral("30"));
  if (QTest::currentTestFailed()) return;
  QTRY_VERIFY_WITH_TIMEOUT(window_->videoProgress() != nullptr && window_->videoProgress()->isVisible() && window_->videoProgress()->value() > 0, 20000);
  QVERIFY2(window_->videoProgress()->labelText().startsWith(QStringLiteral("Writing the video ") + big + QStringLiteral("\nframe ")),
           qPrintable(window_->videoProgress()->labelText()));
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("video-export-progress.png"));
  auto* stop = window_->videoProgress()->findChild<QPushButton*>();
  QVERIFY(stop != nullptr);
  QCOMPARE(stop->text(), QStringLiteral("Stop"));
  QTest::mouseClick(stop, Qt::LeftButton);
  QTRY_VERIFY_WITH_TIMEOUT(!window_->exportingVideo(), 10000);
  QCOMPARE(window_->statusBar()->currentMessage(), QStringLiteral("Stopped: no video written to ") + big);
  QVERIFY(!QFile::exists(big));
  QVERIFY(window_->videoProgress() == nullptr);

  // 640 x 360 (the last size) at 10 frames a second, while the simulation goes on.
  const QString small = keep_.filePath(QStringLiteral("sleeve.mp4"));
  exportVideoThroughTheMenu(small, Qt::Key_End, QStringLiteral("10"));
  if (QTest::currentTestFailed()) return;
  sim().play();
  const std::uint64_t before = sim().recorder().length();
  QTRY_VERIFY_WITH_TIMEOUT(!window_->exportingVideo(), 60000);
  QVERIFY2(sim().recorder().length() > before, "the simulation went on while the video was written");
  sim().pause();
  const QString said = window_->statusBar()->currentMessage();
  QVERIFY2(said.startsWith(QStringLiteral("Wrote the video to ") + small), qPrintable(said));
  const int frames = static_cast<int>(std::floor(recorded / 0.1 + 1e-9)) + 1;
  QVERIFY2(said.contains(QStringLiteral("(%1 frames").arg(frames)), qPrintable(said));
  QProcess probe;
  probe.start(QStringLiteral("ffprobe"), {QStringLiteral("-v"), QStringLiteral("error"), QStringLiteral("-count_frames"), QStringLiteral("-show_entries"),
                                          QStringLiteral("stream=codec_name,width,height,nb_read_frames"), QStringLiteral("-of"), QStringLiteral("csv=p=0"), small});
  QVERIFY(probe.waitForFinished(30000));
  QCOMPARE(QString::fromUtf8(probe.readAllStandardOutput()).trimmed(), QStringLiteral("h264,640,360,%1").arg(frames));

  // The timeline zoomed in with the wheel about 1.5 s: "what the timeline shows" is offered and is what
  // the video holds.
  vaw::ui::TimelineView* timeline = window_->timelineDock()->view();
  const QPointF at(timeline->xOf(1.5), timeline->height() / 2.0);
  QWheelEvent wheel(at, timeline->mapToGlobal(at), QPoint(), QPoint(0, 4 * 120), Qt::NoButton, Qt::NoModifier, Qt::NoScrollPhase, false);
  QCoreApplication::sendEvent(timeline, &wheel);
  const double end = static_cast<double>(sim().recorder().length()) * sim().recorder().session().settings.step();
  const double from = std::clamp(timeline->visibleStart(), 0.0, end), to = std::clamp(timeline->visibleEnd(), 0.0, end);
  QVERIFY2(from > 0.5 && to - from > 1.0, qPrintable(QStringLiteral("%1 to %2 s").arg(from).arg(to)));
  const QString part = keep_.filePath(QStringLiteral("shown.mp4"));
  vaw::guitest::whenModal([part](QWidget* dialog) {
    auto* span = dialog->findChild<QComboBox*>(QStringLiteral("videoSpan"));
    QCOMPARE(span->count(), 2);
    span->setFocus();
    QTest::keyClick(span, Qt::Key_End);
    QVERIFY2(span->currentText().startsWith(QStringLiteral("What the timeline shows")), qPrintable(span->currentText()));
    QVERIFY(dialog->grab().save(vaw::guitest::shotPath(QStringLiteral("video-export-dialog.png"))));
    auto* size = dialog->findChild<QComboBox*>(QStringLiteral("videoSize"));
    size->setFocus();
    QTest::keyClick(size, Qt::Key_End);
    vaw::guitest::typeInto(dialog->findChild<QSpinBox*>(QStringLiteral("videoFps")), QStringLiteral("10"));
    vaw::guitest::whenModal([part](QWidget* w) { vaw::guitest::answerFileDialog(w, part); });
    QTest::mouseClick(dialog->findChild<QDialogButtonBox*>()->button(QDialogButtonBox::Ok), Qt::LeftButton);
  });
  clickFileMenuItem(QStringLiteral("exportVideoAction"));
  if (QTest::currentTestFailed()) return;
  QTRY_VERIFY_WITH_TIMEOUT(window_->exportingVideo(), 10000);
  QTRY_VERIFY_WITH_TIMEOUT(!window_->exportingVideo(), 60000);
  const int spanFrames = static_cast<int>(std::floor((to - from) / 0.1 + 1e-9)) + 1;
  QVERIFY2(window_->statusBar()->currentMessage().contains(QStringLiteral("(%1 frames").arg(spanFrames)), qPrintable(window_->statusBar()->currentMessage()));
  probe.start(QStringLiteral("ffprobe"), {QStringLiteral("-v"), QStringLiteral("error"), QStringLiteral("-count_frames"), QStringLiteral("-show_entries"),
                                          QStringLiteral("stream=nb_read_frames"), QStringLiteral("-of"), QStringLiteral("csv=p=0"), part});
  QVERIFY(probe.waitForFinished(30000));
  QCOMPARE(QString::fromUtf8(probe.readAllStandardOutput()).trimmed(), QString::number(spanFrames));
}

namespace {

// The share of the pixels that one of the two pictures marks and the other does not, over those that
// either marks: 0 for the same silhouettes. `video` has `window`'s vertical field of view, so the window's
// picture scaled to the video's height lines up with the middle of the video's (or the video's with the
// middle of it, when the window is the wider); the rows of the caption band are left out. `marks` is given
// a picture, a pixel and the column where the compared part of the picture starts.
template <class Marks>
double silhouetteMismatch(const QImage& window, const QImage& video, double captionShare, Marks marks) {
  const QImage w = window.convertToFormat(QImage::Format_RGB32).scaledToHeight(video.height(), Qt::SmoothTransformation);
  const QImage v = video.convertToFormat(QImage::Format_RGB32);
  const int width = std::min(w.width(), v.width()), wx = (w.width() - width) / 2, vx = (v.width() - width) / 2;
  const int rows = static_cast<int>(v.height() * (1.0 - captionShare));
  qsizetype either = 0, one = 0;
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < width; ++x) {
      const bool a = marks(w, wx + x, y, wx, rows), b = marks(v, vx + x, y, vx, rows);
      either += a || b ? 1 : 0;
      one += a != b ? 1 : 0;
    }
  return either == 0 ? 1.0 : static_cast<double>(one) / static_cast<double>(either);
}

// The scene's outline: what is not the background (the clear colour, the same in both renderers).
auto notBackground(QRgb background) {
  return [background](const QImage& image, int x, int y, int, int) { return vaw::guitest::differs(image.pixel(x, y), background, 24); };
}

// The coloured parts: pixels whose colour (each channel's share of the three, which the window's lights
// falling off across the table and the wall leave alone) is far from both the wall's (the top left corner)
// and the table's (the bottom left corner above the caption band). The grey base and shaft are not
// marked: the two renderers tint grey differently.
bool coloured(const QImage& image, int x, int y, int x0, int rows) {
  const auto chroma = [](QRgb c) {
    const double sum = std::max(1, qRed(c) + qGreen(c) + qBlue(c));
    return Eigen::Vector3d(qRed(c) / sum, qGreen(c) / sum, qBlue(c) / sum);
  };
  const Eigen::Vector3d wall = chroma(image.pixel(x0 + 2, 2)), table = chroma(image.pixel(x0 + 2, rows - 3)), p = chroma(image.pixel(x, y));
  return (p - wall).cwiseAbs().maxCoeff() > 0.06 && (p - table).cwiseAbs().maxCoeff() > 0.06;
}

}  // namespace

// A video asked for "as the viewport shows it" is drawn from the viewport's eye: its first frame and a
// frame from the middle of a carry show the parts where the window showed them at those times (the
// window's picture captured after seeking to the frame's time). The two renderers light and shade
// differently (Qt3D in the window, the headset's OpenGL renderer in the video), so what is compared is
// where things are: the scene's outline against the background (within 3 % of the pixels either marks:
// 1.4 % measured, the edges' smoothing) and the coloured sleeve's silhouette (within 25 %: 10-13 %
// measured, most of it the window's grab marker, which the video does not draw).
void TestSimulation::aVideoFromTheViewportsEyeShowsWhatTheWindowShowed() {
  open(QStringLiteral("sleeve-on-shaft.vaw.json"));
  const PartId sleeve = carryTheSleeveAside();
  if (QTest::currentTestFailed()) return;
  QTRY_VERIFY_WITH_TIMEOUT(sim().recorder().endTime() >= 2.0, 20000);
  sim().pause();
  const double step = sim().recorder().session().settings.step();
  // The middle frame at 10 frames a second: the first whose time is past the grab of the carry.
  const auto& log = world().transitions();
  const auto grabbed = std::find_if(log.begin(), log.end(), [&](const auto& r) { return r.part == sleeve && r.to == vaw::interact::PartState::InHand; });
  QVERIFY2(grabbed != log.end(), "the sleeve was taken in hand");
  const auto released = std::find_if(grabbed, log.end(), [&](const auto& r) { return r.part == sleeve && r.to != vaw::interact::PartState::InHand; });
  const double middle = released == log.end() ? grabbed->t + 0.5 : 0.5 * (grabbed->t + released->t);
  const int middleFrame = static_cast<int>(std::ceil(middle / 0.1));
  lookFrom(Eigen::Vector3d(0.45, -0.55, 0.45), Eigen::Vector3d(0.12, 0.0, 0.12));
  const auto windowAt = [&](double t) {
    sim().seek(static_cast<std::uint64_t>(std::ceil(t / step - 1e-9)));
    return vaw::guitest::capture(viewport());
  };
  const QImage firstShown = windowAt(0.0), middleShown = windowAt(middleFrame * 0.1);
  QVERIFY(!firstShown.isNull() && !middleShown.isNull());
  QVERIFY(firstShown.save(vaw::guitest::shotPath(QStringLiteral("video-eye-window-first.png"))));
  QVERIFY(middleShown.save(vaw::guitest::shotPath(QStringLiteral("video-eye-window-middle.png"))));

  const QString file = keep_.filePath(QStringLiteral("eye.mp4"));
  exportVideoThroughTheMenu(file, Qt::Key_End, QStringLiteral("10"), QStringLiteral("As the viewport shows it now"));
  if (QTest::currentTestFailed()) return;
  QTRY_VERIFY_WITH_TIMEOUT(!window_->exportingVideo(), 60000);
  QVERIFY2(window_->statusBar()->currentMessage().startsWith(QStringLiteral("Wrote the video to ") + file), qPrintable(window_->statusBar()->currentMessage()));

  // The video's frames decoded back by FFmpeg's own program.
  const QString frames = keep_.filePath(QStringLiteral("eye-frames"));
  QVERIFY(QDir().mkpath(frames));
  QProcess decode;
  decode.start(QStringLiteral("ffmpeg"), {QStringLiteral("-v"), QStringLiteral("error"), QStringLiteral("-i"), file, frames + QStringLiteral("/%04d.png")});
  QVERIFY(decode.waitForFinished(60000));
  QCOMPARE(decode.exitCode(), 0);
  const QImage firstFrame(frames + QStringLiteral("/0001.png")), middleFrameImage(frames + QString::asprintf("/%04d.png", middleFrame + 1));
  QVERIFY2(!firstFrame.isNull() && !middleFrameImage.isNull(), qPrintable(QStringLiteral("frames 1 and %1 decoded").arg(middleFrame + 1)));
  QVERIFY(firstFrame.save(vaw::guitest::shotPath(QStringLiteral("video-eye-frame-first.png"))));
  QVERIFY(middleFrameImage.save(vaw::guitest::shotPath(QStringLiteral("video-eye-frame-middle.png"))));

  // The eye: the scene's outline against the background.
  const auto outline = notBackground(viewport()->clearColor().rgb());
  const double firstOutline = silhouetteMismatch(firstShown, firstFrame, 0.2, outline), middleOutline = silhouetteMismatch(middleShown, middleFrameImage, 0.2, outline);
  // Where the sleeve is: the coloured parts.
  const double firstParts = silhouetteMismatch(firstShown, firstFrame, 0.2, coloured), middleParts = silhouetteMismatch(middleShown, middleFrameImage, 0.2, coloured);
  const double moved = silhouetteMismatch(firstShown, middleFrameImage, 0.2, coloured);
  qInfo("outline %.1f %% and %.1f %% apart, coloured parts %.1f %% and %.1f %% (first frame, frame %d); first window against middle frame %.1f %%",
        100.0 * firstOutline, 100.0 * middleOutline, 100.0 * firstParts, 100.0 * middleParts, middleFrame, 100.0 * moved);
  QVERIFY2(firstOutline < 0.03 && middleOutline < 0.03, "the video's eye is the viewport's: outlines within 3 %");
  QVERIFY2(firstParts < 0.25 && middleParts < 0.25, "the sleeve is where the window showed it: within 25 % of its pixels");
  // The carry shows: the sleeve's silhouette moved, so the comparison above could fail.
  QVERIFY2(moved > 0.5, "the sleeve moved between the two frames");
}

// File > Export glTF: the sleeve carried with the mouse, then the recording written as one glTF binary
// through the menu and the file dialog, said in the status bar; the file is glTF 2.0 (its magic and
// version) and holds the carry's animation.
void TestSimulation::theRecordingExportsAsGltf() {
  open(QStringLiteral("sleeve-on-shaft.vaw.json"));
  (void)carryTheSleeveAside();
  if (QTest::currentTestFailed()) return;
  sim().pause();
  const QString file = keep_.filePath(QStringLiteral("gear.glb"));
  vaw::guitest::whenModal([file](QWidget* w) { vaw::guitest::answerFileDialog(w, file); });
  clickFileMenuItem(QStringLiteral("exportGltfAction"));
  if (QTest::currentTestFailed()) return;
  QTRY_VERIFY_WITH_TIMEOUT(QFile::exists(file) && !window_->exportingGltf(), 30000);
  const QString said = window_->statusBar()->currentMessage();
  QVERIFY2(said.startsWith(QStringLiteral("Wrote the glTF file to ") + file + QStringLiteral(" (")) && said.contains(QStringLiteral(" s of the recording")),
           qPrintable(said));
  QFile glb(file);
  QVERIFY(glb.open(QIODevice::ReadOnly));
  const QByteArray bytes = glb.readAll();
  QVERIFY(bytes.startsWith("glTF"));
  QCOMPARE(static_cast<int>(bytes[4]), 2);  // version 2
  QVERIFY2(bytes.contains("\"animations\""), "the recording's animation is in the file");
}

QTEST_MAIN(TestSimulation)
#include "tst_simulation.moc"
