#include "vaw/ui/interference_dock.hpp"

#include <QBrush>
#include <QColor>
#include <QHeaderView>
#include <QLabel>
#include <QTableView>
#include <QVBoxLayout>
#include <QtConcurrent/QtConcurrentRun>
#include <algorithm>

#include "format.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/background.hpp"

namespace vaw::ui {

using format::str;
using Kind = vaw::collision::Interference::Kind;

InterferenceModel::InterferenceModel(QObject* parent) : QAbstractTableModel(parent) {}

void InterferenceModel::setInterferences(const vaw::Assembly* assembly, std::vector<vaw::collision::Interference> found) {
  beginResetModel();
  rows_.clear();
  first_.clear();
  second_.clear();
  if (assembly != nullptr)
    for (auto& i : found) {
      if (i.kind == Kind::Contact) continue;
      first_.push_back(str(assembly->parts[i.a].name));
      second_.push_back(str(assembly->parts[i.b].name));
      rows_.push_back(std::move(i));
    }
  endResetModel();
}

const vaw::collision::Interference* InterferenceModel::at(int row) const {
  return row >= 0 && row < static_cast<int>(rows_.size()) ? &rows_[static_cast<std::size_t>(row)] : nullptr;
}

int InterferenceModel::rowCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : static_cast<int>(rows_.size()); }
int InterferenceModel::columnCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : ColumnCount; }

QVariant InterferenceModel::data(const QModelIndex& index, int role) const {
  const auto* i = at(index.row());
  if (i == nullptr) return {};
  const auto row = static_cast<std::size_t>(index.row());
  if (role == Qt::DisplayRole) {
    switch (index.column()) {
      case KindColumn:
        return i->kind == Kind::Threaded ? tr("threaded %1").arg(str(i->thread)) : i->kind == Kind::Press ? tr("press fit") : tr("clash");
      case FirstColumn: return first_[row];
      case SecondColumn: return second_[row];
      case VolumeColumn: return QString::number(i->volume * 1e9, 'f', 3);
      case DepthColumn: return QString::number(i->depth * 1e3, 'f', 3);
      default: return {};
    }
  }
  if (role == Qt::ForegroundRole && i->kind == Kind::Clash) return QBrush(QColor(200, 0, 0));
  if (role == Qt::ToolTipRole) {
    if (i->kind == Kind::Clash)
      return tr("%1 and %2 share %3 mm³, %4 mm deep, round (%5, %6, %7) mm: neither a thread nor a press fit, a modelling error")
          .arg(first_[row], second_[row])
          .arg(i->volume * 1e9, 0, 'f', 3)
          .arg(i->depth * 1e3, 0, 'f', 3)
          .arg(i->where.x() * 1e3, 0, 'f', 2)
          .arg(i->where.y() * 1e3, 0, 'f', 2)
          .arg(i->where.z() * 1e3, 0, 'f', 2);
    return tr("A fit by design: the shaft's overlap with its bore (%1 mm into it) is neither a collision nor a block").arg(i->depth * 1e3, 0, 'f', 3);
  }
  if (role == Qt::TextAlignmentRole && (index.column() == VolumeColumn || index.column() == DepthColumn))
    return QVariant::fromValue(Qt::AlignRight | Qt::AlignVCenter);
  return {};
}

QVariant InterferenceModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (orientation != Qt::Horizontal || role != Qt::DisplayRole) return {};
  switch (section) {
    case KindColumn: return tr("Kind");
    case FirstColumn: return tr("Part");
    case SecondColumn: return tr("With");
    case VolumeColumn: return tr("Volume mm³");
    case DepthColumn: return tr("Depth mm");
    default: return {};
  }
}

InterferenceDock::InterferenceDock(AssemblyController& controller, QWidget* parent)
    : QDockWidget(tr("Interferences"), parent), controller_(controller) {
  setObjectName(QStringLiteral("interferenceDock"));
  auto* body = new QWidget(this);
  auto* layout = new QVBoxLayout(body);
  layout->setContentsMargins(4, 4, 4, 4);
  model_ = new InterferenceModel(this);
  view_ = new QTableView(body);
  view_->setObjectName(QStringLiteral("interferenceView"));
  view_->setModel(model_);
  view_->setSelectionBehavior(QAbstractItemView::SelectRows);
  view_->setSelectionMode(QAbstractItemView::SingleSelection);
  view_->setAlternatingRowColors(true);
  view_->verticalHeader()->hide();
  view_->verticalHeader()->setDefaultSectionSize(view_->fontMetrics().height() + 6);
  view_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  view_->horizontalHeader()->setSectionResizeMode(InterferenceModel::SecondColumn, QHeaderView::Stretch);
  layout->addWidget(view_);
  hint_ = new QLabel(tr("Open a CAD assembly to check what overlaps at rest."), body);
  hint_->setObjectName(QStringLiteral("interferenceHint"));
  hint_->setWordWrap(true);
  layout->addWidget(hint_);
  setWidget(body);
  connect(&watcher_, &QFutureWatcher<Outcome>::finished, this, &InterferenceDock::finished);
  connect(view_->selectionModel(), &QItemSelectionModel::selectionChanged, this, &InterferenceDock::rowSelected);
  connect(&controller_, &AssemblyController::assemblyLoaded, this, &InterferenceDock::assemblyLoaded);
}

InterferenceDock::~InterferenceDock() {
  if (cancel_) cancel_->store(true);
  watcher_.disconnect(this);
  watcher_.waitForFinished();
}

void InterferenceDock::assemblyLoaded() {
  std::shared_ptr<const vaw::sim::Scene> scene = controller_.scene();
  // An edit of the constraints reopens the scene: the overlaps are the geometry's, as they were.
  if (scene && shown_ && scene->assembly().cadHash == shown_->assembly().cadHash && !scene->assembly().cadHash.empty() && !checking_) {
    shown_ = scene;
    return;
  }
  if (cancel_) cancel_->store(true);
  model_->setInterferences(nullptr, {});
  emit hideWhere();
  shown_.reset();
  if (!scene || scene->assembly().cadFile.empty()) {
    hint_->setText(tr("Interferences are checked for CAD assemblies (STEP), whose parts come with their assembled places."));
    return;
  }
  hint_->setText(tr("Checking what overlaps at rest…"));
  hint_->setStyleSheet({});
  cancel_ = std::make_shared<std::atomic<bool>>(false);
  checking_ = true;
  auto cancel = cancel_;
  watcher_.setFuture(QtConcurrent::run([scene, cancel] {
    Outcome out;
    out.scene = scene;
    try {
      const BackgroundTask task("interferences");
      const vaw::Assembly& a = scene->assembly();
      out.found = vaw::collision::interferences(a, vaw::collision::assembledPoses(a), [cancel](double, std::size_t, std::size_t) { return !cancel->load(); });
    } catch (const vaw::LoadCancelled&) {
      out.cancelled = true;
    } catch (const std::exception& e) {  // an allocation failing on a huge product: said, the window lives on
      out.error = failureText(e);
    }
    return out;
  }));
}

void InterferenceDock::finished() {
  Outcome out = watcher_.result();
  checking_ = false;
  if (out.cancelled || out.scene != controller_.scene()) return;
  if (!out.error.isEmpty()) {
    hint_->setStyleSheet(QStringLiteral("color: #c80000;"));
    hint_->setText(tr("The check failed: %1").arg(out.error));
    return;
  }
  int count[4] = {0, 0, 0, 0};
  for (const auto& i : out.found) ++count[static_cast<int>(i.kind)];
  shown_ = out.scene;
  model_->setInterferences(&out.scene->assembly(), std::move(out.found));
  const int clashes = count[static_cast<int>(Kind::Clash)];
  hint_->setStyleSheet(clashes > 0 ? QStringLiteral("color: #c80000;") : QString());
  hint_->setText(tr("%1 clash(es), %2 threaded, %3 press fit(s); %4 pair(s) only touch.")
                     .arg(clashes)
                     .arg(count[static_cast<int>(Kind::Threaded)])
                     .arg(count[static_cast<int>(Kind::Press)])
                     .arg(count[static_cast<int>(Kind::Contact)]));
}

void InterferenceDock::rowSelected() {
  const auto rows = view_->selectionModel()->selectedRows();
  const auto* i = model_->at(rows.isEmpty() ? -1 : rows.front().row());
  if (i == nullptr || !shown_) {
    emit hideWhere();
    return;
  }
  emit partSelected(i->b);
  // Drawn on the first part (the base, where there is one), in its frame at its assembled pose: where the
  // overlap is on it, wherever it stands now.
  const vaw::Assembly& a = shown_->assembly();
  const Eigen::Isometry3d at = vaw::collision::assembledPoses(a)[i->a].inverse();
  Viewport::ConstraintGeometry g;
  g.kind = Viewport::ConstraintGeometry::Kind::Axis;
  g.partner = i->a;
  g.point = at * i->where;
  const Eigen::Vector3d d = at.linear() * i->direction;
  g.direction = d.norm() > 0.5 ? d.normalized() : Eigen::Vector3d::UnitZ();
  g.size = std::clamp(a.parts[i->b].mesh->bounds().diagonal().norm(), 0.01, 0.2);
  emit showWhere(g);
}

}  // namespace vaw::ui
