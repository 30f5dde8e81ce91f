// Every background task of the window made to fail in the middle of its work, as an allocation failing
// there would: an import, the order search, the check at rest, the near misses, the report, a sweep with its
// clearance, the export of a swept volume, and a video and a glTF file of the recording. Each is started as a person starts it; each says why it
// failed ("not enough memory"), the window answers, the assembly and the recorded session are as they
// were, and the same task then runs to its end.
//
// The failure: this program replaces operator new, and while a task of the name asked for runs
// (vaw::ui::BackgroundTask, on the task's own thread) the allocation at the depth asked for throws
// std::bad_alloc, once. Each case checks that the failure did happen, so a task that stopped allocating
// there cannot pass unfailed.
//
// Runs under Xvfb (Qt3D needs GL); any Qt warning fails the test.
#include <QDir>
#include <QDoubleSpinBox>
#include <QFile>
#include <QLabel>
#include <QMessageBox>
#include <QPushButton>
#include <QSignalSpy>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QtTest>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>

#include "gui_test_support.hpp"
#include "vaw/paths.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/background.hpp"
#include "vaw/ui/constraints_dock.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/interference_dock.hpp"
#include "vaw/ui/load_feedback.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/message_log_model.hpp"
#include "vaw/ui/path_dock.hpp"
#include "vaw/ui/sequence_dock.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/viewport.hpp"

namespace {

// Allocations on this thread before the one that fails; -1: none fails.
thread_local long failIn = -1;
std::atomic<int> failures{0};
std::atomic<const char*> failingTask{nullptr};
std::atomic<long> failingDepth{0};

void onTask(const char* task, bool starting) {
  const char* t = failingTask.load();
  if (t == nullptr || std::strcmp(t, task) != 0) return;
  failIn = starting ? failingDepth.load() : -1;
}

// Makes the next run of `task` fail at its `depth`-th allocation, until the object goes.
class Failing {
 public:
  Failing(const char* task, long depth) : before_(failures.load()) {
    failingDepth = depth;
    failingTask = task;
  }
  ~Failing() { failingTask = nullptr; }
  Failing(const Failing&) = delete;
  Failing& operator=(const Failing&) = delete;
  [[nodiscard]] bool happened() const { return failures.load() > before_; }

 private:
  int before_;
};

QString sample() { return QFile::decodeName((vaw::resourceDir() / "step" / "bolted-bracket.stp").string().c_str()); }
QString sleeveScene() { return QFile::decodeName((vaw::resourceDir() / "scenes" / "sleeve-on-shaft.vaw.json").string().c_str()); }

}  // namespace

void* operator new(std::size_t size) {
  if (failIn >= 0 && failIn-- == 0) {
    ++failures;
    throw std::bad_alloc();
  }
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

class TestFaults : public QObject {
  Q_OBJECT

 public:
  static void initMain() {
    if (qEnvironmentVariableIsEmpty("QT3D_RENDERER")) qputenv("QT3D_RENDERER", "opengl");
  }

 private slots:
  void initTestCase();
  void cleanup();
  void cleanupTestCase();

  void aFailedImportKeepsTheAssemblyShown_data();
  void aFailedImportKeepsTheAssemblyShown();
  void aFailedOrderSearchSaysWhyAndTheNextFindsTheOrder_data();
  void aFailedOrderSearchSaysWhyAndTheNextFindsTheOrder();
  void aFailedCheckAtRestSaysWhy();
  void aFailedSearchForNearMissesSaysWhy();
  void aFailedReportSaysWhyAndLeavesNoReport();
  void aFailedSweepOrExportSaysWhyAndKeepsTheSession();
  void aFailedVideoOrGltfSaysWhyAndLeavesNoFile();

 private:
  [[nodiscard]] const vaw::Assembly* assembly() const { return controller_->assembly(); }
  // The window still answers: a click in the viewport selects nothing without a warning, the status bar is there.
  [[nodiscard]] bool answers() const;

  vaw::guitest::Workbench bench_;
  std::unique_ptr<vaw::ui::AssemblyController>& controller_ = bench_.controller;
  std::unique_ptr<vaw::ui::MainWindow>& window_ = bench_.window;
};

void TestFaults::initTestCase() {
  vaw::ui::BackgroundTask::setHook(onTask);
  QVERIFY2(QFile::exists(sample()), qPrintable(sample()));
  QVERIFY(bench_.start({.autoPlay = false}));
  QVERIFY2(controller_->importers().find(std::filesystem::path("x.stp")) != nullptr, "the STEP plugin is in VAW_PLUGIN_PATH");
  QVERIFY(bench_.open(sample()));
}

void TestFaults::cleanup() { vaw::guitest::verifyNoWarnings(); }

void TestFaults::cleanupTestCase() {
  vaw::ui::BackgroundTask::setHook(nullptr);
  bench_.stop();
}

bool TestFaults::answers() const {
  if (!window_->isVisible()) return false;
  window_->statusBar()->showMessage(QStringLiteral("still here"));
  QCoreApplication::processEvents();
  return window_->statusBar()->currentMessage() == QStringLiteral("still here");
}

void TestFaults::aFailedImportKeepsTheAssemblyShown_data() {
  QTest::addColumn<long>("depth");
  QTest::newRow("at once") << 0L;
  QTest::newRow("reading the reader's result") << 2000L;
  QTest::newRow("building the collision world") << 30000L;
}

void TestFaults::aFailedImportKeepsTheAssemblyShown() {
  QFETCH(long, depth);
  const vaw::Assembly* before = assembly();
  QVERIFY(before != nullptr);
  const int errors = window_->messagesDock()->model()->count(vaw::ui::MessageLogModel::Severity::Error);
  QSignalSpy failed(controller_.get(), &vaw::ui::AssemblyController::loadFailed);
  {
    const Failing fault("import", depth);
    controller_->open(sample());
    QVERIFY(failed.wait(60000) || !failed.isEmpty());
    QVERIFY2(fault.happened(), "the import allocated less than the depth asked for");
  }
  const auto failure = failed.first().first().value<vaw::ui::LoadFailure>();
  QVERIFY2(failure.message.contains(QStringLiteral("not enough memory")), qPrintable(failure.message));
  QCOMPARE(assembly(), before);
  QVERIFY(window_->simulation().hasWorld());
  QMessageBox* box = window_->loadFeedback()->errorDialog();
  QVERIFY(box != nullptr);
  QCOMPARE(box->text(), failure.message);
  box->close();
  QTRY_VERIFY(window_->loadFeedback()->errorDialog() == nullptr);
  QCOMPARE(window_->messagesDock()->model()->count(vaw::ui::MessageLogModel::Severity::Error), errors + 1);
  QVERIFY(answers());
  // Nothing is left half done: the same file opens.
  QVERIFY(bench_.open(sample()));
}

void TestFaults::aFailedOrderSearchSaysWhyAndTheNextFindsTheOrder_data() {
  QTest::addColumn<long>("depth");
  QTest::newRow("at once") << 0L;
  QTest::newRow("sweeping the ways home") << 600L;
}

void TestFaults::aFailedOrderSearchSaysWhyAndTheNextFindsTheOrder() {
  QFETCH(long, depth);
  vaw::ui::SequenceDock* dock = window_->sequenceDock();
  dock->show();
  dock->raise();
  {
    const Failing fault("order", depth);
    QTest::mouseClick(dock->findButton(), Qt::LeftButton);
    QTRY_VERIFY_WITH_TIMEOUT(!dock->finding(), 60000);
    QVERIFY2(fault.happened(), "the order search allocated less than the depth asked for");
  }
  QVERIFY(dock->plan() == nullptr);
  QCOMPARE(dock->hint()->text(), QStringLiteral("No order: not enough memory"));
  QVERIFY(dock->findButton()->isEnabled());
  QVERIFY(answers());
  QTest::mouseClick(dock->findButton(), Qt::LeftButton);
  QTRY_VERIFY_WITH_TIMEOUT(dock->plan() != nullptr, 60000);
  QCOMPARE(dock->model()->rowCount(), 8);
}

void TestFaults::aFailedCheckAtRestSaysWhy() {
  vaw::ui::InterferenceDock* dock = window_->interferenceDock();
  dock->show();
  dock->raise();
  // Checked once per geometry: another assembly first, so that the sample is checked when it opens.
  QVERIFY(bench_.open(sleeveScene()));
  {
    const Failing fault("interferences", 200);
    QVERIFY(bench_.open(sample()));
    QTRY_VERIFY_WITH_TIMEOUT(!dock->checking(), 60000);
    QVERIFY2(fault.happened(), "the check allocated less than the depth asked for");
  }
  QCOMPARE(dock->hint()->text(), QStringLiteral("The check failed: not enough memory"));
  QVERIFY(answers());
  QVERIFY(bench_.open(sleeveScene()));
  QVERIFY(bench_.open(sample()));
  QTRY_VERIFY_WITH_TIMEOUT(!dock->checking(), 60000);
  QVERIFY2(!dock->hint()->text().contains(QStringLiteral("failed")), qPrintable(dock->hint()->text()));
}

void TestFaults::aFailedSearchForNearMissesSaysWhy() {
  vaw::ui::ConstraintsDock* dock = window_->constraintsDock();
  dock->show();
  dock->raise();
  // A file of its own geometry: near misses are looked for once per geometry.
  QTemporaryDir dir;
  QVERIFY(dir.isValid());
  const QString copy = dir.filePath(QStringLiteral("bracket-copy.stp"));
  QVERIFY(QFile::copy(sample(), copy));
  {
    const Failing fault("near misses", 200);
    QVERIFY(bench_.open(copy));
    QTRY_VERIFY_WITH_TIMEOUT(fault.happened() && !dock->findingNearMisses(), 60000);
  }
  QTRY_COMPARE_WITH_TIMEOUT(dock->nearMissTitle()->text(),
                            QStringLiteral("Near misses could not be looked for: not enough memory"), 5000);
  QVERIFY(dock->model()->rowCount() > 0);
  QVERIFY(answers());
  QVERIFY(bench_.open(sample()));
}

void TestFaults::aFailedReportSaysWhyAndLeavesNoReport() {
  // With an order found: the report is then written at once.
  vaw::ui::SequenceDock* sequence = window_->sequenceDock();
  if (sequence->plan() == nullptr) {
    QTest::mouseClick(sequence->findButton(), Qt::LeftButton);
    QTRY_VERIFY_WITH_TIMEOUT(sequence->plan() != nullptr, 60000);
  }
  QTemporaryDir out;
  QVERIFY(out.isValid());
  const QString dir = out.filePath(QStringLiteral("report"));
  {
    const Failing fault("report", 5000);
    window_->exportReport(dir);
    QVERIFY(window_->writingReport());
    QTRY_VERIFY_WITH_TIMEOUT(!window_->writingReport(), 60000);
    QVERIFY2(fault.happened(), "the report allocated less than the depth asked for");
  }
  const QString said = window_->statusBar()->currentMessage();
  QVERIFY2(said == QStringLiteral("Could not write the report into %1: not enough memory").arg(dir), qPrintable(said));
  QVERIFY(!QFile::exists(dir + QStringLiteral("/report.html")));
  QVERIFY(answers());
  window_->exportReport(dir);
  QTRY_VERIFY_WITH_TIMEOUT(!window_->writingReport(), 60000);
  QVERIFY(QFile::exists(dir + QStringLiteral("/report.html")));
}

// The sleeve carried with the mouse, then swept in the Path panel: the sweep fails at once and deep in its
// voxels, the export of its volume fails, and the recorded carry is still there to sweep and export.
void TestFaults::aFailedSweepOrExportSaysWhyAndKeepsTheSession() {
  QVERIFY(bench_.open(sleeveScene()));
  const vaw::Assembly& a = *assembly();
  const vaw::PartId sleeve = *a.findPart("sleeve");
  auto& sim = window_->simulation();
  Eigen::Isometry3d lifted = sim.world().part(sleeve).pose;
  lifted.translation() += Eigen::Vector3d(-0.06, 0.04, -0.11);
  sim.play();
  vaw::guitest::carryWithMouse(*window_, sleeve, lifted, "sleeve");
  if (QTest::currentTestFailed()) return;
  QTRY_VERIFY_WITH_TIMEOUT(sim.world().part(sleeve).state != vaw::interact::PartState::InHand, 3000);
  sim.pause();
  const std::uint64_t recorded = sim.recorder().length();

  vaw::ui::PathDock* path = window_->pathDock();
  path->show();
  path->raise();
  window_->viewport()->selectPart(sleeve);
  QTRY_VERIFY_WITH_TIMEOUT(path->sweepButton()->isEnabled(), 2000);
  vaw::guitest::typeInto(path->voxelBox(), QStringLiteral("2"));
  QSignalSpy done(path, &vaw::ui::PathDock::finishedSweep);
  for (const long depth : {0L, 2000L, 40000L}) {
    const Failing fault("sweep", depth);
    QTest::mouseClick(path->sweepButton(), Qt::LeftButton);
    QVERIFY(done.wait(60000));
    QVERIFY2(fault.happened(), qPrintable(QStringLiteral("the sweep allocated fewer than %1 times").arg(depth)));
    QVERIFY(path->swept() == nullptr);
    QCOMPARE(path->summary()->text(), QStringLiteral("Not enough memory to sweep at 2 mm voxels: a larger voxel fits."));
    QVERIFY(answers());
  }
  QCOMPARE(sim.recorder().length(), recorded);
  QTest::mouseClick(path->sweepButton(), Qt::LeftButton);
  QVERIFY(done.wait(60000));
  QVERIFY2(path->swept() != nullptr, qPrintable(path->summary()->text()));

  QTemporaryDir keep;
  QVERIFY(keep.isValid());
  const QString target = keep.filePath(QStringLiteral("sleeve-swept.stl"));
  QSignalSpy exported(path, &vaw::ui::PathDock::exported);
  {
    const Failing fault("export", 20);
    vaw::guitest::whenModal([target](QWidget* w) { vaw::guitest::answerFileDialog(w, target); });
    QTest::mouseClick(path->exportButton(), Qt::LeftButton);
    QVERIFY(exported.wait(30000));
    QVERIFY(fault.happened());
  }
  QVERIFY2(exported.last().at(1).toString().contains(QStringLiteral("not enough memory")),
           qPrintable(exported.last().at(1).toString()));
  QVERIFY(!QFile::exists(target));
  QVERIFY(answers());
  QTRY_VERIFY_WITH_TIMEOUT(path->exportButton()->isEnabled(), 5000);
  vaw::guitest::whenModal([target](QWidget* w) { vaw::guitest::answerFileDialog(w, target); });
  QTest::mouseClick(path->exportButton(), Qt::LeftButton);
  QVERIFY(exported.wait(30000));
  QCOMPARE(exported.last().at(1).toString(), QString());
  QVERIFY(QFile::exists(target));
  QCOMPARE(sim.recorder().length(), recorded);
}

// A second of the sleeve's scene recorded, then written as a video and as glTF: each fails at once and later
// in its work (the video at the 4,000th of the 4,000 to 8,000 allocations it makes, the glTF file at its
// 40th), each time said with no file left, the recording as it was; then each is written. Deeper in the glTF
// file an allocation that fails inside nlohmann-json ends the process: its values' destructor allocates
// (json_value::destroy keeps the children on a std::vector), and an assignment that fails half-way leaves a
// value its destructor cannot free (docs/architecture.md, "Background work").
void TestFaults::aFailedVideoOrGltfSaysWhyAndLeavesNoFile() {
  QVERIFY(bench_.open(sleeveScene()));
  auto& sim = window_->simulation();
  sim.play();
  QTRY_VERIFY_WITH_TIMEOUT(sim.recorder().endTime() >= 1.0, 20000);
  sim.pause();
  const std::uint64_t recorded = sim.recorder().length();
  QTemporaryDir keep;
  QVERIFY(keep.isValid());
  const QString target = keep.filePath(QStringLiteral("sleeve.mp4"));
  vaw::video::VideoOptions options;
  options.width = 320;
  options.height = 180;
  options.fps = 10;
  for (const long depth : {0L, 4000L}) {
    const Failing fault("video", depth);
    window_->exportVideo(target, options);
    QVERIFY(window_->exportingVideo());
    QTRY_VERIFY_WITH_TIMEOUT(!window_->exportingVideo(), 60000);
    QVERIFY2(fault.happened(), qPrintable(QStringLiteral("the video allocated fewer than %1 times").arg(depth)));
    const QString said = window_->statusBar()->currentMessage();
    QVERIFY2(said == QStringLiteral("Could not write the video %1: not enough memory").arg(target), qPrintable(said));
    QCOMPARE(QDir(keep.path()).entryList(QDir::Files | QDir::Hidden), QStringList());
    QVERIFY(answers());
  }
  QCOMPARE(sim.recorder().length(), recorded);
  window_->exportVideo(target, options);
  QTRY_VERIFY_WITH_TIMEOUT(!window_->exportingVideo(), 60000);
  QVERIFY2(QFile::exists(target), qPrintable(window_->statusBar()->currentMessage()));

  // The same recording as glTF.
  const QString glb = keep.filePath(QStringLiteral("sleeve.glb"));
  for (const long depth : {0L, 40L}) {
    const Failing fault("gltf", depth);
    window_->exportGltf(glb);
    QVERIFY(window_->exportingGltf());
    QTRY_VERIFY_WITH_TIMEOUT(!window_->exportingGltf(), 60000);
    QVERIFY2(fault.happened(), qPrintable(QStringLiteral("the glTF export allocated fewer than %1 times").arg(depth)));
    const QString said = window_->statusBar()->currentMessage();
    QVERIFY2(said == QStringLiteral("Could not write the glTF file %1: not enough memory").arg(glb), qPrintable(said));
    QVERIFY(!QFile::exists(glb));
    QVERIFY(answers());
  }
  window_->exportGltf(glb);
  QTRY_VERIFY_WITH_TIMEOUT(!window_->exportingGltf(), 60000);
  QVERIFY2(QFile::exists(glb), qPrintable(window_->statusBar()->currentMessage()));
  QCOMPARE(sim.recorder().length(), recorded);
}

QTEST_MAIN(TestFaults)
#include "tst_faults.moc"
