#pragma once
// The scene tree (vaw::Assembly::tree) as a Qt item model: the assembly root, groups, parts,
// environment objects and the mesh nodes of each part's file. The model copies what it shows, so
// it holds no pointer into the assembly; items refer to parts by PartId.
#include <QAbstractItemModel>
#include <optional>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/collision/collision_world.hpp"

namespace vaw::ui {

class SceneTreeModel : public QAbstractItemModel {
  Q_OBJECT
 public:
  enum Column { NameColumn, CategoryColumn, MassColumn, CollisionColumn, ColumnCount };
  enum Role {
    PartIdRole = Qt::UserRole + 1,  // qulonglong PartId for parts and their mesh nodes, else invalid
    KindRole,                       // int(vaw::TreeNode::Kind)
  };

  explicit SceneTreeModel(QObject* parent = nullptr);

  // Rebuilds the model from `assembly` (null: empty model); `collision` says how each object collides.
  void setAssembly(const vaw::Assembly* assembly, const std::vector<vaw::collision::ObjectInfo>& collision = {});

  [[nodiscard]] QModelIndex indexOfPart(vaw::PartId part) const;
  // The part an item stands for: a part, or the part a mesh node belongs to.
  [[nodiscard]] std::optional<vaw::PartId> partAt(const QModelIndex& index) const;
  [[nodiscard]] std::size_t partCount() const;

  [[nodiscard]] QModelIndex index(int row, int column, const QModelIndex& parent = {}) const override;
  [[nodiscard]] QModelIndex parent(const QModelIndex& child) const override;
  [[nodiscard]] int rowCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] int columnCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
  [[nodiscard]] QVariant headerData(int section, Qt::Orientation orientation,
                                    int role = Qt::DisplayRole) const override;

 private:
  struct Item {
    QString name;
    vaw::TreeNode::Kind kind = vaw::TreeNode::Kind::Group;
    std::optional<vaw::PartId> part;
    QString category;
    QString mass;
    QString collision;
    QString collisionToolTip;
    QString toolTip;
    int parent = -1;  // index into items_, -1 for the root
    int row = 0;      // row under its parent
    std::vector<int> children;
  };
  int add(const vaw::Assembly& assembly, const vaw::TreeNode& node, int parent, int row,
          std::optional<vaw::PartId> owningPart);
  void describeCollision(Item& item, vaw::collision::ObjectId id) const;
  [[nodiscard]] const Item* itemAt(const QModelIndex& index) const;

  std::vector<Item> items_;  // items_[0] is the root when the model is not empty
  std::vector<vaw::collision::ObjectInfo> collision_;
};

}  // namespace vaw::ui
