#pragma once
// "Sequence": the order that puts the loaded assembly together, found from its geometry
// (vaw::eval::planSequence, docs/evaluation.md). Find Order runs on a worker thread: sweeping every part's
// ways home through a CAD assembly takes seconds, which the window must not freeze for. The table lists
// the order (each part's step, the way it comes home and the parts it must follow, and why), then in red
// the parts no order inserts with what blocks each way home. A row selected selects its part in the
// window; a part no order inserts also names its blockers in the status bar (the viewport highlights
// one part at a time). After the order, each way home is walked past the parts already in
// (vaw::eval::wayClearances): the Clearance column names the nearest part each passes and how close,
// orange for a near miss. A plan belongs to the scene it was found on: another scene clears it.
#include <QAbstractTableModel>
#include <QDockWidget>
#include <QFutureWatcher>
#include <QString>
#include <atomic>
#include <memory>
#include <optional>
#include <vector>

#include "vaw/evaluation/sequence.hpp"
#include "vaw/evaluation/way_clearance.hpp"
#include "vaw/sim/scene.hpp"

class QLabel;
class QProgressBar;
class QPushButton;
class QTableView;

namespace vaw::ui {

class AssemblyController;

class SequenceModel : public QAbstractTableModel {
  Q_OBJECT
 public:
  enum Column { PositionColumn, StepColumn, PartColumn, HomeColumn, ClearanceColumn, AfterColumn, ColumnCount };

  explicit SequenceModel(QObject* parent = nullptr);
  // The order first, then the parts no order inserts; empty without a plan. Ways home are worded by
  // vaw::eval::travelText, as in the report.
  void setPlan(const vaw::Assembly* assembly, const vaw::eval::SequencePlan* plan);
  // Each way home's nearest pass, for the rows of the plan set; `threshold` (m) marks near misses.
  void setWays(const vaw::Assembly& assembly, const std::vector<vaw::eval::WayClearance>& ways, double threshold);
  [[nodiscard]] bool isNearMiss(int row) const;
  [[nodiscard]] std::optional<vaw::PartId> partAt(int row) const;
  [[nodiscard]] int rowOf(vaw::PartId part) const;
  [[nodiscard]] bool isStuck(int row) const;
  // For a part no order inserts: what blocks it, per way home ("insert on stud-1: nut-1, nut-2; ...").
  [[nodiscard]] QString blockersText(int row) const;

  [[nodiscard]] int rowCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] int columnCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
  [[nodiscard]] QVariant headerData(int section, Qt::Orientation orientation, int role = Qt::DisplayRole) const override;

 private:
  struct Row {
    vaw::PartId part = 0;
    bool stuck = false, nearMiss = false;
    QString position, step, name, home, after, blockers, clearance, clearanceTip;
  };
  std::vector<Row> rows_;
};

class SequenceDock : public QDockWidget {
  Q_OBJECT
 public:
  explicit SequenceDock(AssemblyController& controller, QWidget* parent = nullptr);
  ~SequenceDock() override;
  SequenceDock(const SequenceDock&) = delete;
  SequenceDock& operator=(const SequenceDock&) = delete;

  [[nodiscard]] SequenceModel* model() const { return model_; }
  [[nodiscard]] QTableView* view() const { return view_; }
  [[nodiscard]] QPushButton* findButton() const { return find_; }
  [[nodiscard]] QProgressBar* progressBar() const { return progress_; }
  // The plan's summary, the search's stage, or why no order was found.
  [[nodiscard]] QLabel* hint() const { return hint_; }
  // From Find Order until its outcome is shown.
  [[nodiscard]] bool finding() const { return finding_; }
  // The plan found for the loaded scene, or null.
  [[nodiscard]] const vaw::eval::SequencePlan* plan() const { return plan_ ? &*plan_ : nullptr; }
  // Each way home of plan()'s order walked past the parts already in (no swept volumes); empty without a plan.
  [[nodiscard]] const std::vector<vaw::eval::WayClearance>& ways() const { return ways_; }
  [[nodiscard]] const vaw::eval::WayClearanceOptions& wayOptions() const { return wayOptions_; }

 public slots:
  // Starts the search on the loaded scene; while one runs, stops it.
  void findOrder();
  // Shows `part`'s row as selected (nothing: clears). Does not emit partSelected.
  void selectPart(std::optional<vaw::PartId> part);

 signals:
  void partSelected(std::optional<vaw::PartId> part);
  // A search ended: plan() is the new plan, or null with `why` (an assembly without a base, cancelled).
  void orderFound();
  void orderFailed(const QString& why);
  // A search ended on a scene that was replaced while it ran: its result was dropped.
  void searchOutdated();
  void statusMessage(const QString& text);

 private:
  struct Outcome {
    std::shared_ptr<const vaw::sim::Scene> scene;
    std::optional<vaw::eval::SequencePlan> plan;
    std::vector<vaw::eval::WayClearance> ways;
    QString error;
    bool cancelled = false;
  };
  void assemblyLoaded();
  void finished();
  void rowSelected();
  void showIdle();

  AssemblyController& controller_;
  SequenceModel* model_ = nullptr;
  QTableView* view_ = nullptr;
  QPushButton* find_ = nullptr;
  QProgressBar* progress_ = nullptr;
  QLabel* hint_ = nullptr;
  std::optional<vaw::eval::SequencePlan> plan_;
  std::vector<vaw::eval::WayClearance> ways_;
  vaw::eval::WayClearanceOptions wayOptions_;
  std::shared_ptr<std::atomic<bool>> cancel_;
  QFutureWatcher<Outcome> watcher_;
  bool finding_ = false;
  bool updating_ = false;
};

}  // namespace vaw::ui
