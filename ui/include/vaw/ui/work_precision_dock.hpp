#pragma once
// The work-precision diagram in the window: for the selected part's motion model, each method's error
// against its CPU cost at every step rate, computed on demand in a background thread (with progress and
// cancel), with the method and rate the world uses now highlighted and the Bullet and ODE peers' points
// where they were built. The same measurements as `vaw-sim work-precision` (docs/work-precision.md).
#include <QDockWidget>
#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/dynamics/work_precision.hpp"

class QChart;
class QChartView;
class QComboBox;
class QLabel;
class QProgressBar;
class QPushButton;
class QThread;

namespace vaw::sim {
class World;
}

namespace vaw::ui {

class WorkPrecisionDock : public QDockWidget {
  Q_OBJECT
 public:
  explicit WorkPrecisionDock(QWidget* parent = nullptr);
  ~WorkPrecisionDock() override;

  // The selected part (its motion model picks the scenario when the selection changes) and what the
  // world uses now (the method and rate to highlight).
  void showWorld(const vaw::sim::World& world, std::optional<vaw::PartId> part);
  // Starts the measurement of the chosen scenario (the Compute button); a running one is cancelled.
  void compute();
  void cancel();
  [[nodiscard]] bool busy() const { return thread_ != nullptr; }
  [[nodiscard]] std::string scenario() const;
  [[nodiscard]] const std::vector<vaw::dyn::Record>& records() const { return records_; }
  // The record drawn as "now" (method and rate the world uses), if the measurement holds it.
  [[nodiscard]] std::optional<vaw::dyn::Record> highlighted() const;
  [[nodiscard]] QChart* chart() const;

  // The scenario that shows how a part in this state and model moves, and the method vaw uses there.
  static std::string scenarioFor(const vaw::sim::World& world, vaw::PartId part);
  static std::string methodFor(const std::string& scenario, const vaw::sim::World& world);

 signals:
  void finished();

 private:
  void draw();
  void finish(std::vector<vaw::dyn::Record> records, bool cancelled, const QString& error);
  // Joins and deletes the measuring thread (done, or told to stop) and gives the controls back.
  void endMeasurement(bool complete);

  QComboBox* scenarioBox_ = nullptr;
  QPushButton* computeButton_ = nullptr;
  QPushButton* cancelButton_ = nullptr;
  QProgressBar* progress_ = nullptr;
  QLabel* note_ = nullptr;
  QChartView* view_ = nullptr;
  QThread* thread_ = nullptr;
  std::shared_ptr<std::atomic<bool>> stop_;
  int generation_ = 0;  // of the measurement whose report counts; a cancelled one's is ignored
  std::vector<vaw::dyn::Record> records_;
  std::optional<vaw::PartId> part_;
  std::string followed_;  // the scenario the selected part's model last picked
  std::string method_;  // what the world uses in the charted scenario
  double rate_ = 0.0;
};

}  // namespace vaw::ui
