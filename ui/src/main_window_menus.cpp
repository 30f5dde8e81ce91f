// The menus, the simulation toolbar, the recent files and the help dialogs.
#include "vaw/ui/main_window.hpp"

#include <QAction>
#include <QDialog>
#include <QDialogButtonBox>
#include <QFileInfo>
#include <QKeySequence>
#include <QMenu>
#include <QMenuBar>
#include <QMessageBox>
#include <QSettings>
#include <QTextBrowser>
#include <QToolBar>
#include <QUndoStack>
#include <QVBoxLayout>

#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/constraints_dock.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/motion_chart.hpp"
#include "vaw/ui/path_dock.hpp"
#include "vaw/ui/sequence_dock.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/trials_panel.hpp"
#include "vaw/ui/tuning.hpp"
#include "vaw/ui/viewport.hpp"
#include "vaw/ui/work_precision_dock.hpp"
#include "vaw/version.hpp"

namespace vaw::ui {

namespace {
constexpr int kMaxRecent = 8;
}

void MainWindow::createMenus() {
  QMenu* file = menuBar()->addMenu(tr("&File"));
  QAction* open = file->addAction(tr("&Open..."), this, &MainWindow::openFileDialog);
  open->setShortcut(QKeySequence::Open);
  recentMenu_ = file->addMenu(tr("Open &Recent"));
  recentMenu_->setObjectName(QStringLiteral("recentMenu"));
  updateRecentMenu();
  reloadAction_ = file->addAction(tr("&Reload"), &controller_, &AssemblyController::reload);
  reloadAction_->setShortcut(QKeySequence::Refresh);
  reloadAction_->setEnabled(false);
  file->addSeparator();
  saveAction_ = file->addAction(tr("&Save"), this, &MainWindow::save);
  saveAction_->setObjectName(QStringLiteral("saveAction"));
  saveAction_->setShortcut(QKeySequence::Save);
  saveAction_->setToolTip(tr("Save the scene with its tuning (gravity, friction, methods, rate)"));
  saveAction_->setEnabled(false);
  saveAsAction_ = file->addAction(tr("Save &As..."), this, &MainWindow::saveAs);
  saveAsAction_->setObjectName(QStringLiteral("saveAsAction"));
  saveAsAction_->setShortcut(QKeySequence(tr("Ctrl+Alt+S")));
  saveAsAction_->setEnabled(false);
  QAction* stepSettings = file->addAction(tr("STEP Se&ttings..."), this, &MainWindow::stepSettingsDialog);
  stepSettings->setObjectName(QStringLiteral("stepSettingsAction"));
  stepSettings->setToolTip(tr("How finely STEP parts are tessellated, and the reader's time, memory and instance limits"));
  QAction* save = file->addAction(tr("Save &Session..."), this, &MainWindow::saveSessionDialog);
  save->setObjectName(QStringLiteral("saveSessionAction"));
  save->setShortcut(QKeySequence(tr("Ctrl+Shift+S")));
  file->addAction(tr("Export Timeline as &PNG..."), timelineDock_, &TimelineDock::exportPngRequested);
  file->addAction(tr("Export Timeline as &CSV..."), timelineDock_, &TimelineDock::exportCsvRequested);
  QAction* report = file->addAction(tr("Export R&eport..."), this, &MainWindow::exportReportDialog);
  file->addAction(tr("Export &Video..."), this, &MainWindow::exportVideoDialog)->setObjectName(QStringLiteral("exportVideoAction"));
  file->addAction(tr("Export &glTF..."), this, &MainWindow::exportGltfDialog)->setObjectName(QStringLiteral("exportGltfAction"));
  report->setObjectName(QStringLiteral("exportReportAction"));
  report->setToolTip(tr("The evaluation report: the order, each part's way home, this session's figures (HTML, CSV, JSON)"));
  file->addSeparator();
  QAction* quit = file->addAction(tr("&Quit"), this, &QWidget::close);
  quit->setShortcut(QKeySequence::Quit);

  QMenu* edit = menuBar()->addMenu(tr("&Edit"));
  QAction* undo = undoStack_->createUndoAction(this, tr("&Undo"));
  undo->setShortcut(QKeySequence::Undo);
  undo->setObjectName(QStringLiteral("undoAction"));
  QAction* redo = undoStack_->createRedoAction(this, tr("&Redo"));
  redo->setShortcuts({QKeySequence::Redo, QKeySequence(tr("Ctrl+Y"))});
  redo->setObjectName(QStringLiteral("redoAction"));
  edit->addAction(undo);
  edit->addAction(redo);

  // The simulation's keys work wherever the focus is in the window (the viewport forwards them).
  QMenu* sim = menuBar()->addMenu(tr("&Simulation"));
  const auto simAction = [&](const QString& text, const QKeySequence& key, const char* name, auto slot) {
    QAction* a = sim->addAction(text, simulation_, slot);
    a->setShortcut(key);
    a->setObjectName(QString::fromLatin1(name));
    return a;
  };
  playAction_ = simAction(tr("&Play"), QKeySequence(Qt::Key_Space), "playAction", &SimulationController::togglePlay);
  playAction_->setCheckable(true);
  simAction(tr("&Step"), QKeySequence(Qt::Key_Period), "stepAction", &SimulationController::stepOnce);
  sim->addSeparator();
  simAction(tr("&Faster"), QKeySequence(Qt::Key_BracketRight), "fasterAction", &SimulationController::faster);
  simAction(tr("S&lower"), QKeySequence(Qt::Key_BracketLeft), "slowerAction", &SimulationController::slower);
  QAction* normal = sim->addAction(tr("&Normal Speed"), this, [this] { simulation_->setSpeed(1.0); });
  normal->setShortcut(QKeySequence(Qt::Key_Backslash));
  sim->addSeparator();
  simAction(tr("&Reset"), QKeySequence(tr("Ctrl+R")), "resetAction", &SimulationController::reset);
  simAction(tr("Go to &End of Recording"), QKeySequence(Qt::Key_End), "endAction", &SimulationController::seekToEnd);

  QMenu* view = menuBar()->addMenu(tr("&View"));
  QAction* fit = view->addAction(tr("&Fit to View"), viewport_, &Viewport::fitToView);
  fit->setObjectName(QStringLiteral("fitAction"));
  fit->setShortcut(Qt::Key_F);  // the viewport handles F itself while its 3D window has focus
  QAction* reset = view->addAction(tr("&Reset View"), viewport_, &Viewport::resetView);
  reset->setShortcut(Qt::Key_Home);
  view->addSeparator();
  view->addAction(sceneDock_->toggleViewAction());
  view->addAction(partDock_->toggleViewAction());
  view->addAction(controlsDock_->toggleViewAction());
  view->addAction(timelineDock_->toggleViewAction());
  view->addAction(messagesDock_->toggleViewAction());
  view->addAction(gravityDock_->toggleViewAction());
  view->addAction(frictionDock_->toggleViewAction());
  view->addAction(methodsDock_->toggleViewAction());
  view->addAction(motionDock_->toggleViewAction());
  view->addAction(workPrecisionDock_->toggleViewAction());
  view->addAction(trialsDock_->toggleViewAction());
  view->addAction(constraintsDock_->toggleViewAction());
  view->addAction(sequenceDock_->toggleViewAction());
  view->addAction(pathDock_->toggleViewAction());

  QMenu* help = menuBar()->addMenu(tr("&Help"));
  QAction* bindings = help->addAction(tr("Mouse and &Keys"), this, &MainWindow::showBindings);
  bindings->setShortcut(QKeySequence::HelpContents);
  bindings->setObjectName(QStringLiteral("bindingsAction"));
  help->addAction(tr("&About vaw"), this, &MainWindow::showAbout)->setObjectName(QStringLiteral("aboutAction"));

  QToolBar* bar = addToolBar(tr("Simulation"));
  bar->setObjectName(QStringLiteral("simulationToolBar"));
  for (QAction* a : sim->actions())
    if (!a->isSeparator()) bar->addAction(a);
}

void MainWindow::addRecent(const QString& path) {
  if (path.isEmpty()) return;
  const QString absolute = QFileInfo(path).absoluteFilePath();
  QSettings settings;
  QStringList recent = settings.value(QStringLiteral("recentFiles")).toStringList();
  recent.removeAll(absolute);
  recent.prepend(absolute);
  while (recent.size() > kMaxRecent) recent.removeLast();
  settings.setValue(QStringLiteral("recentFiles"), recent);
  updateRecentMenu();
}

void MainWindow::updateRecentMenu() {
  recentMenu_->clear();
  const QStringList recent = QSettings().value(QStringLiteral("recentFiles")).toStringList();
  for (int i = 0; i < recent.size(); ++i) {
    QAction* a = recentMenu_->addAction(QStringLiteral("&%1 %2").arg(i + 1).arg(QFileInfo(recent[i]).fileName()),
                                        this, [this, path = recent[i]] { openFile(path); });
    a->setToolTip(recent[i]);
    a->setStatusTip(recent[i]);
  }
  recentMenu_->setEnabled(!recent.isEmpty());
}

void MainWindow::showAbout() {
  QMessageBox box(this);
  box.setObjectName(QStringLiteral("aboutBox"));
  box.setWindowTitle(tr("About vaw"));
  box.setTextFormat(Qt::RichText);
  box.setText(tr("<h3>vaw %1</h3><p>Virtual Assembly Workbench: how the parts of an assembly behave when a person handles "
                 "them.</p>")
                  .arg(QString::fromLatin1(vaw::kVersion)));
  box.setInformativeText(
      tr("<p>Built with Qt %1 (LGPL-3.0), Eigen (MPL-2.0), FCL and libccd (BSD-3-Clause), Open Asset Import Library "
         "(BSD-3-Clause), nlohmann-json (MIT), and, where the headset plugin is built, the Khronos OpenXR loader "
         "(Apache-2.0).</p>")
          .arg(QString::fromLatin1(qVersion())));
  box.exec();
}

void MainWindow::showBindings() {
  QDialog dialog(this);
  dialog.setObjectName(QStringLiteral("bindingsDialog"));
  dialog.setWindowTitle(tr("Mouse and keys"));
  auto* layout = new QVBoxLayout(&dialog);
  auto* text = new QTextBrowser(&dialog);
  text->setHtml(tr(
      "<h3>Viewport</h3><table cellspacing=4>"
      "<tr><td><b>Left-drag a part</b></td><td>grab it with the right hand and carry it; let go of the button to release "
      "it (its velocity is the hand's)</td></tr>"
      "<tr><td><b>Ctrl + left-drag</b></td><td>grab with both hands (two-hand parts)</td></tr>"
      "<tr><td><b>Wheel while holding</b></td><td>move the part in depth (forward: away)</td></tr>"
      "<tr><td><b>Q / E, Z / X, C / V</b></td><td>turn the held part about the view's axes</td></tr>"
      "<tr><td><b>I / K, J / L, U / O</b></td><td>tilt the base about x and y, turn it about its vertical</td></tr>"
      "<tr><td><b>H</b>, <b>Shift + arrows</b></td><td>close or open the hoist's hook; raise, lower and turn it</td></tr>"
      "<tr><td><b>Left-drag on the background</b>, <b>Alt + drag</b>, <b>arrow keys</b></td><td>orbit the view</td></tr>"
      "<tr><td><b>Right, middle or Shift + left drag</b>; <b>wheel</b></td><td>pan; zoom</td></tr>"
      "<tr><td><b>F</b>, <b>Home</b></td><td>fit to view, reset the view</td></tr></table>"
      "<h3>Simulation</h3><table cellspacing=4>"
      "<tr><td><b>Space</b></td><td>play or pause</td></tr><tr><td><b>.</b></td><td>one step</td></tr>"
      "<tr><td><b>[ ] \\</b></td><td>slower, faster, normal speed</td></tr>"
      "<tr><td><b>Ctrl+R</b>, <b>End</b></td><td>reset, go to the end of the recording</td></tr>"
      "<tr><td><b>Timeline</b></td><td>drag the playhead to look at the past; wheel zooms, right-drag pans</td></tr>"
      "<tr><td><b>Ctrl+Z / Ctrl+Shift+Z</b></td><td>undo, redo a tuning change</td></tr>"
      "<tr><td><b>Ctrl+S</b></td><td>save the scene with its tuning</td></tr></table>"));
  layout->addWidget(text);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close, &dialog);
  connect(buttons, &QDialogButtonBox::rejected, &dialog, &QDialog::reject);
  layout->addWidget(buttons);
  dialog.resize(620, 520);
  dialog.exec();
}

}  // namespace vaw::ui
