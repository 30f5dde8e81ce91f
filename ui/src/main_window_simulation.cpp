// What the running simulation publishes, and the live views that follow it at a readable rate.
#include "vaw/ui/main_window.hpp"

#include <QAction>
#include <QStatusBar>
#include <QUndoStack>
#include <optional>

#include "format.hpp"
#include "vaw/sim/report.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/message_log_model.hpp"
#include "vaw/ui/motion_chart.hpp"
#include "vaw/ui/part_properties_model.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/timeline.hpp"
#include "vaw/ui/viewport.hpp"

namespace vaw::ui {

namespace {
constexpr int kLiveIntervalMs = 100;  // inspector, timeline playhead and status while running
}

void MainWindow::wireSimulation() {
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

void MainWindow::frameReady() {
  viewport_->applyFrame(simulation_->frame());
  updateCapture();
  if (motionDock_->isVisible() && !motionStale_) motionDock_->follow(*simulation_, false, false);
  // The panels follow at a readable rate while it runs, at once when it is paused (a seek, a step).
  if (!simulation_->isPlaying() || lastLive_.elapsed() >= kLiveIntervalMs) updateLive();
  else if (!liveTimer_.isActive()) liveTimer_.start(static_cast<int>(kLiveIntervalMs - lastLive_.elapsed()));
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

}  // namespace vaw::ui
