#pragma once
// "Interferences": what overlaps in a CAD assembly at rest, as a CAD system's interference check shows it
// (vaw::collision::interferences, docs/evaluation.md "Interferences"): a row per pair of parts that share
// volume, clashes first in red (a modelling error), then the threads modelled at their tap drill and the
// press fits, which are fits; the pairs that only touch are counted. Checked on a worker thread whenever a
// CAD assembly is opened (a second on a thousand parts). A row selected selects its second part and draws
// where the two overlap on the first (the base, where there is one): a line through the overlap's middle
// along the fit's axis, or for a clash along the way it is thinnest.
#include <QAbstractTableModel>
#include <QDockWidget>
#include <QFutureWatcher>
#include <atomic>
#include <memory>
#include <optional>
#include <vector>

#include "vaw/collision/interference.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/ui/viewport.hpp"

class QLabel;
class QTableView;

namespace vaw::ui {

class AssemblyController;

class InterferenceModel : public QAbstractTableModel {
  Q_OBJECT
 public:
  enum Column { KindColumn, FirstColumn, SecondColumn, VolumeColumn, DepthColumn, ColumnCount };

  explicit InterferenceModel(QObject* parent = nullptr);
  // The overlaps but the contacts, clashes first (as vaw::collision::interferences orders them).
  void setInterferences(const vaw::Assembly* assembly, std::vector<vaw::collision::Interference> found);
  [[nodiscard]] const vaw::collision::Interference* at(int row) const;

  [[nodiscard]] int rowCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] int columnCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
  [[nodiscard]] QVariant headerData(int section, Qt::Orientation orientation, int role = Qt::DisplayRole) const override;

 private:
  std::vector<vaw::collision::Interference> rows_;
  std::vector<QString> first_, second_;
};

class InterferenceDock : public QDockWidget {
  Q_OBJECT
 public:
  explicit InterferenceDock(AssemblyController& controller, QWidget* parent = nullptr);
  ~InterferenceDock() override;
  InterferenceDock(const InterferenceDock&) = delete;
  InterferenceDock& operator=(const InterferenceDock&) = delete;

  [[nodiscard]] InterferenceModel* model() const { return model_; }
  [[nodiscard]] QTableView* view() const { return view_; }
  // How many of each kind, or what is being checked.
  [[nodiscard]] QLabel* hint() const { return hint_; }
  [[nodiscard]] bool checking() const { return checking_; }

 signals:
  void partSelected(std::optional<vaw::PartId> part);
  // Where the selected row's two parts overlap, on its first part; hidden when nothing is selected.
  void showWhere(const vaw::ui::Viewport::ConstraintGeometry& geometry);
  void hideWhere();

 private:
  struct Outcome {
    std::shared_ptr<const vaw::sim::Scene> scene;
    std::vector<vaw::collision::Interference> found;
    QString error;
    bool cancelled = false;
  };
  void assemblyLoaded();
  void finished();
  void rowSelected();

  AssemblyController& controller_;
  InterferenceModel* model_ = nullptr;
  QTableView* view_ = nullptr;
  QLabel* hint_ = nullptr;
  QFutureWatcher<Outcome> watcher_;
  std::shared_ptr<std::atomic<bool>> cancel_;
  std::shared_ptr<const vaw::sim::Scene> shown_;
  bool checking_ = false;
};

}  // namespace vaw::ui
