#include "vaw/ui/main_window.hpp"

#include <QAction>
#include <QActionGroup>
#include <QCheckBox>
#include <QCloseEvent>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QMimeData>
#include <QUrl>
#include <QDialog>
#include <QDialogButtonBox>
#include <QMessageBox>
#include <QPushButton>
#include <QSaveFile>
#include <QSettings>
#include <QTextBrowser>
#include <QUndoStack>
#include <QVBoxLayout>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QInputDialog>
#include <QKeySequence>
#include <QLabel>
#include <QMenuBar>
#include <QStatusBar>
#include <QToolBar>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "format.hpp"
#include "vaw/error.hpp"
#include "vaw/sim/report.hpp"
#include "vaw/sim/scene_file.hpp"
#include "vaw/sim/session.hpp"
#include "vaw/version.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/constraints_dock.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/load_feedback.hpp"
#include "vaw/ui/message_log_model.hpp"
#include "vaw/ui/part_properties_model.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/motion_chart.hpp"
#include "vaw/ui/work_precision_dock.hpp"
#include "vaw/ui/timeline.hpp"
#include "vaw/ui/trials_panel.hpp"
#include "vaw/ui/tuning.hpp"
#include "vaw/ui/viewport.hpp"
#include "vaw/ui/xr_controller.hpp"

namespace vaw::ui {

namespace {
constexpr int kLiveIntervalMs = 100;  // inspector, timeline playhead and status while running
constexpr int kMaxRecent = 8;

bool isSceneFile(const QString& path) { return path.endsWith(QStringLiteral(".json"), Qt::CaseInsensitive) && !path.endsWith(QStringLiteral(".vaw-session.json")); }
}

MainWindow::MainWindow(AssemblyController& controller, QWidget* parent)
    : QMainWindow(parent), controller_(controller) {
  setObjectName(QStringLiteral("mainWindow"));
  setWindowTitle(tr("vaw"));
  setAcceptDrops(true);
  simulation_ = new SimulationController(this);
  viewport_ = new Viewport(this);
  setCentralWidget(viewport_);
  sceneDock_ = new SceneDock(this);
  partDock_ = new PartDock(this);
  messagesDock_ = new MessagesDock(this);
  controlsDock_ = new ControlsDock(this);
  timelineDock_ = new TimelineDock(this);
  gravityDock_ = new GravityDock(this);
  frictionDock_ = new FrictionDock(this);
  methodsDock_ = new MethodsDock(this);
  motionDock_ = new MotionChartDock(this);
  workPrecisionDock_ = new WorkPrecisionDock(this);
  trialsDock_ = new TrialsDock(*simulation_, controller_, this);
  undoStack_ = new QUndoStack(this);
  addDockWidget(Qt::LeftDockWidgetArea, sceneDock_);
  addDockWidget(Qt::LeftDockWidgetArea, partDock_);
  addDockWidget(Qt::RightDockWidgetArea, controlsDock_);
  addDockWidget(Qt::RightDockWidgetArea, gravityDock_);
  addDockWidget(Qt::RightDockWidgetArea, frictionDock_);
  addDockWidget(Qt::RightDockWidgetArea, methodsDock_);
  addDockWidget(Qt::RightDockWidgetArea, trialsDock_);
  tabifyDockWidget(controlsDock_, gravityDock_);
  tabifyDockWidget(gravityDock_, frictionDock_);
  tabifyDockWidget(frictionDock_, methodsDock_);
  // Beside the method it measures, in the tall right-hand column that a log-log chart needs.
  addDockWidget(Qt::RightDockWidgetArea, workPrecisionDock_);
  tabifyDockWidget(methodsDock_, workPrecisionDock_);
  tabifyDockWidget(workPrecisionDock_, trialsDock_);
  controlsDock_->raise();
  addDockWidget(Qt::BottomDockWidgetArea, timelineDock_);
  addDockWidget(Qt::BottomDockWidgetArea, messagesDock_);
  addDockWidget(Qt::BottomDockWidgetArea, motionDock_);
  tabifyDockWidget(timelineDock_, messagesDock_);
  tabifyDockWidget(messagesDock_, motionDock_);
  constraintsDock_ = new ConstraintsDock(controller_, *simulation_, *viewport_, *undoStack_, this);
  addDockWidget(Qt::BottomDockWidgetArea, constraintsDock_);
  tabifyDockWidget(motionDock_, constraintsDock_);
  constraintsDock_->attachBaseMenu(sceneDock_);
  // Re-basing reopens what File > Save writes (the CAD scene), or the CAD file itself.
  connect(constraintsDock_, &ConstraintsDock::baseRequested, this, [this](const QString& part) {
    if (maybeSave()) controller_.openWithBase(scenePath_.isEmpty() ? controller_.currentPath() : scenePath_, part.toStdString());
  });
  timelineDock_->raise();
  resizeDocks({sceneDock_, partDock_}, {220, 480}, Qt::Vertical);
  resizeDocks({sceneDock_, controlsDock_}, {380, 330}, Qt::Horizontal);
  resizeDocks({timelineDock_}, {190}, Qt::Vertical);
  loadFeedback_ = new LoadFeedback(controller_, this);
  status_ = new QLabel(this);
  status_->setObjectName(QStringLiteral("simulationStatus"));
  stabilityStatus_ = new QLabel(this);
  stabilityStatus_->setObjectName(QStringLiteral("stabilityStatus"));
  stabilityStatus_->setStyleSheet(QStringLiteral("color: rgb(180, 40, 20); font-weight: bold;"));
  stabilityStatus_->hide();
  statusBar()->addPermanentWidget(stabilityStatus_);
  statusBar()->addPermanentWidget(status_);
  createMenus();
  // VR mode: its own menu and status line; failures and notes land in Messages.
  xr_ = new XrController(*simulation_, viewport_, this);
  xr_->install(menuBar(), statusBar());
  // Queued: the headset reports hands inside a step, and an answer resets the world for the next trial.
  connect(xr_, &XrController::handClosed, trialsDock_, &TrialsDock::headsetAnswer, Qt::QueuedConnection);
  connect(xr_, &XrController::failed, this, [this](vaw::xr::Failure, const QString& text) {
    message(static_cast<int>(MessageLogModel::Severity::Error), text);
    statusBar()->showMessage(text, 15000);
  });
  connect(xr_, &XrController::notice, this, [this](const QString& text, bool warning) {
    message(static_cast<int>(warning ? MessageLogModel::Severity::Warning : MessageLogModel::Severity::Info), text);
  });
  {
    // Where the user left the window and its docks (a closed dock stays closed).
    QSettings settings;
    restoreGeometry(settings.value(QStringLiteral("window/geometry")).toByteArray());
    restoreState(settings.value(QStringLiteral("window/state")).toByteArray());
    // The STEP tessellation chosen in an earlier run (File > STEP Tessellation).
    bool ok = false;
    const double deflection = settings.value(QStringLiteral("import/relativeDeflection")).toDouble(&ok);
    if (ok && deflection > 0.0) {
      vaw::LoadOptions options = controller_.loadOptions();
      options.import.relativeDeflection = deflection;
      controller_.setLoadOptions(options);
    }
  }
  liveTimer_.setSingleShot(true);
  connect(&liveTimer_, &QTimer::timeout, this, &MainWindow::updateLive);
  lastLive_.start();

  // Selection: the views speak PartIds; each ignores a selection it already shows, so the echo stops. The
  // highlight is part of the simulation's frame (one colour rule for every view).
  connect(sceneDock_, &SceneDock::partSelected, viewport_, &Viewport::selectPart);
  connect(viewport_, &Viewport::partSelected, sceneDock_, &SceneDock::selectPart);
  connect(viewport_, &Viewport::partSelected, this, &MainWindow::showSelection);

  // The mouse and keys of the viewport drive the simulation's hands, base and hoist.
  connect(viewport_, &Viewport::grabStarted, this,
          [this](vaw::PartId part, const Eigen::Vector3d& at, bool both) { simulation_->grab(part, at, both); });
  connect(viewport_, &Viewport::handMoved, this, [this](const Eigen::Vector3d& at) { simulation_->moveHand(at); });
  connect(viewport_, &Viewport::grabEnded, simulation_, &SimulationController::release);
  connect(viewport_, &Viewport::handTurn, this, [this](const Eigen::Vector3d& w) { simulation_->setHandTurn(w); });
  connect(viewport_, &Viewport::baseRates, this, [this](double x, double y, double z) {
    simulation_->setBaseRates(BaseAngles{x, y, z});
  });
  connect(viewport_, &Viewport::hoistRates, this, [this](double up, double yaw) { simulation_->setHoistRates(up, yaw); });
  connect(viewport_, &Viewport::hoistToggled, this, [this] {
    simulation_->setHoistEngaged(!simulation_->hoist().engaged);
    controlsDock_->showHoist(simulation_->hoist());
  });
  connect(viewport_, &Viewport::shortcutKey, this, [this](const QKeySequence& key) {
    for (QAction* a : findChildren<QAction*>())
      if (a->isEnabled() && a->shortcuts().contains(key)) {
        a->trigger();
        return;
      }
  });
  connect(controlsDock_, &ControlsDock::baseTargetChanged, this,
          [this](const BaseAngles& target) { simulation_->setBaseTarget(target); });
  connect(controlsDock_, &ControlsDock::hoistEngagedChanged, simulation_, &SimulationController::setHoistEngaged);
  connect(controlsDock_, &ControlsDock::hoistHeightChanged, simulation_, &SimulationController::setHoistHeight);
  connect(controlsDock_, &ControlsDock::hoistYawChanged, simulation_, &SimulationController::setHoistYaw);
  // The tuning panels ask; the undo stack and the simulation's queue do.
  connect(gravityDock_, &GravityDock::editRequested, this, &MainWindow::requestTuning);
  connect(methodsDock_, &MethodsDock::editRequested, this, &MainWindow::requestTuning);
  connect(frictionDock_->model(), &FrictionModel::editRequested, this,
          [this](const vaw::sim::Edit& e) { requestTuning(e, -1); });
  connect(frictionDock_->model(), &FrictionModel::refused, this, [this](const QString& rule) {
    statusBar()->showMessage(tr("Refused: %1").arg(rule), 10000);
  });
  connect(undoStack_, &QUndoStack::cleanChanged, this, &MainWindow::updateTitle);
  // Declining to drop unsaved tuning for the scenario's scene stops the session before its first trial.
  connect(trialsDock_, &TrialsDock::openSceneRequested, this, [this](const QString& path) {
    if (maybeSave()) controller_.open(path);
    else trialsDock_->stop();
  });
  connect(trialsDock_, &TrialsDock::blindingChanged, this, &MainWindow::setBlinded);
  connect(trialsDock_, &TrialsDock::viewRequested, viewport_, &Viewport::lookAt);
  // Hidden, the motion chart does not sample: shown again, it replays what it missed.
  connect(motionDock_, &QDockWidget::visibilityChanged, this, [this](bool visible) {
    if (!visible) return;
    motionStale_ = true;
    updateLive();
  });
  connect(partDock_, &PartDock::axesToggled, this, [this](bool shown) {
    axesShown_ = shown;
    showSelection(viewport_->selectedPart());
    viewport_->applyFrame(simulation_->frame());
  });

  // What the simulation publishes.
  connect(simulation_, &SimulationController::started, this, &MainWindow::simulationStarted);
  connect(simulation_, &SimulationController::frameReady, this, &MainWindow::frameReady);
  connect(simulation_, &SimulationController::logChanged, this, &MainWindow::logChanged);
  connect(simulation_, &SimulationController::refused, this, [this](const QString& text) {
    message(static_cast<int>(MessageLogModel::Severity::Warning), text);
    statusBar()->showMessage(text, 10000);
  });
  connect(simulation_, &SimulationController::editApplied, this, [this](const QString& text) {
    if (!blinded_) message(static_cast<int>(MessageLogModel::Severity::Info), tr("Edit applied: %1").arg(text));
    updateLive();
  });
  connect(simulation_, &SimulationController::editRefused, this, [this](const QString& text) {
    message(static_cast<int>(MessageLogModel::Severity::Warning), tr("Edit refused: %1").arg(text));
    statusBar()->showMessage(tr("Edit refused: %1").arg(text), 10000);
  });
  connect(simulation_, &SimulationController::futureDiscarded, this, [this](double from) {
    const QString text = tr("The recording after %1 s was discarded: the simulation continues from there.")
                             .arg(format::number(from));
    message(static_cast<int>(MessageLogModel::Severity::Info), text);
    statusBar()->showMessage(text, 10000);
  });
  connect(simulation_, &SimulationController::playingChanged, this, [this](bool playing) {
    playAction_->setText(playing ? tr("&Pause") : tr("&Play"));
    playAction_->setChecked(playing);
    if (playing && simulation_->inPast() && !simulation_->isPlayback())
      statusBar()->showMessage(tr("Playing from %1 s: the recorded future after it is discarded.")
                                   .arg(format::number(simulation_->world().time())),
                               10000);
    updateStatus();
  });
  connect(simulation_, &SimulationController::speedChanged, this, &MainWindow::updateStatus);
  connect(simulation_, &SimulationController::pastGivenUp, this, [this](double before) {
    const QString text = tr("Memory is short: the recording gave up its snapshots before %1 s").arg(format::number(before, 4));
    message(static_cast<int>(MessageLogModel::Severity::Warning), text,
            tr("The whole session is still recorded and can be saved, but seeking to a time before %1 s now replays it "
               "from the start, which takes longer (docs/simulation.md, \"The recorder: record, seek, discard\").")
                .arg(format::number(before, 4)));
    statusBar()->showMessage(text, 10000);
  });
  connect(simulation_, &SimulationController::behindChanged, this, [this](bool behind) {
    updateStatus();
    if (!behind || blinded_) return;
    message(static_cast<int>(MessageLogModel::Severity::Warning),
            tr("The simulation cannot keep up with real time: %1").arg(rateText()),
            tr("Simulated time runs slower than the wall clock, so a part falls and slides slower than it would. "
               "Close panels you do not need, make the window smaller, or lower the rate (docs/simulation.md, "
               "\"When the simulation falls behind\")."));
  });
  connect(timelineDock_->view(), &TimelineView::seekRequested, this, [this](double seconds) {
    if (simulation_->hasWorld()) simulation_->seek(simulation_->recorder().stepAt(seconds));
  });
  connect(timelineDock_, &TimelineDock::exportPngRequested, this, [this] {
    const QString file = QFileDialog::getSaveFileName(this, tr("Export timeline as PNG"), QStringLiteral("timeline.png"),
                                                      tr("PNG images (*.png)"));
    if (!file.isEmpty()) exportTimelinePng(file);
  });
  connect(timelineDock_, &TimelineDock::exportCsvRequested, this, [this] {
    const QString file = QFileDialog::getSaveFileName(this, tr("Export timeline as CSV"),
                                                      QStringLiteral("transitions.csv"), tr("CSV files (*.csv)"));
    if (!file.isEmpty()) exportTimelineCsv(file);
  });

  connect(&controller_, &AssemblyController::assemblyLoaded, this, &MainWindow::assemblyLoaded);
  connect(&controller_, &AssemblyController::loadStarted, this, [this](const QString& path) {
    statusBar()->showMessage(tr("Opening %1...").arg(path));
  });
  connect(&controller_, &AssemblyController::loadFailed, this, [this](const LoadFailure& failure) {
    QStringList detail{tr("File: %1").arg(failure.file.isEmpty() ? failure.path : failure.file)};
    if (!failure.field.isEmpty()) detail << tr("Field: %1").arg(failure.field);
    if (!failure.expected.isEmpty()) detail << tr("Expected: %1").arg(failure.expected);
    if (!failure.found.isEmpty()) detail << tr("Found: %1").arg(failure.found);
    messagesDock_->model()->add(MessageLogModel::Severity::Error, failure.message, detail.join(QLatin1Char('\n')));
    statusBar()->showMessage(tr("Could not open %1").arg(QFileInfo(failure.path).fileName()));
  });
  connect(&controller_, &AssemblyController::loadCancelled, this, [this](const QString& path) {
    statusBar()->showMessage(tr("Opening %1 cancelled").arg(QFileInfo(path).fileName()));
  });

  for (const QString& text : controller_.pluginMessages()) {
    messagesDock_->model()->add(MessageLogModel::Severity::Warning, text);
  }
  if (!controller_.pluginMessages().isEmpty()) statusBar()->showMessage(controller_.pluginMessages().last());
  updateStatus();
}

MainWindow::~MainWindow() { simulation_->pause(); }

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
  QAction* tessellation = file->addAction(tr("STEP &Tessellation..."), this, &MainWindow::stepDeflectionDialog);
  tessellation->setObjectName(QStringLiteral("stepDeflectionAction"));
  tessellation->setToolTip(tr("How finely STEP parts are tessellated for display and collision"));
  QAction* save = file->addAction(tr("Save &Session..."), this, &MainWindow::saveSessionDialog);
  save->setObjectName(QStringLiteral("saveSessionAction"));
  save->setShortcut(QKeySequence(tr("Ctrl+Shift+S")));
  file->addAction(tr("Export Timeline as &PNG..."), timelineDock_, &TimelineDock::exportPngRequested);
  file->addAction(tr("Export Timeline as &CSV..."), timelineDock_, &TimelineDock::exportCsvRequested);
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

void MainWindow::message(int severity, const QString& text, const QString& detail) {
  messagesDock_->model()->add(static_cast<MessageLogModel::Severity>(severity), text, detail);
}

void MainWindow::openFileDialog() {
  const QString start =
      controller_.currentPath().isEmpty() ? QString() : QFileInfo(controller_.currentPath()).absolutePath();
  QStringList filters = controller_.fileDialogFilters();
  filters.insert(1, tr("Sessions (*.vaw-session.json)"));
  const QString path = QFileDialog::getOpenFileName(this, tr("Open scene, mesh or session"), start,
                                                    filters.join(QStringLiteral(";;")));
  if (!path.isEmpty()) openFile(path);
}

void MainWindow::stepDeflectionDialog() {
  bool ok = false;
  const double value = QInputDialog::getDouble(
      this, tr("STEP tessellation"),
      tr("Chordal deflection as a fraction of each part's size\n(smaller is finer: more triangles, slower collision)"),
      controller_.loadOptions().import.relativeDeflection, 0.0001, 0.05, 4, &ok);
  if (ok) setStepDeflection(value);
}

void MainWindow::setStepDeflection(double relative) {
  vaw::LoadOptions options = controller_.loadOptions();
  options.import.relativeDeflection = relative;
  controller_.setLoadOptions(options);
  QSettings().setValue(QStringLiteral("import/relativeDeflection"), relative);
  const vaw::Assembly* a = controller_.assembly();
  const QString text = tr("STEP tessellation: deflection %1 of each part's size").arg(relative);
  message(static_cast<int>(MessageLogModel::Severity::Info), text);
  statusBar()->showMessage(text, 8000);
  // The open STEP assembly is tessellated anew, asking first about unsaved changes.
  if (a != nullptr && !a->cadFile.empty() && maybeSave()) controller_.reload();
}

void MainWindow::openFile(const QString& path) {
  if (!maybeSave()) return;
  controller_.open(path);
}

void MainWindow::saveSessionDialog() {
  if (!simulation_->hasWorld() || savingWaitsForTrials()) return;
  const QString file = QFileDialog::getSaveFileName(this, tr("Save session"), QStringLiteral("session.vaw-session.json"),
                                                    tr("Sessions (*.vaw-session.json)"));
  if (!file.isEmpty()) saveSession(file);
}

bool MainWindow::saveSession(const QString& file) {
  if (!simulation_->hasWorld()) return false;
  try {
    vaw::sim::saveSession(simulation_->recorder().session(), std::filesystem::path(QFile::encodeName(file).toStdString()));
    const QString text = tr("Saved the session (%1 s, %2 steps) to %3")
                             .arg(format::number(simulation_->recorder().endTime()))
                             .arg(simulation_->recorder().length())
                             .arg(file);
    message(static_cast<int>(MessageLogModel::Severity::Info), text);
    statusBar()->showMessage(text, 8000);
    return true;
  } catch (const std::exception& e) {  // vaw::OutputError too: a full disk must not take the window down
    message(static_cast<int>(MessageLogModel::Severity::Error), tr("Could not save the session: %1").arg(e.what()));
    return false;
  }
}

bool MainWindow::exportTimelinePng(const QString& file) {
  // Complete or untouched, like every other output: QSaveFile writes beside it and renames on commit.
  QSaveFile out(file);
  const bool ok = out.open(QIODevice::WriteOnly) && timelineDock_->view()->render().save(&out, "PNG") && out.commit();
  message(static_cast<int>(ok ? MessageLogModel::Severity::Info : MessageLogModel::Severity::Error),
          ok ? tr("Exported the timeline to %1").arg(file) : tr("Could not write %1").arg(file));
  return ok;
}

bool MainWindow::exportTimelineCsv(const QString& file) {
  try {
    timelineDock_->model()->writeCsv(file);
    message(static_cast<int>(MessageLogModel::Severity::Info), tr("Exported the timeline to %1").arg(file));
    return true;
  } catch (const std::exception& e) {  // vaw::OutputError too
    message(static_cast<int>(MessageLogModel::Severity::Error), tr("Could not export the timeline: %1").arg(e.what()));
    return false;
  }
}

void MainWindow::assemblyLoaded() {
  const vaw::Assembly* assembly = controller_.assembly();
  const bool edited = controller_.isEditReload();  // its constraints changed: the same file, already announced
  const bool wasPlaying = simulation_->isPlaying();
  const std::string keepName = selectedName_;
  const QString keepFrom = selectedFrom_;
  reloadAction_->setEnabled(true);
  std::optional<vaw::sim::Session> session = controller_.takeSession();
  bool playback = false;
  if (session) {
    try {
      simulation_->startPlayback(controller_.scene(), std::move(*session));
      playback = true;
    } catch (const vaw::InputError& e) {
      message(static_cast<int>(MessageLogModel::Severity::Error), tr("The session cannot be played: %1").arg(e.what()));
    }
  }
  // A scene starts with the tuning its settings block saved.
  if (!playback)
    simulation_->start(controller_.scene(), controller_.sceneReference(), vaw::sim::settingsFor(controller_.scene()->assembly()));
  sceneDock_->setAssembly(assembly, controller_.collisionInfo());
  partDock_->showPart(assembly, std::nullopt);
  if (assembly == nullptr) return;
  // After a reload, the part that was selected stays selected (by name: ids may change).
  if (!keepName.empty() && keepFrom == controller_.currentPath()) viewport_->selectPart(assembly->findPart(keepName));
  if (!edited) scenePath_ = isSceneFile(controller_.currentPath()) ? controller_.currentPath() : QString();
  saveAction_->setEnabled(true);
  saveAsAction_->setEnabled(true);
  if (edited) {
    updateTitle();
    if (wasPlaying) simulation_->play();
    return;
  }
  addRecent(controller_.currentPath());
  for (const auto& warning : assembly->warnings) messagesDock_->model()->add(warning);
  updateTitle();
  const QString summary = tr("Opened %1: %n part(s)", nullptr, static_cast<int>(assembly->parts.size()))
                              .arg(QFileInfo(controller_.currentPath()).fileName()) +
                          tr(", %n triangle(s)", nullptr, static_cast<int>(assembly->totalTriangles())) +
                          (assembly->warnings.empty()
                               ? QString()
                               : tr(", %n warning(s) (see Messages)", nullptr,
                                    static_cast<int>(assembly->warnings.size())));
  messagesDock_->model()->add(MessageLogModel::Severity::Info, summary, controller_.currentPath());
  statusBar()->showMessage(playback ? tr("Opened a session of %1 s: press Play to watch it")
                                          .arg(format::number(simulation_->recorder().endTime()))
                                    : summary);
  if (!playback && autoPlay_) simulation_->play();
}

void MainWindow::simulationStarted() {
  viewport_->setScene(&simulation_->description());
  viewport_->applyFrame(simulation_->frame());
  controlsDock_->setHoist(simulation_->world().hoist());
  controlsDock_->showBaseTarget(simulation_->baseTarget());
  timelineDock_->model()->clear();
  motionStale_ = true;
  // Its edits were of the previous world; a constraint edit's new world keeps the tuning, and the history.
  if (!controller_.isEditReload()) undoStack_->clear();
  logChanged();
  updateLive();
  updateTitle();
}

void MainWindow::showSelection(std::optional<vaw::PartId> part) {
  const vaw::Assembly* assembly = controller_.assembly();
  simulation_->setSelected(part);
  partDock_->showPart(assembly, part, controller_.collisionInfo());
  if (assembly != nullptr && part && *part < assembly->parts.size()) {
    selectedName_ = assembly->parts[*part].name;
    selectedFrom_ = controller_.currentPath();
    const vaw::Part& p = assembly->parts[*part];
    // Half-lengths from the part's extent, so the axes stick out of it.
    const double half = std::max(0.8 * p.extent, 0.02);
    viewport_->showAxes(axesShown_ ? std::optional(Viewport::Axes{*part, p.mass.centerOfMass, p.principal.axes,
                                                                  Eigen::Vector3d::Constant(half)})
                                   : std::nullopt);
  } else {
    selectedName_.clear();
    viewport_->showAxes(std::nullopt);
  }
  updateLive();
}

void MainWindow::frameReady() {
  viewport_->applyFrame(simulation_->frame());
  updateCapture();
  if (motionDock_->isVisible() && !motionStale_) motionDock_->follow(*simulation_, false, false);
  // The panels follow at a readable rate while it runs, at once when it is paused (a seek, a step).
  if (!simulation_->isPlaying() || lastLive_.elapsed() >= kLiveIntervalMs) updateLive();
  else if (!liveTimer_.isActive()) liveTimer_.start(static_cast<int>(kLiveIntervalMs - lastLive_.elapsed()));
}

void MainWindow::updateCapture() {
  const QString before = captureText_;
  captureText_.clear();
  std::optional<Viewport::CaptureZone> zone;
  const vaw::sim::World& w = simulation_->world();
  const auto held = w.held(1);
  const auto hint = held ? w.captureHint(*held) : std::nullopt;
  const vaw::sim::Settings& st = w.settings();
  const double kDeg = std::numbers::pi / 180.0;
  // Near: within five times the capture distance and three times its angle.
  if (hint && hint->distance <= 5.0 * st.recognizeDistance && hint->angle <= 3.0 * st.recognizeAngle * kDeg) {
    const vaw::Assembly& a = w.assembly();
    const vaw::Constraint& c = a.constraints[hint->constraint];
    const QString part = QString::fromStdString(a.parts[*held].name);
    const QString partner = QString::fromStdString(a.parts[c.partner.value_or(a.base.value_or(0))].name);
    const QString off = tr("%1 mm, %2° off").arg(format::number(hint->distance * 1e3, 3)).arg(format::number(hint->angle / kDeg, 2));
    captureText_ = hint->captures ? tr("let go now and %1 goes onto %2 (%3)").arg(part, partner, off)
                                  : tr("%1 is %2 %3: let go within %4 mm and %5°, touching it, to put it on")
                                        .arg(part, off, c.type == vaw::Constraint::Type::Insert ? tr("the axis on %1").arg(partner)
                                                                                                : tr("its face on %1").arg(partner))
                                        .arg(format::number(st.recognizeDistance * 1e3, 2))
                                        .arg(format::number(st.recognizeAngle, 2));
    // Drawn just past the part along the mate's axis or normal, where the part does not hide it: seen along
    // that direction, the part's axis must lie inside the ring.
    const Eigen::Vector3d d = hint->direction.normalized();
    // Per frame: the corners of the part's bounds, not every vertex (a little farther for a turned part).
    const Eigen::AlignedBox3d box = a.parts[*held].mesh->bounds();
    double past = 0.0;
    for (int k = 0; k < 8; ++k)
      past = std::max(past, d.dot(w.part(*held).pose * box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k)) - hint->point));
    zone = Viewport::CaptureZone{c.type == vaw::Constraint::Type::Insert, hint->point + d * (past + 0.5 * st.recognizeDistance), d,
                                 st.recognizeDistance, hint->captures};
  }
  viewport_->showCaptureZone(zone);
  if (captureText_ != before) updateStatus();
}

void MainWindow::updateLive() {
  lastLive_.restart();
  liveTimer_.stop();
  if (!simulation_->hasWorld()) return;
  const auto part = simulation_->selected();
  // One report per update: the inspector shows it and the tuning panels take its stability advice.
  std::optional<vaw::sim::PartReport> selected;
  if (part) selected = vaw::sim::report(simulation_->world(), *part);
  if (selected && partDock_->model()->part() == part) partDock_->model()->updateLive(*selected);
  const vaw::sim::Recorder& r = simulation_->recorder();
  timelineDock_->view()->setTimes(r.world().time(), r.endTime(), !r.atEnd(), simulation_->isPlayback());
  // A recording (played back, or looked at in the past) shows the base as it held it.
  const bool recorded = simulation_->isPlayback() || simulation_->inPast();
  controlsDock_->showBaseTarget(recorded ? simulation_->worldBaseAngles() : simulation_->baseTarget());
  if (simulation_->world().hoist())
    controlsDock_->showHoist(recorded ? simulation_->world().lastInput().hoist : simulation_->hoist());
  updateTuning(selected ? selected->stability : std::nullopt);
  if (motionDock_->isVisible()) {
    motionDock_->follow(*simulation_, motionStale_);
    motionStale_ = false;
  }
  updateStatus();
}

void MainWindow::updateTuning(const std::optional<vaw::sim::StabilityAdvice>& advice) {
  const vaw::sim::World& w = simulation_->world();
  const auto part = simulation_->selected();
  gravityDock_->showWorld(w);
  frictionDock_->model()->showWorld(&w, part);
  const QString name = part ? QString::fromStdString(w.assembly().parts[*part].name) : QString();
  methodsDock_->showWorld(w, advice, name);
  workPrecisionDock_->showWorld(w, part);
  const bool warn = advice && advice->level != vaw::sim::StabilityAdvice::Level::Stable;
  // Whether a rotation method is near its limit depends on the gravity scale: hidden while a blinded trial plays.
  stabilityStatus_->setVisible(warn && !blinded_);
  QString fix;
  if (warn && advice->safeMethod) fix = tr("use %1").arg(QString::fromLatin1(vaw::dyn::name(*advice->safeMethod).data()));
  if (warn && advice->safeRate)
    fix += (fix.isEmpty() ? tr("use ") : tr(" or ")) + tr("%1 Hz").arg(QString::number(*advice->safeRate, 'g', 6));
  stabilityStatus_->setText(
      warn ? tr("⚠ %1: %2 at %3 Hz %4%5")
                 .arg(name, QString::fromLatin1(vaw::dyn::name(w.settings().rotationMethod).data()),
                      QString::number(w.settings().rate, 'g', 6),
                      advice->level == vaw::sim::StabilityAdvice::Level::Unstable ? tr("is unstable") : tr("is near its limit"),
                      fix.isEmpty() ? QString() : QStringLiteral(" (%1)").arg(fix))
           : QString());
  stabilityStatus_->setToolTip(warn ? QString::fromStdString(advice->text) : QString());
}

QString MainWindow::stabilityWarning() const { return stabilityStatus_->isVisible() ? stabilityStatus_->text() : QString(); }

bool MainWindow::hasUnsavedChanges() const { return !undoStack_->isClean(); }

void MainWindow::requestTuning(const vaw::sim::Edit& edit, int mergeKey) {
  if (!simulation_->hasWorld()) return;
  const vaw::sim::World& w = simulation_->world();
  const std::string problem = vaw::sim::validate(edit, w.assembly());
  if (!problem.empty()) {
    const QString text = tr("Refused: %1").arg(QString::fromStdString(problem));
    message(static_cast<int>(MessageLogModel::Severity::Warning), text);
    statusBar()->showMessage(text, 10000);
    updateLive();  // the panel shows the value kept
    return;
  }
  // What the world has now, as a whole value of the same kind: undo sends it back.
  const vaw::sim::Edit before = std::visit(
      [&w](const auto& e) -> vaw::sim::Edit {
        using E = std::decay_t<decltype(e)>;
        if constexpr (std::is_same_v<E, vaw::sim::GravityEdit>) return vaw::sim::GravityEdit{w.settings().gravity};
        else if constexpr (std::is_same_v<E, vaw::sim::MaterialFrictionEdit>)
          return vaw::sim::MaterialFrictionEdit{e.material, w.materialFriction(e.material)};
        else if constexpr (std::is_same_v<E, vaw::sim::PartFrictionEdit>) {
          return vaw::sim::PartFrictionEdit{e.part, w.frictionOverride(e.part)};
        } else if constexpr (std::is_same_v<E, vaw::sim::MethodEdit>) return vaw::sim::MethodEdit{w.settings().rotationMethod};
        else return vaw::sim::RateEdit{w.settings().rate};
      },
      edit);
  undoStack_->push(new EditCommand(*simulation_, before, edit, QString::fromStdString(vaw::sim::describe(edit, w.assembly())),
                                   mergeKey));
}

bool MainWindow::save() {
  if (savingWaitsForTrials()) return false;
  if (scenePath_.isEmpty()) return saveAs();
  return saveScene(scenePath_);
}

bool MainWindow::saveAs() {
  if (!simulation_->hasWorld() || savingWaitsForTrials()) return false;
  const vaw::Assembly& loaded = simulation_->world().assembly();
  // A CAD file is saved as a scene that refers to it (vaw::sim::saveScene).
  const bool cad = !loaded.cadFile.empty();
  if (!cad && !isSceneFile(QFile::decodeName(loaded.source.string().c_str()))) {
    const QString text = tr("Only a scene (.vaw.json) can be saved with its tuning; %1 is not one. Save the session instead.")
                             .arg(QFile::decodeName(loaded.source.filename().string().c_str()));
    message(static_cast<int>(MessageLogModel::Severity::Warning), text);
    statusBar()->showMessage(text, 10000);
    return false;
  }
  QString start = scenePath_.isEmpty() ? QFile::decodeName(loaded.source.string().c_str()) : scenePath_;
  if (cad && scenePath_.isEmpty()) {
    std::filesystem::path next = loaded.cadFile;
    start = QFile::decodeName(next.replace_extension(".vaw.json").string().c_str());
  }
  QString file = QFileDialog::getSaveFileName(this, tr("Save scene with its tuning"), start, tr("Scenes (*.vaw.json)"));
  if (file.isEmpty()) return false;
  if (!file.endsWith(QStringLiteral(".json"))) file += QStringLiteral(".vaw.json");
  return saveScene(file);
}

bool MainWindow::saveScene(const QString& file) {
  if (!simulation_->hasWorld()) return false;
  try {
    vaw::sim::saveScene(simulation_->world().assembly(), simulation_->world(),
                        std::filesystem::path(QFile::encodeName(file).toStdString()));
  } catch (const std::exception& e) {  // vaw::InputError, or vaw::OutputError when the disk refuses it
    const QString text = tr("Could not save the scene: %1").arg(QString::fromUtf8(e.what()));
    message(static_cast<int>(MessageLogModel::Severity::Error), text);
    statusBar()->showMessage(text, 10000);
    return false;
  }
  scenePath_ = file;
  undoStack_->setClean();
  addRecent(file);
  const QString text = tr("Saved the scene with its tuning to %1").arg(file);
  message(static_cast<int>(MessageLogModel::Severity::Info), text);
  statusBar()->showMessage(text, 8000);
  updateTitle();
  return true;
}

bool MainWindow::maybeSave() {
  if (!hasUnsavedChanges()) return true;
  QMessageBox box(QMessageBox::Warning, tr("Unsaved tuning"),
                  tr("The gravity, friction or method settings were changed and not saved."),
                  QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, this);
  box.setObjectName(QStringLiteral("unsavedChangesBox"));
  box.setInformativeText(tr("Save them with the scene?"));
  box.setDefaultButton(QMessageBox::Save);
  switch (box.exec()) {
    case QMessageBox::Save: return save();
    case QMessageBox::Discard: return true;
    default: return false;
  }
}

void MainWindow::dragEnterEvent(QDragEnterEvent* event) {
  const QList<QUrl> urls = event->mimeData()->urls();
  if (!urls.isEmpty() && urls.front().isLocalFile()) event->acceptProposedAction();
}

// A file dropped on the window opens as File > Open would open it (a scene, a mesh, a STEP file, a session).
void MainWindow::dropEvent(QDropEvent* event) {
  const QList<QUrl> urls = event->mimeData()->urls();
  if (urls.isEmpty() || !urls.front().isLocalFile()) return;
  event->acceptProposedAction();
  openFile(urls.front().toLocalFile());
}

void MainWindow::closeEvent(QCloseEvent* event) {
  // Closing ends a trials session (its answers are on disk): the tuning offered for saving is then the
  // scene's own again, not the last trial's scale.
  trialsDock_->stop();
  if (!maybeSave()) {
    event->ignore();
    return;
  }
  // The layout kept is the user's, not the one a blinded trials session closed panels in.
  if (blinded_) setBlinded(false);
  QSettings settings;
  settings.setValue(QStringLiteral("window/geometry"), saveGeometry());
  settings.setValue(QStringLiteral("window/state"), saveState());
  simulation_->pause();
  event->accept();
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

void MainWindow::updateTitle() {
  const vaw::Assembly* assembly = controller_.assembly();
  QString name = assembly == nullptr ? QString() : QString::fromStdString(assembly->name);
  if (name.isEmpty()) name = QFileInfo(controller_.currentPath()).fileName();
  setWindowTitle(name.isEmpty() ? tr("vaw") : tr("%1[*] - vaw").arg(name));
  setWindowModified(hasUnsavedChanges());
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

void MainWindow::setBlinded(bool blinded) {
  blinded_ = blinded;
  gravityDock_->setBlinded(blinded);
  // The inspector's speeds, the timeline's state durations and the motion chart would each give the scale
  // away; those that were open come back afterwards.
  if (blinded) {
    for (QDockWidget* d : {static_cast<QDockWidget*>(partDock_), static_cast<QDockWidget*>(timelineDock_),
                           static_cast<QDockWidget*>(motionDock_)})
      if (d->toggleViewAction()->isChecked()) {
        closedForBlinding_.push_back(d);
        d->hide();
      }
  } else {
    for (QDockWidget* d : closedForBlinding_) d->show();
    // Shown again, a tabbed panel is not the current tab; the timeline was, as it is after a start.
    if (std::find(closedForBlinding_.begin(), closedForBlinding_.end(), timelineDock_) != closedForBlinding_.end())
      timelineDock_->raise();
    closedForBlinding_.clear();
  }
  if (blinded) stabilityStatus_->hide();
  updateStatus();
  logChanged();
}

bool MainWindow::savingWaitsForTrials() {
  if (!trialsDock_->running()) return false;
  const QString text = tr("Nothing was saved: a trials session is running, and the world plays the trial's scale, not the "
                          "scene's. Stop the session first (its answers are on disk, and Start resumes it).");
  message(static_cast<int>(MessageLogModel::Severity::Warning), text);
  statusBar()->showMessage(text, 10000);
  return true;
}

void MainWindow::logChanged() {
  if (!simulation_->hasWorld()) return;
  const vaw::sim::Recorder& r = simulation_->recorder();
  timelineDock_->model()->setLog(&r.scene().assembly(), r.transitions(), r.refusals(),
                                 blinded_ ? std::vector<vaw::sim::EditRecord>{} : r.edits());
  timelineDock_->view()->setTimes(r.world().time(), r.endTime(), !r.atEnd(), simulation_->isPlayback());
}

QString MainWindow::statusText() const {
  if (!simulation_->hasWorld()) return tr("no scene");
  const vaw::sim::World& w = simulation_->world();
  QString mode = simulation_->isPlaying() ? tr("playing") : tr("paused");
  // The clock would time the fall, and so give the trial's scale away.
  if (blinded_) return tr("trials session · %1").arg(mode);
  if (simulation_->isPlayback()) mode += tr(", playback");
  else if (simulation_->inPast()) mode += tr(", in the past");
  const QString speed = simulation_->isBehind() ? rateText() : tr("%1×").arg(format::number(simulation_->speed(), 2));
  const QString text = tr("t %1 s · step %2 µs · %3 active · %4 · %5")
                           .arg(QString::number(w.time(), 'f', 3))
                           .arg(QString::number(static_cast<double>(simulation_->lastStepNanoseconds()) * 1e-3, 'f', 1))
                           .arg(w.activeParts())
                           .arg(speed)
                           .arg(mode);
  return captureText_.isEmpty() ? text : captureText_ + tr(" · ") + text;
}

QString MainWindow::rateText() const {
  const auto r = simulation_->realRate();
  if (!r) return tr("%1×").arg(format::number(simulation_->speed(), 2));
  // Stepping takes most of the wall time: the physics; the timer's ticks come on time but owe more steps than
  // one tick runs: the rate; otherwise what else the thread does, drawing above all.
  const QString neck = r->steppingShare > 0.5        ? tr("the physics is the bottleneck")
                       : simulation_->cappedShare() > 0.5 ? tr("the rate is more than the workbench steps (at most %1 steps a tick)")
                                                                .arg(SimulationController::kMaxCatchUp)
                                                          : tr("rendering is the bottleneck");
  QString text = tr("%1× of real time").arg(QString::number(r->rate, 'f', 2));
  if (std::abs(simulation_->speed() - 1.0) > 1e-9) text += tr(" (%1× asked)").arg(format::number(simulation_->speed(), 2));
  return text + tr(", %1").arg(neck);
}

void MainWindow::updateStatus() { status_->setText(statusText()); }

}  // namespace vaw::ui
