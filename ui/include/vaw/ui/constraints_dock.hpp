#pragma once
// "Constraints": the assembly's constraints (found in a CAD assembly's geometry, or written in a scene) as a
// table the user reviews: accept, reject, swap part and partner. Every change is a QUndoCommand holding the
// whole list before and after, applied by giving AssemblyController a new scene (setConstraints), so
// Ctrl+Z, the window's unsaved mark and File > Save all work on it. The selected row's geometry is drawn in
// the viewport on its partner. "Add from faces" makes a constraint from a face picked in the viewport on each
// of two parts. Below, the near misses of a CAD assembly (faces that look like a fit and were not taken, with
// the test that refused each and its measure), found in the background. The dock also gives the scene tree
// its "Make this the base" menu.
#include <QAbstractTableModel>
#include <QDockWidget>
#include <QFutureWatcher>
#include <QStringList>
#include <QUndoCommand>
#include <functional>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/constraint_recognition.hpp"
#include "vaw/sim/scene.hpp"

class QLabel;
class QMenu;
class QPushButton;
class QShortcut;
class QStandardItemModel;
class QTableView;
class QUndoStack;

namespace vaw::ui {

class AssemblyController;
class SceneDock;
class SimulationController;
class Viewport;

// The constraint with its part and partner exchanged: the partner's geometry becomes the part's and the
// other way round (each stays in its own part's frame), and the direction the new part comes home from is
// the old one reversed, turned from the old partner's frame into the new one's at the assembled poses.
// Needs a partner part (the base cannot become the constrained part).
vaw::Constraint swapped(const vaw::Constraint& c, const vaw::Assembly& assembly);

class ConstraintsModel : public QAbstractTableModel {
  Q_OBJECT
 public:
  enum Column {
    PartColumn,
    PartnerColumn,
    KindColumn,
    FitColumn,
    GeometryColumn,
    ClearanceColumn,
    OverlapColumn,
    StatusColumn,
    ColumnCount
  };

  explicit ConstraintsModel(QObject* parent = nullptr);
  // Holds the scene (shared) until the next call; null: empty.
  void setScene(std::shared_ptr<const vaw::sim::Scene> scene);
  [[nodiscard]] const vaw::Assembly* assembly() const { return scene_ ? &scene_->assembly() : nullptr; }
  [[nodiscard]] std::vector<vaw::Constraint> constraints() const;

  [[nodiscard]] int rowCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] int columnCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
  [[nodiscard]] QVariant headerData(int section, Qt::Orientation orientation, int role = Qt::DisplayRole) const override;

 private:
  std::shared_ptr<const vaw::sim::Scene> scene_;
};

// One change of the constraint list; redo and undo hand the list to the controller.
class ConstraintsCommand : public QUndoCommand {
 public:
  using Apply = std::function<void(const std::vector<vaw::Constraint>&)>;
  ConstraintsCommand(Apply apply, std::vector<vaw::Constraint> before, std::vector<vaw::Constraint> after, const QString& text);
  void redo() override { apply_(after_); }
  void undo() override { apply_(before_); }

 private:
  Apply apply_;
  std::vector<vaw::Constraint> before_, after_;
};

class ConstraintsDock : public QDockWidget {
  Q_OBJECT
 public:
  ConstraintsDock(AssemblyController& controller, SimulationController& simulation, Viewport& viewport, QUndoStack& undoStack,
                  QWidget* parent = nullptr);
  ~ConstraintsDock() override;
  ConstraintsDock(const ConstraintsDock&) = delete;
  ConstraintsDock& operator=(const ConstraintsDock&) = delete;
  [[nodiscard]] ConstraintsModel* model() const { return model_; }
  [[nodiscard]] QTableView* view() const { return view_; }
  [[nodiscard]] QPushButton* acceptButton() const { return accept_; }
  [[nodiscard]] QPushButton* rejectButton() const { return reject_; }
  [[nodiscard]] QPushButton* swapButton() const { return swap_; }
  [[nodiscard]] QPushButton* addFromFacesButton() const { return addFromFaces_; }
  // What the panel says about picking faces, and what a refused edit was refused for.
  [[nodiscard]] QLabel* hint() const { return hint_; }
  [[nodiscard]] bool pickingFaces() const { return picking_; }
  // The near misses: a row each (parts, kind, why), and whether they are still being looked for.
  [[nodiscard]] QTableView* nearMissView() const { return nearView_; }
  [[nodiscard]] QStandardItemModel* nearMissModel() const { return near_; }
  [[nodiscard]] bool findingNearMisses() const { return nearWatcher_.isRunning(); }
  [[nodiscard]] QLabel* nearMissTitle() const { return nearTitle_; }

  // Gives the scene tree a context menu with "Make this the base" on a part.
  void attachBaseMenu(SceneDock* scene);
  // That menu for `part`, as the tree shows it (its parent takes it).
  [[nodiscard]] QMenu* baseMenu(vaw::PartId part, QWidget* parent);

 signals:
  // The user asked to reopen the CAD assembly with `part` as its base.
  void baseRequested(const QString& part);
  // The user chose which way the CAD assembly stands: "auto" or a file axis ("+y", ...).
  void upRequested(const QString& up);
  // A bought-in unit taken apart ("Handle as parts"), or a sub-assembly joined as one unit ("Handle as one
  // unit"), by its name in the file: the assembly reopened so.
  void unitRequested(const QString& name, bool asOne);

 private:
  void assemblyLoaded();
  void selectionChanged();
  void showGeometry();
  void updateButtons();
  [[nodiscard]] std::vector<int> selectedRows() const;
  void change(std::vector<vaw::Constraint> after, const QString& text);
  void apply(const std::vector<vaw::Constraint>& constraints);
  void acceptSelected();
  void rejectSelected();
  void swapSelected();
  void startPicking();
  void stopPicking(const QString& message = {});
  void facePicked(vaw::PartId part, const Eigen::Vector3d& at);
  void addFromFaces(vaw::PartId partA, std::size_t faceA, vaw::PartId partB, std::size_t faceB);
  void tell(const QString& message);
  void showNearMisses();

  AssemblyController& controller_;
  SimulationController& simulation_;
  Viewport& viewport_;
  QUndoStack& undoStack_;
  ConstraintsModel* model_ = nullptr;
  QTableView* view_ = nullptr;
  QPushButton* accept_ = nullptr;
  QPushButton* reject_ = nullptr;
  QPushButton* swap_ = nullptr;
  QPushButton* addFromFaces_ = nullptr;
  QShortcut* cancelPicking_ = nullptr;
  QLabel* hint_ = nullptr;
  QLabel* nearTitle_ = nullptr;
  QTableView* nearView_ = nullptr;
  QStandardItemModel* near_ = nullptr;
  struct NearMisses {
    QString of;  // nearMissKey of the assembly they were found in
    std::vector<vaw::NearMiss> misses;
    QString error;  // why none could be looked for
  };
  // What near misses depend on (the file's geometry, the base, the parts), not the constraints: an edit in
  // the table does not look for them again.
  [[nodiscard]] static QString nearMissKey(const vaw::Assembly& a);
  QFutureWatcher<NearMisses> nearWatcher_;
  std::optional<NearMisses> nearFound_;  // the last found
  // Kept across the rebuild an edit causes: the names of the rows selected, and the file they belong to.
  QStringList keepSelected_;
  QString keepFrom_;
  // Picking faces: on, and the face picked first (its part and its index in the part's CAD solid).
  bool picking_ = false;
  std::optional<std::pair<vaw::PartId, std::size_t>> firstFace_;
};

}  // namespace vaw::ui
