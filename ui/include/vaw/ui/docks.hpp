#pragma once
// The dock panels of the main window. Each one sits on its own model and speaks PartIds.
#include <QDockWidget>
#include <optional>

#include "vaw/assembly.hpp"
#include "vaw/collision/collision_world.hpp"

class QTreeView;
class QTableView;
class QLabel;

namespace vaw::ui {

class SceneTreeModel;
class PartPropertiesModel;
class MessageLogModel;

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

// "Part": the selected part's properties.
class PartDock : public QDockWidget {
  Q_OBJECT
 public:
  explicit PartDock(QWidget* parent = nullptr);
  [[nodiscard]] PartPropertiesModel* model() const { return model_; }
  [[nodiscard]] QTableView* view() const { return view_; }

 public slots:
  void showPart(const vaw::Assembly* assembly, std::optional<vaw::PartId> part,
                const std::vector<vaw::collision::ObjectInfo>& collision = {});

 private:
  PartPropertiesModel* model_ = nullptr;
  QTableView* view_ = nullptr;
  QLabel* emptyHint_ = nullptr;
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
