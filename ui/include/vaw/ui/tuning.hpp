#pragma once
// The tuning panels: gravity scales (with the head-tracking demand calculator), friction per material and
// per part, and the methods and step rate with the stability warning. The panels never change the world:
// they ask for a vaw::sim::Edit (editRequested), which the main window validates, wraps in an EditCommand on
// its undo stack and sends through the simulation controller's queue, so every change takes effect at the
// next step, is recorded in the session and can be undone. They show what the world has (showWorld), so an
// undo, a seek or a played-back session shows in them too.
#include <QAbstractTableModel>
#include <QDockWidget>
#include <QUndoCommand>
#include <map>
#include <optional>
#include <utility>

#include "vaw/sim/edit.hpp"
#include "vaw/sim/report.hpp"
#include "vaw/sim/world.hpp"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QPushButton;
class QSlider;
class QSpinBox;
class QTableView;

namespace vaw::ui {

class SimulationController;

// One tuning change on the undo stack: redo sends `after`, undo sends `before` (both whole values, so the
// order of undos never matters). Consecutive commands with the same non-negative merge key (one spin box
// stepped several times, a slider dragged) merge into one.
class EditCommand : public QUndoCommand {
 public:
  EditCommand(SimulationController& simulation, vaw::sim::Edit before, vaw::sim::Edit after, const QString& text,
               int mergeKey = -1);
  void redo() override;
  void undo() override;
  [[nodiscard]] int id() const override { return mergeKey_; }
  bool mergeWith(const QUndoCommand* other) override;
  [[nodiscard]] const vaw::sim::Edit& after() const { return after_; }

 private:
  SimulationController& simulation_;
  vaw::sim::Edit before_, after_;
  int mergeKey_;
};

// Merge keys of the panels' edits.
enum MergeKey : int { FreeFlightScaleKey = 1, SlideScaleKey, RotationScaleKey, RateKey };

// Friction per material, and the selected part's own override (its last row, checkable), with the friction
// angles each pair implies. Values come from the world; an edited cell becomes an edit request when the new
// set of coefficients keeps the rules (validateFriction), otherwise the cell is marked with the broken rule
// and keeps its value.
class FrictionModel : public QAbstractTableModel {
  Q_OBJECT
 public:
  enum Column { NameColumn, StaticColumn, KineticColumn, RotationalColumn, StaticAngleColumn, KineticAngleColumn, ColumnCount };
  explicit FrictionModel(QObject* parent = nullptr);

  // Rebuilds the rows when the materials or the selected part changed, otherwise updates the values.
  void showWorld(const vaw::sim::World* world, std::optional<vaw::PartId> selected);
  [[nodiscard]] int materialRow(const std::string& material) const;
  [[nodiscard]] int partRow() const;  // -1 without a selected part
  // The rule the cell's last refused value broke; empty when it has none.
  [[nodiscard]] QString problem(int row, int column) const;

  [[nodiscard]] int rowCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] int columnCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] QVariant data(const QModelIndex& index, int role) const override;
  [[nodiscard]] QVariant headerData(int section, Qt::Orientation orientation, int role) const override;
  [[nodiscard]] Qt::ItemFlags flags(const QModelIndex& index) const override;
  bool setData(const QModelIndex& index, const QVariant& value, int role) override;

 signals:
  void editRequested(const vaw::sim::Edit& edit);
  void refused(const QString& rule);

 private:
  struct Row {
    std::string material;            // the material's name, or the part's material for the part row
    std::optional<vaw::PartId> part;  // the part row
    QString name;
    vaw::FrictionValues values;
    bool overridden = false;  // the part row: it has its own friction
  };
  std::vector<Row> rows_;
  std::map<std::pair<int, int>, QString> problems_;
  const vaw::sim::World* world_ = nullptr;
};

// "Gravity": the three scales, each as a factor and in m/s^2, presets, and the head-tracking demand
// calculator (vaw::human::recommendScale) with a button that applies the free-flight scale it recommends.
class GravityDock : public QDockWidget {
  Q_OBJECT
 public:
  explicit GravityDock(QWidget* parent = nullptr);
  void showWorld(const vaw::sim::World& world);
  // While a blinded trials session runs, the scales are hidden and left as they were (the world's are the
  // trial's, which the participant must not see), and nothing here can change them.
  void setBlinded(bool blinded);
  [[nodiscard]] bool isBlinded() const { return blinded_; }

 signals:
  void editRequested(const vaw::sim::Edit& edit, int mergeKey);

 private:
  struct Scale {
    QSlider* slider = nullptr;
    QDoubleSpinBox* factor = nullptr;
    QDoubleSpinBox* metres = nullptr;  // m/s^2
  };
  Scale makeScale(const QString& name, int key, QWidget* parent);
  void request(int key, double factor);
  void updateDemand();

  Scale scales_[3];  // free flight, slide, rotation
  QWidget* scalesBox_ = nullptr;
  QWidget* demandBox_ = nullptr;
  QLabel* blindNote_ = nullptr;
  bool blinded_ = false;
  vaw::dyn::GravityScales shown_;
  QDoubleSpinBox *distance_ = nullptr, *fallHeight_ = nullptr, *pitchLimit_ = nullptr, *accelLimit_ = nullptr;
  QCheckBox* useAccel_ = nullptr;
  QLabel* demand_ = nullptr;
  QPushButton* apply_ = nullptr;
  double recommended_ = 1.0;
};

// "Friction": the table of FrictionModel.
class FrictionDock : public QDockWidget {
  Q_OBJECT
 public:
  explicit FrictionDock(QWidget* parent = nullptr);
  [[nodiscard]] FrictionModel* model() const { return model_; }
  [[nodiscard]] QTableView* view() const { return view_; }
  [[nodiscard]] QLabel* problemLabel() const { return problem_; }

 private:
  FrictionModel* model_ = nullptr;
  QTableView* view_ = nullptr;
  QLabel* problem_ = nullptr;
};

// "Methods": how each motion model is integrated (only what the core offers for it), the step rate, and
// the selected part's stability with the change it suggests.
class MethodsDock : public QDockWidget {
  Q_OBJECT
 public:
  explicit MethodsDock(QWidget* parent = nullptr);
  void showWorld(const vaw::sim::World& world, const std::optional<vaw::sim::StabilityAdvice>& advice,
                 const QString& partName);
  [[nodiscard]] QLabel* stabilityLabel() const { return stability_; }

 signals:
  void editRequested(const vaw::sim::Edit& edit, int mergeKey);

 private:
  QComboBox* rotation_ = nullptr;
  QSpinBox* rate_ = nullptr;
  QLabel* stability_ = nullptr;
  QPushButton* suggestion_ = nullptr;
  std::optional<vaw::sim::StabilityAdvice> advice_;
};

}  // namespace vaw::ui
