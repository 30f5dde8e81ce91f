// The trials panel driven as an experimenter and a participant drive it: a short constant-stimuli session
// answered with the number keys, paused with P, cut off by closing the window (with a torn record left at
// the end of the file, as a crash inside a write leaves it) and resumed in a new window, then analysed.
// Each trial is checked against the running world: the trial's scale is the world's free-flight gravity
// and the block's fall takes the time that scale gives, while the Gravity panel shows none of it.
// Screenshots go to the build tree (tests/gui/trials-*.png).
//
// Runs under Xvfb (Qt3D needs GL); any Qt warning fails the test. QSettings live in the test's own
// XDG_CONFIG_HOME (tests/gui/CMakeLists.txt), cleared at the start.
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFile>
#include <QLabel>
#include <QLineEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QRegularExpression>
#include <QScreen>
#include <QSettings>
#include <QSignalSpy>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QUndoStack>
#include <QtCharts/QChart>
#include <QtCharts/QChartView>
#include <QtTest>
#include <cmath>
#include <memory>
#include <vector>

#include "gui_test_support.hpp"
#include "vaw/trials/results.hpp"
#include "vaw/trials/runner.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/timeline.hpp"
#include "vaw/ui/trials_panel.hpp"
#include "vaw/ui/tuning.hpp"
#include "vaw/units.hpp"

using vaw::ui::AssemblyController;
using vaw::ui::MainWindow;
using vaw::ui::TrialsDock;

namespace {

// Three scales twice each: six trials, shuffled by the seed.
const char* kDesign = R"({
  "format": "vaw-trial-design",
  "version": 1,
  "name": "GUI test: short constant stimuli",
  "participant": "P00",
  "seed": 42,
  "scenario": "drop-from-hand",
  "motion": "free-flight",
  "question": {"text": "Did the block fall too fast or too slow to look real?", "answers": "too-fast-too-slow"},
  "method": {"kind": "constant-stimuli", "scales": [0.2, 0.5, 1.0], "repetitions": 2},
  "viewing": {"distance_m": 0.6, "fall_height_m": 0.9}
})";

constexpr double kFallHeight = 0.9;  // m, the block's underside above the table in drop-from-hand.vaw.json
constexpr int kTrials = 6;

struct Given {
  double scale = 0.0;
  bool tooFast = false;
};

}  // namespace

class TestTrials : public QObject {
  Q_OBJECT

 public:
  static void initMain() {
    if (qEnvironmentVariableIsEmpty("QT3D_RENDERER")) qputenv("QT3D_RENDERER", "opengl");
  }

 private slots:
  void initTestCase();
  void cleanup();
  void cleanupTestCase();

  void malformedDesignIsShownNotThrown();
  void shortSessionByKeysPausesResumesAndAnalyses();
  void adjustmentAndTwoIntervalAnswers();
  void everyScenarioPlaysInThePanel();

 private:
  [[nodiscard]] TrialsDock* dock() const { return window_->trialsDock(); }
  [[nodiscard]] vaw::ui::SimulationController& sim() const { return window_->simulation(); }
  [[nodiscard]] const vaw::sim::World& world() const { return sim().world(); }
  void makeWindow();
  void press(int key);
  void shot(QWidget* widget, const QString& name);
  // Waits for the trial to reach its answer, checks it against the world and answers it with a key: "too
  // fast" when the scale the world played is above 0.4; `shotName`: a screenshot of the window first.
  void answerOne(std::vector<Given>& given, const QString& shotName = {});
  // Writes `json` as a design, loads it and starts it on a new results file; returns that file.
  QString startDesign(const QString& name, const QByteArray& json);

  vaw::guitest::Workbench bench_;
  std::unique_ptr<AssemblyController>& controller_ = bench_.controller;
  std::unique_ptr<MainWindow>& window_ = bench_.window;
  QTemporaryDir dir_;
};

void TestTrials::initTestCase() {
  QVERIFY(dir_.isValid());
  QVERIFY(bench_.start());
}

void TestTrials::makeWindow() { QVERIFY(bench_.restart()); }

void TestTrials::press(int key) { vaw::guitest::pressKey(window_.get(), key); }

void TestTrials::shot(QWidget* widget, const QString& name) { vaw::guitest::shot(window_.get(), widget, name); }

void TestTrials::cleanup() {
  vaw::guitest::verifyNoWarnings();
}

void TestTrials::cleanupTestCase() {
  bench_.stop();
}

// A design with a bad field: the panel names the file and the field, and nothing starts.
void TestTrials::malformedDesignIsShownNotThrown() {
  const QString bad = dir_.filePath(QStringLiteral("bad.vaw-trial.json"));
  QFile f(bad);
  QVERIFY(f.open(QIODevice::WriteOnly));
  f.write(QByteArray(kDesign).replace("\"repetitions\": 2", "\"repetitions\": 0"));
  f.close();
  QVERIFY(!dock()->loadDesign(bad));
  QVERIFY2(dock()->problem().contains(QStringLiteral("bad.vaw-trial.json")) &&
               dock()->problem().contains(QStringLiteral("repetitions")),
           qPrintable(dock()->problem()));
  QVERIFY(!dock()->findChild<QPushButton*>(QStringLiteral("trialsStart"))->isEnabled());
  QVERIFY(!dock()->running());

  // A results file with a malformed record: resuming and analysing it name the file, the line and the
  // field, and nothing starts.
  const QString design = dir_.filePath(QStringLiteral("good.vaw-trial.json"));
  {
    QFile good(design);
    QVERIFY(good.open(QIODevice::WriteOnly));
    good.write(kDesign);
  }
  const QString results = dir_.filePath(QStringLiteral("bad.vaw-results.jsonl"));
  {
    auto runner = vaw::trials::Runner::open(vaw::trials::loadDesign(design.toStdString()), results.toStdString());
    runner.answer(vaw::trials::Answer{vaw::trials::Judgement::TooFast, {}});
  }
  {
    QFile record(results);
    QVERIFY(record.open(QIODevice::Append));
    record.write(R"({"answer":"sideways","caught":false,"regrasp_time_s":null,"scale":0.5,"trial":1})" "\n");
  }
  QVERIFY(!dock()->analyzeFiles({results}));
  QVERIFY2(dock()->problem().contains(QStringLiteral("bad.vaw-results.jsonl")) &&
               dock()->problem().contains(QStringLiteral("line 3.")),
           qPrintable(dock()->problem()));
  QVERIFY(dock()->analysis().empty());
  dock()->resumeFile(results);
  QVERIFY(!dock()->running());
  QVERIFY2(dock()->problem().contains(QStringLiteral("line 3")), qPrintable(dock()->problem()));
}

void TestTrials::answerOne(std::vector<Given>& given, const QString& shotName) {
  QTRY_VERIFY_WITH_TIMEOUT(dock()->phase() == TrialsDock::Phase::Answering, 20000);
  const auto& trial = dock()->runner()->next();
  QVERIFY(trial.has_value());
  QCOMPARE(trial->index, static_cast<int>(given.size()));
  // Played: the world ran the trial's scale, and the block fell for as long as that scale takes.
  const double scale = world().settings().gravity.freeFlight;
  QCOMPARE(scale, trial->scale);
  const auto& log = world().transitions();
  QVERIFY(log.size() >= 2);
  const auto& hit = log.back();
  const auto& release = log[log.size() - 2];
  QVERIFY(release.event == vaw::interact::Event::Release);
  const auto m = QRegularExpression(QStringLiteral("at t=([0-9.]+) s")).match(QString::fromStdString(hit.cause));
  QVERIFY2(m.hasMatch(), hit.cause.c_str());
  const double fall = m.captured(1).toDouble() - (release.t - world().settings().step());
  const double expected = std::sqrt(2.0 * kFallHeight / (vaw::kStandardGravity * scale));
  QVERIFY2(std::abs(fall - expected) < 0.01 * expected,
           qPrintable(QStringLiteral("fell %1 s at scale %2, expected %3 s").arg(fall).arg(scale).arg(expected)));
  // Not shown: the Gravity panel hides its scales and keeps the value it had before the session.
  auto* gravity = window_->gravityDock();
  QVERIFY(gravity->isBlinded());
  auto* factor = gravity->findChild<QDoubleSpinBox*>(QStringLiteral("gravityFreeFlight"));
  QVERIFY(!factor->isVisibleTo(gravity));
  QCOMPARE(factor->value(), 0.25);
  QVERIFY(!dock()->findChild<QLabel*>(QStringLiteral("trialsQuestion"))->text().contains(QString::number(scale)));
  // Nor the fall's speed or duration: the inspector and the timeline are closed.
  QVERIFY(!window_->partDock()->isVisible());
  QVERIFY(!window_->timelineDock()->isVisible());

  if (!shotName.isEmpty()) shot(window_.get(), shotName);
  const bool tooFast = scale > 0.4;
  const int before = dock()->runner()->answered();
  press(tooFast ? Qt::Key_2 : Qt::Key_1);
  given.push_back({scale, tooFast});
  QTRY_VERIFY(!dock()->running() || dock()->runner()->answered() == before + 1);
}

void TestTrials::shortSessionByKeysPausesResumesAndAnalyses() {
  const QString design = dir_.filePath(QStringLiteral("short.vaw-trial.json"));
  {
    QFile f(design);
    QVERIFY(f.open(QIODevice::WriteOnly));
    f.write(kDesign);
  }
  QVERIFY(dock()->loadDesign(design));
  dock()->show();
  dock()->raise();
  auto* participant = dock()->findChild<QLineEdit*>(QStringLiteral("trialsParticipant"));
  QCOMPARE(participant->text(), QStringLiteral("P00"));
  participant->setFocus();
  QTest::keyClick(participant, Qt::Key_A, Qt::ControlModifier);
  QTest::keyClicks(participant, QStringLiteral("P07"));
  // The results file is named from the participant, next to the design.
  const QString results = dir_.filePath(QStringLiteral("P07-short.vaw-results.jsonl"));
  QCOMPARE(dock()->resultsPath(), results);
  QTest::mouseClick(dock()->findChild<QPushButton*>(QStringLiteral("trialsStart")), Qt::LeftButton);
  QVERIFY2(dock()->running(), qPrintable(dock()->problem()));

  std::vector<Given> given;
  answerOne(given, QStringLiteral("trials-answering.png"));
  answerOne(given);

  // Paused: the keys do nothing and the session does not move on; P again goes on.
  QTRY_VERIFY_WITH_TIMEOUT(dock()->phase() == TrialsDock::Phase::Answering, 20000);
  press(Qt::Key_P);
  QVERIFY(dock()->paused());
  QVERIFY(!sim().isPlaying());
  press(Qt::Key_2);
  QTest::qWait(500);
  QCOMPARE(dock()->runner()->answered(), 2);
  QVERIFY(dock()->findChild<QProgressBar*>(QStringLiteral("trialsProgress"))->text().contains(QStringLiteral("trial 3 of 6")));
  shot(dock(), QStringLiteral("trials-paused.png"));
  press(Qt::Key_P);
  QVERIFY(!dock()->paused());
  answerOne(given);
  QCOMPARE(dock()->runner()->answered(), 3);

  // The window closed mid-session, and a write cut short at the end of the file, as a crash leaves it.
  QVERIFY(window_->close());
  window_.reset();
  controller_.reset();
  {
    QFile f(results);
    QVERIFY(f.open(QIODevice::Append));
    f.write(R"({"answer":"too-fa)");
  }
  makeWindow();
  QVERIFY(dock()->loadDesign(design));
  dock()->setParticipant(QStringLiteral("P07"));
  QCOMPARE(dock()->resultsPath(), results);
  dock()->show();
  dock()->raise();
  QTest::mouseClick(dock()->findChild<QPushButton*>(QStringLiteral("trialsStart")), Qt::LeftButton);
  QVERIFY2(dock()->running(), qPrintable(dock()->problem()));
  QCOMPARE(dock()->runner()->answered(), 3);
  QVERIFY2(dock()->notice().contains(QStringLiteral("Resumed at trial 4 of 6")), qPrintable(dock()->notice()));
  QVERIFY2(dock()->notice().contains(QStringLiteral("torn record at line 5")), qPrintable(dock()->notice()));
  while (given.size() < static_cast<std::size_t>(kTrials)) answerOne(given);

  // Complete: the analysis and its chart in the panel; the Gravity panel and the world's tuning are back.
  QTRY_VERIFY_WITH_TIMEOUT(dock()->phase() == TrialsDock::Phase::Done, 5000);
  QCOMPARE(dock()->analysis().size(), std::size_t{1});
  const auto& participants = dock()->analysis().front().participants;
  QCOMPARE(participants.size(), std::size_t{1});
  QCOMPARE(participants.front().participant, std::string("P07"));
  QVERIFY(participants.front().fit && participants.front().fit->ok);
  const double pse = participants.front().fit->pse;
  QVERIFY2(pse > 0.2 && pse < 1.0, qPrintable(QString::number(pse)));
  QVERIFY(dock()->analysis().front().predicted.has_value());
  auto* summary = dock()->findChild<QLabel*>(QStringLiteral("trialsSummary"));
  QVERIFY2(summary->text().contains(QStringLiteral("PSE")) && summary->text().contains(QStringLiteral("P07")),
           qPrintable(summary->text()));
  QVERIFY(dock()->chartView()->isVisible());
  QVERIFY(dock()->chartView()->chart()->series().size() >= 3);
  QTRY_VERIFY(!window_->gravityDock()->isBlinded());
  QTRY_COMPARE(world().settings().gravity.freeFlight, 0.25);
  QVERIFY(window_->gravityDock()->findChild<QDoubleSpinBox*>(QStringLiteral("gravityFreeFlight"))->isVisibleTo(window_->gravityDock()));
  QVERIFY(window_->partDock()->isVisible());
  QVERIFY(window_->timelineDock()->isVisible());
  // A trial's tuning is not the user's: nothing to save, nothing to undo.
  QVERIFY(!window_->hasUnsavedChanges());
  QCOMPARE(window_->undoStack()->count(), 0);
  shot(dock(), QStringLiteral("trials-analysis.png"));
  shot(window_.get(), QStringLiteral("trials-window.png"));

  // On disk: one record per answer, in order, with the scale played and the key pressed.
  const vaw::trials::ResultsFile file = vaw::trials::readResults(std::filesystem::path(QFile::encodeName(results).toStdString()));
  QVERIFY(!file.torn);
  QCOMPARE(file.records.size(), given.size());
  for (std::size_t i = 0; i < given.size(); ++i) {
    const auto& r = file.records[i];
    QCOMPARE(r.trial.index, static_cast<int>(i));
    QCOMPARE(r.trial.scale, given[i].scale);
    QVERIFY(std::get<vaw::trials::Judgement>(r.answer.response) ==
            (given[i].tooFast ? vaw::trials::Judgement::TooFast : vaw::trials::Judgement::TooSlow));
    QVERIFY(!r.answer.measures.caught);  // nobody took the block back
  }
}

QString TestTrials::startDesign(const QString& name, const QByteArray& json) {
  const QString design = dir_.filePath(name + QStringLiteral(".vaw-trial.json"));
  QFile f(design);
  if (!f.open(QIODevice::WriteOnly)) return {};
  f.write(json);
  f.close();
  if (!dock()->loadDesign(design)) return {};
  const QString results = dir_.filePath(name + QStringLiteral(".vaw-results.jsonl"));
  dock()->setResultsPath(results);
  QTest::mouseClick(dock()->findChild<QPushButton*>(QStringLiteral("trialsStart")), Qt::LeftButton);
  return dock()->running() ? results : QString();
}

// Adjustment: Faster and Slower play the fall again at the scale times or over 1.12, and Accept records the
// setting. Two intervals: both falls play, the trial's and the reference's, and "first" is recorded.
void TestTrials::adjustmentAndTwoIntervalAnswers() {
  const QString adjusted = startDesign(QStringLiteral("adjust"), R"({"format": "vaw-trial-design", "version": 1,
    "name": "adjust", "participant": "A01", "seed": 5, "scenario": "drop-from-hand", "motion": "free-flight",
    "question": {"text": "Make the fall look real.", "answers": "setting"},
    "method": {"kind": "adjustment", "trials": 2, "range": [0.05, 2.0], "start_range": [0.3, 0.6]}})");
  QVERIFY2(!adjusted.isEmpty(), qPrintable(dock()->problem()));
  QTRY_VERIFY_WITH_TIMEOUT(dock()->phase() == TrialsDock::Phase::Answering, 20000);
  const double start = dock()->runner()->next()->scale;
  QCOMPARE(world().settings().gravity.freeFlight, start);
  QVERIFY(dock()->findChild<QPushButton*>(QStringLiteral("trialsAnswer3"))->isVisible());
  for (const auto& [key, factor] : {std::pair{Qt::Key_2, 1.12}, std::pair{Qt::Key_2, 1.12 * 1.12}, std::pair{Qt::Key_1, 1.12}}) {
    press(key);
    QTRY_VERIFY_WITH_TIMEOUT(dock()->phase() == TrialsDock::Phase::Answering, 20000);
    QVERIFY2(std::abs(world().settings().gravity.freeFlight - start * factor) < 1e-9 * start,
             qPrintable(QStringLiteral("%1 after a factor %2 from %3").arg(world().settings().gravity.freeFlight).arg(factor).arg(start)));
  }
  const double set = world().settings().gravity.freeFlight;
  // Blinded: the status bar's clock, which would time the fall, is not shown.
  QVERIFY2(window_->findChild<QLabel*>(QStringLiteral("simulationStatus"))->text().startsWith(QStringLiteral("trials session")),
           qPrintable(window_->findChild<QLabel*>(QStringLiteral("simulationStatus"))->text()));
  // File > Save would write the trial's scale as the scene's tuning: it waits for the session.
  vaw::guitest::pressKey(window_.get(), Qt::Key_S, Qt::ControlModifier);
  QVERIFY2(window_->statusBar()->currentMessage().contains(QStringLiteral("trials session is running")),
           qPrintable(window_->statusBar()->currentMessage()));
  press(Qt::Key_3);
  // The second trial in the headset's gestures: the right hand alone is Faster, once the other hand has not
  // followed within 0.3 s; both hands closing together accept.
  QTRY_VERIFY_WITH_TIMEOUT(dock()->phase() == TrialsDock::Phase::Answering && dock()->runner()->answered() == 1, 20000);
  const double start2 = dock()->runner()->next()->scale;
  dock()->headsetAnswer(1);
  QTest::qWait(100);
  QCOMPARE(world().settings().gravity.freeFlight, start2);
  QTRY_VERIFY_WITH_TIMEOUT(std::abs(world().settings().gravity.freeFlight - start2 * 1.12) < 1e-9, 2000);
  QTRY_VERIFY_WITH_TIMEOUT(dock()->phase() == TrialsDock::Phase::Answering, 20000);
  dock()->headsetAnswer(0);
  dock()->headsetAnswer(1);
  QTRY_VERIFY_WITH_TIMEOUT(dock()->phase() == TrialsDock::Phase::Done, 5000);
  // The scene's own scale is back at once, so a session started right away finds it, not the last trial's.
  QCOMPARE(world().settings().gravity.freeFlight, 0.25);
  {
    const auto file = vaw::trials::readResults(adjusted.toStdString());
    QCOMPARE(file.records.size(), std::size_t{2});
    QCOMPARE(std::get<vaw::trials::Setting>(file.records[0].answer.response).scale, set);
    QCOMPARE(file.records[0].trial.scale, start);
    QVERIFY(std::abs(std::get<vaw::trials::Setting>(file.records[1].answer.response).scale - start2 * 1.12) < 1e-9);
  }

  const QString twice = startDesign(QStringLiteral("two"), R"({"format": "vaw-trial-design", "version": 1,
    "name": "two", "participant": "T01", "seed": 9, "scenario": "drop-from-hand", "motion": "free-flight",
    "question": {"text": "Which fell faster?", "answers": "two-interval", "reference_scale": 1.0},
    "method": {"kind": "constant-stimuli", "scales": [0.3, 0.6], "repetitions": 1}})");
  QVERIFY2(!twice.isEmpty(), qPrintable(dock()->problem()));
  for (int i = 0; i < 2; ++i) {
    // The first interval's fall, then the second's; the answers wait for both.
    const auto& t = *dock()->runner()->next();
    const double first = t.referenceFirst ? *t.referenceScale : t.scale, second = t.referenceFirst ? t.scale : *t.referenceScale;
    QTRY_VERIFY_WITH_TIMEOUT(world().settings().gravity.freeFlight == first && dock()->phase() == TrialsDock::Phase::Moving, 20000);
    QVERIFY(!dock()->findChild<QPushButton*>(QStringLiteral("trialsAnswer1"))->isEnabled());
    QTRY_VERIFY_WITH_TIMEOUT(dock()->phase() == TrialsDock::Phase::Answering, 20000);
    QCOMPARE(world().settings().gravity.freeFlight, second);
    QVERIFY(dock()->findChild<QPushButton*>(QStringLiteral("trialsAnswer1"))->text().startsWith(QStringLiteral("First")));
    press(Qt::Key_1);
    QTRY_VERIFY(dock()->phase() != TrialsDock::Phase::Answering);
  }
  QTRY_VERIFY_WITH_TIMEOUT(dock()->phase() == TrialsDock::Phase::Done, 5000);
  const auto file = vaw::trials::readResults(twice.toStdString());
  QCOMPARE(file.records.size(), std::size_t{2});
  for (const auto& r : file.records)
    QVERIFY(std::get<vaw::trials::Judgement>(r.answer.response) == vaw::trials::Judgement::First);
}

// The throw, the slide off the tilted base and the gear's swing, each a two-trial session at twice real time:
// the panel opens the scenario's scene, the world plays the trial's scale for the design's motion, the
// part goes through the scenario's states, and the answer is recorded.
void TestTrials::everyScenarioPlaysInThePanel() {
  struct Case {
    const char* scenario;
    const char* motion;
    const char* scene;
    const char* states;  // the part's states, from the hand's taking it to the end of the presentation
  };
  const Case cases[] = {
      {"throw", "free-flight", "drop-from-hand.vaw.json", "INHAND INSPACE STATIC"},
      {"slide-off-tilted-base", "slide", "block-on-plate.vaw.json", "INHAND ONBASESTATIC ONBASESLIDE INSPACE STATIC"},
      {"gear-pendulum", "rotation", "gear-on-shaft.vaw.json", "INHAND ONBASESTATIC ONBASESLIDE"},
  };
  for (const Case& c : cases) {
    const QString name = QString::fromLatin1(c.scenario);
    const QByteArray json = QStringLiteral(R"({"format": "vaw-trial-design", "version": 1, "name": "%1",
      "participant": "S01", "seed": 3, "scenario": "%1", "motion": "%2",
      "question": {"text": "Too fast or too slow?", "answers": "too-fast-too-slow"},
      "method": {"kind": "constant-stimuli", "scales": [0.5, 1.0], "repetitions": 1}})")
                                .arg(name, QString::fromLatin1(c.motion))
                                .toUtf8();
    const QString results = startDesign(name, json);
    QVERIFY2(!results.isEmpty(), qPrintable(name + QStringLiteral(": ") + dock()->problem()));
    sim().setSpeed(2.0);
    for (int trial = 0; trial < 2; ++trial) {
      QTRY_VERIFY_WITH_TIMEOUT(dock()->phase() == TrialsDock::Phase::Answering, 30000);
      QVERIFY2(controller_->currentPath().endsWith(QString::fromLatin1(c.scene)), qPrintable(controller_->currentPath()));
      QCOMPARE(vaw::trials::scaleFor(world().settings().gravity, dock()->runner()->design().motion),
               dock()->runner()->next()->scale);
      const vaw::PartId part = world().assembly().base == vaw::PartId{0} ? 1 : 0;
      QStringList states;
      for (const auto& t : world().transitions())
        if (t.part == part) states << QString::fromLatin1(std::string(vaw::interact::name(t.to)).c_str());
      QCOMPARE(states.join(QLatin1Char(' ')), QString::fromLatin1(c.states));
      if (name == QStringLiteral("gear-pendulum"))
        QVERIFY2(world().time() >= 6.0, "the swing is watched for 6 s after the release");
      if (trial == 0) shot(window_.get(), QStringLiteral("trials-%1.png").arg(name));
      press(Qt::Key_2);
      QTRY_VERIFY(dock()->phase() != TrialsDock::Phase::Answering);
    }
    QTRY_VERIFY_WITH_TIMEOUT(dock()->phase() == TrialsDock::Phase::Done, 5000);
    const auto file = vaw::trials::readResults(results.toStdString());
    QCOMPARE(file.records.size(), std::size_t{2});
    for (const auto& r : file.records) QVERIFY(!r.answer.measures.caught);
  }
  sim().setSpeed(1.0);
}

QTEST_MAIN(TestTrials)
#include "tst_trials.moc"
