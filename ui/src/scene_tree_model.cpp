#include "vaw/ui/scene_tree_model.hpp"

#include <QStyle>

#include "format.hpp"
#include "standard_icon.hpp"
#include "vaw/sim/scene.hpp"

namespace vaw::ui {

namespace {

QString kindName(vaw::TreeNode::Kind kind) {
  switch (kind) {
    case vaw::TreeNode::Kind::Assembly: return SceneTreeModel::tr("assembly");
    case vaw::TreeNode::Kind::Group: return SceneTreeModel::tr("group");
    case vaw::TreeNode::Kind::Part: return SceneTreeModel::tr("part");
    case vaw::TreeNode::Kind::Environment: return SceneTreeModel::tr("environment");
    case vaw::TreeNode::Kind::MeshNode: return SceneTreeModel::tr("mesh node");
  }
  return {};
}

}  // namespace

SceneTreeModel::SceneTreeModel(QObject* parent) : QAbstractItemModel(parent) {}

void SceneTreeModel::setAssembly(const vaw::Assembly* assembly, const std::vector<vaw::collision::ObjectInfo>& collision) {
  beginResetModel();
  items_.clear();
  collision_ = collision;
  if (assembly != nullptr) {
    vaw::TreeNode root = assembly->tree;
    if (root.name.empty()) root.name = assembly->name;
    add(*assembly, root, -1, 0, std::nullopt);
  }
  endResetModel();
}

int SceneTreeModel::add(const vaw::Assembly& assembly, const vaw::TreeNode& node, int parent, int row,
                        std::optional<vaw::PartId> owningPart) {
  using Kind = vaw::TreeNode::Kind;
  Item item;
  item.name = format::str(node.name);
  item.kind = node.kind;
  item.parent = parent;
  item.row = row;
  item.toolTip = kindName(node.kind);
  switch (node.kind) {
    case Kind::Part:
      if (node.index < assembly.parts.size()) {
        const vaw::Part& part = assembly.parts[node.index];
        item.part = part.id;
        item.category = format::str(std::string(vaw::name(part.category.category)));
        item.mass = format::mass(part.mass.mass);
        item.toolTip = tr("part \"%1\": %2, %3\n%4")
                           .arg(item.name, item.category, item.mass, format::str(part.category.reason));
        if (!part.unitMembers.empty()) {
          // A bought-in unit moves as one: the tree says so and why (docs/step.md, "Units").
          item.category = tr("unit of %1 parts").arg(part.unitMembers.size());
          item.toolTip += tr("\nA unit of %1 parts handled as one: %2. Its context menu takes it apart (Handle as parts).")
                              .arg(part.unitMembers.size())
                              .arg(format::str(part.unitReason));
        }
        if (assembly.base && *assembly.base == part.id) {
          item.category += tr(" (base)");
          if (!assembly.baseReason.empty()) item.toolTip += tr("\nThe base: %1").arg(format::str(assembly.baseReason));
        }
        describeCollision(item, vaw::collision::ObjectId::part(part.id));
      }
      owningPart = item.part;
      break;
    case Kind::Environment:
      if (node.index < assembly.environment.size()) {
        const vaw::EnvironmentObject& e = assembly.environment[node.index];
        item.category = e.implied ? tr("floor (default: %1 m below the table's top)").arg(format::number(vaw::sim::kDefaultFloorDepth, 2))
                                  : format::str(e.kind);
        describeCollision(item, vaw::collision::ObjectId::environment(node.index));
      }
      break;
    case Kind::MeshNode:
      item.part = owningPart;
      item.category = kindName(node.kind);
      break;
    case Kind::Assembly:
    case Kind::Group:
      break;
  }
  const int self = static_cast<int>(items_.size());
  items_.push_back(std::move(item));
  std::vector<int> children;
  children.reserve(node.children.size());
  int childRow = 0;
  for (const auto& child : node.children) children.push_back(add(assembly, child, self, childRow++, owningPart));
  items_[static_cast<std::size_t>(self)].children = std::move(children);
  return self;
}

// Model no more than the scene needs, and show it.
void SceneTreeModel::describeCollision(Item& item, vaw::collision::ObjectId id) const {
  for (const auto& info : collision_) {
    if (!(info.id == id)) continue;
    const QString text = format::collision(info);
    item.collision = text;
    item.collisionToolTip = tr("collides as: %1\n%2").arg(text, format::str(info.proxyReason));
    return;
  }
}

const SceneTreeModel::Item* SceneTreeModel::itemAt(const QModelIndex& index) const {
  if (!index.isValid() || index.model() != this) return nullptr;
  const auto id = static_cast<std::size_t>(index.internalId());
  return id < items_.size() ? &items_[id] : nullptr;
}

QModelIndex SceneTreeModel::indexOfPart(vaw::PartId part) const {
  for (std::size_t i = 0; i < items_.size(); ++i) {
    if (items_[i].kind == vaw::TreeNode::Kind::Part && items_[i].part == part) {
      return createIndex(items_[i].row, 0, static_cast<quintptr>(i));
    }
  }
  return {};
}

std::optional<vaw::PartId> SceneTreeModel::partAt(const QModelIndex& index) const {
  const Item* item = itemAt(index);
  return item != nullptr ? item->part : std::nullopt;
}

std::size_t SceneTreeModel::partCount() const {
  std::size_t n = 0;
  for (const auto& item : items_) n += item.kind == vaw::TreeNode::Kind::Part ? 1 : 0;
  return n;
}

QModelIndex SceneTreeModel::index(int row, int column, const QModelIndex& parent) const {
  if (row < 0 || column < 0 || column >= ColumnCount) return {};
  if (!parent.isValid()) {
    return (row == 0 && !items_.empty()) ? createIndex(0, column, quintptr{0}) : QModelIndex();
  }
  const Item* p = itemAt(parent);
  if (p == nullptr || parent.column() != 0 || row >= static_cast<int>(p->children.size())) return {};
  return createIndex(row, column, static_cast<quintptr>(p->children[static_cast<std::size_t>(row)]));
}

QModelIndex SceneTreeModel::parent(const QModelIndex& child) const {
  const Item* item = itemAt(child);
  if (item == nullptr || item->parent < 0) return {};
  const auto& p = items_[static_cast<std::size_t>(item->parent)];
  return createIndex(p.row, 0, static_cast<quintptr>(item->parent));
}

int SceneTreeModel::rowCount(const QModelIndex& parent) const {
  if (!parent.isValid()) return items_.empty() ? 0 : 1;
  if (parent.column() != 0) return 0;
  const Item* p = itemAt(parent);
  return p != nullptr ? static_cast<int>(p->children.size()) : 0;
}

int SceneTreeModel::columnCount(const QModelIndex& /*parent*/) const { return ColumnCount; }

QVariant SceneTreeModel::data(const QModelIndex& index, int role) const {
  const Item* item = itemAt(index);
  if (item == nullptr) return {};
  switch (role) {
    case Qt::DisplayRole:
      switch (index.column()) {
        case NameColumn: return item->name;
        case CategoryColumn: return item->category;
        case MassColumn: return item->mass;
        case CollisionColumn: return item->collision;
        default: return {};
      }
    case Qt::ToolTipRole: return index.column() == CollisionColumn && !item->collisionToolTip.isEmpty() ? item->collisionToolTip : item->toolTip;
    case Qt::DecorationRole: {
      if (index.column() != NameColumn) return {};
      switch (item->kind) {
        case vaw::TreeNode::Kind::Assembly: return standardIcon(QStyle::SP_DirHomeIcon);
        case vaw::TreeNode::Kind::Group: return standardIcon(QStyle::SP_DirIcon);
        case vaw::TreeNode::Kind::Part: return standardIcon(QStyle::SP_FileIcon);
        case vaw::TreeNode::Kind::Environment: return standardIcon(QStyle::SP_DriveHDIcon);
        case vaw::TreeNode::Kind::MeshNode: return standardIcon(QStyle::SP_FileLinkIcon);
      }
      return {};
    }
    case Qt::TextAlignmentRole:
      if (index.column() == MassColumn) return QVariant::fromValue(Qt::AlignRight | Qt::AlignVCenter);
      return {};
    case PartIdRole:
      return item->part ? QVariant::fromValue(static_cast<qulonglong>(*item->part)) : QVariant();
    case KindRole: return static_cast<int>(item->kind);
    default: return {};
  }
}

QVariant SceneTreeModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (orientation != Qt::Horizontal || role != Qt::DisplayRole) return {};
  switch (section) {
    case NameColumn: return tr("Name");
    case CategoryColumn: return tr("Category");
    case MassColumn: return tr("Mass");
    case CollisionColumn: return tr("Collision");
    default: return {};
  }
}

}  // namespace vaw::ui
