// A STEP assembly in the workbench, used as a person uses it: opened (and dropped on the window), then
// assembled with the mouse in the order its constraints allow: a nut at its place before its stud is
// refused with the reason in Messages; the studs go into the plate, the bracket over the studs, the nut
// onto its stud against the bracket, each PLACED. Real mouse presses, moves and wheel turns in the 3D
// view; any Qt warning fails the test; screenshots go to the build tree (tests/gui/step-*.png). Then a
// bolted assembly as CAD systems write it: a headed bolt through its bracket into the plate.
#include <Qt3DExtras/Qt3DWindow>
#include <Qt3DRender/QCamera>
#include <QDir>
#include <QDoubleSpinBox>
#include <QMenu>
#include <QMimeData>
#include <QSettings>
#include <QSignalSpy>
#include <QTableView>
#include <QTreeView>
#include <QUrl>
#include <QWheelEvent>
#include <QtTest>
#include <cmath>
#include <memory>

#include "gui_test_support.hpp"
#include "step_fixtures.hpp"
#include "vaw/paths.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/message_log_model.hpp"
#include "vaw/ui/part_properties_model.hpp"
#include "vaw/ui/scene_tree_model.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/viewport.hpp"

using vaw::PartId;
using vaw::interact::PartState;
using vaw::ui::AssemblyController;
using vaw::ui::MainWindow;

namespace {

QString sampleFile() { return QFile::decodeName((vaw::resourceDir() / "step" / "bolted-bracket.stp").string().c_str()); }

}  // namespace

class TestStep : public QObject {
  Q_OBJECT

 public:
  static void initMain() {
    if (qEnvironmentVariableIsEmpty("QT3D_RENDERER")) qputenv("QT3D_RENDERER", "opengl");
  }

 private slots:
  void initTestCase();
  void cleanup();
  void cleanupTestCase();

  void droppedStepFileOpensWithItsTreeAndBrepMass();
  void bracketIsAssembledWithTheMouseInOrder();
  void coarserTessellationIsChosenAndReadAgain();
  void headedBoltGoesThroughItsBracketIntoThePlate();
  void aYUpFileStandsOnItsPlateAndTheUserCanChooseAnotherUp();

 private:
  [[nodiscard]] vaw::ui::Viewport* viewport() const { return window_->viewport(); }
  [[nodiscard]] vaw::ui::SimulationController& sim() const { return window_->simulation(); }
  [[nodiscard]] const vaw::Assembly& assembly() const { return *controller_->assembly(); }
  [[nodiscard]] const vaw::sim::World& world() const { return sim().world(); }
  [[nodiscard]] PartId part(const char* name) const { return *assembly().findPart(name); }
  [[nodiscard]] PartState state(const char* name) const { return world().part(part(name)).state; }
  [[nodiscard]] bool messagesMention(const QString& text) const;
  void open(const QString& file = sampleFile());
  // The bolted rod of tests/step/test_real_exports.cpp written in `style` to a file of the temp folder.
  [[nodiscard]] static QString writeBoltedRod(const char* stem, const vaw::steptest::ExportStyle& style);
  void carry(const char* name, const Eigen::Isometry3d& target) { vaw::guitest::carryWithMouse(*window_, part(name), target, name); }
  [[nodiscard]] Eigen::Isometry3d above(const char* name, double mm) const {
    Eigen::Isometry3d t = *assembly().parts[part(name)].finalPose;
    t.translation().z() += mm * 1e-3;
    return t;
  }

  vaw::guitest::Workbench bench_;
  std::unique_ptr<AssemblyController>& controller_ = bench_.controller;
  std::unique_ptr<MainWindow>& window_ = bench_.window;
};

void TestStep::initTestCase() {
  QVERIFY(bench_.start({.clearSettings = false, .autoPlay = std::nullopt, .size = {1280, 800}, .activate = false}));
}

void TestStep::cleanup() {
  if (window_) sim().pause();
  vaw::guitest::verifyNoWarnings();
}

void TestStep::cleanupTestCase() {
  bench_.stop();
}

bool TestStep::messagesMention(const QString& text) const {
  const auto* model = window_->messagesDock()->model();
  for (int row = 0; row < model->rowCount(); ++row)
    if (model->text(row).contains(text)) return true;
  return false;
}

void TestStep::open(const QString& file) {
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  controller_->open(file);
  QVERIFY(loaded.wait(60000) || !loaded.isEmpty());
  QVERIFY(sim().hasWorld());
  sim().setSpeed(1.0);
  QVERIFY(!vaw::guitest::capture(viewport()).isNull());
}


QString TestStep::writeBoltedRod(const char* stem, const vaw::steptest::ExportStyle& style) {
  const QString file =
      QDir(QDir::tempPath()).filePath(QStringLiteral("vaw-gui-%1-%2.stp").arg(QLatin1String(stem)).arg(QCoreApplication::applicationPid()));
  vaw::steptest::writeBoltedRod(file.toStdString(), style);
  return file;
}

// The sample dropped on the window as from a file manager: the tree shows the file's assembly, the part
// panel the B-rep as the mass source.
void TestStep::droppedStepFileOpensWithItsTreeAndBrepMass() {
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  QMimeData mime;
  mime.setUrls({QUrl::fromLocalFile(sampleFile())});
  const QPoint at(window_->width() / 2, window_->height() / 2);
  QDragEnterEvent enter(at, Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
  QCoreApplication::sendEvent(window_.get(), &enter);
  QVERIFY(enter.isAccepted());
  QDropEvent drop(at, Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
  QCoreApplication::sendEvent(window_.get(), &drop);
  QVERIFY(loaded.wait(60000) || !loaded.isEmpty());
  QCOMPARE(assembly().parts.size(), std::size_t{8});
  QCOMPARE(assembly().constraints.size(), std::size_t{15});
  QCOMPARE(assembly().parts[*assembly().base].name, std::string("base-plate"));
  const QAbstractItemModel* tree = window_->sceneDock()->view()->model();
  const QModelIndexList group = tree->match(tree->index(0, 0), Qt::DisplayRole, QStringLiteral("pin-assembly"), 1,
                                            Qt::MatchRecursive | Qt::MatchContains);
  QVERIFY2(!group.isEmpty(), "the sub-assembly is a group of the tree");
  QCOMPARE(tree->rowCount(group.front()), 2);
  window_->sceneDock()->selectPart(part("stud-2"));
  window_->partDock()->showPart(&assembly(), part("stud-2"));
  const auto* props = window_->partDock()->model();
  bool brep = false;
  for (int row = 0; row < props->rowCount(); ++row)
    brep = brep || props->data(props->index(row, 1)).toString().contains(QStringLiteral("exact B-rep"));
  QVERIFY2(brep, "the part panel names the B-rep as the mass source");
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("step-opened.png"));
}

void TestStep::bracketIsAssembledWithTheMouseInOrder() {
  open();
  // The nut at its place before its stud: refused, with the partner named.
  const Eigen::Isometry3d nutWaits = world().part(part("nut-1")).pose;
  carry("nut-1", above("nut-1", 0.0));
  QTRY_VERIFY_WITH_TIMEOUT(messagesMention(QStringLiteral("its partner stud-1 is not placed yet")), 3000);
  QVERIFY(state("nut-1") != PartState::Placed);
  QTRY_VERIFY_WITH_TIMEOUT(state("nut-1") == PartState::Static, 5000);
  // Put back where it waited, out of the bracket's way.
  Eigen::Isometry3d aside = nutWaits;
  aside.translation().z() += 0.002;
  carry("nut-1", aside);
  QTRY_VERIFY_WITH_TIMEOUT(state("nut-1") == PartState::Static, 5000);

  // The studs' tips into their holes: each slides home and is PLACED.
  for (const char* stud : {"stud-1", "stud-2"}) {
    carry(stud, above(stud, 5.0));
    QTRY_VERIFY2_WITH_TIMEOUT(state(stud) == PartState::Placed, stud, 5000);
  }
  // The bracket over both studs, then the nut onto its stud: down until the bracket stops it.
  carry("bracket", above("bracket", 4.0));
  QTRY_VERIFY2_WITH_TIMEOUT(state("bracket") == PartState::Placed, "bracket", 5000);
  carry("nut-1", above("nut-1", 6.0));
  QTRY_VERIFY2_WITH_TIMEOUT(state("nut-1") == PartState::Placed, "nut-1", 5000);
  QTest::qWait(200);
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("step-assembled.png"));
}

// File > STEP Settings, answered in its dialog: the open file is read again, coarser, and the reader's
// time limit is the one typed.
void TestStep::coarserTessellationIsChosenAndReadAgain() {
  open();
  const std::size_t fine = assembly().totalTriangles();
  const double fineDeflection = assembly().parts[part("stud-1")].cad->deflection;
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  QTimer::singleShot(0, this, [] {
    QWidget* dialog = QApplication::activeModalWidget();
    QVERIFY(dialog != nullptr);
    auto* timeout = dialog->findChild<QDoubleSpinBox*>(QStringLiteral("stepTimeout"));
    auto* deflection = dialog->findChild<QDoubleSpinBox*>(QStringLiteral("stepDeflection"));
    QVERIFY(timeout != nullptr && deflection != nullptr);
    for (const auto& [box, text] : {std::pair{timeout, QStringLiteral("120")}, std::pair{deflection, QStringLiteral("0.01")}}) {
      QTest::keyClick(box, Qt::Key_A, Qt::ControlModifier);
      QTest::keyClicks(box, vaw::guitest::inLocale(text));
    }
    vaw::guitest::shot(nullptr, dialog, QStringLiteral("step-settings.png"));
    // Return in a field of the form is OK.
    QTest::keyClick(deflection, Qt::Key_Return);
  });
  window_->findChild<QAction*>(QStringLiteral("stepSettingsAction"))->trigger();
  QVERIFY(loaded.wait(60000) || !loaded.isEmpty());
  QCOMPARE(controller_->loadOptions().import.relativeDeflection, 0.01);
  QCOMPARE(controller_->loadOptions().import.timeoutSeconds, 120.0);
  QCOMPARE(QSettings().value(QStringLiteral("import/timeoutSeconds")).toDouble(), 120.0);
  QVERIFY2(assembly().totalTriangles() < fine,
           qPrintable(QStringLiteral("%1 triangles, %2 before").arg(assembly().totalTriangles()).arg(fine)));
  QCOMPARE(assembly().parts[part("stud-1")].cad->deflection / fineDeflection, 10.0);
  QCOMPARE(assembly().constraints.size(), std::size_t{15});
  // Back to the defaults for the other tests and runs (the choice is kept in the settings).
  window_->setStepSettings(vaw::ImportOptions{});
  QVERIFY(loaded.wait(60000));
}

// A bolted assembly as CAD systems write it (cylinders in quarters, B-spline faces; the fixture of
// tests/step/test_real_exports.cpp): a bolt tried before its bracket is refused with the partner named; the
// bracket on the plate, then the headed bolt through it into the plate slides home and is PLACED, held by
// its head on the bracket; the base turned over, the bolt's nut goes onto it and home against the plate.
void TestStep::headedBoltGoesThroughItsBracketIntoThePlate() {
  const QString file = writeBoltedRod("bolted-rod", {4, true, true, false, false, "AP214"});
  open(file);
  QFile::remove(file);
  QCOMPARE(assembly().constraints.size(), std::size_t{38});

  // The bolt at its place before its bracket: the bracket is its partner, and is not placed.
  carry("bolt-4", above("bolt-4", 3.0));
  QTRY_VERIFY_WITH_TIMEOUT(messagesMention(QStringLiteral("its partner bracket-2 is not placed yet")), 3000);
  QVERIFY(state("bolt-4") != PartState::Placed);

  // The bracket onto the plate, then the bolt's tip into the bracket's hole: down through the bracket and
  // the plate until its head lies on the bracket.
  carry("bracket-1", above("bracket-1", 4.0));
  QTRY_VERIFY2_WITH_TIMEOUT(state("bracket-1") == PartState::Placed, "bracket-1", 5000);
  carry("bolt-1", above("bolt-1", 6.0));
  QTRY_VERIFY2_WITH_TIMEOUT(state("bolt-1") == PartState::Placed, "bolt-1", 5000);
  const Eigen::Isometry3d home = *assembly().parts[part("bolt-1")].finalPose;
  QVERIFY2((world().part(part("bolt-1")).pose.translation() - home.translation()).norm() < 1e-4, "the bolt is home, its head on the bracket");

  // Its nut goes on from under the plate: turned over in the Base panel (180 degrees about x), the base holds
  // the bolt's end up, and the nut comes down onto it and the plate's underside.
  const Eigen::Isometry3d held = world().basePose();
  vaw::guitest::typeInto(window_->controlsDock()->tiltX(), QStringLiteral("180"));
  QTRY_VERIFY_WITH_TIMEOUT(std::abs(std::abs(sim().baseAngles().tiltX) - M_PI) < 1e-9, 15000);
  QCOMPARE(state("bolt-1"), PartState::Placed);
  const Eigen::Isometry3d nutHome = world().basePose() * held.inverse() * *assembly().parts[part("nut-1")].finalPose;
  // Carried as it lay on the table, the other way up from its home (the same nut), its centre 4 mm over its
  // home: it goes onto the bolt and comes down to the plate. It is not PLACED: placing compares orientations
  // and does not yet know that a nut turned end over end is the same nut (tests/step/test_real_exports.cpp
  // places it carried the right way up).
  const Eigen::Vector3d com = assembly().parts[part("nut-1")].mass.centerOfMass;
  Eigen::Isometry3d overIt = world().part(part("nut-1")).pose;
  overIt.translation() = nutHome * com - overIt.linear() * com + Eigen::Vector3d(0, 0, 0.004);
  carry("nut-1", overIt);
  QTRY_VERIFY2_WITH_TIMEOUT(state("nut-1") == PartState::OnBaseStatic, "nut-1", 5000);
  QTRY_VERIFY2_WITH_TIMEOUT((world().part(part("nut-1")).pose * com - nutHome * com).norm() < 1e-4, "the nut is home, on the plate", 5000);
  QTest::qWait(200);
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("step-headed-bolt.png"));
}

// A Pro/ENGINEER-style file (AP203, inches, Y up, instances unnamed) stands on its plate with the parts named
// by their products; the scene tree's context menu turns it to stand with the file's +Z up instead.
void TestStep::aYUpFileStandsOnItsPlateAndTheUserCanChooseAnotherUp() {
  const QString file = writeBoltedRod("proe", {2, false, false, true, true, "AP203"});
  open(file);
  const auto plateHeight = [this] {
    Eigen::AlignedBox3d box;
    const vaw::Part& plate = assembly().parts[*assembly().base];
    for (const auto& v : plate.mesh->vertices) box.extend(plate.pose * v);
    return box.sizes().z();
  };
  QCOMPARE(assembly().parts[*assembly().base].name, std::string("PLATE"));
  QVERIFY(assembly().findPart("BOLT #6").has_value());
  QCOMPARE(assembly().cadUp, std::string("auto"));
  QVERIFY2(std::abs(plateHeight() - 0.010) < 1e-6, "the plate lies flat");
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("step-y-up-flat.png"));

  // Right-click the rod in the tree, Which way is up > The file's +Z up.
  QMenu* menu = vaw::guitest::openSceneTreeMenu(*window_, part("ROD"));
  QVERIFY2(menu != nullptr, "the scene tree's context menu shows");
  QMenu* up = menu->findChild<QMenu*>(QStringLiteral("upMenu"));
  QVERIFY(up != nullptr);
  QAction* autoUp = up->findChild<QAction*>(QStringLiteral("upauto"));
  QVERIFY(autoUp != nullptr && autoUp->isChecked());
  QTest::mouseClick(menu, Qt::LeftButton, {}, menu->actionGeometry(up->menuAction()).center());
  QTRY_VERIFY(up->isVisible());
  QAction* zUp = up->findChild<QAction*>(QStringLiteral("up+z"));
  QVERIFY(zUp != nullptr);
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("step-up-menu.png"));
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  QTest::mouseClick(up, Qt::LeftButton, {}, up->actionGeometry(zUp).center());
  QVERIFY(loaded.wait(60000));
  QCOMPARE(assembly().cadUp, std::string("+z"));
  QVERIFY2(std::abs(plateHeight() - 0.100) < 1e-6, "the plate stands on its long side, as the file has it");

  // Standing so, a right click on the plate's broad face in the view: Put This Face Down lays it on that
  // face, the bracket side up or down as the face chosen says.
  const PartId plate = *assembly().base;
  const vaw::CadSolid& solid = *assembly().parts[plate].cad;
  std::optional<std::size_t> broad;
  for (std::size_t f = 0; f < solid.faces.size(); ++f)
    if (solid.faces[f].surface == vaw::CadFace::Surface::Plane && (!broad || solid.faces[f].area > solid.faces[*broad].area)) broad = f;
  QVERIFY(broad.has_value());
  QVERIFY2(std::abs((assembly().parts[plate].pose.linear() * solid.faces[*broad].direction).z()) < 1e-9, "the broad face stands upright");
  const QPoint at = vaw::guitest::aimAtFace(*window_->viewport(), assembly().parts[plate], plate, *broad);
  QVERIFY2(at.x() >= 0, "a view shows the broad face");
  QTest::mouseClick(window_->viewport()->view3d(), Qt::RightButton, {}, at);
  QMenu* viewMenu = nullptr;
  QTRY_VERIFY_WITH_TIMEOUT((viewMenu = window_->findChild<QMenu*>(QStringLiteral("viewportMenu"))) != nullptr && viewMenu->isVisible(), 5000);
  QAction* faceDown = viewMenu->findChild<QAction*>(QStringLiteral("faceDownAction"));
  QVERIFY(faceDown != nullptr);
  QVERIFY2(faceDown->isEnabled(), qPrintable(faceDown->toolTip()));
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("step-face-down-menu.png"));
  const Eigen::Vector3d broadNormal = solid.faces[*broad].direction;
  QTest::mouseClick(viewMenu, Qt::LeftButton, {}, viewMenu->actionGeometry(faceDown).center());
  QVERIFY(loaded.wait(60000));
  QVERIFY2(assembly().cadUp == "+y" || assembly().cadUp == "-y", assembly().cadUp.c_str());
  QVERIFY2(std::abs(plateHeight() - 0.010) < 1e-6, "the plate lies on the face chosen");
  QVERIFY2((assembly().parts[*assembly().base].pose.linear() * broadNormal - Eigen::Vector3d(0, 0, -1)).norm() < 1e-9, "that face down");
  vaw::guitest::shot(window_.get(), window_.get(), QStringLiteral("step-face-down.png"));

  // A face of another part is not the base's: the action says why it cannot.
  const PartId rod = part("ROD");
  const vaw::CadSolid& rodSolid = *assembly().parts[rod].cad;
  std::size_t rodSide = 0;
  for (std::size_t f = 0; f < rodSolid.faces.size(); ++f)
    if (rodSolid.faces[f].area > rodSolid.faces[rodSide].area) rodSide = f;
  const QPoint onRod = vaw::guitest::aimAtFace(*window_->viewport(), assembly().parts[rod], rod, rodSide);
  QVERIFY2(onRod.x() >= 0, "a view shows the rod's side");
  QTest::mouseClick(window_->viewport()->view3d(), Qt::RightButton, {}, onRod);
  QTRY_VERIFY_WITH_TIMEOUT((viewMenu = window_->findChild<QMenu*>(QStringLiteral("viewportMenu"))) != nullptr && viewMenu->isVisible(), 5000);
  faceDown = viewMenu->findChild<QAction*>(QStringLiteral("faceDownAction"));
  QVERIFY(faceDown != nullptr && !faceDown->isEnabled());
  QVERIFY2(faceDown->toolTip().contains(QStringLiteral("PLATE")), qPrintable(faceDown->toolTip()));
  viewMenu->close();
  QFile::remove(file);
}

QTEST_MAIN(TestStep)
#include "tst_step.moc"
