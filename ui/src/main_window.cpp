// Composition: the docks in their places, each one's wiring, and the layout kept between runs.
#include "vaw/ui/main_window.hpp"

#include <QCloseEvent>
#include <QSettings>
#include <QStatusBar>
#include <QUndoStack>
#include <clocale>
#include <cmath>

#include "vaw/paths.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/constraints_dock.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/interference_dock.hpp"
#include "vaw/ui/load_feedback.hpp"
#include "vaw/ui/message_log_model.hpp"
#include "vaw/ui/motion_chart.hpp"
#include "vaw/ui/path_dock.hpp"
#include "vaw/ui/sequence_dock.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/trials_panel.hpp"
#include "vaw/ui/tuning.hpp"
#include "vaw/ui/viewport.hpp"
#include "vaw/ui/work_precision_dock.hpp"
#include "vaw/ui/xr_controller.hpp"

namespace vaw::ui {

MainWindow::MainWindow(AssemblyController& controller, QWidget* parent)
    : QMainWindow(parent), controller_(controller) {
  // Qt applies the user's locale to the C library on Linux (a decimal comma under de_DE). The core writes
  // and reads its numbers through it (messages, panels' texts, scenes, reports, CSV, the reader's
  // progress), always with a point, as on the command line: the window's process keeps the C library's
  // numbers in C, while Qt's own widgets (QLocale) still show and take the user's.
  std::setlocale(LC_NUMERIC, "C");
  setObjectName(QStringLiteral("mainWindow"));
  setWindowTitle(tr("vaw"));
  setAcceptDrops(true);
  simulation_ = new SimulationController(this);
  viewport_ = new Viewport(this);
  setCentralWidget(viewport_);
  createDocks();
  loadFeedback_ = new LoadFeedback(controller_, this);
  createStatusBar();
  createMenus();
  // VR mode: its own menu and status line; failures and notes land in Messages.
  xr_ = new XrController(*simulation_, viewport_, this);
  xr_->install(menuBar(), statusBar());
  {
    // Where the user left the window and its docks (a closed dock stays closed).
    QSettings settings;
    restoreGeometry(settings.value(QStringLiteral("window/geometry")).toByteArray());
    restoreState(settings.value(QStringLiteral("window/state")).toByteArray());
    // The STEP settings chosen in an earlier run (File > STEP Settings); a value that is not a positive
    // number keeps the default.
    vaw::LoadOptions options = controller_.loadOptions();
    const auto restore = [&settings](const char* key, double& value, double least) {
      bool ok = false;
      const double v = settings.value(QString::fromLatin1(key)).toDouble(&ok);
      if (ok && std::isfinite(v) && v >= least) value = v;
    };
    restore("import/relativeDeflection", options.import.relativeDeflection, 1e-5);
    restore("import/timeoutSeconds", options.import.timeoutSeconds, 1.0);
    restore("import/readerMemoryMB", options.import.readerMemoryMB, 0.0);
    restore("import/maxInstances", options.import.maxInstances, 1.0);
    restore("import/resultCacheMB", options.import.resultCacheMB, 0.0);
    options.import.resultCache = vaw::userCacheDir();
    controller_.setLoadOptions(options);
  }
  liveTimer_.setSingleShot(true);
  connect(&liveTimer_, &QTimer::timeout, this, &MainWindow::updateLive);
  lastLive_.start();

  wireConstraints();
  wireSequence();
  wirePath();
  wireXr();
  wireViewport();
  wireControls();
  wireTuning();
  wireTrials();
  wireMotion();
  wirePart();
  wireSimulation();
  wireTimeline();
  wireLoading();

  for (const QString& text : controller_.pluginMessages()) {
    messagesDock_->model()->add(MessageLogModel::Severity::Warning, text);
  }
  if (!controller_.pluginMessages().isEmpty()) statusBar()->showMessage(controller_.pluginMessages().last());
  updateStatus();
}

void MainWindow::createDocks() {
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
  interferenceDock_ = new InterferenceDock(controller_, this);
  addDockWidget(Qt::BottomDockWidgetArea, interferenceDock_);
  tabifyDockWidget(constraintsDock_, interferenceDock_);
  sequenceDock_ = new SequenceDock(controller_, this);
  addDockWidget(Qt::BottomDockWidgetArea, sequenceDock_);
  tabifyDockWidget(interferenceDock_, sequenceDock_);
  pathDock_ = new PathDock(*simulation_, *viewport_, controller_.importers(), this);
  addDockWidget(Qt::BottomDockWidgetArea, pathDock_);
  tabifyDockWidget(sequenceDock_, pathDock_);
  timelineDock_->raise();
  resizeDocks({sceneDock_, partDock_}, {220, 480}, Qt::Vertical);
  resizeDocks({sceneDock_, controlsDock_}, {380, 330}, Qt::Horizontal);
  resizeDocks({timelineDock_}, {190}, Qt::Vertical);
}

MainWindow::~MainWindow() {
  simulation_->pause();
  // The report's worker posts its progress to this window: it stops before the window goes.
  if (reportCancel_) reportCancel_->store(true);
  reportWatcher_.disconnect(this);
  reportWatcher_.waitForFinished();
}

void MainWindow::message(int severity, const QString& text, const QString& detail) {
  messagesDock_->model()->add(static_cast<MessageLogModel::Severity>(severity), text, detail);
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

}  // namespace vaw::ui
