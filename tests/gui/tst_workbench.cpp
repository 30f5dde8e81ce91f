// The workbench window as a user meets it: it opens the default assembly, the scene tree lists its
// parts, the viewport draws them, selection follows between tree and viewport, and a malformed file
// gives an error that names it while the previous assembly stays open.
//
// Runs under Xvfb (Qt3D needs an X server and GL; see tests/gui/CMakeLists.txt). Any Qt warning fails
// the test, except the harmless ones listed in kAllowedWarnings.
#include <Qt3DExtras/Qt3DWindow>
#include <Qt3DRender/QCamera>
#include <Qt3DRender/QRenderCapture>
#include <QAbstractItemModelTester>
#include <QFile>
#include <QMessageBox>
#include <QProgressDialog>
#include <QPushButton>
#include <QThread>
#include <QRegularExpression>
#include <QSet>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTreeView>
#include <QWheelEvent>
#include <QtTest>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>

#include "gui_test_support.hpp"
#include "vaw/paths.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/load_feedback.hpp"
#include "vaw/ui/main_window.hpp"
#include "vaw/ui/message_log_model.hpp"
#include "vaw/ui/part_properties_model.hpp"
#include "vaw/ui/scene_tree_model.hpp"
#include "vaw/ui/viewport.hpp"

using vaw::PartId;
using vaw::ui::AssemblyController;
using vaw::ui::MainWindow;

namespace {

QString str(std::optional<PartId> id) {
  return id ? QString::number(static_cast<qulonglong>(*id)) : QStringLiteral("none");
}

// z up: the camera's right vector is horizontal and its up vector points upwards.
bool levelHorizon(const Qt3DRender::QCamera* camera) {
  const QVector3D view = (camera->viewCenter() - camera->position()).normalized();
  const QVector3D right = QVector3D::crossProduct(view, camera->upVector()).normalized();
  return std::abs(right.z()) < 1e-4f && QVector3D::crossProduct(right, view).z() > 0.0f;
}

using vaw::guitest::differs;

}  // namespace

class TestWorkbench : public QObject {
  Q_OBJECT

 public:
  // Before QApplication exists: Qt3D's OpenGL renderer (its captures are not flipped).
  static void initMain() {
    if (qEnvironmentVariableIsEmpty("QT3D_RENDERER")) qputenv("QT3D_RENDERER", "opengl");
  }

 private slots:
  void initTestCase();
  void cleanup();
  void cleanupTestCase();

  void opensDefaultAssembly();
  void sceneTreeListsParts();
  void viewportRendersAssembly();
  void fitFramesTheParts();
  void mouseOrbitsAndZooms();
  void treeSelectionSelectsInViewport();
  void viewportClickSelectsInTree();
  void backgroundClickClearsSelection();
  void malformedSceneKeepsPreviousAssembly_data();
  void malformedSceneKeepsPreviousAssembly();
  void reloadKeepsSelection();
  void slowLoadShowsProgressAndCancels();
  void fileDialogFiltersAndMissingPlugins();

 private:
  [[nodiscard]] vaw::ui::Viewport* viewport() const { return window_->viewport(); }
  [[nodiscard]] vaw::ui::SceneTreeModel* tree() const { return window_->sceneDock()->model(); }
  [[nodiscard]] const vaw::Assembly& assembly() const { return *controller_->assembly(); }
  QImage capture();
  double nonBackgroundFraction(const QImage& image) const;
  QPoint pointOnPart(PartId part);

  vaw::guitest::Workbench bench_;
  std::unique_ptr<AssemblyController>& controller_ = bench_.controller;
  std::unique_ptr<MainWindow>& window_ = bench_.window;
  std::vector<std::unique_ptr<QAbstractItemModelTester>> testers_;
};

void TestWorkbench::initTestCase() {
  // Every model is checked for the whole run, through every reset and insertion.
  const auto test = [this](QAbstractItemModel* model) {
    testers_.push_back(std::make_unique<QAbstractItemModelTester>(
        model, QAbstractItemModelTester::FailureReportingMode::QtTest));
  };
  QVERIFY(bench_.start({.clearSettings = false, .autoPlay = std::nullopt, .size = {1200, 760}, .activate = false}, [&](MainWindow& window) {
    test(window.sceneDock()->model());
    test(window.partDock()->model());
    test(window.messagesDock()->model());
  }));
  QVERIFY2(!controller_->importers().importerNames().empty(),
           qPrintable(controller_->pluginMessages().join(QLatin1Char('\n'))));

  const QString path = QFile::decodeName(vaw::defaultScenePath().string().c_str());
  QVERIFY2(QFile::exists(path), qPrintable(path));
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  QSignalSpy failed(controller_.get(), &AssemblyController::loadFailed);
  controller_->open(path);
  QVERIFY(loaded.wait(60000) || !loaded.isEmpty());
  QCOMPARE(failed.count(), 0);
  vaw::guitest::verifyNoWarnings();
}

void TestWorkbench::cleanup() { vaw::guitest::verifyNoWarnings(); }

void TestWorkbench::cleanupTestCase() {
  testers_.clear();
  bench_.stop();
}

QImage TestWorkbench::capture() { return vaw::guitest::capture(viewport()); }

double TestWorkbench::nonBackgroundFraction(const QImage& image) const {
  return vaw::guitest::nonBackgroundFraction(viewport(), image);
}

QPoint TestWorkbench::pointOnPart(PartId id) {
  return vaw::guitest::pointOnPart(viewport(), assembly(), id, assembly().parts[id].pose);
}

void TestWorkbench::opensDefaultAssembly() {
  QVERIFY(controller_->assembly() != nullptr);
  QVERIFY(assembly().findPart("base").has_value());
  QVERIFY(assembly().findPart("sleeve").has_value());
  QCOMPARE(viewport()->partCount(), assembly().parts.size());
  QVERIFY(window_->windowTitle().contains(QString::fromStdString(assembly().name)));
}

void TestWorkbench::sceneTreeListsParts() {
  const auto* model = tree();
  QCOMPARE(model->rowCount(), 1);  // the assembly root
  const QModelIndex root = model->index(0, 0);
  QCOMPARE(root.data().toString(), QString::fromStdString(assembly().name));
  QCOMPARE(model->partCount(), assembly().parts.size());

  const QModelIndexList parts =
      model->match(root, vaw::ui::SceneTreeModel::KindRole, static_cast<int>(vaw::TreeNode::Kind::Part), -1,
                   Qt::MatchExactly | Qt::MatchRecursive);
  QCOMPARE(static_cast<std::size_t>(parts.size()), assembly().parts.size());
  QStringList names;
  for (const QModelIndex& index : parts) names << index.data().toString();
  QVERIFY2(names.contains(QStringLiteral("base")), qPrintable(names.join(QLatin1Char(','))));
  QVERIFY2(names.contains(QStringLiteral("sleeve")), qPrintable(names.join(QLatin1Char(','))));

  for (const vaw::Part& part : assembly().parts) {
    const QModelIndex index = model->indexOfPart(part.id);
    QVERIFY(index.isValid());
    QCOMPARE(index.data().toString(), QString::fromStdString(part.name));
    QVERIFY(model->partAt(index) == part.id);
    QVERIFY(!index.siblingAtColumn(vaw::ui::SceneTreeModel::MassColumn).data().toString().isEmpty());
  }
  // Environment objects are in the tree too.
  for (const vaw::EnvironmentObject& object : assembly().environment) {
    const auto found = model->match(root, Qt::DisplayRole, QString::fromStdString(object.name), 1,
                                    Qt::MatchExactly | Qt::MatchRecursive);
    QCOMPARE(found.size(), 1);
    QVERIFY(!model->partAt(found.first()));
  }
  // The collision proxy of each object is shown: the sleeve collides as its mesh, the table (a box
  // primitive) as an exact box.
  const auto collisionOf = [&](const QString& name) {
    const auto found = model->match(root, Qt::DisplayRole, name, 1, Qt::MatchExactly | Qt::MatchRecursive);
    return found.isEmpty() ? QString() : found.first().siblingAtColumn(vaw::ui::SceneTreeModel::CollisionColumn).data().toString();
  };
  QVERIFY2(collisionOf(QStringLiteral("sleeve")).startsWith(QStringLiteral("mesh, 512 tri")), qPrintable(collisionOf(QStringLiteral("sleeve"))));
  QVERIFY2(collisionOf(QStringLiteral("table")).startsWith(QStringLiteral("box")), qPrintable(collisionOf(QStringLiteral("table"))));
}

void TestWorkbench::viewportRendersAssembly() {
  QImage image;
  double fraction = 0.0;
  // The first frames after a load may still be uploading geometry.
  for (int attempt = 0; attempt < 3 && fraction < 0.2; ++attempt) {
    image = capture();
    QVERIFY(!image.isNull());
    fraction = nonBackgroundFraction(image);
  }
  QCOMPARE(image.size(), viewport()->view3d()->size() * viewport()->view3d()->devicePixelRatio());
  // Parts and table fill much of the view; the clear colour is only the sky above the table.
  QVERIFY2(fraction > 0.2, qPrintable(QStringLiteral("non-background fraction %1").arg(fraction)));
  // Lit, not flat: many distinct shades.
  QSet<QRgb> shades;
  for (int y = 0; y < image.height(); y += 4) {
    for (int x = 0; x < image.width(); x += 4) shades.insert(image.pixel(x, y));
  }
  QVERIFY2(shades.size() > 50, qPrintable(QString::number(shades.size())));
}

// The initial view looks from front-right-above with z up; F (in the 3D view) frames the parts again
// after the camera was moved away, keeping the direction.
void TestWorkbench::fitFramesTheParts() {
  Qt3DRender::QCamera* camera = viewport()->camera();
  QVERIFY(levelHorizon(camera));
  const QVector3D eye = camera->position() - camera->viewCenter();
  QVERIFY2(eye.x() > 0 && eye.y() < 0 && eye.z() > 0, qPrintable(QStringLiteral("%1 %2 %3").arg(eye.x()).arg(eye.y()).arg(eye.z())));

  const auto checkFramed = [this](const char* when) {
    const QSize size = viewport()->view3d()->size();
    const Eigen::AlignedBox3d box = viewport()->partsBounds();
    QVERIFY(!box.isEmpty());
    const QPointF centre = viewport()->projectToWindow(box.center());
    QVERIFY2(std::abs(centre.x() - size.width() / 2.0) < 2 && std::abs(centre.y() - size.height() / 2.0) < 2, when);
    double minX = 1e9, maxX = -1e9, minY = 1e9, maxY = -1e9;
    for (int c = 0; c < 8; ++c) {
      const QPointF p = viewport()->projectToWindow(box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
      minX = std::min(minX, p.x()), maxX = std::max(maxX, p.x()), minY = std::min(minY, p.y()), maxY = std::max(maxY, p.y());
    }
    QVERIFY2(minX >= 0 && minY >= 0 && maxX <= size.width() && maxY <= size.height(), when);
    // ...and fills a good part of the view.
    QVERIFY2(std::max((maxX - minX) / size.width(), (maxY - minY) / size.height()) > 0.4, when);
  };
  checkFramed("initial view");
  if (QTest::currentTestFailed()) return;

  const QVector3D direction = (camera->position() - camera->viewCenter()).normalized();
  camera->setViewCenter(camera->viewCenter() + QVector3D(5, 5, 0));
  camera->setPosition(camera->viewCenter() + direction * 40.0f);
  viewport()->view3d()->requestActivate();
  QTest::keyClick(viewport()->view3d(), Qt::Key_F);
  checkFramed("after F");
  const QVector3D after = (camera->position() - camera->viewCenter()).normalized();
  QVERIFY((after - direction).length() < 1e-4f);
}

// Left drag orbits about the vertical through the view centre (the horizon stays level), the wheel
// zooms towards the view centre. Home restores the initial view.
void TestWorkbench::mouseOrbitsAndZooms() {
  Qt3DRender::QCamera* camera = viewport()->camera();
  Qt3DExtras::Qt3DWindow* window = viewport()->view3d();
  const QVector3D centre = camera->viewCenter();
  const QVector3D eye = camera->position() - centre;
  const QPoint start(window->width() / 2, window->height() / 2);

  QTest::mousePress(window, Qt::LeftButton, Qt::NoModifier, start);
  for (int step = 1; step <= 10; ++step) {
    QTest::mouseMove(window, start + QPoint(12 * step, 0));
    QTest::qWait(20);  // Qt3D reads input once per frame
  }
  QTest::mouseRelease(window, Qt::LeftButton, Qt::NoModifier, start + QPoint(120, 0));
  QTRY_VERIFY((camera->position() - centre - eye).length() > 1e-3f * eye.length());
  const QVector3D orbited = camera->position() - camera->viewCenter();
  QVERIFY((camera->viewCenter() - centre).length() < 1e-5f * eye.length());
  QVERIFY2(std::abs(orbited.z() - eye.z()) < 1e-3f * eye.length(), "a horizontal drag changed the elevation");
  QVERIFY(std::abs(orbited.length() - eye.length()) < 1e-3f * eye.length());
  QVERIFY(levelHorizon(camera));

  const float before = (camera->position() - camera->viewCenter()).length();
  QWheelEvent wheel(QPointF(start), window->mapToGlobal(QPointF(start)), QPoint(), QPoint(0, 120), Qt::NoButton,
                    Qt::NoModifier, Qt::NoScrollPhase, false);
  QCoreApplication::sendEvent(window, &wheel);
  QTRY_VERIFY((camera->position() - camera->viewCenter()).length() < before * 0.999f);
  QTest::qWait(100);
  const float after = (camera->position() - camera->viewCenter()).length();
  QVERIFY2(after > 0.5f * before && after < 0.97f * before, qPrintable(QString::number(after / before)));

  QTest::keyClick(window, Qt::Key_Home);
  QVERIFY(((camera->position() - camera->viewCenter()).normalized() - eye.normalized()).length() < 1e-4f);
}

void TestWorkbench::treeSelectionSelectsInViewport() {
  const PartId sleeve = *assembly().findPart("sleeve");
  const QPoint onSleeve = pointOnPart(sleeve);
  QVERIFY2(onSleeve.x() >= 0, "the sleeve is not visible");
  const QImage before = capture();

  QTreeView* view = window_->sceneDock()->view();
  view->setCurrentIndex(tree()->indexOfPart(sleeve));
  QVERIFY2(viewport()->selectedPart() == sleeve, qPrintable(str(viewport()->selectedPart())));
  // The Part panel shows it.
  QVERIFY(window_->partDock()->model()->part() == sleeve);
  QCOMPARE(window_->partDock()->model()->value(QStringLiteral("Name")), QStringLiteral("sleeve"));
  QVERIFY(!window_->partDock()->model()->value(QStringLiteral("Mass")).isEmpty());
  QVERIFY(!window_->partDock()->model()->value(QStringLiteral("Category")).isEmpty());
  QVERIFY2(window_->partDock()->model()->value(QStringLiteral("Collision")).startsWith(QStringLiteral("mesh")),
           qPrintable(window_->partDock()->model()->value(QStringLiteral("Collision"))));
  // Its fit on the shaft, with the clearance.
  QVERIFY2(window_->partDock()->model()->value(QStringLiteral("Fit")).contains(QStringLiteral("clearance 0 mm")),
           qPrintable(window_->partDock()->model()->value(QStringLiteral("Fit"))));

  // ...and the viewport highlights it.
  const QImage after = capture();
  const QPoint px = onSleeve * viewport()->view3d()->devicePixelRatio();
  QVERIFY2(differs(before.pixel(px), after.pixel(px), 30),
           qPrintable(QStringLiteral("%1 -> %2").arg(before.pixel(px), 0, 16).arg(after.pixel(px), 0, 16)));

  // A mesh node or a group is not a part: choosing one clears the viewport's selection.
  view->setCurrentIndex(tree()->index(0, 0));
  QVERIFY2(!viewport()->selectedPart(), qPrintable(str(viewport()->selectedPart())));
  QCOMPARE(window_->partDock()->model()->rowCount(), 0);
}

void TestWorkbench::viewportClickSelectsInTree() {
  for (const char* name : {"base", "sleeve"}) {
    const PartId id = *assembly().findPart(name);
    const QPoint p = pointOnPart(id);
    QVERIFY2(p.x() >= 0, name);
    QTest::mouseClick(viewport()->view3d(), Qt::LeftButton, Qt::NoModifier, p);
    QTRY_VERIFY2_WITH_TIMEOUT(viewport()->selectedPart() == id, qPrintable(str(viewport()->selectedPart())), 10000);
    QVERIFY2(window_->sceneDock()->currentPart() == id, qPrintable(str(window_->sceneDock()->currentPart())));
    QCOMPARE(window_->sceneDock()->view()->currentIndex().data().toString(), QString::fromLatin1(name));
    QVERIFY(window_->sceneDock()->view()->selectionModel()->isRowSelected(
        window_->sceneDock()->view()->currentIndex().row(), window_->sceneDock()->view()->currentIndex().parent()));
    QCOMPARE(window_->partDock()->model()->value(QStringLiteral("Name")), QString::fromLatin1(name));
  }
}

void TestWorkbench::backgroundClickClearsSelection() {
  const PartId base = *assembly().findPart("base");
  viewport()->selectPart(base);
  QVERIFY(window_->sceneDock()->currentPart() == base);

  // A pixel that shows no part: the clear colour or the room's floor, which is no part either.
  const QImage image = capture();
  const QRgb background = viewport()->clearColor().rgb();
  const qreal dpr = viewport()->view3d()->devicePixelRatio();
  QPoint empty(-1, -1);
  for (int y = 2; y < image.height() && empty.x() < 0; y += 8) {
    for (int x = 2; x < image.width() && empty.x() < 0; x += 8) {
      const QPoint at = (QPointF(x, y) / dpr).toPoint();
      if (!differs(image.pixel(x, y), background, 0) || !viewport()->partAt(at)) empty = QPoint(x, y);
    }
  }
  QVERIFY2(empty.x() >= 0, "no background or floor visible");
  QTest::mouseClick(viewport()->view3d(), Qt::LeftButton, Qt::NoModifier, (QPointF(empty) / dpr).toPoint());
  QTRY_VERIFY2_WITH_TIMEOUT(!viewport()->selectedPart(), qPrintable(str(viewport()->selectedPart())), 10000);
  QVERIFY(!window_->sceneDock()->currentPart());
  QCOMPARE(window_->partDock()->model()->rowCount(), 0);
}

void TestWorkbench::malformedSceneKeepsPreviousAssembly_data() {
  QTest::addColumn<QByteArray>("content");
  QTest::addColumn<QString>("field");  // expected in the diagnostic's field; empty: not checked
  QTest::newRow("json syntax") << QByteArray("{\"format\": \"vaw-scene\", \"version\": 1,\n  \"name\": \n") << QString();
  QTest::newRow("bad primitive size")
      << QByteArray(R"({"format": "vaw-scene", "version": 1, "name": "bad", "units": "mm",
  "materials": {"steel": {"density": 7850, "friction": {"static": 0.3, "kinetic": 0.2, "rotational": 0.0},
                          "color": "#8a939c"}},
  "parts": [{"name": "block", "material": "steel", "primitive": {"type": "box", "size": [10, 20]}}]})")
      << QStringLiteral("parts[0]");
}

void TestWorkbench::malformedSceneKeepsPreviousAssembly() {
  QFETCH(QByteArray, content);
  QFETCH(QString, field);
  QTemporaryDir dir;
  QVERIFY(dir.isValid());
  const QString path = dir.filePath(QStringLiteral("broken.vaw.json"));
  {
    QFile file(path);
    QVERIFY(file.open(QIODevice::WriteOnly));
    file.write(content);
  }
  const vaw::Assembly* previous = controller_->assembly();
  const std::string previousName = previous->name;
  const std::size_t previousParts = previous->parts.size();
  const QString previousPath = controller_->currentPath();
  const int errorsBefore = window_->messagesDock()->model()->count(vaw::ui::MessageLogModel::Severity::Error);

  QSignalSpy failed(controller_.get(), &AssemblyController::loadFailed);
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  controller_->open(path);
  QVERIFY(failed.wait(30000) || !failed.isEmpty());
  QCOMPARE(loaded.count(), 0);

  // The diagnostic names the file, the field and what was expected.
  const auto failure = failed.first().first().value<vaw::ui::LoadFailure>();
  QVERIFY2(failure.inputError, qPrintable(failure.message));
  QVERIFY2(failure.file.contains(QStringLiteral("broken.vaw.json")), qPrintable(failure.file));
  QVERIFY2(failure.message.contains(QStringLiteral("broken.vaw.json")), qPrintable(failure.message));
  QVERIFY2(!failure.expected.isEmpty(), qPrintable(failure.message));
  if (!field.isEmpty()) QVERIFY2(failure.field.contains(field), qPrintable(failure.field));

  // The error dialog shows it (non-blocking, so the test can read and close it).
  QMessageBox* box = window_->loadFeedback()->errorDialog();
  QVERIFY(box != nullptr);
  QVERIFY(box->isVisible());
  QCOMPARE(box->text(), failure.message);
  QVERIFY(box->detailedText().contains(QStringLiteral("Expected: ") + failure.expected));
  if (!failure.field.isEmpty()) QVERIFY(box->detailedText().contains(QStringLiteral("Field: ") + failure.field));
  box->close();
  QTRY_VERIFY(window_->loadFeedback()->errorDialog() == nullptr);
  QCOMPARE(window_->messagesDock()->model()->count(vaw::ui::MessageLogModel::Severity::Error), errorsBefore + 1);

  // Nothing lost: the previous assembly is still loaded and shown.
  QVERIFY(controller_->assembly() == previous);
  QCOMPARE(controller_->assembly()->name, previousName);
  QCOMPARE(controller_->assembly()->parts.size(), previousParts);
  QCOMPARE(controller_->currentPath(), previousPath);
  QCOMPARE(tree()->partCount(), previousParts);
  QVERIFY(tree()->indexOfPart(*assembly().findPart("sleeve")).isValid());
  QCOMPARE(viewport()->partCount(), previousParts);
  QVERIFY(nonBackgroundFraction(capture()) > 0.2);
}

void TestWorkbench::reloadKeepsSelection() {
  const PartId sleeve = *assembly().findPart("sleeve");
  viewport()->selectPart(sleeve);
  const vaw::Assembly* before = controller_->assembly();
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  controller_->reload();
  QVERIFY(loaded.wait(60000) || !loaded.isEmpty());
  QVERIFY(controller_->assembly() != before);
  QVERIFY2(viewport()->selectedPart() == assembly().findPart("sleeve"), qPrintable(str(viewport()->selectedPart())));
  QVERIFY(window_->sceneDock()->currentPart() == viewport()->selectedPart());
  QCOMPARE(window_->partDock()->model()->value(QStringLiteral("Name")), QStringLiteral("sleeve"));
}

// A load that takes a while shows a progress dialog (QProgressDialog shows itself once the estimated
// duration exceeds 300 ms); its Cancel stops the load and
// the previous assembly stays. The core loads the bundled scenes in milliseconds, so the controller
// is given a slow loader that reports progress and honours the cancel answer like the core does.
void TestWorkbench::slowLoadShowsProgressAndCancels() {
  controller_->setLoader([](const std::filesystem::path& file, const vaw::ImporterRegistry& importers,
                            const vaw::LoadOptions& options, const vaw::ProgressFn& progress) {
    for (int step = 0; step <= 400; ++step) {  // at most 20 s
      if (!progress(step / 400.0, "slow step " + std::to_string(step))) throw vaw::LoadCancelled();
      QThread::msleep(50);
    }
    return vaw::loadAny(file, importers, options, {});
  });
  const vaw::Assembly* previous = controller_->assembly();
  QSignalSpy progressed(controller_.get(), &AssemblyController::progress);
  QSignalSpy cancelled(controller_.get(), &AssemblyController::loadCancelled);
  QSignalSpy loaded(controller_.get(), &AssemblyController::assemblyLoaded);
  controller_->reload();
  QVERIFY(controller_->isLoading());

  const auto visibleProgressDialog = [this]() -> QProgressDialog* {
    const auto dialog = window_->findChild<QProgressDialog*>(QStringLiteral("loadProgressDialog"));
    return dialog != nullptr && dialog->isVisible() ? dialog : nullptr;
  };
  QTRY_VERIFY_WITH_TIMEOUT(visibleProgressDialog() != nullptr, 10000);
  QTRY_VERIFY(!progressed.isEmpty());
  QTRY_VERIFY(visibleProgressDialog()->labelText().startsWith(QStringLiteral("slow step")));

  auto* cancel = visibleProgressDialog()->findChild<QPushButton*>();
  QVERIFY(cancel != nullptr);
  cancel->click();
  QVERIFY(cancelled.wait(10000) || !cancelled.isEmpty());
  QCOMPARE(loaded.count(), 0);
  QVERIFY(!controller_->isLoading());
  QVERIFY(controller_->assembly() == previous);
  QTRY_VERIFY(visibleProgressDialog() == nullptr);
  QCOMPARE(viewport()->partCount(), previous->parts.size());
  controller_->setLoader({});
}

// File > Open offers scenes, the importers' mesh formats and all files; without any importer
// plugin the controller says so (and the window shows it in Messages).
void TestWorkbench::fileDialogFiltersAndMissingPlugins() {
  const QStringList filters = controller_->fileDialogFilters();
  QVERIFY2(filters.join(QLatin1Char('|')).contains(QStringLiteral("*.vaw.json")), qPrintable(filters.join(QLatin1Char('|'))));
  QVERIFY(filters.last().contains(QStringLiteral("(*)")));
  for (const auto& ext : controller_->importers().extensions()) {
    QVERIFY(filters.first().contains(QStringLiteral("*.") + QString::fromStdString(ext)));
  }

  AssemblyController bare(std::vector<std::filesystem::path>{}, nullptr);
  QVERIFY(bare.importers().importerNames().empty());
  QVERIFY2(bare.pluginMessages().join(QLatin1Char('\n')).contains(QStringLiteral("No mesh importer plugin")),
           qPrintable(bare.pluginMessages().join(QLatin1Char('\n'))));
  MainWindow window(bare);
  auto* messages = window.messagesDock()->model();
  QVERIFY(messages->rowCount() > 0);
  QVERIFY(messages->text(0).contains(QStringLiteral("No mesh importer plugin")));
}

QTEST_MAIN(TestWorkbench)
#include "tst_workbench.moc"
