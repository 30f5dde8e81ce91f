#include "vaw/ui/main_window.hpp"

#include <QAction>
#include <QActionGroup>
#include <QCheckBox>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QKeySequence>
#include <QLabel>
#include <QMenuBar>
#include <QStatusBar>
#include <QToolBar>
#include <cmath>

#include "format.hpp"
#include "vaw/error.hpp"
#include "vaw/sim/report.hpp"
#include "vaw/sim/session.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/load_feedback.hpp"
#include "vaw/ui/message_log_model.hpp"
#include "vaw/ui/part_properties_model.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/timeline.hpp"
#include "vaw/ui/viewport.hpp"
#include "vaw/ui/xr_controller.hpp"

namespace vaw::ui {

namespace {
constexpr int kLiveIntervalMs = 100;  // inspector, timeline playhead and status while running
}

MainWindow::MainWindow(AssemblyController& controller, QWidget* parent)
    : QMainWindow(parent), controller_(controller) {
  setObjectName(QStringLiteral("mainWindow"));
  setWindowTitle(tr("vaw"));
  simulation_ = new SimulationController(this);
  viewport_ = new Viewport(this);
  setCentralWidget(viewport_);
  sceneDock_ = new SceneDock(this);
  partDock_ = new PartDock(this);
  messagesDock_ = new MessagesDock(this);
  controlsDock_ = new ControlsDock(this);
  timelineDock_ = new TimelineDock(this);
  addDockWidget(Qt::LeftDockWidgetArea, sceneDock_);
  addDockWidget(Qt::LeftDockWidgetArea, partDock_);
  addDockWidget(Qt::RightDockWidgetArea, controlsDock_);
  addDockWidget(Qt::BottomDockWidgetArea, timelineDock_);
  addDockWidget(Qt::BottomDockWidgetArea, messagesDock_);
  tabifyDockWidget(timelineDock_, messagesDock_);
  timelineDock_->raise();
  resizeDocks({sceneDock_, partDock_}, {220, 480}, Qt::Vertical);
  resizeDocks({sceneDock_, controlsDock_}, {380, 230}, Qt::Horizontal);
  resizeDocks({timelineDock_}, {190}, Qt::Vertical);
  loadFeedback_ = new LoadFeedback(controller_, this);
  status_ = new QLabel(this);
  status_->setObjectName(QStringLiteral("simulationStatus"));
  statusBar()->addPermanentWidget(status_);
  createMenus();
  // VR mode: its own menu and status line; failures and notes land in Messages.
  xr_ = new XrController(*simulation_, viewport_, this);
  xr_->install(menuBar(), statusBar());
  connect(xr_, &XrController::failed, this, [this](vaw::xr::Failure, const QString& text) {
    message(static_cast<int>(MessageLogModel::Severity::Error), text);
    statusBar()->showMessage(text, 15000);
  });
  connect(xr_, &XrController::notice, this, [this](const QString& text, bool warning) {
    message(static_cast<int>(warning ? MessageLogModel::Severity::Warning : MessageLogModel::Severity::Info), text);
  });
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
    message(static_cast<int>(MessageLogModel::Severity::Info), tr("Edit applied: %1").arg(text));
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
  reloadAction_ = file->addAction(tr("&Reload"), &controller_, &AssemblyController::reload);
  reloadAction_->setShortcut(QKeySequence::Refresh);
  reloadAction_->setEnabled(false);
  file->addSeparator();
  QAction* save = file->addAction(tr("Save &Session..."), this, &MainWindow::saveSessionDialog);
  save->setObjectName(QStringLiteral("saveSessionAction"));
  save->setShortcut(QKeySequence(tr("Ctrl+Shift+S")));
  file->addAction(tr("Export Timeline as &PNG..."), timelineDock_, &TimelineDock::exportPngRequested);
  file->addAction(tr("Export Timeline as &CSV..."), timelineDock_, &TimelineDock::exportCsvRequested);
  file->addSeparator();
  QAction* quit = file->addAction(tr("&Quit"), this, &QWidget::close);
  quit->setShortcut(QKeySequence::Quit);

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
  if (!path.isEmpty()) controller_.open(path);
}

void MainWindow::saveSessionDialog() {
  if (!simulation_->hasWorld()) return;
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
  } catch (const vaw::InputError& e) {
    message(static_cast<int>(MessageLogModel::Severity::Error), tr("Could not save the session: %1").arg(e.what()));
    return false;
  }
}

bool MainWindow::exportTimelinePng(const QString& file) {
  const bool ok = timelineDock_->view()->render().save(file, "PNG");
  message(static_cast<int>(ok ? MessageLogModel::Severity::Info : MessageLogModel::Severity::Error),
          ok ? tr("Exported the timeline to %1").arg(file) : tr("Could not write %1").arg(file));
  return ok;
}

bool MainWindow::exportTimelineCsv(const QString& file) {
  try {
    timelineDock_->model()->writeCsv(file);
    message(static_cast<int>(MessageLogModel::Severity::Info), tr("Exported the timeline to %1").arg(file));
    return true;
  } catch (const vaw::InputError& e) {
    message(static_cast<int>(MessageLogModel::Severity::Error), tr("Could not export the timeline: %1").arg(e.what()));
    return false;
  }
}

void MainWindow::assemblyLoaded() {
  const vaw::Assembly* assembly = controller_.assembly();
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
  if (!playback) simulation_->start(controller_.scene(), controller_.sceneReference());
  sceneDock_->setAssembly(assembly, controller_.collisionInfo());
  partDock_->showPart(assembly, std::nullopt);
  if (assembly == nullptr) return;
  // After a reload, the part that was selected stays selected (by name: ids may change).
  if (!keepName.empty() && keepFrom == controller_.currentPath()) viewport_->selectPart(assembly->findPart(keepName));
  for (const auto& warning : assembly->warnings) messagesDock_->model()->add(warning);
  const QString name = QString::fromStdString(assembly->name);
  setWindowTitle(tr("%1 - vaw").arg(name.isEmpty() ? QFileInfo(controller_.currentPath()).fileName() : name));
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
  logChanged();
  updateLive();
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
  // The panels follow at a readable rate while it runs, at once when it is paused (a seek, a step).
  if (!simulation_->isPlaying() || lastLive_.elapsed() >= kLiveIntervalMs) updateLive();
  else if (!liveTimer_.isActive()) liveTimer_.start(static_cast<int>(kLiveIntervalMs - lastLive_.elapsed()));
}

void MainWindow::updateLive() {
  lastLive_.restart();
  liveTimer_.stop();
  if (!simulation_->hasWorld()) return;
  const auto part = simulation_->selected();
  if (part && partDock_->model()->part() == part) partDock_->model()->updateLive(vaw::sim::report(simulation_->world(), *part));
  const vaw::sim::Recorder& r = simulation_->recorder();
  timelineDock_->view()->setTimes(r.world().time(), r.endTime(), !r.atEnd(), simulation_->isPlayback());
  // A recording (played back, or looked at in the past) shows the base as it held it.
  const bool recorded = simulation_->isPlayback() || simulation_->inPast();
  controlsDock_->showBaseTarget(recorded ? simulation_->worldBaseAngles() : simulation_->baseTarget());
  if (simulation_->world().hoist())
    controlsDock_->showHoist(recorded ? simulation_->world().lastInput().hoist : simulation_->hoist());
  updateStatus();
}

void MainWindow::logChanged() {
  if (!simulation_->hasWorld()) return;
  const vaw::sim::Recorder& r = simulation_->recorder();
  timelineDock_->model()->setLog(&r.scene().assembly(), r.transitions(), r.refusals(), r.edits());
  timelineDock_->view()->setTimes(r.world().time(), r.endTime(), !r.atEnd(), simulation_->isPlayback());
}

QString MainWindow::statusText() const {
  if (!simulation_->hasWorld()) return tr("no scene");
  const vaw::sim::World& w = simulation_->world();
  QString mode = simulation_->isPlaying() ? tr("playing") : tr("paused");
  if (simulation_->isPlayback()) mode += tr(", playback");
  else if (simulation_->inPast()) mode += tr(", in the past");
  return tr("t %1 s · step %2 µs · %3 active · %4× · %5")
      .arg(QString::number(w.time(), 'f', 3))
      .arg(QString::number(static_cast<double>(simulation_->lastStepNanoseconds()) * 1e-3, 'f', 1))
      .arg(w.activeParts())
      .arg(format::number(simulation_->speed(), 2))
      .arg(mode);
}

void MainWindow::updateStatus() { status_->setText(statusText()); }

}  // namespace vaw::ui
