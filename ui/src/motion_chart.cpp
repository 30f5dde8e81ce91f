#include "vaw/ui/motion_chart.hpp"

#include <QtCharts/QChart>
#include <QtCharts/QChartView>
#include <QtCharts/QLineSeries>
#include <QtCharts/QValueAxis>
#include <algorithm>
#include <iterator>
#include <limits>

#include "vaw/sim/recorder.hpp"
#include "vaw/sim/report.hpp"
#include "vaw/ui/simulation_controller.hpp"

namespace vaw::ui {

MotionChartDock::MotionChartDock(QWidget* parent) : QDockWidget(tr("Motion"), parent) {
  setObjectName(QStringLiteral("motionDock"));
  auto* chart = new QChart();
  chart->setObjectName(QStringLiteral("motionChart"));
  energy_ = new QLineSeries(chart);
  energy_->setName(tr("kinetic + m g z (J, left)"));
  speed_ = new QLineSeries(chart);
  speed_->setName(tr("speed (m/s, right)"));
  playhead_ = new QLineSeries(chart);
  playhead_->setName(tr("playhead (s, below)"));
  playhead_->setPen(QPen(QColor(200, 30, 30), 1.5));
  chart->addSeries(energy_);
  chart->addSeries(speed_);
  chart->addSeries(playhead_);
  time_ = new QValueAxis(chart);
  time_->setTitleText(tr("t (s)"));
  energyAxis_ = new QValueAxis(chart);
  energyAxis_->setTitleText(tr("kinetic + m g z (J)"));
  speedAxis_ = new QValueAxis(chart);
  speedAxis_->setTitleText(tr("speed (m/s)"));
  // A dock is short: the legend names the quantities and units, the axes carry small labels only.
  QFont small = time_->labelsFont();
  small.setPointSizeF(7.0);
  for (QValueAxis* a : {time_, energyAxis_, speedAxis_}) {
    a->setTitleVisible(false);
    a->setLabelsFont(small);
    a->setTickCount(5);
  }
  chart->addAxis(time_, Qt::AlignBottom);
  chart->addAxis(energyAxis_, Qt::AlignLeft);
  chart->addAxis(speedAxis_, Qt::AlignRight);
  for (QLineSeries* s : {energy_, playhead_}) {
    s->attachAxis(time_);
    s->attachAxis(energyAxis_);
  }
  speed_->attachAxis(time_);
  speed_->attachAxis(speedAxis_);
  chart->setTitle(tr("Select a part to chart its energy and speed"));
  chart->legend()->setAlignment(Qt::AlignBottom);
  chart->setMargins(QMargins(2, 2, 2, 2));
  view_ = new QChartView(chart, this);
  view_->setRenderHint(QPainter::Antialiasing);
  view_->setMinimumHeight(160);
  setWidget(view_);
}

MotionChartDock::Sample MotionChartDock::sample(const vaw::sim::World& world, vaw::PartId id) {
  const vaw::sim::PartRuntime& r = world.part(id);
  const auto e = vaw::sim::energy(world.assembly().parts[id], r.pose, r.velocity, r.angularVelocity);
  return {world.time(), e.kinetic + e.potential, r.velocity.norm()};
}

void MotionChartDock::keep(std::uint64_t step, const Sample& x) {
  // Kept only where no kept sample is within the spacing (a look back at the past finds its steps there).
  const auto next = samples_.lower_bound(step);
  if (next != samples_.end() && next->first - step < spacing_) return;
  if (next != samples_.begin() && step - std::prev(next)->first < spacing_) return;
  samples_.emplace_hint(next, step, x);
  if (samples_.size() <= kMaxSamples) return;
  spacing_ *= 2;
  bool odd = false;
  for (auto it = std::next(samples_.begin()); it != samples_.end();) {
    const bool last = std::next(it) == samples_.end();
    it = (odd = !odd) && !last ? samples_.erase(it) : std::next(it);
  }
}

void MotionChartDock::refill(const SimulationController& simulation) {
  samples_.clear();
  shown_.reset();
  if (!part_) return;
  // The recording so far, replayed headless: the same inputs and edits give the same states.
  const vaw::sim::Recorder& live = simulation.recorder();
  vaw::sim::Recorder replay(live.scenePtr(), live.session());
  spacing_ = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(replay.world().settings().rate / 90.0));
  keep(0, sample(replay.world(), *part_));
  while (replay.playNext())
    if (replay.step() % spacing_ == 0) keep(replay.step(), sample(replay.world(), *part_));
  shown_.emplace(replay.step(), sample(replay.world(), *part_));
}

void MotionChartDock::follow(const SimulationController& simulation, bool newWorld, bool redraw) {
  if (!simulation.hasWorld()) return;
  const auto selected = simulation.selected();
  const vaw::sim::World& w = simulation.world();
  const std::uint64_t now = w.stepCount();
  if (newWorld || selected != part_) {
    part_ = selected;
    refill(simulation);
    view_->chart()->setTitle(part_ ? tr("%1: energy and speed").arg(QString::fromStdString(w.assembly().parts[*part_].name))
                                   : tr("Select a part to chart its energy and speed"));
  } else if (part_) {
    // A discarded future leaves the chart too; the step shown now is sampled (live, or a look at the past).
    const std::uint64_t length = simulation.recorder().length();
    samples_.erase(samples_.upper_bound(length), samples_.end());
    shown_.emplace(now, sample(w, *part_));
    keep(now, shown_->second);
  }
  if (redraw) this->redraw(w.time());
}

void MotionChartDock::redraw(double now) {
  QList<QPointF> e, s;
  e.reserve(static_cast<qsizetype>(samples_.size()));
  s.reserve(static_cast<qsizetype>(samples_.size()));
  double eMin = std::numeric_limits<double>::infinity(), eMax = -eMin, sMax = 0.0, tMax = 1.0;
  const auto add = [&](const Sample& x) {
    e.append(QPointF(x.t, x.energy));
    s.append(QPointF(x.t, x.speed));
    eMin = std::min(eMin, x.energy);
    eMax = std::max(eMax, x.energy);
    sMax = std::max(sMax, x.speed);
    tMax = std::max(tMax, x.t);
  };
  // The step shown now in its place among the kept ones, unless it is one of them.
  const auto shownAt = shown_ ? samples_.lower_bound(shown_->first) : samples_.end();
  const bool drawShown = shown_ && (shownAt == samples_.end() || shownAt->first != shown_->first);
  for (auto it = samples_.begin();; ++it) {
    if (drawShown && it == shownAt) add(shown_->second);
    if (it == samples_.end()) break;
    add(it->second);
  }
  energy_->replace(e);
  speed_->replace(s);
  if (samples_.empty()) eMin = 0.0, eMax = 1.0;
  const double pad = std::max(1e-6, 0.05 * (eMax - eMin));
  energyAxis_->setRange(eMin - pad, eMax + pad);
  speedAxis_->setRange(0.0, std::max(1e-3, 1.05 * sMax));
  time_->setRange(0.0, tMax);
  playhead_->replace(QList<QPointF>{QPointF(now, eMin - pad), QPointF(now, eMax + pad)});
}

}  // namespace vaw::ui
