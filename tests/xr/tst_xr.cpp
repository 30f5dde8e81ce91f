// VR mode without a headset: the workbench enters the simulated OpenXR runtime (tests/xr/runtime) through the
// real loader and its core validation layer, and the runtime plays a script of head and hand poses written
// here from the scene's own geometry. Each test asserts on what the runtime recorded (calls, states, frames,
// images, breaches of the specification) and on the world.
//
// Runs under Xvfb with GLX; any Qt warning fails the test, and so does any error in the validation layer's
// report (VAW_XR_VALIDATION_REPORT) or any breach the runtime recorded.
#include <QFile>
#include <QImage>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QLabel>
#include <QSignalSpy>
#include <QStatusBar>
#include <QTemporaryDir>
#include <Qt3DRender/QCamera>
#include <QtTest>
#include <memory>

#include "gui_test_support.hpp"
#include "vaw/primitives.hpp"
#include "sim_runtime.hpp"
#include "vaw/paths.hpp"
#include "vaw/trials/results.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/trials_panel.hpp"
#include "vaw/ui/viewport.hpp"
#include "vaw/ui/xr_controller.hpp"

using vaw::PartId;
using vaw::interact::Event;
using vaw::interact::PartState;
using vaw::ui::AssemblyController;
using vaw::ui::MainWindow;
using vaw::xr::Failure;

namespace {

// Where the plugin puts the table in a STAGE space (vaw::xr::Placement's defaults): the world's x, y, z are
// the stage's x, -z, y, the table top 0.90 m above the floor, its centre 0.45 m ahead.
QJsonArray stage(const Eigen::Vector3d& w) { return {w.x(), w.z() + 0.90, -w.y() - 0.45}; }

QString stateName(XrSessionState s) {
  switch (s) {
    case XR_SESSION_STATE_IDLE: return QStringLiteral("IDLE");
    case XR_SESSION_STATE_READY: return QStringLiteral("READY");
    case XR_SESSION_STATE_SYNCHRONIZED: return QStringLiteral("SYNCHRONIZED");
    case XR_SESSION_STATE_VISIBLE: return QStringLiteral("VISIBLE");
    case XR_SESSION_STATE_FOCUSED: return QStringLiteral("FOCUSED");
    case XR_SESSION_STATE_STOPPING: return QStringLiteral("STOPPING");
    case XR_SESSION_STATE_LOSS_PENDING: return QStringLiteral("LOSS_PENDING");
    case XR_SESSION_STATE_EXITING: return QStringLiteral("EXITING");
    default: return QStringLiteral("UNKNOWN");
  }
}

QString eventsOf(const std::vector<vaw::sim::TransitionRecord>& log, PartId part, std::uint64_t before = UINT64_MAX) {
  QStringList out;
  for (const auto& t : log)
    if (t.part == part && t.step < before)
      out << QString::fromStdString(std::string(vaw::interact::name(t.event)) + ":" + std::string(vaw::interact::name(t.to)) +
                                    "@" + std::to_string(t.step));
  return out.join(QLatin1Char(' '));
}

// The share of pixels that differ from the image's corner (the background), and of pixels where two differ.
double sceneFraction(const QImage& img) {
  const QRgb bg = img.pixel(0, 0);
  qsizetype n = 0;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x) n += vaw::guitest::differs(img.pixel(x, y), bg, 12) ? 1 : 0;
  return static_cast<double>(n) / (static_cast<double>(img.width()) * img.height());
}
double differingFraction(const QImage& a, const QImage& b) {
  qsizetype n = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) n += vaw::guitest::differs(a.pixel(x, y), b.pixel(x, y), 12) ? 1 : 0;
  return static_cast<double>(n) / (static_cast<double>(a.width()) * a.height());
}

QImage toImage(const vaw::simxr::Image& img) {
  QImage out(img.width, img.height, QImage::Format_RGBA8888);
  for (int y = 0; y < img.height; ++y)
    std::memcpy(out.scanLine(y), &img.rgba[static_cast<std::size_t>(y) * img.width * 4], static_cast<std::size_t>(img.width) * 4);
  return out;
}

}  // namespace

class TestXr : public QObject {
  Q_OBJECT

 public:
  static void initMain() {
    if (qEnvironmentVariableIsEmpty("QT3D_RENDERER")) qputenv("QT3D_RENDERER", "opengl");
  }

 private slots:
  void initTestCase();
  void init();
  void cleanup();
  void cleanupTestCase();

  void sessionWalksEveryStateWithTheMatchingCalls();
  void pinchGrabsAndThrowReleasesAsTheDesktopDoes();
  void measuredHandVelocityIsTheReleaseVelocityUnscaled();
  void losingTheSessionMidThrowReturnsToTheDesktopWithTheWorldIntact();
  void runtimeCrashReturnsToTheDesktop();
  void withoutHandTrackingTheControllersGrab();
  void bothHandsTakeATwoHandPart();
  void trialsAreDroppedAndAnsweredWithTheHands();
  void noRuntimeAndNoHeadsetSaySo();
  void recenterPutsTheTableInFrontOfTheWearer();
  void sweptVolumeShowsInTheHeadsetToo();

 private:
  [[nodiscard]] vaw::ui::SimulationController& sim() const { return window_->simulation(); }
  [[nodiscard]] vaw::ui::XrController& xr() const { return window_->xr(); }
  [[nodiscard]] const vaw::sim::World& world() const { return sim().world(); }
  [[nodiscard]] const vaw::Assembly& assembly() const { return *controller_->assembly(); }
  [[nodiscard]] static vaw::simxr::Record& record() { return *vaw_simxr_record(); }
  void open(const QString& scene);
  // Writes the script and points the runtime at it.
  void script(const QJsonObject& s);
  // Enters VR and waits until the workbench is back on the desktop; the steps the headset ran.
  std::uint64_t runInHeadset(int timeoutMs = 60000);
  // The right hand pinching the block up and throwing it along +y, in the stage's coordinates.
  QJsonObject throwScript(PartId part, double duration);
  void checkSpecification();

  std::unique_ptr<AssemblyController> controller_;
  std::unique_ptr<MainWindow> window_;
  QTemporaryDir dir_;
  QList<QPair<Failure, QString>> failures_;
  QStringList notices_;
};

void TestXr::initTestCase() {
  vaw::guitest::failOnWarnings();
  QVERIFY2(!qEnvironmentVariableIsEmpty("XR_RUNTIME_JSON"), "run through ctest: XR_RUNTIME_JSON names the simulated runtime");
  // The loader refuses to create an instance when an enabled layer is missing, so with this set every test
  // runs through the core validation layer.
  QVERIFY2(qEnvironmentVariable("XR_ENABLE_API_LAYERS").contains(QStringLiteral("XR_APILAYER_LUNARG_core_validation")),
           "run through ctest: XR_ENABLE_API_LAYERS enables the core validation layer");
  controller_ = std::make_unique<AssemblyController>();
  window_ = std::make_unique<MainWindow>(*controller_);
  window_->resize(1024, 700);
  window_->show();
  QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
  connect(&xr(), &vaw::ui::XrController::failed, this, [this](Failure f, const QString& text) { failures_.append({f, text}); });
  connect(&xr(), &vaw::ui::XrController::notice, this, [this](const QString& text, bool) { notices_ << text; });
  // Steps that ran in the headset stop where the headset stopped: the desktop's timer does not go on.
  connect(&xr(), &vaw::ui::XrController::modeChanged, this, [this](bool in) {
    if (!in) sim().pause();
  });
}

void TestXr::init() {
  vaw_simxr_reset();
  failures_.clear();
  notices_.clear();
  if (const QString report = qEnvironmentVariable("VAW_XR_VALIDATION_REPORT"); !report.isEmpty()) QFile::remove(report);
}

void TestXr::cleanup() {
  if (window_) sim().pause();
  vaw::guitest::verifyNoWarnings();
}

void TestXr::cleanupTestCase() {
  window_.reset();
  controller_.reset();
  vaw::guitest::restoreMessageHandler();
}

void TestXr::open(const QString& scene) {
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  controller_->open(QFile::decodeName((vaw::resourceDir() / "scenes").string().c_str()) + QLatin1Char('/') + scene);
  QVERIFY(loaded.wait(60000) || !loaded.isEmpty());
  QVERIFY(sim().hasWorld());
  sim().reset();
  sim().pause();
  QCOMPARE(world().stepCount(), std::uint64_t{0});
}

void TestXr::script(const QJsonObject& s) {
  const QString file = dir_.filePath(QStringLiteral("script.json"));
  QFile f(file);
  QVERIFY(f.open(QIODevice::WriteOnly));
  f.write(QJsonDocument(s).toJson());
  f.close();
  qputenv("VAW_SIMXR_SCRIPT", QFile::encodeName(file));
}

std::uint64_t TestXr::runInHeadset(int timeoutMs) {
  QSignalSpy mode(&xr(), &vaw::ui::XrController::modeChanged);
  xr().enter();
  if (!xr().inHeadset()) return 0;  // failed at once: failures_ says why
  [&] { QTRY_VERIFY_WITH_TIMEOUT(!xr().inHeadset(), timeoutMs); }();
  return world().stepCount();
}

QJsonObject TestXr::throwScript(PartId part, double duration) {
  const vaw::Part& p = assembly().parts[part];
  const Eigen::Vector3d com = p.pose * p.mass.centerOfMass;
  const Eigen::Vector3d up = com + Eigen::Vector3d(0.0, 0.0, 0.12);
  const Eigen::Vector3d out = up + Eigen::Vector3d(0.0, 0.15, 0.03);
  const auto key = [](double t, const Eigen::Vector3d& at, double pinch) {
    return QJsonObject{{QStringLiteral("t"), t}, {QStringLiteral("position"), stage(at)}, {QStringLiteral("pinch"), pinch}};
  };
  QJsonArray right{key(0.0, com, 0.08),  key(0.25, com, 0.08), key(0.32, com, 0.015), key(0.6, up, 0.015),
                   key(0.70, up + 0.6 * (out - up), 0.015), key(0.75, out, 0.08), key(duration, out, 0.08)};
  return QJsonObject{{QStringLiteral("refresh"), 90},
                     {QStringLiteral("duration"), duration},
                     {QStringLiteral("joint_velocities"), false},
                     {QStringLiteral("right"), right}};
}

void TestXr::checkSpecification() {
  QVERIFY2(record().violations.empty(),
           qPrintable(QStringLiteral("the runtime caught breaches of the specification:\n") +
                      QString::fromStdString([&] {
                        std::string s;
                        for (const auto& v : record().violations) s += v + "\n";
                        return s;
                      }())));
  QCOMPARE(record().liveHandles, std::size_t{0});  // everything vaw created, it destroyed
  QCOMPARE(record().instancesDestroyed, record().instancesCreated);
  QFile report(qEnvironmentVariable("VAW_XR_VALIDATION_REPORT"));
  if (report.open(QIODevice::ReadOnly)) {
    const QString text = QString::fromUtf8(report.readAll());
    QVERIFY2(!text.contains(QStringLiteral("VALID_ERROR")),
             qPrintable(QStringLiteral("the core validation layer reported errors:\n") + text.left(4000)));
  }
}

// IDLE -> READY (xrBeginSession) -> SYNCHRONIZED -> VISIBLE -> FOCUSED, and at the script's end the runtime
// winds down through VISIBLE and SYNCHRONIZED to STOPPING (xrEndSession) -> IDLE -> EXITING
// (xrDestroySession); the status bar names the runtime.
void TestXr::sessionWalksEveryStateWithTheMatchingCalls() {
  open(QStringLiteral("block-on-plate.vaw.json"));
  script(QJsonObject{{QStringLiteral("duration"), 0.5}});
  QSignalSpy states(&xr(), &vaw::ui::XrController::sessionStateChanged);
  // While in the headset the desktop's camera is the wearer's head (the mean of the eyes).
  double mirrorError = 0.0;
  int mirrored = 0;
  const auto mirror = connect(&xr(), &vaw::ui::XrController::frameShown, this, [&] {
    if (!xr().lastFrame().rendered) return;
    const QVector3D c = window_->viewport()->camera()->position();
    mirrorError = std::max(mirrorError, (Eigen::Vector3d(c.x(), c.y(), c.z()) - xr().lastFrame().head.translation()).norm());
    ++mirrored;
  });
  const QVector3D desktopCamera = window_->viewport()->camera()->position();
  const std::uint64_t steps = runInHeadset();
  disconnect(mirror);
  QVERIFY(mirrored > 30);
  QVERIFY2(mirrorError < 1e-4, qPrintable(QString::number(mirrorError)));
  // The script's head stands 1.65 m above the floor: 0.75 m above the table top.
  QVERIFY2(std::abs(xr().lastFrame().head.translation().z() - 0.75) < 1e-3, qPrintable(QString::number(xr().lastFrame().head.translation().z())));
  QCOMPARE(window_->viewport()->camera()->position(), desktopCamera);  // back where it was
  QCOMPARE(xr().framesShown(), static_cast<std::uint64_t>(record().frames.size()));
  QVERIFY2(failures_.isEmpty(), qPrintable(failures_.isEmpty() ? QString() : failures_.front().second));
  QStringList seen;
  for (XrSessionState s : record().states) seen << stateName(s);
  QCOMPARE(seen.join(QLatin1Char(' ')),
           QStringLiteral("IDLE READY SYNCHRONIZED VISIBLE FOCUSED VISIBLE SYNCHRONIZED STOPPING IDLE EXITING"));
  QCOMPARE(states.size(), 10);
  const auto callIn = [&](const char* fn) {
    for (const auto& c : record().calls)
      if (std::string(c.function) == fn) return stateName(c.state) + QStringLiteral(" ") + QString::number(c.result);
    return QStringLiteral("never called");
  };
  QCOMPARE(callIn("xrGetOpenGLGraphicsRequirementsKHR"), QStringLiteral("UNKNOWN 0"));  // before the session
  QCOMPARE(callIn("xrBeginSession"), QStringLiteral("READY 0"));
  QCOMPARE(callIn("xrEndSession"), QStringLiteral("STOPPING 0"));
  QCOMPARE(callIn("xrDestroySession"), QStringLiteral("EXITING 0"));
  // Frames at the headset's rate for the half second, each step paced by them: 90 Hz for 0.5 s.
  QVERIFY2(record().frames.size() >= 45 && record().frames.size() <= 48, qPrintable(QString::number(record().frames.size())));
  QVERIFY2(steps >= 44 && steps <= 46, qPrintable(QString::number(steps)));
  QCOMPARE(record().sessionsCreated, 1);
  QCOMPARE(record().sessionsDestroyed, 1);
  const auto* status = window_->statusBar()->findChild<QLabel*>(QStringLiteral("vrStatus"));
  QVERIFY(status != nullptr);
  QVERIFY2(status->text().contains(QStringLiteral("vaw simulated runtime")), qPrintable(status->text()));
  QVERIFY(!sim().hasInputSource());
  QVERIFY(!sim().isPacedExternally());
  checkSpecification();
}

// A scripted pinch takes the block, lifts it and throws it: INHAND, then INSPACE at the release, as the desktop
// does for the same motion (the same hand positions at the same steps through the mouse's inputs): the same
// transitions at the same steps and the same trajectory. The submitted images show the scene in both eyes, and
// the eyes differ.
void TestXr::pinchGrabsAndThrowReleasesAsTheDesktopDoes() {
  open(QStringLiteral("block-on-plate.vaw.json"));
  const PartId block = *assembly().findPart("block");
  QJsonObject s = throwScript(block, 1.6);
  s[QStringLiteral("capture_at")] = QJsonArray{0.5};
  script(s);
  const std::uint64_t steps = runInHeadset();
  QVERIFY2(failures_.isEmpty(), qPrintable(failures_.isEmpty() ? QString() : failures_.front().second));
  QVERIFY(steps > 100);
  const QString vrEvents = eventsOf(world().transitions(), block);
  QVERIFY2(vrEvents.startsWith(QStringLiteral("grab:INHAND@")), qPrintable(vrEvents));
  QVERIFY2(vrEvents.contains(QStringLiteral("release:INSPACE@")), qPrintable(vrEvents));
  checkSpecification();

  // The images: scene in both eyes, the eyes differ (stereo), saved for a person to look at.
  QCOMPARE(record().captures.size(), std::size_t{1});
  const QImage left = toImage(record().captures[0].eyes[0]), right = toImage(record().captures[0].eyes[1]);
  left.save(qEnvironmentVariable("VAW_XR_SHOT_DIR") + QStringLiteral("/xr-left-eye.png"));
  right.save(qEnvironmentVariable("VAW_XR_SHOT_DIR") + QStringLiteral("/xr-right-eye.png"));
  QVERIFY2(sceneFraction(left) > 0.02, qPrintable(QString::number(sceneFraction(left))));
  QVERIFY2(sceneFraction(right) > 0.02, qPrintable(QString::number(sceneFraction(right))));
  QVERIFY2(differingFraction(left, right) > 0.005, qPrintable(QString::number(differingFraction(left, right))));

  // The headset's run, step by step, from its recording.
  const vaw::sim::Session vr = sim().recorder().session();
  QCOMPARE(vr.inputs.size(), steps);
  std::vector<Eigen::Vector3d> vrPath;
  for (std::uint64_t k = 1; k <= steps; ++k) {
    sim().seek(k);
    vrPath.push_back(world().part(block).pose.translation());
  }
  // The desktop's: the mouse's hand at the same points, closing and opening at the same steps.
  sim().reset();
  sim().pause();
  bool closed = false;
  std::vector<Eigen::Vector3d> desktopPath;
  for (std::uint64_t k = 0; k < steps; ++k) {
    const vaw::sim::HandInput& h = vr.inputs[k].right;
    if (h.grab && !closed) sim().grab(block, h.pose.translation(), false);
    else if (!h.grab && closed) sim().release();
    sim().moveHand(h.pose.translation());
    closed = h.grab;
    sim().stepOnce();
    desktopPath.push_back(world().part(block).pose.translation());
  }
  QCOMPARE(eventsOf(world().transitions(), block), vrEvents);
  double worst = 0.0;
  for (std::size_t k = 0; k < desktopPath.size(); ++k) worst = std::max(worst, (desktopPath[k] - vrPath[k]).norm());
  QVERIFY2(worst < 1e-9, qPrintable(QStringLiteral("trajectories differ by %1 m").arg(worst)));
  const double travelled = (vrPath.back() - vrPath.front()).norm();
  QVERIFY2(travelled > 0.1, qPrintable(QString::number(travelled)));
}

// With joint velocities the runtime flags valid, the block leaves with the hand's measured velocity: the
// script's hand speed at the release, not the windowed fit and not 1.5 times it.
void TestXr::measuredHandVelocityIsTheReleaseVelocityUnscaled() {
  open(QStringLiteral("block-on-plate.vaw.json"));
  const PartId block = *assembly().findPart("block");
  QJsonObject s = throwScript(block, 1.0);
  s[QStringLiteral("joint_velocities")] = true;
  script(s);
  runInHeadset();
  QVERIFY(failures_.isEmpty());
  const vaw::sim::TransitionRecord* release = nullptr;
  for (const auto& t : world().transitions())
    if (t.part == block && t.event == Event::Release) release = &t;
  QVERIFY(release != nullptr);
  QVERIFY2(QString::fromStdString(release->cause).contains(QStringLiteral("measured by the hand's tracker")),
           release->cause.c_str());
  // From 0.70 s to 0.75 s the script moves the pinch point by 0.4 x (0, 0.15, 0.03) m: 1.22 m/s.
  const vaw::sim::Session& session = sim().recorder().session();
  const auto& in = session.inputs[release->step].right;
  QVERIFY(in.velocity.has_value());
  const double speed = in.velocity->linear.norm(), expected = Eigen::Vector3d(0.0, 0.15 * 0.4, 0.03 * 0.4).norm() / 0.05;
  QVERIFY2(std::abs(speed - expected) < 0.05 * expected, qPrintable(QStringLiteral("%1 vs %2 m/s").arg(speed).arg(expected)));
  checkSpecification();
}

// The headset goes away while the block is in the air in the hand: the workbench is back on the desktop,
// paused, with the world exactly as the last step left it (the block still in the hand), the recording intact,
// the desktop's hands back; a message says the session was lost.
void TestXr::losingTheSessionMidThrowReturnsToTheDesktopWithTheWorldIntact() {
  open(QStringLiteral("block-on-plate.vaw.json"));
  const PartId block = *assembly().findPart("block");
  QJsonObject s = throwScript(block, 1.6);
  s[QStringLiteral("events")] = QJsonArray{QJsonObject{{QStringLiteral("t"), 0.68}, {QStringLiteral("lose_session"), true}}};
  script(s);
  const std::uint64_t steps = runInHeadset();
  QCOMPARE(failures_.size(), 1);
  QCOMPARE(failures_.front().first, Failure::SessionLost);
  QVERIFY2(failures_.front().second.contains(QStringLiteral("lost the session")) ||
               failures_.front().second.contains(QStringLiteral("losing the session")),
           qPrintable(failures_.front().second));
  QVERIFY2(failures_.front().second.contains(QStringLiteral("Back on the desktop")), qPrintable(failures_.front().second));
  QVERIFY(!sim().isPlaying());
  QVERIFY(!sim().hasInputSource());
  QVERIFY(!sim().isPacedExternally());
  QCOMPARE(world().part(block).state, PartState::InHand);
  QCOMPARE(sim().recorder().length(), steps);
  const std::uint64_t hash = world().stateHash();
  QTest::qWait(200);
  QCOMPARE(world().stateHash(), hash);
  // The desktop carries on with the block in its hand: letting go throws it from where it is.
  sim().release();
  sim().stepOnce();
  QCOMPARE(world().part(block).state, PartState::InSpace);
  checkSpecification();
}

// The runtime itself goes away (its instance is lost, as when it crashes): the same graceful return.
void TestXr::runtimeCrashReturnsToTheDesktop() {
  open(QStringLiteral("block-on-plate.vaw.json"));
  script(QJsonObject{{QStringLiteral("duration"), 2.0},
                     {QStringLiteral("events"), QJsonArray{QJsonObject{{QStringLiteral("t"), 0.3}, {QStringLiteral("lose_instance"), true}}}}});
  runInHeadset();
  QCOMPARE(failures_.size(), 1);
  QCOMPARE(failures_.front().first, Failure::RuntimeLost);
  QVERIFY2(failures_.front().second.contains(QStringLiteral("vaw simulated runtime")), qPrintable(failures_.front().second));
  QVERIFY(sim().hasWorld());
  QVERIFY(!xr().inHeadset());
  checkSpecification();
}

// A runtime without XR_EXT_hand_tracking: the workbench says so and the controllers' select grabs.
void TestXr::withoutHandTrackingTheControllersGrab() {
  open(QStringLiteral("block-on-plate.vaw.json"));
  const PartId block = *assembly().findPart("block");
  const vaw::Part& p = assembly().parts[block];
  const Eigen::Vector3d com = p.pose * p.mass.centerOfMass, up = com + Eigen::Vector3d(0.0, 0.0, 0.1);
  const auto key = [](double t, const Eigen::Vector3d& at, bool select) {
    return QJsonObject{{QStringLiteral("t"), t}, {QStringLiteral("position"), stage(at)}, {QStringLiteral("select"), select}};
  };
  script(QJsonObject{{QStringLiteral("duration"), 1.0},
                     {QStringLiteral("hand_tracking"), false},
                     {QStringLiteral("right_controller"), QJsonArray{key(0.0, com, false), key(0.3, com, true), key(0.6, up, true)}}});
  runInHeadset();
  QVERIFY2(failures_.isEmpty(), qPrintable(failures_.isEmpty() ? QString() : failures_.front().second));
  QVERIFY2(notices_.join(QLatin1Char('\n')).contains(QStringLiteral("does not offer hand tracking")), qPrintable(notices_.join(QLatin1Char('\n'))));
  QVERIFY2(eventsOf(world().transitions(), block).startsWith(QStringLiteral("grab:INHAND@")),
           qPrintable(eventsOf(world().transitions(), block)));
  QVERIFY((world().part(block).pose.translation() - com).z() > 0.05);
  checkSpecification();
}

// A trials session in the headset: the participant's right hand takes the block and lets it go, and a pinch
// answers, the left hand as the first button ("too slow"), the right as the second ("too fast").
void TestXr::trialsAreDroppedAndAnsweredWithTheHands() {
  open(QStringLiteral("drop-from-hand.vaw.json"));
  const PartId block = *assembly().findPart("block");
  const Eigen::Vector3d at = world().part(block).pose.translation(), aside = at + Eigen::Vector3d(-0.3, 0.0, -0.3);
  const QString design = dir_.filePath(QStringLiteral("vr.vaw-trial.json"));
  {
    QFile f(design);
    QVERIFY(f.open(QIODevice::WriteOnly));
    f.write(R"({"format": "vaw-trial-design", "version": 1, "name": "VR", "participant": "V01", "seed": 3,
      "scenario": "drop-from-hand", "motion": "free-flight",
      "question": {"text": "Too fast or too slow?", "answers": "too-fast-too-slow"},
      "method": {"kind": "constant-stimuli", "scales": [0.25, 1.0], "repetitions": 1}})");
  }
  vaw::ui::TrialsDock* trials = window_->trialsDock();
  QVERIFY(trials->loadDesign(design));
  const QString results = dir_.filePath(QStringLiteral("vr.vaw-results.jsonl"));
  trials->setResultsPath(results);
  // Each hand open (pinch gap 8 cm) except over the given intervals (1.5 cm), with sharp edges.
  const auto hand = [](const Eigen::Vector3d& where, const std::vector<std::pair<double, double>>& pinches, double end) {
    QJsonArray keys;
    const auto key = [&](double t, double gap) {
      keys.append(QJsonObject{{QStringLiteral("t"), t}, {QStringLiteral("position"), stage(where)}, {QStringLiteral("pinch"), gap}});
    };
    key(0.0, 0.08);
    for (const auto& [from, to] : pinches) {
      key(from, 0.08);
      key(from + 0.04, 0.015);
      key(to, 0.015);
      key(to + 0.04, 0.08);
    }
    key(end, 0.08);
    return keys;
  };
  constexpr double kEnd = 7.5;
  // The right hand drops the block at 1.0-1.6 s and 4.0-4.6 s (held still longer than the release estimator's
  // window) and answers at 6.0 s; the left answers at 3.0 s, each after the block has landed.
  script(QJsonObject{{QStringLiteral("duration"), kEnd},
                     {QStringLiteral("right"), hand(at, {{1.0, 1.6}, {4.0, 4.6}, {6.0, 6.3}}, kEnd)},
                     {QStringLiteral("left"), hand(aside, {{3.0, 3.3}}, kEnd)}});
  xr().enter();
  QTRY_VERIFY_WITH_TIMEOUT(xr().mode() == vaw::ui::XrController::Mode::Headset && sim().hasInputSource(), 20000);
  trials->start();
  QVERIFY2(trials->running(), qPrintable(trials->problem()));
  QTRY_VERIFY_WITH_TIMEOUT(!xr().inHeadset(), 60000);
  QVERIFY2(failures_.isEmpty(), qPrintable(failures_.isEmpty() ? QString() : failures_.front().second));
  QVERIFY2(trials->phase() == vaw::ui::TrialsDock::Phase::Done, qPrintable(trials->notice() + trials->problem()));
  const vaw::trials::ResultsFile file = vaw::trials::readResults(std::filesystem::path(QFile::encodeName(results).toStdString()));
  QCOMPARE(file.records.size(), std::size_t{2});
  QVERIFY(std::get<vaw::trials::Judgement>(file.records[0].answer.response) == vaw::trials::Judgement::TooSlow);
  QVERIFY(std::get<vaw::trials::Judgement>(file.records[1].answer.response) == vaw::trials::Judgement::TooFast);
  QVERIFY(file.records[0].trial.scale != file.records[1].trial.scale);
  // The second fall was the participant's: the right hand took the block, and it left that hand.
  const QString events = eventsOf(world().transitions(), block);
  QVERIFY2(events.startsWith(QStringLiteral("grab:INHAND@")) && events.contains(QStringLiteral("release:INSPACE@")),
           qPrintable(events));
  checkSpecification();
}

// The hoist demo's tray needs both hands: the right pinches it (refused alone), the left joins, and the two
// lift it together. The runtime here offers no STAGE space: the table is placed below the head (LOCAL).
void TestXr::bothHandsTakeATwoHandPart() {
  open(QStringLiteral("hoist-demo.vaw.json"));
  const PartId tray = *assembly().findPart("tray");
  const vaw::Part& p = assembly().parts[tray];
  const Eigen::Vector3d com = p.pose * p.mass.centerOfMass;
  // LOCAL: the space's origin is the script's local_origin (1.6 m up), the table top 0.45 m below it.
  const auto local = [](const Eigen::Vector3d& w) { return QJsonArray{w.x(), w.z() + 1.6 - 0.45, -w.y() - 0.45}; };
  QJsonObject s{{QStringLiteral("duration"), 1.0}, {QStringLiteral("stage"), false}};
  for (int hand = 0; hand < 2; ++hand) {
    const Eigen::Vector3d side(hand == 0 ? -0.08 : 0.08, 0.0, 0.0);
    const auto key = [&](double t, const Eigen::Vector3d& at, double pinch) {
      return QJsonObject{{QStringLiteral("t"), t}, {QStringLiteral("position"), local(at + side)}, {QStringLiteral("pinch"), pinch}};
    };
    s[hand == 0 ? QStringLiteral("left") : QStringLiteral("right")] =
        QJsonArray{key(0.0, com, 0.08), key(hand == 0 ? 0.35 : 0.25, com, 0.08), key(hand == 0 ? 0.40 : 0.30, com, 0.015),
                   key(0.45, com, 0.015), key(0.8, com + Eigen::Vector3d(0.0, 0.0, 0.1), 0.015)};
  }
  script(s);
  runInHeadset();
  QVERIFY2(failures_.isEmpty(), qPrintable(failures_.isEmpty() ? QString() : failures_.front().second));
  QVERIFY(!xr().runtime().stage);
  QCOMPARE(world().part(tray).state, PartState::InHand);
  QCOMPARE(world().part(tray).holder, vaw::sim::Holder::Both);
  const double lifted = world().part(tray).pose.translation().z() - p.pose.translation().z();
  QVERIFY2(lifted > 0.08, qPrintable(QString::number(lifted)));
  checkSpecification();
}

// No runtime at all, and a runtime that sees no headset: a message that says which, and the desktop goes on.
void TestXr::noRuntimeAndNoHeadsetSaySo() {
  open(QStringLiteral("block-on-plate.vaw.json"));
  const QByteArray manifest = qgetenv("XR_RUNTIME_JSON");
  qputenv("XR_RUNTIME_JSON", QFile::encodeName(dir_.filePath(QStringLiteral("no-such-runtime.json"))));
  xr().enter();
  qputenv("XR_RUNTIME_JSON", manifest);
  QCOMPARE(failures_.size(), 1);
  QCOMPARE(failures_.front().first, Failure::NoRuntime);
  QVERIFY2(failures_.front().second.contains(QStringLiteral("no OpenXR runtime")), qPrintable(failures_.front().second));
  QVERIFY(!xr().inHeadset());

  script(QJsonObject{{QStringLiteral("headset"), false}});
  xr().enter();
  QCOMPARE(failures_.size(), 2);
  QCOMPARE(failures_.back().first, Failure::NoHeadset);
  QVERIFY2(failures_.back().second.contains(QStringLiteral("sees no headset")), qPrintable(failures_.back().second));
  QVERIFY(!xr().inHeadset());
  QVERIFY(sim().hasWorld());
  checkSpecification();
}

// VR > Recenter: a wearer who stands away from the stage's origin and looks to the side has the table out of
// view; recentring puts its centre 0.45 m ahead along their gaze and its top 0.45 m below their eyes.
void TestXr::recenterPutsTheTableInFrontOfTheWearer() {
  open(QStringLiteral("block-on-plate.vaw.json"));
  // Standing 0.8 m to the right of the origin and 0.3 m behind it, eyes 1.5 m up, turned 90 degrees left.
  script(QJsonObject{{QStringLiteral("duration"), 1.0},
                     {QStringLiteral("head"), QJsonArray{QJsonObject{
                                                  {QStringLiteral("t"), 0},
                                                  {QStringLiteral("position"), QJsonArray{0.8, 1.5, 0.3}},
                                                  {QStringLiteral("rotation"), QJsonObject{{QStringLiteral("axis"), QJsonArray{0, 1, 0}},
                                                                                           {QStringLiteral("angle"), 90}}}}}}});
  QVERIFY(!xr().recenterAction()->isEnabled());
  Eigen::Isometry3d before = Eigen::Isometry3d::Identity();
  int frames = 0;
  const auto at = connect(&xr(), &vaw::ui::XrController::frameShown, this, [&] {
    if (!xr().lastFrame().rendered) return;
    if (++frames == 20) {
      before = xr().lastFrame().head;
      QVERIFY(xr().recenterAction()->isEnabled());
      xr().recenterAction()->trigger();
    }
  });
  runInHeadset();
  disconnect(at);
  QVERIFY2(frames > 40, qPrintable(QString::number(frames)));
  QVERIFY2(failures_.isEmpty(), qPrintable(failures_.isEmpty() ? QString() : failures_.front().second));
  // Before: the stage placement (table top 0.9 m above the floor, eyes 0.6 m above it, the table to the side).
  QVERIFY2(std::abs(before.translation().z() - 0.6) < 1e-3, qPrintable(QString::number(before.translation().z())));
  const Eigen::Isometry3d& head = xr().lastFrame().head;
  QVERIFY2(std::abs(head.translation().z() - 0.45) < 1e-3, qPrintable(QString::number(head.translation().z())));
  Eigen::Vector3d gaze = head.linear() * Eigen::Vector3d(0.0, 0.0, -1.0);
  gaze.z() = 0.0;
  // The world's origin, the table's centre in the bundled scenes.
  const Eigen::Vector2d origin = head.translation().head<2>() + 0.45 * gaze.normalized().head<2>();
  QVERIFY2(origin.norm() < 1e-3, qPrintable(QString::number(origin.norm())));
  QVERIFY2(gaze.normalized().y() > 0.999, "the world's +y is ahead of the wearer again");
  QVERIFY(notices_.join(QLatin1Char(' ')).contains(QStringLiteral("Recentred")));
  checkSpecification();
}

// The desktop's swept volume (the Path panel's) is drawn in the headset too, translucent: a box round the
// block shown before entering tints what is behind it blue without hiding it, and hidden in the headset
// it is gone from the next frames.
void TestXr::sweptVolumeShowsInTheHeadsetToo() {
  open(QStringLiteral("block-on-plate.vaw.json"));
  QJsonObject s{{QStringLiteral("duration"), 0.8}};
  s[QStringLiteral("capture_at")] = QJsonArray{0.3, 0.7};
  script(s);
  const PartId block = *assembly().findPart("block");
  vaw::TriMesh box = vaw::primitives::box(Eigen::Vector3d(0.25, 0.25, 0.25));
  Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
  at.translation() = world().part(block).pose.translation();
  box.transform(at);
  window_->viewport()->showSweptVolume(vaw::view::flatShaded(box));
  int frames = 0;
  const auto hide = connect(&xr(), &vaw::ui::XrController::frameShown, this, [&] {
    if (xr().lastFrame().rendered && ++frames == 45) window_->viewport()->showSweptVolume(nullptr);
  });
  runInHeadset();
  disconnect(hide);
  QVERIFY2(failures_.isEmpty(), qPrintable(failures_.isEmpty() ? QString() : failures_.front().second));
  QVERIFY2(frames > 60, qPrintable(QString::number(frames)));
  QCOMPARE(record().captures.size(), std::size_t{2});
  const QImage with = toImage(record().captures[0].eyes[0]), without = toImage(record().captures[1].eyes[0]);
  with.save(qEnvironmentVariable("VAW_XR_SHOT_DIR") + QStringLiteral("/xr-swept-volume.png"));
  // The box covers a part of the view (about 5 %), and where it does the picture is bluer than without it, but
  // not the box's own colour: what is behind shows through.
  QVERIFY2(differingFraction(with, without) > 0.02, qPrintable(QString::number(differingFraction(with, without))));
  double blueWith = 0.0, blueWithout = 0.0;
  qsizetype n = 0, opaque = 0;
  const QColor own = QColor::fromRgbF(vaw::view::kSweptColor.r, vaw::view::kSweptColor.g, vaw::view::kSweptColor.b);
  for (int y = 0; y < with.height(); ++y)
    for (int x = 0; x < with.width(); ++x) {
      const QRgb a = with.pixel(x, y), b = without.pixel(x, y);
      if (!vaw::guitest::differs(a, b, 12)) continue;
      ++n;
      blueWith += qBlue(a) - qRed(a);
      blueWithout += qBlue(b) - qRed(b);
      opaque += vaw::guitest::differs(a, own.rgb(), 6) ? 0 : 1;
    }
  QVERIFY(n > 0);
  blueWith /= static_cast<double>(n);
  blueWithout /= static_cast<double>(n);
  QVERIFY2(blueWith > blueWithout + 20.0, qPrintable(QStringLiteral("%1 %2").arg(blueWith).arg(blueWithout)));
  QVERIFY2(opaque < n / 20, qPrintable(QStringLiteral("%1 of %2 pixels are the box's own colour").arg(opaque).arg(n)));
  QVERIFY(!window_->viewport()->sweptVolumeShown());
  checkSpecification();
}

QTEST_MAIN(TestXr)
#include "tst_xr.moc"
