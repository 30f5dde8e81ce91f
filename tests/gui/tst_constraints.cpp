// The Constraints panel driven as a person drives it, on the bundled STEP sample (bolted-bracket.stp): rows
// clicked with the mouse, Accept / Reject / Swap clicked, Ctrl+Z, File > Save As through its dialog, the scene
// opened again; the scene tree's context menu opened with a right click to make the bracket the base; a
// constraint made again from a face of each part clicked in the viewport ("Add from faces…"). Each
// step asserts on the loaded assembly, the table and the viewport's overlay. Screenshots go to the build
// tree (tests/gui/constraints-*.png).
//
// Runs under Xvfb (Qt3D needs GL); any Qt warning fails the test.
#include <QFile>
#include <QFileDialog>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QLabel>
#include <QLineEdit>
#include <QMenu>
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
#include <functional>
#include <memory>
#include <optional>

#include "gui_test_support.hpp"
#include "vaw/paths.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/constraints_dock.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/part_properties_model.hpp"
#include "vaw/ui/scene_tree_model.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/viewport.hpp"

using vaw::PartId;
using vaw::ui::AssemblyController;
using vaw::ui::ConstraintsModel;
using vaw::ui::MainWindow;

namespace {

// How long a condition may take to come true. A full `ctest -j2` runs two GUI tests at once on two cores
// with software OpenGL, and a reload or a recognition then takes several times its time alone; the
// tests wait for the condition, so a generous cap costs nothing when it comes at once.
constexpr int kSettle = 30000;

QString sample() { return QFile::decodeName((vaw::resourceDir() / "step" / "bolted-bracket.stp").string().c_str()); }

QJsonObject readJson(const QString& file) {
  QFile f(file);
  if (!f.open(QIODevice::ReadOnly)) return {};
  return QJsonDocument::fromJson(f.readAll()).object();
}

double distanceToLine(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = (b - a).normalized();
  return ((p - a) - d * d.dot(p - a)).norm();
}

}  // namespace

class TestConstraints : public QObject {
  Q_OBJECT

 public:
  static void initMain() {
    if (qEnvironmentVariableIsEmpty("QT3D_RENDERER")) qputenv("QT3D_RENDERER", "opengl");
  }

 private slots:
  void initTestCase();
  void cleanup();
  void cleanupTestCase();

  void swapExchangesPartAndPartner();
  void reviewUndoSaveAndReopen();
  void anotherPartBecomesTheBase();
  void addFromFaces();

 private:
  [[nodiscard]] vaw::ui::Viewport* viewport() const { return window_->viewport(); }
  [[nodiscard]] vaw::ui::ConstraintsDock* dock() const { return window_->constraintsDock(); }
  [[nodiscard]] ConstraintsModel* model() const { return dock()->model(); }
  [[nodiscard]] QTableView* table() const { return dock()->view(); }
  [[nodiscard]] const vaw::Assembly& assembly() const { return *controller_->assembly(); }
  [[nodiscard]] QString cell(int row, int column) const { return model()->index(row, column).data().toString(); }
  void open(const QString& path);
  void showDock();
  void clickRow(int row, Qt::KeyboardModifiers modifiers = {});
  int firstRow(const QString& kind, bool withPartnerPart = false) const;
  [[nodiscard]] int countStatus(const QString& status) const;
  [[nodiscard]] int rowNamed(const std::string& name) const;
  [[nodiscard]] std::optional<std::size_t> cylinderFace(PartId part, bool convex) const;
  void clickFace(PartId part, std::size_t face);
  void shot(QWidget* widget, const QString& name) { vaw::guitest::shot(window_.get(), widget, name); }

  vaw::guitest::Workbench bench_;
  std::unique_ptr<AssemblyController>& controller_ = bench_.controller;
  std::unique_ptr<MainWindow>& window_ = bench_.window;
  QTemporaryDir dir_;
  QString saved_;  // the scene the review saved, which the base test opens
};

void TestConstraints::initTestCase() {
  QVERIFY(dir_.isValid());
  QVERIFY2(QFile::exists(sample()), qPrintable(sample()));
  QVERIFY(bench_.start({.autoPlay = false}));
  QVERIFY2(controller_->importers().find(std::filesystem::path("x.stp")) != nullptr, "the STEP plugin is in VAW_PLUGIN_PATH");
}

void TestConstraints::cleanup() { vaw::guitest::verifyNoWarnings(); }

void TestConstraints::cleanupTestCase() {
  bench_.stop();
}

void TestConstraints::open(const QString& path) {
  QVERIFY(bench_.open(path));
}

void TestConstraints::showDock() {
  dock()->show();
  dock()->raise();
  // Room for the fifteen rows.
  window_->resizeDocks({dock()}, {330}, Qt::Vertical);
  QTest::qWait(50);
  QVERIFY(dock()->isVisible());
}

void TestConstraints::clickRow(int row, Qt::KeyboardModifiers modifiers) {
  const QModelIndex index = model()->index(row, ConstraintsModel::PartColumn);
  table()->scrollTo(index);
  QTest::mouseClick(table()->viewport(), Qt::LeftButton, modifiers, table()->visualRect(index).center());
}

int TestConstraints::firstRow(const QString& kind, bool withPartnerPart) const {
  for (int row = 0; row < model()->rowCount(); ++row) {
    const vaw::Constraint& c = assembly().constraints[static_cast<std::size_t>(row)];
    if (cell(row, ConstraintsModel::KindColumn) == kind && (!withPartnerPart || c.partner)) return row;
  }
  return -1;
}

int TestConstraints::countStatus(const QString& status) const {
  int n = 0;
  for (int row = 0; row < model()->rowCount(); ++row) n += cell(row, ConstraintsModel::StatusColumn) == status ? 1 : 0;
  return n;
}

// Swap on a nut's constraint on its stud: the stud becomes the part, each one's geometry stays in its own
// frame, and the stud comes home from the opposite direction, in the nut's frame. Undo brings it back.
void TestConstraints::swapExchangesPartAndPartner() {
  open(sample());
  showDock();
  QCOMPARE(model()->rowCount(), 15);
  const int row = firstRow(QStringLiteral("insert"), true);
  QVERIFY(row >= 0);
  const vaw::Constraint before = assembly().constraints[static_cast<std::size_t>(row)];
  const vaw::Constraint expected = vaw::ui::swapped(before, assembly());
  // The part's home direction in world terms at the assembled poses is the reverse of the partner's.
  const auto pose = [this](PartId id) { return assembly().parts[id].finalPose.value_or(assembly().parts[id].pose); };
  const Eigen::Vector3d oldWorld = pose(*before.partner).linear() * before.homeDirection;
  const Eigen::Vector3d newWorld = pose(*expected.partner).linear() * expected.homeDirection;
  QVERIFY((oldWorld + newWorld).norm() < 1e-9);
  QVERIFY((vaw::ui::swapped(expected, assembly()).homeDirection - before.homeDirection).norm() < 1e-12);
  QCOMPARE(vaw::ui::swapped(expected, assembly()).name, before.name);

  clickRow(row);
  QVERIFY(dock()->swapButton()->isEnabled());
  const QString part = cell(row, ConstraintsModel::PartColumn), partner = cell(row, ConstraintsModel::PartnerColumn);
  QTest::mouseClick(dock()->swapButton(), Qt::LeftButton);
  QTRY_COMPARE_WITH_TIMEOUT(cell(row, ConstraintsModel::PartColumn), partner, kSettle);
  QCOMPARE(cell(row, ConstraintsModel::PartnerColumn), part);
  const vaw::Constraint& after = assembly().constraints[static_cast<std::size_t>(row)];
  QCOMPARE(after.part, expected.part);
  QCOMPARE(after.partner, expected.partner);
  QVERIFY((after.partAxis.point - before.baseAxis.point).norm() < 1e-12);
  QVERIFY((after.homeDirection - expected.homeDirection).norm() < 1e-12);
  QVERIFY(window_->hasUnsavedChanges());
  // The swapped row stays selected, and its axis is now drawn on the old part.
  QTRY_VERIFY_WITH_TIMEOUT(viewport()->constraintGeometry().has_value(), kSettle);
  QCOMPARE(viewport()->constraintGeometry()->partner, before.part);

  vaw::guitest::pressKey(window_.get(), Qt::Key_Z, Qt::ControlModifier);
  QTRY_COMPARE_WITH_TIMEOUT(cell(row, ConstraintsModel::PartColumn), part, kSettle);
  QCOMPARE(assembly().constraints[static_cast<std::size_t>(row)].partner, before.partner);
  QVERIFY(!window_->hasUnsavedChanges());

  // A constraint on the base cannot be swapped: the base is never the constrained part.
  const int onBase = [this] {
    for (int r = 0; r < model()->rowCount(); ++r)
      if (!assembly().constraints[static_cast<std::size_t>(r)].partner) return r;
    return -1;
  }();
  QVERIFY(onBase >= 0);
  clickRow(onBase);
  QVERIFY(!dock()->swapButton()->isEnabled());
  QVERIFY(dock()->swapButton()->toolTip().contains(QStringLiteral("base")));
}

// Click an insert: its axis shows on its partner. Reject it (14 rows), Ctrl+Z (15), accept a mate, save
// through File > Save As, open the saved scene: 15 rows, the mate accepted.
void TestConstraints::reviewUndoSaveAndReopen() {
  open(sample());
  showDock();
  QCOMPARE(model()->rowCount(), 15);
  QCOMPARE(table()->objectName(), QStringLiteral("constraintsView"));
  // Opened again, the file keeps the row the previous test selected: nothing selected, nothing drawn.
  table()->clearSelection();
  QVERIFY(!viewport()->constraintGeometry());
  QCOMPARE(countStatus(QStringLiteral("found")), 15);

  const int insert = firstRow(QStringLiteral("insert"));
  QVERIFY(insert >= 0);
  QVERIFY(cell(insert, ConstraintsModel::GeometryColumn).startsWith(QStringLiteral("axis through (")));
  QVERIFY(cell(insert, ConstraintsModel::ClearanceColumn).endsWith(QStringLiteral(" mm")));
  clickRow(insert);
  QTRY_VERIFY_WITH_TIMEOUT(viewport()->constraintGeometry().has_value(), kSettle);
  const vaw::Constraint c = assembly().constraints[static_cast<std::size_t>(insert)];
  const PartId partner = c.partner.value_or(*assembly().base);
  QCOMPARE(viewport()->constraintGeometry()->partner, partner);
  QCOMPARE(viewport()->constraintGeometry()->kind, vaw::ui::Viewport::ConstraintGeometry::Kind::Axis);
  // Drawn through the partner's axis where the simulation has the partner now.
  QTRY_COMPARE_WITH_TIMEOUT(viewport()->constraintSegments().size(), std::size_t{1}, kSettle);
  const Eigen::Isometry3d partnerPose = window_->simulation().world().part(partner).pose;
  const auto [from, to] = viewport()->constraintSegments().front();
  QVERIFY(distanceToLine(partnerPose * c.baseAxis.point, from, to) < 1e-9);
  QVERIFY(((to - from).normalized().cross(partnerPose.linear() * c.baseAxis.direction)).norm() < 1e-9);
  QVERIFY((to - from).norm() > assembly().parts[partner].extent);
  // Magenta pixels where the axis sticks out of the parts.
  // Looked at from close by, as a person zooms in on what they review.
  const Eigen::Vector3d centre = 0.5 * (from + to);
  viewport()->lookAt(centre + Eigen::Vector3d(0.08, 0.26, 0.14), centre);
  const QImage image = vaw::guitest::capture(viewport());
  QVERIFY(!image.isNull());
  int magenta = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const QRgb p = image.pixel(x, y);
      magenta += qRed(p) > qGreen(p) + 60 && qBlue(p) > qGreen(p) + 50 ? 1 : 0;
    }
  shot(window_.get(), QStringLiteral("constraints-insert-axis.png"));
  shot(dock(), QStringLiteral("constraints-dock.png"));
  image.save(vaw::guitest::shotPath(QStringLiteral("constraints-insert-axis-3d.png")));
  QVERIFY2(magenta > 20, qPrintable(QStringLiteral("%1 magenta pixels").arg(magenta)));

  // Reject: 14 rows, nothing selected, no overlay; Ctrl+Z: 15 again.
  const std::string rejected = c.name;
  QTest::mouseClick(dock()->rejectButton(), Qt::LeftButton);
  QTRY_COMPARE_WITH_TIMEOUT(model()->rowCount(), 14, kSettle);
  QCOMPARE(assembly().constraints.size(), std::size_t{14});
  QVERIFY(window_->hasUnsavedChanges());
  QVERIFY(window_->windowTitle().contains(QStringLiteral("*")) || window_->isWindowModified());
  QTRY_VERIFY_WITH_TIMEOUT(!viewport()->constraintGeometry(), kSettle);
  vaw::guitest::pressKey(window_.get(), Qt::Key_Z, Qt::ControlModifier);
  QTRY_COMPARE_WITH_TIMEOUT(model()->rowCount(), 15, kSettle);
  QCOMPARE(assembly().constraints[static_cast<std::size_t>(insert)].name, rejected);
  QVERIFY(!window_->hasUnsavedChanges());

  // Accept a mate: its plane shows, and it stays selected through the rebuild.
  const int mate = firstRow(QStringLiteral("mate"));
  QVERIFY(mate >= 0);
  QVERIFY(cell(mate, ConstraintsModel::GeometryColumn).startsWith(QStringLiteral("plane ")));
  QCOMPARE(cell(mate, ConstraintsModel::ClearanceColumn), QStringLiteral("—"));
  QVERIFY(cell(mate, ConstraintsModel::OverlapColumn).endsWith(QStringLiteral("mm²")));
  clickRow(mate);
  QTRY_COMPARE_WITH_TIMEOUT(viewport()->constraintSegments().size(), std::size_t{5}, kSettle);
  const std::string acceptedName = assembly().constraints[static_cast<std::size_t>(mate)].name;
  QTest::mouseClick(dock()->acceptButton(), Qt::LeftButton);
  QTRY_COMPARE_WITH_TIMEOUT(cell(mate, ConstraintsModel::StatusColumn), QStringLiteral("accepted"), kSettle);
  QVERIFY(assembly().constraints[static_cast<std::size_t>(mate)].accepted);
  QVERIFY(!dock()->acceptButton()->isEnabled());
  QTRY_COMPARE_WITH_TIMEOUT(viewport()->constraintSegments().size(), std::size_t{5}, kSettle);
  QVERIFY(window_->hasUnsavedChanges());
  shot(window_.get(), QStringLiteral("constraints-mate-plane.png"));

  // File > Save As, through its dialog.
  saved_ = dir_.filePath(QStringLiteral("reviewed.vaw.json"));
  const QString target = saved_;
  vaw::guitest::whenModal([target](QWidget* w) { vaw::guitest::answerFileDialog(w, target); });
  vaw::guitest::pressKey(window_.get(), Qt::Key_S, Qt::ControlModifier | Qt::AltModifier);
  QTRY_VERIFY_WITH_TIMEOUT(QFile::exists(saved_), kSettle);
  QVERIFY(!window_->hasUnsavedChanges());
  const QJsonArray written = readJson(saved_).value(QStringLiteral("constraints")).toArray();
  QCOMPARE(written.size(), 15);
  int acceptedInFile = 0;
  for (const auto& v : written) acceptedInFile += v.toObject().value(QStringLiteral("accepted")).toBool() ? 1 : 0;
  QCOMPARE(acceptedInFile, 1);

  open(saved_);
  QCOMPARE(controller_->currentPath(), QFileInfo(saved_).absoluteFilePath());
  QCOMPARE(model()->rowCount(), 15);
  QCOMPARE(countStatus(QStringLiteral("accepted")), 1);
  for (int row = 0; row < model()->rowCount(); ++row)
    if (assembly().constraints[static_cast<std::size_t>(row)].name == acceptedName)
      QCOMPARE(cell(row, ConstraintsModel::StatusColumn), QStringLiteral("accepted"));
}

// A right click on the bracket in the scene tree, "Make this the base": the saved scene opens again with the
// bracket as its base, the constraints found anew (other partners), the Part panel says "base", and File >
// Save writes it.
void TestConstraints::anotherPartBecomesTheBase() {
  if (saved_.isEmpty() || controller_->currentPath() != QFileInfo(saved_).absoluteFilePath()) QSKIP("needs the saved scene");
  const PartId plate = *assembly().base;
  const auto bracket = assembly().findPart("bracket");
  QVERIFY(bracket.has_value());
  QVERIFY(plate != *bracket);
  QStringList partnersBefore;
  for (int row = 0; row < model()->rowCount(); ++row) partnersBefore << cell(row, ConstraintsModel::PartnerColumn);

  // The base cannot be made the base again; a scene file of its own cannot change its base at all.
  {
    std::unique_ptr<QMenu> menu(dock()->baseMenu(plate, nullptr));
    QAction* a = menu->findChild<QAction*>(QStringLiteral("makeBaseAction"));
    QVERIFY(a != nullptr);
    QVERIFY(!a->isEnabled());
    QVERIFY(a->toolTip().contains(QStringLiteral("base already")));
  }

  QMenu* menu = vaw::guitest::openSceneTreeMenu(*window_, *bracket);
  QVERIFY2(menu != nullptr, "the scene tree's context menu shows");
  QAction* makeBase = menu->findChild<QAction*>(QStringLiteral("makeBaseAction"));
  QVERIFY(makeBase != nullptr);
  QVERIFY(makeBase->isEnabled());
  shot(window_.get(), QStringLiteral("constraints-base-menu.png"));
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  QTest::mouseClick(menu, Qt::LeftButton, {}, menu->actionGeometry(makeBase).center());
  QVERIFY(loaded.wait(60000) || !loaded.isEmpty());

  QCOMPARE(assembly().base, bracket);
  QCOMPARE(controller_->currentPath(), QFileInfo(saved_).absoluteFilePath());
  QVERIFY(model()->rowCount() > 0);
  QStringList partnersAfter;
  for (int row = 0; row < model()->rowCount(); ++row) partnersAfter << cell(row, ConstraintsModel::PartnerColumn);
  QVERIFY(partnersAfter != partnersBefore);
  QVERIFY(partnersAfter.contains(QStringLiteral("bracket (base)")));
  QVERIFY(!partnersAfter.contains(QStringLiteral("plate (base)")));
  // Found anew: nothing accepted any more.
  QCOMPARE(countStatus(QStringLiteral("accepted")), 0);

  // The Part panel calls the bracket the base.
  window_->sceneDock()->selectPart(bracket);
  viewport()->selectPart(bracket);
  QString role;
  QTRY_VERIFY_WITH_TIMEOUT([&] {
    auto* props = window_->partDock()->model();
    for (int row = 0; row < props->rowCount(); ++row)
      if (props->index(row, vaw::ui::PartPropertiesModel::PropertyColumn).data().toString() == QStringLiteral("Role"))
        role = props->index(row, vaw::ui::PartPropertiesModel::ValueColumn).data().toString();
    return role.startsWith(QStringLiteral("base"));
  }(), kSettle);
  shot(window_.get(), QStringLiteral("constraints-bracket-base.png"));

  // File > Save writes the new base into the scene.
  vaw::guitest::pressKey(window_.get(), Qt::Key_S, Qt::ControlModifier);
  QTRY_COMPARE_WITH_TIMEOUT(readJson(saved_).value(QStringLiteral("cad")).toObject().value(QStringLiteral("base")).toString(),
                            QStringLiteral("bracket"), kSettle);

  // Reopened, the saved scene keeps the bracket as its base, with the constraints it saved.
  const int rows = model()->rowCount();
  open(saved_);
  QCOMPARE(assembly().base, bracket);
  QCOMPARE(model()->rowCount(), rows);
}

int TestConstraints::rowNamed(const std::string& name) const {
  for (int row = 0; row < model()->rowCount(); ++row)
    if (assembly().constraints[static_cast<std::size_t>(row)].name == name) return row;
  return -1;
}

std::optional<std::size_t> TestConstraints::cylinderFace(PartId part, bool convex) const {
  const auto& faces = assembly().parts[part].cad->faces;
  for (std::size_t i = 0; i < faces.size(); ++i)
    if (faces[i].surface == vaw::CadFace::Surface::Cylinder && faces[i].convex == convex && faces[i].triangleCount > 0) return i;
  return std::nullopt;
}

// Turns the camera onto a face of `part` where it waits, as a person would (from above for a bore or an
// upward face, from the side for a shaft), and returns a window point where the viewport's pick meets
// that very face (the point under a triangle's centroid, if nothing is in front). (-1, -1) if no view
// shows it.
void TestConstraints::clickFace(PartId part, std::size_t face) {
  const QPoint at = vaw::guitest::aimAtFace(*viewport(), assembly().parts[part], part, face);
  QVERIFY2(at.x() >= 0,
           qPrintable(
               QStringLiteral("no view shows face %1 of %2").arg(face).arg(QString::fromStdString(assembly().parts[part].name))));
  QTest::mouseClick(viewport()->view3d(), Qt::LeftButton, {}, at);
}

// Reject the sleeve's insert on the pin, then make it again by clicking the sleeve's bore and the pin's
// side in the viewport, each where it waits on the table. Pairs that do not fit are refused with the reason;
// the same pair twice is refused as there already; Ctrl+Z takes the added one away.
void TestConstraints::addFromFaces() {
  open(sample());
  showDock();
  QCOMPARE(model()->rowCount(), 15);
  table()->clearSelection();
  const auto sleeve = assembly().findPart("sleeve"), pin = assembly().findPart("pin"), stud = assembly().findPart("stud-1");
  QVERIFY(sleeve && pin && stud);
  const PartId plate = *assembly().base;
  const int row = rowNamed("insert sleeve on pin");
  QVERIFY(row >= 0);
  const vaw::Constraint rejected = assembly().constraints[static_cast<std::size_t>(row)];
  QCOMPARE(rejected.part, *sleeve);
  QCOMPARE(rejected.partner, pin);
  QVERIFY(rejected.found.has_value());
  clickRow(row);
  QTest::mouseClick(dock()->rejectButton(), Qt::LeftButton);
  QTRY_COMPARE_WITH_TIMEOUT(model()->rowCount(), 14, kSettle);

  // Each of these parts has one cylinder of the kind: the sleeve's bore, the pin's and the stud's sides.
  const auto bore = cylinderFace(*sleeve, false), shaft = cylinderFace(*pin, true), studSide = cylinderFace(*stud, true);
  QVERIFY(bore && shaft && studSide);
  const auto hint = [this] { return dock()->hint()->text(); };

  // Pressed and cancelled with Esc: nothing picked.
  QPushButton* add = dock()->addFromFacesButton();
  QVERIFY(add->isEnabled());
  QTest::mouseClick(add, Qt::LeftButton);
  QVERIFY(dock()->pickingFaces());
  QVERIFY(add->isChecked());
  QVERIFY(viewport()->pickingFaces());
  QVERIFY2(hint().startsWith(QStringLiteral("Click a face of the part that goes on")), qPrintable(hint()));
  vaw::guitest::pressKey(window_.get(), Qt::Key_Escape);
  QVERIFY(!dock()->pickingFaces());
  QVERIFY(!add->isChecked());
  QVERIFY(!viewport()->pickingFaces());
  QVERIFY(hint().contains(QStringLiteral("cancelled")));

  // The sleeve's bore and a stud's side: coaxial with neither. The reason gives the distance between the
  // axes at the assembled poses.
  const auto assembled = [this](PartId id) { return assembly().parts[id].finalPose.value_or(assembly().parts[id].pose); };
  const auto axisWorld = [&](PartId id, std::size_t face) {
    const vaw::CadFace& f = assembly().parts[id].cad->faces[face];
    return std::pair{Eigen::Vector3d(assembled(id) * f.point), Eigen::Vector3d(assembled(id).linear() * f.direction)};
  };
  const auto [borePoint, boreAxis] = axisWorld(*sleeve, *bore);
  const auto [studPoint, studAxis] = axisWorld(*stud, *studSide);
  QVERIFY(boreAxis.cross(studAxis).norm() < 1e-9);
  const Eigen::Vector3d rel = studPoint - borePoint;
  const double apart = (rel - boreAxis * boreAxis.dot(rel)).norm();
  QTest::mouseClick(add, Qt::LeftButton);
  clickFace(*sleeve, *bore);
  QTRY_VERIFY2(hint().startsWith(QStringLiteral("Click the face of its partner")), qPrintable(hint()));
  QVERIFY(hint().contains(QStringLiteral("sleeve: a hole")));
  QCOMPARE(viewport()->selectedPart(), sleeve);
  clickFace(*stud, *studSide);
  QTRY_VERIFY_WITH_TIMEOUT(!dock()->pickingFaces(), kSettle);
  const QString refused =
      QStringLiteral("Not a constraint between sleeve and stud-1: the axes are %1 mm apart.").arg(apart * 1000.0, 0, 'f', 1);
  QCOMPARE(hint(), refused);
  QCOMPARE(window_->statusBar()->currentMessage(), refused);
  QCOMPARE(model()->rowCount(), 14);
  shot(window_.get(), QStringLiteral("constraints-faces-refused.png"));

  // The plate's top and the pin's side: a plane and a cylinder.
  std::optional<std::size_t> plateTop;
  const auto& plateFaces = assembly().parts[plate].cad->faces;
  for (std::size_t i = 0; i < plateFaces.size(); ++i)
    if (plateFaces[i].surface == vaw::CadFace::Surface::Plane &&
        (assembled(plate).linear() * plateFaces[i].direction).z() > 0.999 &&
        (!plateTop || (assembled(plate) * plateFaces[i].point).z() > (assembled(plate) * plateFaces[*plateTop].point).z()))
      plateTop = i;
  QVERIFY(plateTop);
  QTest::mouseClick(add, Qt::LeftButton);
  clickFace(plate, *plateTop);
  QTRY_VERIFY_WITH_TIMEOUT(hint().startsWith(QStringLiteral("Click the face of its partner (base-plate: a flat face)")), kSettle);
  clickFace(*pin, *shaft);
  QTRY_VERIFY_WITH_TIMEOUT(!dock()->pickingFaces(), kSettle);
  QCOMPARE(hint(),
           QStringLiteral(
               "Not a constraint between base-plate and pin: the two faces are not both cylinders, both cones or both planes."));

  // The sleeve's bore, then the pin's side: the insert is back, accepted, selected, its axis drawn.
  QTest::mouseClick(add, Qt::LeftButton);
  clickFace(*sleeve, *bore);
  QTRY_VERIFY_WITH_TIMEOUT(hint().startsWith(QStringLiteral("Click the face of its partner")), kSettle);
  clickFace(*pin, *shaft);
  QTRY_COMPARE_WITH_TIMEOUT(model()->rowCount(), 15, kSettle);
  const int added = rowNamed("insert sleeve on pin");
  QVERIFY(added >= 0);
  const vaw::Constraint c = assembly().constraints[static_cast<std::size_t>(added)];
  QCOMPARE(c.part, *sleeve);
  QCOMPARE(c.partner, pin);
  QVERIFY(c.accepted);
  QCOMPARE(cell(added, ConstraintsModel::StatusColumn), QStringLiteral("accepted"));
  QVERIFY((c.partAxis.point - rejected.partAxis.point).norm() < 1e-9);
  QVERIFY((c.baseAxis.point - rejected.baseAxis.point).norm() < 1e-9);
  QVERIFY((c.homeDirection - rejected.homeDirection).norm() < 1e-9);
  QVERIFY(std::abs(c.found->clearance - rejected.found->clearance) < 1e-12);
  QCOMPARE(added, row);  // where recognition had it
  QVERIFY(hint().startsWith(QStringLiteral("Added \"insert sleeve on pin\"")));
  QVERIFY(window_->hasUnsavedChanges());
  QTRY_VERIFY_WITH_TIMEOUT(table()->selectionModel()->isRowSelected(added, {}), kSettle);
  QTRY_VERIFY_WITH_TIMEOUT(viewport()->constraintGeometry().has_value(), kSettle);
  QCOMPARE(viewport()->constraintGeometry()->partner, *pin);
  shot(window_.get(), QStringLiteral("constraints-faces-added.png"));

  // The same two faces again: there already.
  QTest::mouseClick(add, Qt::LeftButton);
  clickFace(*pin, *shaft);
  QTRY_VERIFY_WITH_TIMEOUT(hint().startsWith(QStringLiteral("Click the face of its partner")), kSettle);
  clickFace(*sleeve, *bore);
  QTRY_VERIFY_WITH_TIMEOUT(!dock()->pickingFaces(), kSettle);
  QCOMPARE(hint(), QStringLiteral("Not added: \"insert sleeve on pin\" is there already."));
  QCOMPARE(model()->rowCount(), 15);

  vaw::guitest::pressKey(window_.get(), Qt::Key_Z, Qt::ControlModifier);
  QTRY_COMPARE_WITH_TIMEOUT(model()->rowCount(), 14, kSettle);
  QCOMPARE(rowNamed("insert sleeve on pin"), -1);
}

QTEST_MAIN(TestConstraints)
#include "tst_constraints.moc"
