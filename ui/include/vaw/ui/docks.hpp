#pragma once
// The dock panels of the main window. Each one sits on its own model and speaks PartIds.
#include <QDockWidget>
#include <optional>

#include "vaw/assembly.hpp"
#include "vaw/collision/collision_world.hpp"
#include "vaw/ui/simulation_controller.hpp"

class QTreeView;
class QTableView;
class QLabel;
class QCheckBox;
class QDoubleSpinBox;
class QGroupBox;
class QPushButton;
class QSlider;

namespace vaw::ui {

class SceneTreeModel;
class PartPropertiesModel;
class MessageLogModel;
class TimelineModel;
class TimelineView;

// "Scene": the scene tree. Selecting a part (or one of its mesh nodes) emits partSelected.
class SceneDock : public QDockWidget {
  Q_OBJECT
 public:
  explicit SceneDock(QWidget* parent = nullptr);
  void setAssembly(const vaw::Assembly* assembly, const std::vector<vaw::collision::ObjectInfo>& collision = {});
  [[nodiscard]] SceneTreeModel* model() const { return model_; }
  [[nodiscard]] QTreeView* view() const { return view_; }
  // The part the current tree item stands for.
  [[nodiscard]] std::optional<vaw::PartId> currentPart() const;

 public slots:
  // Makes `part` the current item (nothing: clears a part selection). Does not emit partSelected.
  void selectPart(std::optional<vaw::PartId> part);

 signals:
  void partSelected(std::optional<vaw::PartId> part);

 private:
  SceneTreeModel* model_ = nullptr;
  QTreeView* view_ = nullptr;
  bool updating_ = false;
};

// "Part": the part-state inspector of the selected part (live state, then its properties).
class PartDock : public QDockWidget {
  Q_OBJECT
 public:
  explicit PartDock(QWidget* parent = nullptr);
  [[nodiscard]] PartPropertiesModel* model() const { return model_; }
  [[nodiscard]] QTableView* view() const { return view_; }
  [[nodiscard]] QCheckBox* axesBox() const { return axes_; }

 public slots:
  void showPart(const vaw::Assembly* assembly, std::optional<vaw::PartId> part,
                const std::vector<vaw::collision::ObjectInfo>& collision = {});

 signals:
  void axesToggled(bool shown);

 private:
  PartPropertiesModel* model_ = nullptr;
  QTableView* view_ = nullptr;
  QLabel* emptyHint_ = nullptr;
  QCheckBox* axes_ = nullptr;
};

// "Base and hoist": the left hand's base (tilt about the world's x and y axes, turn about its vertical;
// the keys I/K, J/L, U/O in the viewport do the same) and the hoist's controls, when the scene has one.
class ControlsDock : public QDockWidget {
  Q_OBJECT
 public:
  explicit ControlsDock(QWidget* parent = nullptr);
  // Shows the hoist's controls for `hoist` (none: hides them).
  void setHoist(const std::optional<vaw::Hoist>& hoist);
  // Shows a target the keys set, without sending it back.
  void showBaseTarget(const BaseAngles& target);
  void showHoist(const vaw::sim::HoistInput& hoist);
  [[nodiscard]] QDoubleSpinBox* tiltX() const { return tiltX_; }
  [[nodiscard]] QDoubleSpinBox* tiltY() const { return tiltY_; }
  [[nodiscard]] QDoubleSpinBox* turn() const { return turn_; }
  [[nodiscard]] QPushButton* levelButton() const { return level_; }
  [[nodiscard]] QCheckBox* hoistEngaged() const { return engaged_; }
  [[nodiscard]] QDoubleSpinBox* hoistHeight() const { return height_; }
  [[nodiscard]] QDoubleSpinBox* hoistYaw() const { return yaw_; }

 signals:
  void baseTargetChanged(const vaw::ui::BaseAngles& target);  // radians
  void hoistEngagedChanged(bool engaged);
  void hoistHeightChanged(double metres);
  void hoistYawChanged(double radians);

 private:
  void emitBase();
  QDoubleSpinBox* tiltX_ = nullptr;
  QDoubleSpinBox* tiltY_ = nullptr;
  QDoubleSpinBox* turn_ = nullptr;
  QPushButton* level_ = nullptr;
  QGroupBox* hoistBox_ = nullptr;
  QCheckBox* engaged_ = nullptr;
  QDoubleSpinBox* height_ = nullptr;
  QSlider* heightSlider_ = nullptr;
  QDoubleSpinBox* yaw_ = nullptr;
};

// "Timeline": the state-transition timeline with its export buttons.
class TimelineDock : public QDockWidget {
  Q_OBJECT
 public:
  explicit TimelineDock(QWidget* parent = nullptr);
  [[nodiscard]] TimelineModel* model() const { return model_; }
  [[nodiscard]] TimelineView* view() const { return view_; }

 signals:
  void exportPngRequested();
  void exportCsvRequested();

 private:
  TimelineModel* model_ = nullptr;
  TimelineView* view_ = nullptr;
};

// "Messages": load warnings and errors, plugin problems.
class MessagesDock : public QDockWidget {
  Q_OBJECT
 public:
  explicit MessagesDock(QWidget* parent = nullptr);
  [[nodiscard]] MessageLogModel* model() const { return model_; }
  [[nodiscard]] QTreeView* view() const { return view_; }

 private:
  MessageLogModel* model_ = nullptr;
  QTreeView* view_ = nullptr;
};

}  // namespace vaw::ui
