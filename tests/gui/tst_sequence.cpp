// The Sequence panel and File > Export Report on the bundled STEP sample (bolted-bracket.stp): Find Order
// clicked, the order read from the table (the bracket at step 2, the nuts at step 3 after it), a row clicked
// selects its part in the window, the report written with this window's session, a folder that cannot be
// written reported in Messages; a part no order inserts shown in red, its blockers named when clicked;
// another assembly opened clears the plan, and a report asked for then finds the order first; a mesh without
// a base says why it has no order. The screenshots go to the build tree (tests/gui/sequence-*.png).
//
// Runs under Xvfb (Qt3D needs GL); any Qt warning fails the test.
#include <QBrush>
#include <QColor>
#include <QDir>
#include <QFile>
#include <QLabel>
#include <QProgressBar>
#include <QProgressDialog>
#include <QPushButton>
#include <QSettings>
#include <QSignalSpy>
#include <QStatusBar>
#include <QTableView>
#include <QTemporaryDir>
#include <QTreeView>
#include <QUndoStack>
#include <Qt3DExtras/Qt3DWindow>
#include <QtTest>
#include <algorithm>
#include <memory>

#include "gui_test_support.hpp"
#include "vaw/paths.hpp"
#include "vaw/sim/session.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/message_log_model.hpp"
#include "vaw/ui/sequence_dock.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/viewport.hpp"

using vaw::PartId;
using vaw::ui::AssemblyController;
using vaw::ui::MainWindow;
using vaw::ui::SequenceModel;

namespace {

QString sample() { return QFile::decodeName((vaw::resourceDir() / "step" / "bolted-bracket.stp").string().c_str()); }

QString readText(const QString& file) {
  QFile f(file);
  return f.open(QIODevice::ReadOnly) ? QString::fromUtf8(f.readAll()) : QString();
}

}  // namespace

class TestSequence : public QObject {
  Q_OBJECT

 public:
  static void initMain() {
    if (qEnvironmentVariableIsEmpty("QT3D_RENDERER")) qputenv("QT3D_RENDERER", "opengl");
  }

 private slots:
  void initTestCase();
  void cleanup();
  void cleanupTestCase();

  void findOrderSelectAndExport();
  void stuckPartNamesItsBlockers();
  void anotherAssemblyClearsThePlan();
  void withoutBaseSaysWhy();
  void reportOfALongSessionKeepsTheWindowAnsweringAndStops();

 private:
  [[nodiscard]] vaw::ui::SequenceDock* dock() const { return window_->sequenceDock(); }
  [[nodiscard]] SequenceModel* model() const { return dock()->model(); }
  [[nodiscard]] QTableView* table() const { return dock()->view(); }
  [[nodiscard]] const vaw::Assembly& assembly() const { return *controller_->assembly(); }
  [[nodiscard]] QString cell(int row, int column) const { return model()->index(row, column).data().toString(); }
  [[nodiscard]] int rowNamed(const QString& part) const;
  void open(const QString& path);
  void showDock();

  vaw::guitest::Workbench bench_;
  std::unique_ptr<AssemblyController>& controller_ = bench_.controller;
  std::unique_ptr<MainWindow>& window_ = bench_.window;
};

void TestSequence::initTestCase() {
  QVERIFY2(QFile::exists(sample()), qPrintable(sample()));
  QVERIFY(bench_.start({.autoPlay = false}));
  QVERIFY2(controller_->importers().find(std::filesystem::path("x.stp")) != nullptr, "the STEP plugin is in VAW_PLUGIN_PATH");
}

void TestSequence::cleanup() { vaw::guitest::verifyNoWarnings(); }

void TestSequence::cleanupTestCase() {
  bench_.stop();
}

void TestSequence::open(const QString& path) {
  QVERIFY(bench_.open(path));
}

void TestSequence::showDock() {
  dock()->show();
  dock()->raise();
  // Room for the eight rows.
  window_->resizeDocks({dock()}, {300}, Qt::Vertical);
  QTest::qWait(50);
  QVERIFY(dock()->isVisible());
}

int TestSequence::rowNamed(const QString& part) const {
  for (int row = 0; row < model()->rowCount(); ++row)
    if (cell(row, SequenceModel::PartColumn) == part) return row;
  return -1;
}

void TestSequence::findOrderSelectAndExport() {
  open(sample());
  showDock();
  QCOMPARE(model()->rowCount(), 0);
  QVERIFY(dock()->findButton()->isEnabled());
  QTest::mouseClick(dock()->findButton(), Qt::LeftButton);
  QVERIFY(dock()->finding() || dock()->plan() != nullptr);
  QTRY_VERIFY_WITH_TIMEOUT(dock()->plan() != nullptr, 60000);
  QVERIFY(!dock()->progressBar()->isVisible());
  QVERIFY(dock()->findButton()->isEnabled());

  // The base and seven parts, every one inserted by the order.
  QCOMPARE(model()->rowCount(), 8);
  QCOMPARE(cell(0, SequenceModel::PartColumn), QStringLiteral("base-plate"));
  QCOMPARE(cell(0, SequenceModel::PositionColumn), QStringLiteral("1"));
  for (int row = 0; row < model()->rowCount(); ++row) QVERIFY(!model()->isStuck(row));
  QVERIFY2(dock()->hint()->text().startsWith(QStringLiteral("An order puts every part in place: 7 after the base.")),
           qPrintable(dock()->hint()->text()));
  const int bracket = rowNamed(QStringLiteral("bracket"));
  QVERIFY(bracket >= 0);
  QCOMPARE(cell(bracket, SequenceModel::StepColumn), QStringLiteral("2"));
  QCOMPARE(cell(bracket, SequenceModel::HomeColumn), QStringLiteral("down: insert on stud-1"));
  QCOMPARE(cell(bracket, SequenceModel::AfterColumn), QStringLiteral("stud-1 (partner), stud-2 (partner)"));
  for (const QString& nut : {QStringLiteral("nut-1"), QStringLiteral("nut-2")}) {
    const int row = rowNamed(nut);
    QVERIFY2(row >= 0, qPrintable(nut));
    QCOMPARE(cell(row, SequenceModel::StepColumn), QStringLiteral("3"));
    QVERIFY2(cell(row, SequenceModel::AfterColumn).contains(QStringLiteral("bracket (")),
             qPrintable(cell(row, SequenceModel::AfterColumn)));
    QVERIFY(cell(row, SequenceModel::AfterColumn).startsWith(QStringLiteral("bracket (partner, in its way), stud-")));
    // Screwed down its stud beside the bracket's upright, 1 mm off: a near miss, in orange.
    QCOMPARE(cell(row, SequenceModel::ClearanceColumn), QStringLiteral("1.015 mm to bracket"));
    QVERIFY(model()->isNearMiss(row));
    QCOMPARE(model()->index(row, SequenceModel::ClearanceColumn).data(Qt::BackgroundRole).value<QBrush>().color(), QColor(250, 200, 150));
    const QString tip = model()->index(row, SequenceModel::ClearanceColumn).data(Qt::ToolTipRole).toString();
    QVERIFY2(tip.contains(QStringLiteral("a near miss (under 5 mm)")) && tip.contains(QStringLiteral("Rests on bracket.")), qPrintable(tip));
  }
  // The bracket slides down both studs onto the plate, nothing else near; the sleeve passes 5 mm off.
  QCOMPARE(cell(bracket, SequenceModel::ClearanceColumn), QStringLiteral("clear"));
  QVERIFY(!model()->isNearMiss(bracket));
  QVERIFY(!model()->isNearMiss(rowNamed(QStringLiteral("sleeve"))));
  QVERIFY2(dock()->hint()->text().contains(QStringLiteral("2 ways home pass a part already in closer than 5 mm (orange).")),
           qPrintable(dock()->hint()->text()));

  // A row clicked selects its part in the window: the viewport, the simulation's highlight, the scene tree.
  const PartId bracketId = *assembly().findPart("bracket");
  const QModelIndex index = model()->index(bracket, SequenceModel::PartColumn);
  table()->scrollTo(index);
  QTest::mouseClick(table()->viewport(), Qt::LeftButton, {}, table()->visualRect(index).center());
  QTRY_COMPARE(window_->viewport()->selectedPart(), std::optional<PartId>(bracketId));
  QCOMPARE(window_->simulation().selected(), std::optional<PartId>(bracketId));
  QCOMPARE(window_->sceneDock()->currentPart(), std::optional<PartId>(bracketId));
  // And the other way: a part selected elsewhere shows as the selected row.
  const PartId pin = *assembly().findPart("pin");
  window_->viewport()->selectPart(pin);
  QCOMPARE(table()->selectionModel()->selectedRows().size(), 1);
  QCOMPARE(table()->selectionModel()->selectedRows().front().row(), rowNamed(QStringLiteral("pin")));
  window_->viewport()->selectPart(bracketId);
  QVERIFY(!vaw::guitest::capture(window_->viewport()).isNull());
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("sequence-order.png"));

  // A few steps simulated: the report has this session.
  for (int i = 0; i < 20; ++i) window_->simulation().stepOnce();
  QVERIFY(window_->simulation().recorder().length() > 0);
  QTemporaryDir out;
  QVERIFY(out.isValid());
  const QString dir = out.filePath(QStringLiteral("report"));
  window_->exportReport(dir);
  QTRY_VERIFY_WITH_TIMEOUT(!window_->writingReport(), 60000);
  QVERIFY(QFile::exists(dir + QStringLiteral("/report.html")));
  QVERIFY(QFile::exists(dir + QStringLiteral("/parts.csv")));
  QVERIFY(readText(dir + QStringLiteral("/parts.csv")).contains(QStringLiteral("bracket")));
  // With the panel's ways home: their table and ways.csv.
  QVERIFY2(readText(dir + QStringLiteral("/ways.csv")).contains(QStringLiteral("\nnut-1,down: insert on stud-1,")),
           qPrintable(readText(dir + QStringLiteral("/ways.csv"))));
  QVERIFY(readText(dir + QStringLiteral("/report.html")).contains(QStringLiteral("<table id='ways'>")));
  QVERIFY2(readText(dir + QStringLiteral("/sessions.csv")).contains(QStringLiteral("this session")),
           qPrintable(readText(dir + QStringLiteral("/sessions.csv"))));
  QVERIFY2(window_->statusBar()->currentMessage().contains(dir + QStringLiteral("/report.html")),
           qPrintable(window_->statusBar()->currentMessage()));

  // A folder that cannot be made (a file stands where it would be): said in Messages, naming the folder.
  QFile blocker(out.filePath(QStringLiteral("a-file")));
  QVERIFY(blocker.open(QIODevice::WriteOnly));
  blocker.close();
  const QString bad = blocker.fileName() + QStringLiteral("/report");
  vaw::ui::MessageLogModel* log = window_->messagesDock()->model();
  const int errors = log->count(vaw::ui::MessageLogModel::Severity::Error);
  window_->exportReport(bad);
  QTRY_VERIFY_WITH_TIMEOUT(!window_->writingReport(), 60000);
  QCOMPARE(log->count(vaw::ui::MessageLogModel::Severity::Error), errors + 1);
  QVERIFY2(log->text(log->rowCount() - 1).contains(bad), qPrintable(log->text(log->rowCount() - 1)));
  QVERIFY(window_->statusBar()->currentMessage().startsWith(QStringLiteral("Could not write the report into ")));
}

// The sample has no part that no order inserts: the plan found, with the bracket made one (its nuts in its
// way down, the base plate up), shows it in red after the order; clicked, it is selected and its blockers
// are named in the status bar.
void TestSequence::stuckPartNamesItsBlockers() {
  vaw::eval::SequencePlan plan = *dock()->plan();
  const PartId bracket = *assembly().findPart("bracket");
  const auto at = std::find(plan.order.begin(), plan.order.end(), bracket);
  QVERIFY(at != plan.order.end());
  const auto k = at - plan.order.begin();
  plan.order.erase(at);
  plan.way.erase(plan.way.begin() + k);
  plan.step.erase(plan.step.begin() + k);
  plan.stuck.push_back({bracket, {{*assembly().findPart("nut-1"), *assembly().findPart("nut-2")}, {*assembly().base}}, {}});
  model()->setPlan(&assembly(), &plan);
  QCOMPARE(model()->rowCount(), 8);
  const int row = rowNamed(QStringLiteral("bracket"));
  QCOMPARE(row, 7);
  QVERIFY(model()->isStuck(row));
  QCOMPARE(cell(row, SequenceModel::StepColumn), QStringLiteral("no order"));
  QCOMPARE(model()->index(row, SequenceModel::PartColumn).data(Qt::ForegroundRole).value<QBrush>().color(), QColor(200, 0, 0));
  const QString blockers = QStringLiteral("insert on stud-1: nut-1, nut-2; insert on stud-1 (other end): base-plate");
  QCOMPARE(model()->blockersText(row), blockers);
  window_->viewport()->selectPart(std::nullopt);
  const QModelIndex index = model()->index(row, SequenceModel::PartColumn);
  table()->scrollTo(index);
  QTest::mouseClick(table()->viewport(), Qt::LeftButton, {}, table()->visualRect(index).center());
  QTRY_COMPARE(window_->viewport()->selectedPart(), std::optional<PartId>(bracket));
  QCOMPARE(window_->statusBar()->currentMessage(), QStringLiteral("bracket has no way home: ") + blockers);
  vaw::guitest::shot(window_.get(), dock(), QStringLiteral("sequence-stuck.png"));
}

// Opened again, the plan is gone; File > Export Report then finds the order before it writes.
void TestSequence::anotherAssemblyClearsThePlan() {
  QVERIFY(dock()->plan() != nullptr);
  open(sample());
  QCOMPARE(model()->rowCount(), 0);
  QVERIFY(dock()->plan() == nullptr);
  QTemporaryDir out;
  QVERIFY(out.isValid());
  window_->exportReport(out.path());
  // Until the writer is done, not until report.html is there: the folder is removed when the test ends, and
  // a writer still busy in it races the removal.
  QTRY_VERIFY_WITH_TIMEOUT(
      window_->statusBar()->currentMessage().startsWith(QStringLiteral("Wrote the report to ") + out.path()), 60000);
  QVERIFY(!window_->writingReport());
  QCOMPARE(model()->rowCount(), 8);
  QVERIFY(QFile::exists(out.filePath(QStringLiteral("report.html"))));
  QVERIFY(QFile::exists(out.filePath(QStringLiteral("parts.csv"))));
}

// A mesh has no base: Find Order says so in the panel, and a report asked for says why none was written.
void TestSequence::withoutBaseSaysWhy() {
  open(QFile::decodeName((vaw::resourceDir() / "meshes" / "sleeve.obj").string().c_str()));
  QVERIFY(!assembly().base.has_value());
  showDock();
  QTest::mouseClick(dock()->findButton(), Qt::LeftButton);
  QTRY_VERIFY_WITH_TIMEOUT(!dock()->finding(), 30000);
  QVERIFY(dock()->plan() == nullptr);
  QCOMPARE(model()->rowCount(), 0);
  QVERIFY2(dock()->hint()->text().startsWith(QStringLiteral("No order: ")), qPrintable(dock()->hint()->text()));
  QVERIFY(dock()->hint()->text().contains(QStringLiteral("expected an assembly with a base part")));
  QTemporaryDir out;
  QVERIFY(out.isValid());
  window_->exportReport(out.path());
  QTRY_VERIFY_WITH_TIMEOUT(
      window_->statusBar()->currentMessage().startsWith(QStringLiteral("No report written to ") + out.path()), 30000);
  QVERIFY(!QFile::exists(out.filePath(QStringLiteral("report.html"))));
  vaw::guitest::shot(window_.get(), dock(), QStringLiteral("sequence-no-base.png"));
}

// A long session (16 minutes at 1 kHz, the most a session file holds) in the window: File > Export Report
// replays it off the GUI thread, so a row clicked in the Sequence panel meanwhile selects its part at once,
// and Stop in the report's progress window ends it with nothing written. The replay is paced for the test
// (MainWindow::setReportPace, 30 ms at each of its hundred progress reports), so that it runs for seconds on
// any machine.
void TestSequence::reportOfALongSessionKeepsTheWindowAnsweringAndStops() {
  window_->setReportPace(30);
  QTemporaryDir out;
  QVERIFY(out.isValid());
  vaw::sim::Session longSession;
  longSession.scene = QFile::encodeName(sample()).toStdString();
  longSession.settings.rate = 1000.0;
  for (int i = 0; i < 960 * 1000; ++i) longSession.inputs.push_back(vaw::sim::Input{});
  const QString file = out.filePath(QStringLiteral("longSession.vaw-session.json"));
  vaw::sim::saveSession(longSession, std::filesystem::path(QFile::encodeName(file).toStdString()));
  open(file);
  QCOMPARE(window_->simulation().recorder().length(), std::uint64_t{960 * 1000});
  showDock();
  QTest::mouseClick(dock()->findButton(), Qt::LeftButton);
  QTRY_VERIFY_WITH_TIMEOUT(dock()->plan() != nullptr, 60000);

  const QString dir = out.filePath(QStringLiteral("report"));
  window_->exportReport(dir);
  QVERIFY(window_->writingReport());
  // The window answers while the session is replayed: a row clicked selects its part.
  const int row = rowNamed(QStringLiteral("pin"));
  QVERIFY(row >= 0);
  const QModelIndex index = model()->index(row, SequenceModel::PartColumn);
  table()->scrollTo(index);
  QTest::mouseClick(table()->viewport(), Qt::LeftButton, {}, table()->visualRect(index).center());
  QTRY_COMPARE_WITH_TIMEOUT(window_->viewport()->selectedPart(), assembly().findPart("pin"), 1000);
  QVERIFY2(window_->writingReport(), "the replay was still running when the row was clicked");

  // Its progress window shows how far it is, and Stop ends it.
  QTRY_VERIFY_WITH_TIMEOUT(window_->reportProgress() != nullptr && window_->reportProgress()->isVisible() &&
                               window_->reportProgress()->value() > 0, 10000);
  QProgressDialog* progress = window_->reportProgress();
  QCOMPARE(progress->labelText(), QStringLiteral("Writing the report into %1\nreplaying this session").arg(dir));
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("sequence-report-progress.png"));
  auto* stop = progress->findChild<QPushButton*>();
  QVERIFY(stop != nullptr);
  QCOMPARE(stop->text(), QStringLiteral("Stop"));
  QTest::mouseClick(stop, Qt::LeftButton);
  QTRY_VERIFY_WITH_TIMEOUT(!window_->writingReport(), 5000);
  QCOMPARE(window_->statusBar()->currentMessage(), QStringLiteral("Stopped: no report written to ") + dir);
  QVERIFY(!QFile::exists(dir + QStringLiteral("/report.html")));
  QVERIFY(window_->reportProgress() == nullptr);
  window_->setReportPace(0);
}

QTEST_MAIN(TestSequence)
#include "tst_sequence.moc"
