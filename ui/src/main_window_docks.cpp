// Each dock's wiring to the controllers and the window, beside the handlers that serve that dock alone (the
// tuning panels' is in main_window_tuning.cpp), and the headset's notes.
#include "vaw/ui/main_window.hpp"

#include <QAction>
#include <QFileDialog>
#include <QKeySequence>
#include <QLabel>
#include <QMenu>
#include <QSaveFile>
#include <QStatusBar>
#include <algorithm>
#include <utility>

#include "vaw/cad_assembly.hpp"
#include "vaw/constraint_recognition.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/constraints_dock.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/interference_dock.hpp"
#include "vaw/ui/part_properties_model.hpp"
#include "vaw/ui/message_log_model.hpp"
#include "vaw/ui/motion_chart.hpp"
#include "vaw/ui/path_dock.hpp"
#include "vaw/ui/sequence_dock.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/timeline.hpp"
#include "vaw/ui/trials_panel.hpp"
#include "vaw/ui/tuning.hpp"
#include "vaw/ui/viewport.hpp"
#include "vaw/ui/xr_controller.hpp"

namespace vaw::ui {

void MainWindow::wireViewport() {
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
}

void MainWindow::showSelection(std::optional<vaw::PartId> part) {
  const vaw::Assembly* assembly = controller_.assembly();
  simulation_->setSelected(part);
  partDock_->showPart(assembly, part, controller_.collisionInfo());
  showSwept();
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

void MainWindow::wirePart() {
  connect(partDock_, &PartDock::axesToggled, this, [this](bool shown) {
    axesShown_ = shown;
    showSelection(viewport_->selectedPart());
    viewport_->applyFrame(simulation_->frame());
  });
}

void MainWindow::wireControls() {
  connect(controlsDock_, &ControlsDock::baseTargetChanged, this,
          [this](const BaseAngles& target) { simulation_->setBaseTarget(target); });
  connect(controlsDock_, &ControlsDock::hoistEngagedChanged, simulation_, &SimulationController::setHoistEngaged);
  connect(controlsDock_, &ControlsDock::hoistHeightChanged, simulation_, &SimulationController::setHoistHeight);
  connect(controlsDock_, &ControlsDock::hoistYawChanged, simulation_, &SimulationController::setHoistYaw);
}

void MainWindow::wireMotion() {
  // Hidden, the motion chart does not sample: shown again, it replays what it missed.
  connect(motionDock_, &QDockWidget::visibilityChanged, this, [this](bool visible) {
    if (!visible) return;
    motionStale_ = true;
    updateLive();
  });
}

void MainWindow::wireTimeline() {
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
}

void MainWindow::logChanged() {
  if (!simulation_->hasWorld()) return;
  const vaw::sim::Recorder& r = simulation_->recorder();
  timelineDock_->model()->setLog(&r.scene().assembly(), r.transitions(), r.refusals(),
                                 blinded_ ? std::vector<vaw::sim::EditRecord>{} : r.edits());
  timelineDock_->view()->setTimes(r.world().time(), r.endTime(), !r.atEnd(), simulation_->isPlayback());
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

void MainWindow::wireTrials() {
  // Queued: the headset reports hands inside a step, and an answer resets the world for the next trial.
  connect(xr_, &XrController::handClosed, trialsDock_, &TrialsDock::headsetAnswer, Qt::QueuedConnection);
  // Declining to drop unsaved tuning for the scenario's scene stops the session before its first trial.
  connect(trialsDock_, &TrialsDock::openSceneRequested, this, [this](const QString& path) {
    if (maybeSave()) controller_.open(path);
    else trialsDock_->stop();
  });
  connect(trialsDock_, &TrialsDock::blindingChanged, this, &MainWindow::setBlinded);
  connect(trialsDock_, &TrialsDock::viewRequested, viewport_, &Viewport::lookAt);
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

void MainWindow::wireConstraints() {
  // Re-basing reopens what File > Save writes (the CAD scene), or the CAD file itself.
  connect(constraintsDock_, &ConstraintsDock::baseRequested, this, [this](const QString& part) {
    if (maybeSave()) controller_.openWithBase(scenePath_.isEmpty() ? controller_.currentPath() : scenePath_, part.toStdString());
  });
  connect(constraintsDock_, &ConstraintsDock::upRequested, this, [this](const QString& up) {
    if (maybeSave()) controller_.openWithUp(scenePath_.isEmpty() ? controller_.currentPath() : scenePath_, up.toStdString());
  });
  connect(constraintsDock_, &ConstraintsDock::unitRequested, this, [this](const QString& name, bool asOne) {
    if (maybeSave()) controller_.openWithUnit(scenePath_.isEmpty() ? controller_.currentPath() : scenePath_, name.toStdString(), asOne);
  });
  connect(viewport_, &Viewport::contextMenuRequested, this, &MainWindow::showViewportMenu);
}

void MainWindow::showViewportMenu(const QPoint& windowPos) {
  const vaw::Assembly* a = controller_.assembly();
  const auto pick = viewport_->pick(windowPos);
  if (a == nullptr || !pick || pick->part >= a->parts.size()) return;
  auto* menu = new QMenu(this);
  menu->setObjectName(QStringLiteral("viewportMenu"));
  menu->setAttribute(Qt::WA_DeleteOnClose);
  menu->setToolTipsVisible(true);
  QAction* down = menu->addAction(tr("Put This Face Down"));
  down->setObjectName(QStringLiteral("faceDownAction"));
  // The face under the click, in the part's own frame (where it is drawn now: tilted, or waiting).
  const vaw::Part& p = a->parts[pick->part];
  std::optional<std::string> up;
  QString why;
  if (a->cadFile.empty()) {
    why = tr("Only a CAD assembly (STEP) can be turned to stand another way: a scene file places its base itself");
  } else if (a->base != pick->part) {
    why = tr("The assembly stands on its base, %1: right-click a face of it").arg(QString::fromStdString(a->parts[*a->base].name));
  } else if (const auto pose = viewport_->partPose(pick->part); p.cad && pose) {
    Eigen::AlignedBox3d bounds;
    for (const auto& v : p.cad->mesh.vertices) bounds.extend(v);
    const auto face = vaw::faceAt(*p.cad, pose->inverse() * pick->point, 0.01 * bounds.diagonal().norm());
    if (!face || p.cad->faces[*face].surface != vaw::CadFace::Surface::Plane)
      why = tr("Only a flat face can rest on the table: right-click a flat face of %1").arg(QString::fromStdString(p.name));
    else
      up = vaw::upForFaceDown(*a, p.cad->faces[*face].direction);
  }
  if (up) {
    why = tr("Reopen the assembly standing on this face; the constraints keep their parts");
    const std::string choice = *up;
    connect(down, &QAction::triggered, this, [this, choice] {
      if (maybeSave()) controller_.openWithUp(scenePath_.isEmpty() ? controller_.currentPath() : scenePath_, choice);
    });
  } else {
    down->setEnabled(false);
  }
  down->setToolTip(why);
  down->setStatusTip(why);
  menu->popup(viewport_->windowToGlobal(windowPos));
}

void MainWindow::showSwept() {
  const auto shown = partDock_->model()->part();
  const vaw::SweptVolume* sv = pathDock_->swept();
  if (sv == nullptr || !shown || pathDock_->resultPart() != shown) {
    partDock_->model()->setSwept({});
    return;
  }
  partDock_->model()->setSwept(tr("%1 cm³, voxel %2 mm%3").arg(1e6 * sv->volume, 0, 'f', 1).arg(1e3 * sv->voxel, 0, 'g', 3)
                                   .arg(sv->relativeToBase ? tr(", on the base") : QString()),
                               tr("The volume its carried path swept from %1 to %2 s (View > Path)").arg(sv->from, 0, 'f', 2).arg(sv->to, 0, 'f', 2));
}

void MainWindow::wirePath() {
  connect(viewport_, &Viewport::partSelected, pathDock_, &PathDock::setPart);
  connect(pathDock_, &PathDock::finishedSweep, this, &MainWindow::showSwept);
  connect(pathDock_, &PathDock::cleared, this, &MainWindow::showSwept);
  connect(simulation_, &SimulationController::started, pathDock_, &PathDock::clear);
  connect(pathDock_, &PathDock::statusMessage, this, [this](const QString& text) { statusBar()->showMessage(text, 15000); });
}

void MainWindow::wireSequence() {
  connect(&reportWatcher_, &QFutureWatcher<ReportOutcome>::finished, this, &MainWindow::reportFinished);
  // A row selects its part as the scene tree does: through the viewport, whose selection every view follows.
  connect(interferenceDock_, &InterferenceDock::partSelected, viewport_, &Viewport::selectPart);
  connect(interferenceDock_, &InterferenceDock::showWhere, viewport_, &Viewport::showConstraintGeometry);
  connect(interferenceDock_, &InterferenceDock::hideWhere, viewport_, &Viewport::hideConstraintGeometry);
  connect(sequenceDock_, &SequenceDock::partSelected, viewport_, &Viewport::selectPart);
  connect(viewport_, &Viewport::partSelected, sequenceDock_, &SequenceDock::selectPart);
  connect(sequenceDock_, &SequenceDock::statusMessage, this,
          [this](const QString& text) { statusBar()->showMessage(text, 15000); });
  // File > Export Report before Find Order: the report waits for the order.
  connect(sequenceDock_, &SequenceDock::orderFound, this, [this] {
    if (!pendingReport_.isEmpty()) writeReport(std::exchange(pendingReport_, QString()));
  });
  const auto notWritten = [this](const QString& why) {
    if (pendingReport_.isEmpty()) return;
    const QString text = tr("No report written to %1: %2").arg(std::exchange(pendingReport_, QString()), why);
    message(static_cast<int>(MessageLogModel::Severity::Error), text);
    statusBar()->showMessage(text, 15000);
  };
  connect(sequenceDock_, &SequenceDock::orderFailed, this, notWritten);
  // A report asked for while an outdated search still ran waits for a search of the scene loaded now, not
  // for whichever search ends next.
  connect(sequenceDock_, &SequenceDock::searchOutdated, this, [this] {
    if (!pendingReport_.isEmpty() && !sequenceDock_->finding()) sequenceDock_->findOrder();
  });
  connect(&controller_, &AssemblyController::assemblyLoaded, this,
          [notWritten] { notWritten(tr("the assembly was opened again or changed")); });
}

void MainWindow::wireXr() {
  connect(xr_, &XrController::failed, this, [this](vaw::xr::Failure, const QString& text) {
    message(static_cast<int>(MessageLogModel::Severity::Error), text);
    statusBar()->showMessage(text, 15000);
  });
  connect(xr_, &XrController::notice, this, [this](const QString& text, bool warning) {
    message(static_cast<int>(warning ? MessageLogModel::Severity::Warning : MessageLogModel::Severity::Info), text);
  });
}

}  // namespace vaw::ui
