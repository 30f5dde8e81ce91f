// The status bar: the stability warning, the capture hint and the permanent time, step cost, speed and mode.
#include "vaw/ui/main_window.hpp"

#include <QLabel>
#include <QStatusBar>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "format.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/viewport.hpp"
#include "vaw/units.hpp"

namespace vaw::ui {

void MainWindow::createStatusBar() {
  status_ = new QLabel(this);
  status_->setObjectName(QStringLiteral("simulationStatus"));
  stabilityStatus_ = new QLabel(this);
  stabilityStatus_->setObjectName(QStringLiteral("stabilityStatus"));
  stabilityStatus_->setStyleSheet(QStringLiteral("color: rgb(180, 40, 20); font-weight: bold;"));
  stabilityStatus_->hide();
  statusBar()->addPermanentWidget(stabilityStatus_);
  statusBar()->addPermanentWidget(status_);
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

QString MainWindow::stabilityWarning() const { return stabilityStatus_->isVisible() ? stabilityStatus_->text() : QString(); }

void MainWindow::updateCapture() {
  const QString before = captureText_;
  captureText_.clear();
  std::optional<Viewport::CaptureZone> zone;
  const vaw::sim::World& w = simulation_->world();
  const auto held = w.held(1);
  const auto hint = held ? w.captureHint(*held) : std::nullopt;
  const vaw::sim::Settings& st = w.settings();
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

}  // namespace vaw::ui
