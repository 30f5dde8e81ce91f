#include "vaw/ui/sequence_dock.hpp"
#include "format.hpp"

#include <QBrush>
#include <QColor>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QItemSelectionModel>
#include <QLabel>
#include <QProgressBar>
#include <QPushButton>
#include <QStringList>
#include <QTableView>
#include <QVBoxLayout>
#include <QtConcurrent/QtConcurrentRun>
#include <algorithm>
#include <exception>
#include <map>
#include <utility>

#include "vaw/importer.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/background.hpp"

namespace vaw::ui {

namespace {

using format::str;

QString names(const vaw::Assembly& a, const std::vector<vaw::PartId>& parts) {
  QStringList out;
  for (const vaw::PartId p : parts) out << str(a.parts[p].name);
  return out.join(QStringLiteral(", "));
}

// "bracket (partner, in its way), stud-1 (partner)": each part it must follow once, with every reason.
QString afterText(const vaw::Assembly& a, const vaw::eval::SequencePlan& plan, vaw::PartId part) {
  struct Why {
    bool partner = false, inItsWay = false;
  };
  std::map<vaw::PartId, Why> reasons;
  for (const auto& e : plan.precedence) {
    if (e.after != part) continue;
    Why& why = reasons[e.before];
    (e.reason == vaw::eval::Precedence::Reason::Partner ? why.partner : why.inItsWay) = true;
  }
  QStringList out;
  for (const auto& [before, why] : reasons) {
    QStringList words;
    if (why.partner) words << QObject::tr("partner");
    if (why.inItsWay) words << QObject::tr("in its way");
    out << QStringLiteral("%1 (%2)").arg(str(a.parts[before].name), words.join(QStringLiteral(", ")));
  }
  return out.join(QStringLiteral(", "));
}

}  // namespace

SequenceModel::SequenceModel(QObject* parent) : QAbstractTableModel(parent) {}

void SequenceModel::setPlan(const vaw::Assembly* assembly, const vaw::eval::SequencePlan* plan) {
  beginResetModel();
  rows_.clear();
  if (assembly != nullptr && plan != nullptr) {
    const vaw::Assembly& a = *assembly;
    for (std::size_t i = 0; i < plan->order.size(); ++i) {
      const vaw::PartId p = plan->order[i];
      Row row;
      row.part = p;
      row.name = str(a.parts[p].name);
      row.position = QString::number(i + 1);
      const vaw::eval::Direction* way = plan->wayOf(p);
      row.step = way == nullptr ? tr("base") : QString::number(plan->step[i]);
      row.home = way == nullptr ? tr("(the base)") : str(vaw::eval::travelText(way->out) + ": " + way->from);
      row.after = afterText(a, *plan, p);
      rows_.push_back(std::move(row));
    }
    for (const vaw::eval::Stuck& stuck : plan->stuck) {
      Row row;
      row.part = stuck.part;
      row.name = str(a.parts[stuck.part].name);
      row.step = tr("no order");
      row.stuck = true;
      const vaw::eval::PartCheck* check = plan->checkOf(stuck.part);
      QStringList ways;
      for (std::size_t k = 0; k < stuck.blockers.size(); ++k) {
        const QString from =
            check != nullptr && k < check->directions.size() ? str(check->directions[k].from) : tr("way %1").arg(k + 1);
        ways << QStringLiteral("%1: %2").arg(from, stuck.blockers[k].empty() ? tr("free") : names(a, stuck.blockers[k]));
      }
      if (!stuck.waitsFor.empty()) ways << tr("waits for its partner %1, which no order inserts").arg(names(a, stuck.waitsFor));
      row.blockers = ways.join(QStringLiteral("; "));
      row.home = tr("no way home: %1").arg(row.blockers);
      rows_.push_back(std::move(row));
    }
  }
  endResetModel();
}

void SequenceModel::setWays(const vaw::Assembly& a, const std::vector<vaw::eval::WayClearance>& ways, double threshold) {
  const auto mm = [](double m) { return QString::number(1e3 * m, 'f', 3); };
  for (const vaw::eval::WayClearance& w : ways) {
    const int row = rowOf(w.part);
    if (row < 0) continue;
    Row& r = rows_[static_cast<std::size_t>(row)];
    const vaw::eval::WayObject* n = w.nearest();
    r.nearMiss = w.nearMiss(threshold);
    r.clearance = n ? tr("%1 mm to %2").arg(mm(n->least), str(a.parts[n->part].name)) : tr("clear");
    QStringList tip;
    if (n)
      tip << tr("Passes %1 %2 mm off, %3 mm out from home%4.")
                 .arg(str(a.parts[n->part].name), mm(n->least), mm(n->at),
                      r.nearMiss ? tr(": a near miss (under %1 mm)").arg(1e3 * threshold) : QString());
    else
      tip << tr("Nothing already in comes within %1 mm of its way home.").arg(1e3 * vaw::eval::WayClearanceOptions{}.reach);
    if (!w.guides.empty()) tip << tr("Slides on %1.").arg(names(a, w.guides));
    if (!w.seatedOn.empty()) tip << tr("Rests on %1.").arg(names(a, w.seatedOn));
    r.clearanceTip = tip.join(QLatin1Char(' '));
  }
  if (!rows_.empty()) emit dataChanged(index(0, ClearanceColumn), index(rowCount() - 1, ClearanceColumn));
}

bool SequenceModel::isNearMiss(int row) const { return row >= 0 && row < rowCount() && rows_[static_cast<std::size_t>(row)].nearMiss; }

std::optional<vaw::PartId> SequenceModel::partAt(int row) const {
  if (row < 0 || row >= rowCount()) return std::nullopt;
  return rows_[static_cast<std::size_t>(row)].part;
}

int SequenceModel::rowOf(vaw::PartId part) const {
  const auto it = std::find_if(rows_.begin(), rows_.end(), [part](const Row& r) { return r.part == part; });
  return it == rows_.end() ? -1 : static_cast<int>(it - rows_.begin());
}

bool SequenceModel::isStuck(int row) const { return row >= 0 && row < rowCount() && rows_[static_cast<std::size_t>(row)].stuck; }

QString SequenceModel::blockersText(int row) const {
  return isStuck(row) ? rows_[static_cast<std::size_t>(row)].blockers : QString();
}

int SequenceModel::rowCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : static_cast<int>(rows_.size()); }

int SequenceModel::columnCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : ColumnCount; }

QVariant SequenceModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (orientation != Qt::Horizontal) return {};
  if (role == Qt::DisplayRole) {
    switch (section) {
      case PositionColumn: return tr("#");
      case StepColumn: return tr("Step");
      case PartColumn: return tr("Part");
      case HomeColumn: return tr("Comes home");
      case ClearanceColumn: return tr("Clearance");
      case AfterColumn: return tr("After");
      default: return {};
    }
  }
  if (role == Qt::ToolTipRole) {
    switch (section) {
      case StepColumn: return tr("Parts of one step need no order among them; the base is step 0");
      case HomeColumn: return tr("The way the part comes in, and the constraint that gives it");
      case ClearanceColumn:
        return tr("The nearest part already in that the way home passes, and how close; orange: a near miss (under %1 mm), "
                  "leaving out the parts it slides on and the last approach onto those it rests on")
            .arg(1e3 * vaw::eval::WayClearanceOptions{}.threshold);
      case AfterColumn:
        return tr(
            "The parts it must follow. partner: it is constrained to that part; in its way: it would stand in the way "
            "that part comes home by");
      default: return {};
    }
  }
  return {};
}

QVariant SequenceModel::data(const QModelIndex& index, int role) const {
  if (!index.isValid() || index.row() >= rowCount()) return {};
  const Row& r = rows_[static_cast<std::size_t>(index.row())];
  if (role == Qt::DisplayRole || (role == Qt::ToolTipRole && index.column() >= HomeColumn)) {
    switch (index.column()) {
      case PositionColumn: return r.position;
      case StepColumn: return r.step;
      case PartColumn: return r.name;
      case HomeColumn: return r.home;
      case ClearanceColumn: return role == Qt::ToolTipRole ? r.clearanceTip : r.clearance;
      case AfterColumn: return r.after;
      default: return {};
    }
  }
  if (role == Qt::ForegroundRole && r.stuck) return QBrush(QColor(200, 0, 0));
  if (role == Qt::BackgroundRole && r.nearMiss && index.column() == ClearanceColumn) return QBrush(QColor(250, 200, 150));
  return {};
}

SequenceDock::SequenceDock(AssemblyController& controller, QWidget* parent)
    : QDockWidget(tr("Sequence"), parent), controller_(controller) {
  setObjectName(QStringLiteral("sequenceDock"));
  auto* body = new QWidget(this);
  auto* layout = new QVBoxLayout(body);
  layout->setContentsMargins(4, 4, 4, 4);
  model_ = new SequenceModel(this);
  view_ = new QTableView(body);
  view_->setObjectName(QStringLiteral("sequenceView"));
  view_->setModel(model_);
  view_->setSelectionBehavior(QAbstractItemView::SelectRows);
  view_->setSelectionMode(QAbstractItemView::SingleSelection);
  view_->setAlternatingRowColors(true);
  view_->verticalHeader()->hide();
  view_->verticalHeader()->setDefaultSectionSize(view_->fontMetrics().height() + 6);
  view_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  view_->horizontalHeader()->setSectionResizeMode(SequenceModel::AfterColumn, QHeaderView::Stretch);
  layout->addWidget(view_);
  auto* bar = new QHBoxLayout;
  find_ = new QPushButton(tr("Find Order"), body);
  find_->setObjectName(QStringLiteral("sequenceFind"));
  find_->setToolTip(tr("Sweep every part's ways home through the assembly and find an order that puts it together"));
  bar->addWidget(find_);
  progress_ = new QProgressBar(body);
  progress_->setObjectName(QStringLiteral("sequenceProgress"));
  progress_->setRange(0, 1000);
  progress_->setTextVisible(false);
  progress_->setMaximumWidth(160);
  progress_->hide();
  bar->addWidget(progress_);
  hint_ = new QLabel(body);
  hint_->setObjectName(QStringLiteral("sequenceHint"));
  hint_->setWordWrap(true);
  hint_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  bar->addWidget(hint_, 1);
  layout->addLayout(bar);
  setWidget(body);

  connect(find_, &QPushButton::clicked, this, &SequenceDock::findOrder);
  connect(&watcher_, &QFutureWatcher<Outcome>::finished, this, &SequenceDock::finished);
  connect(view_->selectionModel(), &QItemSelectionModel::selectionChanged, this, &SequenceDock::rowSelected);
  connect(&controller_, &AssemblyController::assemblyLoaded, this, &SequenceDock::assemblyLoaded);
  showIdle();
}

SequenceDock::~SequenceDock() {
  // The worker posts progress to this dock: it must stop before the dock goes.
  if (cancel_) cancel_->store(true);
  watcher_.disconnect(this);
  watcher_.waitForFinished();
}

void SequenceDock::showIdle() {
  const bool loaded = controller_.assembly() != nullptr;
  find_->setText(tr("Find Order"));
  find_->setEnabled(loaded && !finding());
  progress_->hide();
  if (!plan_)
    hint_->setText(loaded ? tr("Find Order moves every part home along its ways and finds an order that puts the assembly together.")
                          : tr("Open an assembly to find its order."));
}

void SequenceDock::assemblyLoaded() {
  // Another scene, or this one with other constraints: the ways home and the order may differ.
  if (cancel_) cancel_->store(true);
  plan_.reset();
  ways_.clear();
  model_->setPlan(nullptr, nullptr);
  hint_->setStyleSheet({});
  showIdle();
}

void SequenceDock::findOrder() {
  if (finding()) {
    if (cancel_) cancel_->store(true);
    find_->setEnabled(false);
    hint_->setText(tr("Stopping…"));
    return;
  }
  std::shared_ptr<const vaw::sim::Scene> scene = controller_.scene();
  if (!scene) return;
  plan_.reset();
  ways_.clear();
  model_->setPlan(nullptr, nullptr);
  hint_->setStyleSheet({});
  hint_->setText(tr("Finding the order…"));
  progress_->setValue(0);
  progress_->show();
  find_->setText(tr("Stop"));
  cancel_ = std::make_shared<std::atomic<bool>>(false);
  finding_ = true;
  auto cancel = cancel_;
  // Queued calls reach the dock on the GUI thread; the destructor waits for the worker, so `this` lives.
  const vaw::ProgressFn progress = [this, cancel](double fraction, const std::string& stage) {
    const QString text = str(stage);
    QMetaObject::invokeMethod(
        this,
        [this, cancel, fraction, text] {
          if (cancel->load() || cancel != cancel_) return;
          progress_->setValue(static_cast<int>(std::clamp(fraction, 0.0, 1.0) * 1000.0));
          if (!text.isEmpty()) hint_->setText(text);
        },
        Qt::QueuedConnection);
    return !cancel->load();
  };
  watcher_.setFuture(QtConcurrent::run([scene, progress, options = wayOptions_] {
    Outcome out;
    out.scene = scene;
    try {
      const BackgroundTask task("order");
      // The ways home's walk is the search's last fifth or so, on the products measured (docs/evaluation.md).
      out.plan = vaw::eval::planSequence(scene->assembly(), {}, [&](double f, const std::string& stage) { return progress(0.8 * f, stage); });
      out.ways = vaw::eval::wayClearances(scene->assembly(), *out.plan, options,
                                          [&](double f, const std::string& stage) { return progress(0.8 + 0.2 * f, stage); });
    } catch (const vaw::LoadCancelled&) {
      out.cancelled = true;
    } catch (const std::exception& e) {  // vaw::InputError: an assembly without a base has no order
      out.error = failureText(e);
    }
    return out;
  }));
}

void SequenceDock::finished() {
  Outcome out = watcher_.result();
  finding_ = false;
  showIdle();
  // Found on a scene that was replaced meanwhile: it says nothing about the one loaded now.
  if (out.scene != controller_.scene()) {
    emit searchOutdated();
    return;
  }
  if (!out.plan) {
    const QString why = out.cancelled ? tr("Stopped: no order found.") : tr("No order: %1").arg(out.error);
    hint_->setStyleSheet(out.cancelled ? QString() : QStringLiteral("color: #c80000;"));
    hint_->setText(why);
    emit orderFailed(why);
    return;
  }
  plan_ = std::move(out.plan);
  ways_ = std::move(out.ways);
  const vaw::Assembly& a = out.scene->assembly();
  model_->setPlan(&a, &*plan_);
  model_->setWays(a, ways_, wayOptions_.threshold);
  const int inserted = static_cast<int>(plan_->order.size()) - 1;
  QString text = plan_->complete()
                     ? tr("An order puts every part in place: %1 after the base.").arg(inserted)
                     : tr("No order inserts %1 of the parts (red): select one to see what blocks it.").arg(plan_->stuck.size());
  const auto misses = std::count_if(ways_.begin(), ways_.end(), [this](const auto& w) { return w.nearMiss(wayOptions_.threshold); });
  if (misses > 0)
    text += QLatin1Char(' ') + (misses == 1 ? tr("1 way home passes a part already in closer than %1 mm (orange).").arg(1e3 * wayOptions_.threshold)
                                            : tr("%1 ways home pass a part already in closer than %2 mm (orange).")
                                                  .arg(misses)
                                                  .arg(1e3 * wayOptions_.threshold));
  if (!plan_->skipped.empty())
    text += QLatin1Char(' ') + tr("Without a final pose, not in the order: %1.").arg(names(a, plan_->skipped));
  hint_->setText(text);
  emit orderFound();
}

void SequenceDock::rowSelected() {
  if (updating_) return;
  const auto rows = view_->selectionModel()->selectedRows();
  const int row = rows.isEmpty() ? -1 : rows.front().row();
  const std::optional<vaw::PartId> part = model_->partAt(row);
  emit partSelected(part);
  // The viewport highlights one part: what blocks a stuck part is named instead.
  if (model_->isStuck(row))
    emit statusMessage(tr("%1 has no way home: %2")
                           .arg(model_->index(row, SequenceModel::PartColumn).data().toString(), model_->blockersText(row)));
}

void SequenceDock::selectPart(std::optional<vaw::PartId> part) {
  const int row = part ? model_->rowOf(*part) : -1;
  const auto selected = view_->selectionModel()->selectedRows();
  if ((selected.isEmpty() && row < 0) || (!selected.isEmpty() && selected.front().row() == row)) return;
  updating_ = true;
  if (row < 0) {
    view_->clearSelection();
  } else {
    view_->selectRow(row);
    view_->scrollTo(model_->index(row, 0));
  }
  updating_ = false;
}

}  // namespace vaw::ui
