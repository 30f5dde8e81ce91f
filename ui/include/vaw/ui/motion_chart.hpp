#pragma once
// "Motion": the selected part's energy (kinetic plus m g z) and speed over the recording, with the
// timeline's playhead. Samples are taken as the simulation runs; when the selection or the world changes,
// the recording is replayed headless once (vaw::sim::Recorder over the session) to fill in the past, and a
// recorded future that is discarded leaves the chart with it. An energy that grows on a part nobody holds
// is the picture of an unstable method.
#include <QDockWidget>
#include <map>
#include <optional>
#include <utility>

#include "vaw/assembly.hpp"

class QChart;
class QChartView;
class QLineSeries;
class QValueAxis;
class QLabel;

namespace vaw::sim {
class World;
}

namespace vaw::ui {

class SimulationController;

class MotionChartDock : public QDockWidget {
  Q_OBJECT
 public:
  explicit MotionChartDock(QWidget* parent = nullptr);
  // Follows the controller: samples the step shown now (cheap: after every published frame) and, with
  // `redraw`, draws (at the panels' rate). A new world or selection is replayed to fill in its past.
  void follow(const SimulationController& simulation, bool newWorld, bool redraw = true);

  struct Sample {
    double t = 0.0;
    double energy = 0.0;  // J
    double speed = 0.0;   // m/s, of the centre of mass
  };
  // At most about kMaxSamples (a chart is a few hundred pixels wide): when the recording outgrows them, every
  // other one goes and the spacing doubles, so an hour's session costs what a minute's does. The step shown
  // now is drawn as well (the line ends at the playhead) without being kept.
  static constexpr std::size_t kMaxSamples = 4096;
  [[nodiscard]] const std::map<std::uint64_t, Sample>& samples() const { return samples_; }
  [[nodiscard]] std::uint64_t spacing() const { return spacing_; }
  [[nodiscard]] static Sample sample(const vaw::sim::World& world, vaw::PartId part);

 private:
  void refill(const SimulationController& simulation);
  void keep(std::uint64_t step, const Sample& sample);
  void redraw(double now);

  QChartView* view_ = nullptr;
  QLineSeries *energy_ = nullptr, *speed_ = nullptr, *playhead_ = nullptr;
  QValueAxis *time_ = nullptr, *energyAxis_ = nullptr, *speedAxis_ = nullptr;
  std::optional<vaw::PartId> part_;
  std::map<std::uint64_t, Sample> samples_;  // by step, about spacing_ steps apart
  std::uint64_t spacing_ = 1;
  std::optional<std::pair<std::uint64_t, Sample>> shown_;  // the step shown now
  bool dirty_ = false;
};

}  // namespace vaw::ui
