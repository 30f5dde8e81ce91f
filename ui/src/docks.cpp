#include "vaw/ui/docks.hpp"

#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QItemSelectionModel>
#include <QLabel>
#include <QPushButton>
#include <QSignalBlocker>
#include <QSlider>
#include <QStackedWidget>
#include <QTableView>
#include <QToolButton>
#include <QTreeView>
#include <QVBoxLayout>
#include <cmath>
#include <numbers>

#include "vaw/ui/message_log_model.hpp"
#include "vaw/ui/part_properties_model.hpp"
#include "vaw/ui/scene_tree_model.hpp"
#include "vaw/ui/timeline.hpp"
#include "vaw/units.hpp"

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
  stack->setObjectName(QStringLiteral("partStack"));
  stack->addWidget(emptyHint_);
  stack->addWidget(view_);
  axes_ = new QCheckBox(tr("Show principal axes in the viewport"), this);
  axes_->setObjectName(QStringLiteral("showAxes"));
  connect(axes_, &QCheckBox::toggled, this, &PartDock::axesToggled);
  auto* body = new QWidget(this);
  auto* layout = new QVBoxLayout(body);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(stack, 1);
  layout->addWidget(axes_);
  setWidget(body);
}

void PartDock::showPart(const vaw::Assembly* assembly, std::optional<vaw::PartId> part,
                        const std::vector<vaw::collision::ObjectInfo>& collision) {
  const vaw::collision::ObjectInfo* info = nullptr;
  for (const auto& c : collision)
    if (part && c.id == vaw::collision::ObjectId::part(*part)) info = &c;
  model_->setPart(assembly, part, info);
  auto* stack = widget()->findChild<QStackedWidget*>(QStringLiteral("partStack"));
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

namespace {
using vaw::kDeg;

QDoubleSpinBox* angleBox(const QString& name, QWidget* parent) {
  auto* box = new QDoubleSpinBox(parent);
  box->setObjectName(name);
  box->setRange(-180.0, 180.0);
  box->setDecimals(1);
  box->setSingleStep(1.0);
  box->setSuffix(QStringLiteral(" °"));
  box->setKeyboardTracking(false);  // typed values take effect on Enter or leaving the field
  return box;
}
}  // namespace

ControlsDock::ControlsDock(QWidget* parent) : QDockWidget(tr("Base and hoist"), parent) {
  setObjectName(QStringLiteral("controlsDock"));
  auto* body = new QWidget(this);
  auto* layout = new QVBoxLayout(body);
  auto* baseBox = new QGroupBox(tr("Base (left hand)"), body);
  auto* form = new QFormLayout(baseBox);
  tiltX_ = angleBox(QStringLiteral("baseTiltX"), baseBox);
  tiltY_ = angleBox(QStringLiteral("baseTiltY"), baseBox);
  turn_ = angleBox(QStringLiteral("baseTurn"), baseBox);
  tiltX_->setToolTip(tr("Tilt about the world's x axis through the base's centre (keys I / K in the viewport)"));
  tiltY_->setToolTip(tr("Tilt about the world's y axis through the base's centre (keys L / J)"));
  turn_->setToolTip(tr("Turn about the base's own vertical (keys U / O)"));
  form->addRow(tr("Tilt about x"), tiltX_);
  form->addRow(tr("Tilt about y"), tiltY_);
  form->addRow(tr("Turn"), turn_);
  level_ = new QPushButton(tr("Level"), baseBox);
  level_->setObjectName(QStringLiteral("baseLevel"));
  form->addRow(QString(), level_);
  auto* note = new QLabel(tr("The base turns to what is set here at 30 °/s at most, lifted so that it stays clear of the table."), baseBox);
  note->setWordWrap(true);
  form->addRow(note);
  layout->addWidget(baseBox);
  for (QDoubleSpinBox* box : {tiltX_, tiltY_, turn_})
    connect(box, &QDoubleSpinBox::valueChanged, this, &ControlsDock::emitBase);
  connect(level_, &QPushButton::clicked, this, [this] {
    for (QDoubleSpinBox* box : {tiltX_, tiltY_, turn_}) {
      const QSignalBlocker block(box);
      box->setValue(0.0);
    }
    emitBase();
  });

  hoistBox_ = new QGroupBox(tr("Hoist"), body);
  auto* hoistForm = new QFormLayout(hoistBox_);
  engaged_ = new QCheckBox(tr("Hook closed (H)"), hoistBox_);
  engaged_->setObjectName(QStringLiteral("hoistEngaged"));
  height_ = new QDoubleSpinBox(hoistBox_);
  height_->setObjectName(QStringLiteral("hoistHeight"));
  height_->setSuffix(QStringLiteral(" mm"));
  height_->setDecimals(0);
  height_->setSingleStep(10.0);
  height_->setKeyboardTracking(false);
  height_->setToolTip(tr("Height of the hook (Shift+Up / Shift+Down in the viewport)"));
  heightSlider_ = new QSlider(Qt::Horizontal, hoistBox_);
  yaw_ = angleBox(QStringLiteral("hoistYaw"), hoistBox_);
  yaw_->setToolTip(tr("Turn of the hook about the vertical (Shift+Left / Shift+Right)"));
  hoistForm->addRow(engaged_);
  hoistForm->addRow(tr("Height"), height_);
  hoistForm->addRow(QString(), heightSlider_);
  hoistForm->addRow(tr("Turn"), yaw_);
  layout->addWidget(hoistBox_);
  hoistBox_->hide();
  connect(engaged_, &QCheckBox::toggled, this, &ControlsDock::hoistEngagedChanged);
  connect(height_, &QDoubleSpinBox::valueChanged, this, [this](double mm) {
    const QSignalBlocker block(heightSlider_);
    heightSlider_->setValue(static_cast<int>(std::lround(mm)));
    emit hoistHeightChanged(mm * 1e-3);
  });
  connect(heightSlider_, &QSlider::valueChanged, this, [this](int mm) { height_->setValue(mm); });
  connect(yaw_, &QDoubleSpinBox::valueChanged, this, [this](double deg) { emit hoistYawChanged(deg * kDeg); });

  auto* hand = new QLabel(tr("<b>Right hand (mouse)</b>: drag a part to grab it (Ctrl: both hands), the wheel moves "
                             "it in depth (forward: away), Q/E, Z/X and C/V turn it, releasing the button lets it go. Alt+drag orbits."),
                          body);
  hand->setWordWrap(true);
  layout->addWidget(hand);
  layout->addStretch(1);
  setWidget(body);
}

void ControlsDock::emitBase() {
  emit baseTargetChanged(BaseAngles{tiltX_->value() * kDeg, tiltY_->value() * kDeg, turn_->value() * kDeg});
}

void ControlsDock::showBaseTarget(const BaseAngles& target) {
  const auto set = [](QDoubleSpinBox* box, double rad) {
    if (box->hasFocus()) return;  // the user is typing there
    const QSignalBlocker block(box);
    box->setValue(std::remainder(rad / kDeg, 360.0));
  };
  set(tiltX_, target.tiltX);
  set(tiltY_, target.tiltY);
  set(turn_, target.turn);
}

void ControlsDock::setHoist(const std::optional<vaw::Hoist>& hoist) {
  hoistBox_->setVisible(hoist.has_value());
  if (!hoist) return;
  hoistBox_->setTitle(tr("Hoist \"%1\"").arg(QString::fromStdString(hoist->name)));
  const QSignalBlocker b1(height_), b2(heightSlider_), b3(engaged_), b4(yaw_);
  height_->setRange(hoist->lowest * 1e3, hoist->highest * 1e3);
  heightSlider_->setRange(static_cast<int>(std::lround(hoist->lowest * 1e3)), static_cast<int>(std::lround(hoist->highest * 1e3)));
  height_->setValue(hoist->height * 1e3);
  heightSlider_->setValue(static_cast<int>(std::lround(hoist->height * 1e3)));
  engaged_->setChecked(false);
  yaw_->setValue(0.0);
}

void ControlsDock::showHoist(const vaw::sim::HoistInput& hoist) {
  const QSignalBlocker b1(height_), b2(heightSlider_), b3(engaged_), b4(yaw_);
  engaged_->setChecked(hoist.engaged);
  if (!height_->hasFocus()) height_->setValue(hoist.height * 1e3);
  heightSlider_->setValue(static_cast<int>(std::lround(hoist.height * 1e3)));
  if (!yaw_->hasFocus()) yaw_->setValue(std::remainder(hoist.yaw / kDeg, 360.0));
}

TimelineDock::TimelineDock(QWidget* parent) : QDockWidget(tr("Timeline"), parent) {
  setObjectName(QStringLiteral("timelineDock"));
  model_ = new TimelineModel(this);
  auto* body = new QWidget(this);
  auto* layout = new QVBoxLayout(body);
  layout->setContentsMargins(2, 2, 2, 2);
  layout->setSpacing(2);
  auto* bar = new QHBoxLayout();
  auto* hint = new QLabel(tr("Drag the playhead to look at the past; wheel: zoom, right-drag: pan, double-click: fit."), body);
  hint->setWordWrap(true);
  auto* png = new QToolButton(body);
  png->setText(tr("Export PNG..."));
  png->setObjectName(QStringLiteral("exportTimelinePng"));
  auto* csv = new QToolButton(body);
  csv->setText(tr("Export CSV..."));
  csv->setObjectName(QStringLiteral("exportTimelineCsv"));
  bar->addWidget(hint, 1);
  bar->addWidget(png);
  bar->addWidget(csv);
  layout->addLayout(bar);
  view_ = new TimelineView(model_, body);
  layout->addWidget(view_, 1);
  setWidget(body);
  connect(png, &QToolButton::clicked, this, &TimelineDock::exportPngRequested);
  connect(csv, &QToolButton::clicked, this, &TimelineDock::exportCsvRequested);
}

}  // namespace vaw::ui
