// Assemblies as designers model them, in the workbench as a person uses it (docs/step.md, "Fits as designers
// model them"): a cap screw put by hand into a hole modelled at its tap drill goes home through its thread
// and is PLACED; the Interferences panel lists the threads and press fits, and a row clicked shows where the
// two parts overlap; a bought-in unit is one row of the tree, taken apart from its context menu; and the real
// SolidWorks rotary table (read where the real exports are kept; skipped, naming the folder, where they are
// not) opens, its shaft and bearing go home by hand and its thread shows where it is. Real mouse events in
// the 3D view and the panels; any Qt warning fails the test; screenshots in the build tree (tests/gui).
#include <QDir>
#include <QHeaderView>
#include <QLabel>
#include <QMenu>
#include <QMenuBar>
#include <QPushButton>
#include <QSignalSpy>
#include <QStandardItemModel>
#include <QTableView>
#include <QTemporaryDir>
#include <QtTest>
#include <memory>

#include "gui_test_support.hpp"
#include "step_fixtures.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/constraints_dock.hpp"
#include "vaw/ui/interference_dock.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/scene_tree_model.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/viewport.hpp"

using vaw::PartId;
using vaw::interact::PartState;
using vaw::ui::AssemblyController;
using vaw::ui::MainWindow;

class TestDesignedFits : public QObject {
  Q_OBJECT

 public:
  static void initMain() {
    if (qEnvironmentVariableIsEmpty("QT3D_RENDERER")) qputenv("QT3D_RENDERER", "opengl");
  }

 private slots:
  void initTestCase();
  void cleanup();
  void cleanupTestCase();

  void aCapScrewGoesHomeThroughItsTappedHole();
  void anOversizedDowelIsANearMissInTheConstraintsPanel();
  void aBearingIsOneUnitUntilTakenApart();
  void theRotaryTableOpensAndShowsWhereItsThreadIs();
  void aKeyIsAPrismaticFitInTheConstraintsPanel();

 private:
  [[nodiscard]] vaw::ui::SimulationController& sim() const { return window_->simulation(); }
  [[nodiscard]] const vaw::Assembly& assembly() const { return *controller_->assembly(); }
  [[nodiscard]] PartId part(const char* name) const { return *assembly().findPart(name); }
  [[nodiscard]] PartState state(const char* name) const { return sim().world().part(part(name)).state; }
  void open(const QString& file);
  // Carried to `mmAbove` over its place and let go, as a fitter does: true when it comes to rest PLACED.
  [[nodiscard]] bool place(const char* name, double mmAbove, int timeoutMs) {
    carry(name, mmAbove);
    return !QTest::currentTestFailed() && QTest::qWaitFor([&] { return state(name) == PartState::Placed; }, timeoutMs);
  }
  void carry(const char* name, double mmAbove) {
    Eigen::Isometry3d t = *assembly().parts[part(name)].finalPose;
    t.translation().z() += mmAbove * 1e-3;
    vaw::guitest::carryWithMouse(*window_, part(name), t, name);
  }
  // A click on the Interferences panel's row naming both parts, as a person does; false when none does.
  bool clickInterference(const QString& a, const QString& b);

  vaw::guitest::Workbench bench_;
  std::unique_ptr<AssemblyController>& controller_ = bench_.controller;
  std::unique_ptr<MainWindow>& window_ = bench_.window;
};

void TestDesignedFits::initTestCase() {
  QVERIFY(bench_.start({.clearSettings = true, .autoPlay = std::nullopt, .size = {1280, 800}, .activate = false}));
}

void TestDesignedFits::cleanup() {
  if (window_) sim().pause();
  vaw::guitest::verifyNoWarnings();
}

void TestDesignedFits::cleanupTestCase() { bench_.stop(); }

void TestDesignedFits::open(const QString& file) {
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  controller_->open(file);
  QVERIFY(loaded.wait(120000) || !loaded.isEmpty());
  QVERIFY(sim().hasWorld());
  sim().setSpeed(1.0);
  QVERIFY(!vaw::guitest::capture(window_->viewport()).isNull());
}

bool TestDesignedFits::clickInterference(const QString& a, const QString& b) {
  vaw::ui::InterferenceDock* dock = window_->interferenceDock();
  dock->show();
  dock->raise();
  QTableView* view = dock->view();
  for (int row = 0; row < dock->model()->rowCount(); ++row) {
    const QString x = dock->model()->index(row, vaw::ui::InterferenceModel::FirstColumn).data().toString();
    const QString y = dock->model()->index(row, vaw::ui::InterferenceModel::SecondColumn).data().toString();
    if (!((x == a && y == b) || (x == b && y == a))) continue;
    view->scrollTo(dock->model()->index(row, 0));
    const QRect cell = view->visualRect(dock->model()->index(row, vaw::ui::InterferenceModel::KindColumn));
    QTest::mouseClick(view->viewport(), Qt::LeftButton, {}, cell.center());
    return true;
  }
  return false;
}

void TestDesignedFits::aCapScrewGoesHomeThroughItsTappedHole() {
  const QString file = QDir(QDir::tempPath()).filePath(QStringLiteral("vaw-gui-fastened-%1.stp").arg(QCoreApplication::applicationPid()));
  vaw::steptest::writeFastenedBlock(file.toStdString());
  open(file);
  QFile::remove(file);
  // Checked in the background when the file opened: four threads and two press fits, no clash.
  vaw::ui::InterferenceDock* dock = window_->interferenceDock();
  QTRY_VERIFY_WITH_TIMEOUT(!dock->checking() && dock->model()->rowCount() == 6, 20000);
  QVERIFY2(dock->hint()->text().startsWith(QStringLiteral("0 clash")), qPrintable(dock->hint()->text()));
  // Every fit taken: no near miss in the Constraints panel.
  QTRY_VERIFY_WITH_TIMEOUT(!window_->constraintsDock()->findingNearMisses(), 20000);
  QCOMPARE(window_->constraintsDock()->nearMissModel()->rowCount(), 0);
  // The panel names each insert's fit: the cap screw's thread at the tap drill into the base, its head in
  // the bracket's counterbore.
  {
    vaw::ui::ConstraintsDock* constraints = window_->constraintsDock();
    constraints->raise();
    const auto* model = constraints->model();
    QStringList fits;
    for (int row = 0; row < model->rowCount(); ++row) {
      const QString who = model->index(row, vaw::ui::ConstraintsModel::PartColumn).data().toString() + QStringLiteral(" on ") +
                          model->index(row, vaw::ui::ConstraintsModel::PartnerColumn).data().toString();
      fits << who + QStringLiteral(": ") + model->index(row, vaw::ui::ConstraintsModel::FitColumn).data().toString();
    }
    QVERIFY2(fits.contains(QStringLiteral("cap-screw-1 on base (base): threaded M6")), qPrintable(fits.join(QLatin1Char('\n'))));
    QVERIFY2(fits.contains(QStringLiteral("cap-screw-1 on bracket: clearance, counterbore")), qPrintable(fits.join(QLatin1Char('\n'))));
    QVERIFY2(fits.contains(QStringLiteral("dowel-1 on base (base): press")), qPrintable(fits.join(QLatin1Char('\n'))));
    QVERIFY2(fits.contains(QStringLiteral("csk-screw-1 on cover: clearance, countersink")),
             qPrintable(fits.join(QLatin1Char('\n'))));
    const int row = static_cast<int>(fits.indexOf(QStringLiteral("cap-screw-1 on bracket: clearance, counterbore")));
    constraints->view()->scrollTo(model->index(row, 0), QAbstractItemView::PositionAtTop);
    QTest::qWait(200);
    vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("designed-fits-panel.png"));
  }

  // As a fitter: the dowels pressed into the base, the bracket over them, a cap screw into its counterbore
  // and on down through its thread at the tap drill: home, PLACED.
  for (const char* dowel : {"dowel-1", "dowel-2"}) {
    QVERIFY2(place(dowel, 3.0, 5000), dowel);
  }
  QVERIFY2(place("bracket", 3.0, 5000), "bracket");
  QVERIFY2(place("cap-screw-1", 4.0, 5000), "cap-screw-1");
  const Eigen::Isometry3d home = *assembly().parts[part("cap-screw-1")].finalPose;
  QVERIFY2((sim().world().part(part("cap-screw-1")).pose.translation() - home.translation()).norm() < 1e-4,
           "the screw is home, its head on the counterbore's floor, its shank 0.5 mm into the thread");

  // The thread clicked in the panel: the screw selected, the overlap drawn on the base along its axis.
  QVERIFY(clickInterference(QStringLiteral("cap-screw-1"), QStringLiteral("base")));
  QTRY_VERIFY_WITH_TIMEOUT(window_->viewport()->constraintGeometry().has_value(), 3000);
  const auto shown = *window_->viewport()->constraintGeometry();
  QCOMPARE(shown.partner, part("base"));
  QVERIFY(std::abs(std::abs(shown.direction.z()) - 1.0) < 1e-6);
  QTest::qWait(200);
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("designed-cap-screw-home.png"));
}

// The dowel drawn 0.3 mm larger than its hole: no fit of any kind, so no constraint; the Constraints panel
// says why under its table, and a row clicked selects the dowel.
void TestDesignedFits::anOversizedDowelIsANearMissInTheConstraintsPanel() {
  const QString file = QDir(QDir::tempPath()).filePath(QStringLiteral("vaw-gui-clash-%1.stp").arg(QCoreApplication::applicationPid()));
  vaw::steptest::writeFastenedBlock(file.toStdString(), {.clash = true});
  open(file);
  QFile::remove(file);
  vaw::ui::ConstraintsDock* dock = window_->constraintsDock();
  dock->show();
  dock->raise();
  QTRY_VERIFY_WITH_TIMEOUT(!dock->findingNearMisses() && dock->nearMissModel()->rowCount() == 2, 20000);
  for (int row = 0; row < 2; ++row) {
    const QString parts = dock->nearMissModel()->index(row, 0).data().toString();
    const QString why = dock->nearMissModel()->index(row, 2).data().toString();
    QVERIFY2(parts.endsWith(QStringLiteral("and dowel-1")), qPrintable(parts));
    QCOMPARE(dock->nearMissModel()->index(row, 1).data().toString(), QStringLiteral("insert"));
    QVERIFY2(why.contains(QStringLiteral("0.3 mm larger in radius than the bore")), qPrintable(why));
  }
  QVERIFY2(dock->findChild<QLabel*>(QStringLiteral("nearMissTitle"))->text().startsWith(QStringLiteral("2 near misses")),
           qPrintable(dock->findChild<QLabel*>(QStringLiteral("nearMissTitle"))->text()));
  QTableView* view = dock->nearMissView();
  QTest::mouseClick(view->viewport(), Qt::LeftButton, {}, view->visualRect(dock->nearMissModel()->index(0, 2)).center());
  QTRY_COMPARE_WITH_TIMEOUT(window_->viewport()->selectedPart(), std::optional<PartId>(part("dowel-1")), 2000);
  QTest::qWait(200);
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("designed-near-miss.png"));

  // An edit of the table (a constraint rejected) leaves the geometry as it was: the near misses stay, not
  // looked for again.
  QTableView* table = dock->view();
  QTest::mouseClick(table->viewport(), Qt::LeftButton, {}, table->visualRect(dock->model()->index(0, 0)).center());
  const int before = dock->model()->rowCount();
  QTest::mouseClick(dock->rejectButton(), Qt::LeftButton);
  QTRY_COMPARE_WITH_TIMEOUT(dock->model()->rowCount(), before - 1, 5000);
  QVERIFY(!dock->findingNearMisses());
  QCOMPARE(dock->nearMissModel()->rowCount(), 2);
}

void TestDesignedFits::aBearingIsOneUnitUntilTakenApart() {
  const QString file = QDir(QDir::tempPath()).filePath(QStringLiteral("vaw-gui-bearing-%1.stp").arg(QCoreApplication::applicationPid()));
  vaw::steptest::writeBearingInHousing(file.toStdString());
  open(file);
  QCOMPARE(assembly().parts.size(), std::size_t{3});
  const QModelIndex bearing = window_->sceneDock()->model()->indexOfPart(part("bearing"));
  QVERIFY(bearing.isValid());
  QCOMPARE(window_->sceneDock()->model()->rowCount(bearing), 10);
  QVERIFY(bearing.data(Qt::ToolTipRole).toString().contains(QStringLiteral("A unit of 10 parts")));
  // It goes into its housing whole.
  QVERIFY2(place("bearing", 3.0, 5000), "bearing");
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("designed-bearing-unit.png"));

  // Right-click it in the tree, Handle as parts: its rings and balls each a part.
  QMenu* menu = vaw::guitest::openSceneTreeMenu(*window_, part("bearing"));
  QVERIFY(menu != nullptr);
  QAction* apart = menu->findChild<QAction*>(QStringLiteral("unitApartAction"));
  QVERIFY(apart != nullptr && apart->isEnabled());
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  QTest::mouseClick(menu, Qt::LeftButton, {}, menu->actionGeometry(apart).center());
  QVERIFY(loaded.wait(60000) || !loaded.isEmpty());
  QCOMPARE(assembly().parts.size(), std::size_t{12});
  QVERIFY(assembly().findPart("ball-4").has_value());

  // Saved (File > Save As) and opened again, it is still apart: the choice went with the scene.
  // A folder of its own: the file dialog lists the folder it opens in.
  QTemporaryDir dir;
  QVERIFY(dir.isValid());
  const QString scene = dir.filePath(QStringLiteral("bearing-apart.vaw.json"));
  vaw::guitest::whenModal([scene](QWidget* w) { vaw::guitest::answerFileDialog(w, scene); });
  QMenuBar* bar = window_->menuBar();
  QAction* fileMenu = bar->actions().value(0);
  QVERIFY(fileMenu != nullptr && fileMenu->menu() != nullptr);
  QTest::mouseClick(bar, Qt::LeftButton, {}, bar->actionGeometry(fileMenu).center());
  QTRY_VERIFY_WITH_TIMEOUT(fileMenu->menu()->isVisible(), 5000);
  QAction* saveAs = window_->findChild<QAction*>(QStringLiteral("saveAsAction"));
  QVERIFY(saveAs != nullptr && saveAs->isEnabled());
  QTest::mouseClick(fileMenu->menu(), Qt::LeftButton, {}, fileMenu->menu()->actionGeometry(saveAs).center());
  QTRY_VERIFY_WITH_TIMEOUT(QFile::exists(scene), 10000);
  open(scene);
  QCOMPARE(assembly().parts.size(), std::size_t{12});
  QVERIFY(assembly().findPart("ring-outer").has_value());
  QFile::remove(file);
}

void TestDesignedFits::theRotaryTableOpensAndShowsWhereItsThreadIs() {
  const QString file = QDir(QStringLiteral(VAW_CAD_EXPORTS_DIR)).filePath(QStringLiteral("Drehtisch.STEP"));
  if (!QFile::exists(file)) QSKIP(qPrintable(QStringLiteral("no %1 (the real CAD exports are not here)").arg(file)));
  open(file);
  vaw::ui::InterferenceDock* dock = window_->interferenceDock();
  QTRY_VERIFY_WITH_TIMEOUT(!dock->checking() && dock->model()->rowCount() > 0, 30000);
  // The base is the floor plate with its internal gear; the stepper motor one unit.
  QVERIFY(assembly().parts[*assembly().base].name.rfind("Bodenplatte", 0) == 0);
  QVERIFY(assembly().findPart("NEMA 17_Predeterminado").has_value());
  // The shaft onto the floor plate and the lower bearing down over it, by hand.
  QVERIFY2(place("rotationswelle", 3.0, 8000), "rotationswelle");
  QVERIFY2(place("Kugellager", 3.0, 8000), "Kugellager");
  // A screw home by hand. What the table rests on goes in first: the four M4 screws that hold the bearing
  // holder to it, the rack holder and the pinion's spacer (none has a constraint of its own: each released
  // at its file pose) and the holder onto the shaft; then the table released in its place, and the rack
  // holder's M4 screw let go above its clearance hole falls home through it: PLACED at its file pose.
  for (const char* name : {"socket head cap screw_iso_ISO 4762 M4 x 12 - 12N", "socket head cap screw_iso_ISO 4762 M4 x 12 - 12N #2",
                           "socket head cap screw_iso_ISO 4762 M4 x 12 - 12N #3", "socket head cap screw_iso_ISO 4762 M4 x 12 - 12N #4",
                           "Zahnstangenhalterung", "zwischenstuckWelleRitzel"}) {
    QVERIFY2(place(name, 0.0, 8000), name);
  }
  QVERIFY2(place("lagerhalterung", 3.0, 8000), "lagerhalterung");
  QVERIFY2(place("Tischneu", 0.0, 8000), "Tischneu");
  const char* tableScrew = "socket head cap screw_iso_ISO 4762 M4 x 12 - 12N #6";
  QVERIFY2(place(tableScrew, 4.0, 8000), tableScrew);
  const Eigen::Isometry3d screwHome = *assembly().parts[part(tableScrew)].finalPose;
  QVERIFY2((sim().world().part(part(tableScrew)).pose.translation() - screwHome.translation()).norm() < 1e-4, "the screw is home");
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("designed-rotary-table-screw-home.png"));
  // An M4 thread clicked in the panel shows where it is.
  const QString screw = QStringLiteral("socket head cap screw_iso_ISO 4762 M4 x 12 - 12N");
  const QString nut = QStringLiteral("hex nut style 1 gradeab_iso_ISO - 4032 - M4 - W - N #4");
  QVERIFY(clickInterference(screw, nut));
  QTRY_VERIFY_WITH_TIMEOUT(window_->viewport()->constraintGeometry().has_value(), 3000);
  QTest::qWait(200);
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("designed-rotary-table.png"));
}

// The feather key between the keyway's walls and between the hub slot's: one prismatic fit each, its width
// in the Fit column; a click on its row shows its plane on the shaft.
void TestDesignedFits::aKeyIsAPrismaticFitInTheConstraintsPanel() {
  const QString file =
      QDir(QDir::tempPath()).filePath(QStringLiteral("vaw-gui-keyed-%1.stp").arg(QCoreApplication::applicationPid()));
  vaw::steptest::writeKeyedHub(file.toStdString());
  open(file);
  QFile::remove(file);
  vaw::ui::ConstraintsDock* constraints = window_->constraintsDock();
  constraints->show();
  constraints->raise();
  const auto* model = constraints->model();
  QStringList fits;
  int keyRow = -1;
  for (int row = 0; row < model->rowCount(); ++row) {
    const QString fit = model->index(row, vaw::ui::ConstraintsModel::FitColumn).data().toString();
    fits << model->index(row, vaw::ui::ConstraintsModel::PartColumn).data().toString() + QStringLiteral(" on ") +
                model->index(row, vaw::ui::ConstraintsModel::PartnerColumn).data().toString() + QStringLiteral(": ") + fit;
    if (fit.startsWith(QStringLiteral("prismatic")) && keyRow < 0) keyRow = row;
  }
  QCOMPARE(fits.filter(QStringLiteral(": prismatic, 6.0 mm wide")).size(), 2);
  QVERIFY2(fits.contains(QStringLiteral("key on shaft: prismatic, 6.0 mm wide")), qPrintable(fits.join(QLatin1Char('\n'))));
  QVERIFY2(fits.contains(QStringLiteral("hub on key: prismatic, 6.0 mm wide")), qPrintable(fits.join(QLatin1Char('\n'))));
  // A click on the row selects the key fit and shows its plane in the viewport.
  constraints->view()->scrollTo(model->index(keyRow, 0), QAbstractItemView::PositionAtTop);
  const QRect cell = constraints->view()->visualRect(model->index(keyRow, vaw::ui::ConstraintsModel::FitColumn));
  QTest::mouseClick(constraints->view()->viewport(), Qt::LeftButton, {}, cell.center());
  QTRY_VERIFY_WITH_TIMEOUT(window_->viewport()->constraintGeometry().has_value(), 3000);
  QCOMPARE(window_->viewport()->constraintGeometry()->partner, part("shaft"));
  QTest::qWait(200);
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("designed-key-fit.png"));
}

QTEST_MAIN(TestDesignedFits)
#include "tst_designed_fits.moc"
