#include "vaw/ui/docks.hpp"

#include <QHeaderView>
#include <QItemSelectionModel>
#include <QLabel>
#include <QStackedWidget>
#include <QTableView>
#include <QTreeView>

#include "vaw/ui/message_log_model.hpp"
#include "vaw/ui/part_properties_model.hpp"
#include "vaw/ui/scene_tree_model.hpp"

namespace vaw::ui {

SceneDock::SceneDock(QWidget* parent) : QDockWidget(tr("Scene"), parent) {
  setObjectName(QStringLiteral("sceneDock"));
  model_ = new SceneTreeModel(this);
  view_ = new QTreeView(this);
  view_->setObjectName(QStringLiteral("sceneTree"));
  view_->setModel(model_);
  view_->setSelectionMode(QAbstractItemView::SingleSelection);
  view_->setSelectionBehavior(QAbstractItemView::SelectRows);
  view_->setUniformRowHeights(true);
  view_->setAlternatingRowColors(true);
  view_->header()->setStretchLastSection(false);
  // Names first: they size to their contents; the collision proxy takes what is left (full text in
  // its tooltip).
  view_->header()->setSectionResizeMode(SceneTreeModel::NameColumn, QHeaderView::ResizeToContents);
  view_->header()->setSectionResizeMode(SceneTreeModel::CategoryColumn, QHeaderView::ResizeToContents);
  view_->header()->setSectionResizeMode(SceneTreeModel::MassColumn, QHeaderView::ResizeToContents);
  view_->header()->setSectionResizeMode(SceneTreeModel::CollisionColumn, QHeaderView::Stretch);
  setWidget(view_);
  connect(view_->selectionModel(), &QItemSelectionModel::currentRowChanged, this,
          [this](const QModelIndex& current) {
            if (!updating_) emit partSelected(model_->partAt(current));
          });
}

void SceneDock::setAssembly(const vaw::Assembly* assembly, const std::vector<vaw::collision::ObjectInfo>& collision) {
  updating_ = true;
  model_->setAssembly(assembly, collision);
  view_->expandToDepth(1);
  updating_ = false;
}

std::optional<vaw::PartId> SceneDock::currentPart() const {
  return model_->partAt(view_->selectionModel()->currentIndex());
}

void SceneDock::selectPart(std::optional<vaw::PartId> part) {
  if (currentPart() == part) return;
  updating_ = true;
  if (part) {
    const QModelIndex index = model_->indexOfPart(*part);
    view_->selectionModel()->setCurrentIndex(
        index, QItemSelectionModel::ClearAndSelect | QItemSelectionModel::Rows);
    if (index.isValid()) view_->scrollTo(index);
  } else {
    view_->selectionModel()->clearSelection();
    view_->selectionModel()->setCurrentIndex({}, QItemSelectionModel::NoUpdate);
  }
  updating_ = false;
}

PartDock::PartDock(QWidget* parent) : QDockWidget(tr("Part"), parent) {
  setObjectName(QStringLiteral("partDock"));
  model_ = new PartPropertiesModel(this);
  view_ = new QTableView(this);
  view_->setObjectName(QStringLiteral("partProperties"));
  view_->setModel(model_);
  view_->setSelectionBehavior(QAbstractItemView::SelectRows);
  view_->setWordWrap(true);
  view_->verticalHeader()->hide();
  view_->horizontalHeader()->setSectionResizeMode(PartPropertiesModel::PropertyColumn,
                                                   QHeaderView::ResizeToContents);
  view_->horizontalHeader()->setStretchLastSection(true);
  emptyHint_ = new QLabel(tr("Select a part in the scene tree or the viewport."), this);
  emptyHint_->setAlignment(Qt::AlignCenter);
  emptyHint_->setWordWrap(true);
  auto* stack = new QStackedWidget(this);
  stack->addWidget(emptyHint_);
  stack->addWidget(view_);
  setWidget(stack);
}

void PartDock::showPart(const vaw::Assembly* assembly, std::optional<vaw::PartId> part,
                        const std::vector<vaw::collision::ObjectInfo>& collision) {
  const vaw::collision::ObjectInfo* info = nullptr;
  for (const auto& c : collision)
    if (part && c.id == vaw::collision::ObjectId::part(*part)) info = &c;
  model_->setPart(assembly, part, info);
  auto* stack = static_cast<QStackedWidget*>(widget());
  stack->setCurrentWidget(model_->rowCount() > 0 ? static_cast<QWidget*>(view_) : emptyHint_);
  view_->resizeRowsToContents();
}

MessagesDock::MessagesDock(QWidget* parent) : QDockWidget(tr("Messages"), parent) {
  setObjectName(QStringLiteral("messagesDock"));
  model_ = new MessageLogModel(this);
  view_ = new QTreeView(this);
  view_->setObjectName(QStringLiteral("messages"));
  view_->setModel(model_);
  view_->setRootIsDecorated(false);
  view_->setUniformRowHeights(true);
  view_->setWordWrap(false);
  view_->header()->setSectionResizeMode(MessageLogModel::SeverityColumn, QHeaderView::ResizeToContents);
  setWidget(view_);
  connect(model_, &QAbstractItemModel::rowsInserted, view_, [this] { view_->scrollToBottom(); });
}

}  // namespace vaw::ui
