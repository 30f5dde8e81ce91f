#include "vaw/ui/timeline.hpp"
#include "qt_convert.hpp"

#include <QFile>
#include <QHelpEvent>
#include <QImage>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <QToolTip>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>
#include <map>

#include "format.hpp"
#include "vaw/sim/session.hpp"
#include "vaw/view/frame.hpp"

namespace vaw::ui {

namespace {


QString stateName(interact::PartState s) { return QString::fromStdString(std::string(interact::name(s))); }

// A "nice" tick step (1, 2, 5 x 10^k) giving roughly `count` ticks over `span`.
double tickStep(double span, int count) {
  const double raw = span / std::max(1, count);
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw) return m * p;
  return 10.0 * p;
}

}  // namespace

// ---- TimelineModel ----

TimelineModel::TimelineModel(QObject* parent) : QAbstractTableModel(parent) {}

void TimelineModel::clear() {
  beginResetModel();
  assembly_ = nullptr;
  transitions_.clear();
  refusals_.clear();
  edits_.clear();
  entries_.clear();
  endResetModel();
}

std::vector<TimelineModel::Entry> TimelineModel::entriesOf(const std::vector<vaw::sim::TransitionRecord>& transitions,
                                                           const std::vector<vaw::sim::Refusal>& refusals,
                                                           const std::vector<vaw::sim::EditRecord>& edits) {
  std::vector<Entry> entries;
  entries.reserve(transitions.size() + refusals.size() + edits.size());
  for (std::size_t i = 0; i < transitions.size(); ++i) entries.push_back({Kind::Transition, i, transitions[i].t});
  for (std::size_t i = 0; i < refusals.size(); ++i) entries.push_back({Kind::Refusal, i, refusals[i].t});
  for (std::size_t i = 0; i < edits.size(); ++i) entries.push_back({Kind::Edit, i, edits[i].t});
  std::stable_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.t < b.t; });
  return entries;
}

void TimelineModel::setLog(const vaw::Assembly* assembly, const std::vector<vaw::sim::TransitionRecord>& transitions,
                           const std::vector<vaw::sim::Refusal>& refusals, const std::vector<vaw::sim::EditRecord>& edits) {
  std::vector<Entry> entries = entriesOf(transitions, refusals, edits);
  // Appended at the end in time (the usual case while recording): the old rows are a prefix of the new ones
  // and the records they point at are the same.
  bool prefix = assembly == assembly_ && entries.size() >= entries_.size() && transitions.size() >= transitions_.size() &&
                refusals.size() >= refusals_.size() && edits.size() >= edits_.size();
  for (std::size_t i = 0; prefix && i < entries_.size(); ++i)
    prefix = entries[i].kind == entries_[i].kind && entries[i].index == entries_[i].index;
  for (std::size_t i = 0; prefix && i < transitions_.size(); ++i)
    prefix = transitions[i].step == transitions_[i].step && transitions[i].part == transitions_[i].part;
  if (prefix && entries.size() == entries_.size()) return;
  if (prefix) beginInsertRows({}, static_cast<int>(entries_.size()), static_cast<int>(entries.size()) - 1);
  else beginResetModel();
  assembly_ = assembly;
  transitions_ = transitions;
  refusals_ = refusals;
  edits_ = edits;
  entries_ = std::move(entries);
  if (prefix) endInsertRows();
  else endResetModel();
}

QString TimelineModel::describe(const Entry& e) const {
  const auto partName = [this](vaw::PartId p) {
    return assembly_ && p < assembly_->parts.size() ? QString::fromStdString(assembly_->parts[p].name) : QString::number(p);
  };
  switch (e.kind) {
    case Kind::Transition: {
      const auto& t = transitions_[e.index];
      return tr("%1 s, %2: %3 → %4 by %5 (%6)")
          .arg(format::number(t.t), partName(t.part), stateName(t.from), stateName(t.to),
               QString::fromStdString(std::string(interact::name(t.event))), QString::fromStdString(t.cause));
    }
    case Kind::Refusal: {
      const auto& r = refusals_[e.index];
      return tr("%1 s, %2: %3 refused in %4: %5")
          .arg(format::number(r.t), partName(r.part), QString::fromStdString(std::string(interact::name(r.event))),
               stateName(r.state), QString::fromStdString(r.reason));
    }
    case Kind::Edit: {
      const auto& ed = edits_[e.index];
      return tr("%1 s, edit: %2")
          .arg(format::number(ed.t), assembly_ ? QString::fromStdString(vaw::sim::describe(ed.edit, *assembly_)) : QString());
    }
  }
  return {};
}

void TimelineModel::writeCsv(const QString& file) const {
  if (assembly_ == nullptr) vaw::fail(file.toStdString(), "", "a loaded scene to export the timeline of");
  vaw::sim::writeTransitionsCsv(*assembly_, transitions_, refusals_, std::filesystem::path(QFile::encodeName(file).toStdString()));
}

int TimelineModel::rowCount(const QModelIndex& parent) const {
  return parent.isValid() ? 0 : static_cast<int>(entries_.size());
}
int TimelineModel::columnCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : ColumnCount; }

QVariant TimelineModel::data(const QModelIndex& index, int role) const {
  if (!checkIndex(index, CheckIndexOption::IndexIsValid | CheckIndexOption::ParentIsInvalid)) return {};
  const Entry& e = entries_[static_cast<std::size_t>(index.row())];
  if (role == Qt::ToolTipRole) return describe(e);
  if (role != Qt::DisplayRole) return {};
  const auto partName = [this](vaw::PartId p) {
    return assembly_ && p < assembly_->parts.size() ? QString::fromStdString(assembly_->parts[p].name) : QString();
  };
  std::uint64_t step = 0;
  QString part, from, to, event, cause;
  switch (e.kind) {
    case Kind::Transition: {
      const auto& t = transitions_[e.index];
      step = t.step;
      part = partName(t.part);
      from = stateName(t.from);
      to = stateName(t.to);
      event = QString::fromStdString(std::string(interact::name(t.event)));
      cause = QString::fromStdString(t.cause);
      break;
    }
    case Kind::Refusal: {
      const auto& r = refusals_[e.index];
      step = r.step;
      part = partName(r.part);
      from = stateName(r.state);
      to = QStringLiteral("REFUSED");
      event = QString::fromStdString(std::string(interact::name(r.event)));
      cause = QString::fromStdString(r.reason);
      break;
    }
    case Kind::Edit: {
      const auto& ed = edits_[e.index];
      step = ed.step;
      event = QStringLiteral("edit");
      cause = assembly_ ? QString::fromStdString(vaw::sim::describe(ed.edit, *assembly_)) : QString();
      break;
    }
  }
  switch (index.column()) {
    case StepColumn: return QVariant::fromValue(static_cast<qulonglong>(step));
    case TimeColumn: return e.t;
    case PartColumn: return part;
    case FromColumn: return from;
    case ToColumn: return to;
    case EventColumn: return event;
    case CauseColumn: return cause;
    default: return {};
  }
}

QVariant TimelineModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (orientation != Qt::Horizontal || role != Qt::DisplayRole) return {};
  static const char* names[] = {"step", "t", "part", "from", "to", "event", "cause"};
  return section >= 0 && section < ColumnCount ? QString::fromLatin1(names[section]) : QVariant();
}

// ---- TimelineView ----

TimelineView::TimelineView(TimelineModel* model, QWidget* parent) : QWidget(parent), model_(model) {
  setObjectName(QStringLiteral("timeline"));
  setMouseTracking(true);
  setAttribute(Qt::WA_OpaquePaintEvent);
  const auto changed = [this] {
    relayout();
    update();
  };
  connect(model_, &QAbstractItemModel::rowsInserted, this, changed);
  connect(model_, &QAbstractItemModel::modelReset, this, changed);
}

QSize TimelineView::sizeHint() const {
  return {800, kAxis + kEditLane + kLane * static_cast<int>(std::max<std::size_t>(lanes_.size() + 1, 4)) + kLegend};
}
QSize TimelineView::minimumSizeHint() const { return {300, kAxis + kEditLane + 2 * kLane + kLegend}; }

void TimelineView::relayout() {
  lanes_.clear();
  folded_ = 0;
  const vaw::Assembly* a = model_->assembly();
  if (a == nullptr) return;
  std::vector<char> changed(a->parts.size(), 0);
  for (const auto& t : model_->transitions()) changed[t.part] = 1;
  for (const auto& r : model_->refusals()) changed[r.part] = 1;
  for (vaw::PartId id = 0; id < a->parts.size(); ++id) {
    if (changed[id]) lanes_.push_back(id);
    else ++folded_;
  }
  updateGeometry();
}

void TimelineView::setTimes(double playhead, double end, bool past, bool playback) {
  playhead_ = playhead;
  end_ = end;
  past_ = past;
  playback_ = playback;
  if (followed_) {
    const double span = std::max(5.0, t1_ - t0_);
    if (playhead_ > t1_ - 0.05 * span) {
      t1_ = playhead_ + 0.2 * span;
      t0_ = t1_ - span;
    }
    if (playhead_ < t0_) {
      t0_ = std::max(0.0, playhead_ - 0.1 * span);
      t1_ = t0_ + span;
    }
  }
  update();
}

void TimelineView::setVisibleRange(double start, double end) {
  if (!(end > start)) return;
  t0_ = start;
  t1_ = end;
  followed_ = false;
  update();
}

double TimelineView::xOf(double t) const {
  const double w = std::max(1, width() - kLabel - 8);
  return kLabel + (t - t0_) / (t1_ - t0_) * w;
}

double TimelineView::timeAt(double x) const {
  const double w = std::max(1, width() - kLabel - 8);
  return t0_ + (x - kLabel) / w * (t1_ - t0_);
}

QRect TimelineView::laneRect(std::size_t lane) const {
  return {kLabel, lanesTop() + static_cast<int>(lane) * kLane, width() - kLabel - 8, kLane - 3};
}

void TimelineView::paintEvent(QPaintEvent*) {
  QPainter p(this);
  draw(p, rect());
}

QImage TimelineView::render(qreal scale) const {
  QImage image(size() * scale, QImage::Format_ARGB32);
  image.setDevicePixelRatio(scale);
  QPainter p(&image);
  draw(p, rect());
  return image;
}

void TimelineView::draw(QPainter& p, const QRect& area) const {
  p.setRenderHint(QPainter::Antialiasing, true);
  p.fillRect(area, palette().base());
  const int right = area.width() - 8;
  const QFontMetrics fm = p.fontMetrics();
  // Time axis.
  p.setPen(palette().text().color());
  const double step = tickStep(t1_ - t0_, std::max(2, (right - kLabel) / 90));
  for (double t = std::ceil(t0_ / step) * step; t <= t1_ + 1e-9; t += step) {
    const double x = xOf(t);
    p.drawLine(QPointF(x, kAxis - 5), QPointF(x, kAxis));
    p.drawText(QRectF(x - 40, 2, 80, kAxis - 6), Qt::AlignCenter, QStringLiteral("%1 s").arg(format::number(t, 3)));
  }
  p.drawText(QRect(4, 2, kLabel - 8, kAxis - 4), Qt::AlignLeft | Qt::AlignVCenter, tr("time"));
  p.drawLine(kLabel, kAxis, right, kAxis);
  p.setClipRect(QRect(kLabel, 0, right - kLabel, area.height()));
  const double tEnd = std::max(end_, playhead_);
  // Edits: diamonds on their own lane.
  p.setClipping(false);
  p.drawText(QRect(4, kAxis, kLabel - 8, kEditLane), Qt::AlignLeft | Qt::AlignVCenter, tr("edits"));
  p.setClipping(true);
  p.setPen(Qt::NoPen);
  p.setBrush(QColor(90, 90, 200));
  for (const auto& e : model_->edits()) {
    const double x = xOf(e.t);
    const double y = kAxis + kEditLane / 2.0;
    QPainterPath d;
    d.moveTo(x, y - 5);
    d.lineTo(x + 5, y);
    d.lineTo(x, y + 5);
    d.lineTo(x - 5, y);
    d.closeSubpath();
    p.drawPath(d);
  }
  // Lanes: the state segments of each part that changed state, with a tick per transition.
  const vaw::Assembly* a = model_->assembly();
  std::map<vaw::PartId, std::size_t> laneOf;
  for (std::size_t i = 0; i < lanes_.size(); ++i) laneOf[lanes_[i]] = i;
  std::vector<double> since(lanes_.size(), 0.0);
  std::vector<interact::PartState> state(lanes_.size(), interact::PartState::Static);
  std::vector<char> started(lanes_.size(), 0);
  const auto segment = [&](std::size_t lane, double from, double to, interact::PartState s) {
    const QRect r = laneRect(lane);
    const double x0 = xOf(from), x1 = xOf(to);
    if (x1 < kLabel || x0 > right) return;
    p.setPen(Qt::NoPen);
    p.setBrush(toQColor(vaw::view::stateColor(s)));
    p.drawRect(QRectF(x0, r.top(), std::max(1.0, x1 - x0), r.height()));
  };
  for (const auto& t : model_->transitions()) {
    const auto it = laneOf.find(t.part);
    if (it == laneOf.end()) continue;
    const std::size_t lane = it->second;
    segment(lane, since[lane], t.t, started[lane] ? state[lane] : t.from);
    since[lane] = t.t;
    state[lane] = t.to;
    started[lane] = 1;
  }
  for (std::size_t lane = 0; lane < lanes_.size(); ++lane) segment(lane, since[lane], tEnd, state[lane]);
  p.setPen(QPen(QColor(30, 30, 30), 1.2));
  for (const auto& t : model_->transitions()) {
    const auto it = laneOf.find(t.part);
    if (it == laneOf.end()) continue;
    const QRect r = laneRect(it->second);
    const double x = xOf(t.t);
    p.drawLine(QPointF(x, r.top() - 1), QPointF(x, r.bottom() + 1));
  }
  // Refusals: a red cross in the part's lane.
  p.setPen(QPen(QColor(210, 30, 30), 2.0));
  for (const auto& rf : model_->refusals()) {
    const auto it = laneOf.find(rf.part);
    if (it == laneOf.end()) continue;
    const QRect r = laneRect(it->second);
    const double x = xOf(rf.t), y = r.center().y();
    p.drawLine(QPointF(x - 4, y - 4), QPointF(x + 4, y + 4));
    p.drawLine(QPointF(x - 4, y + 4), QPointF(x + 4, y - 4));
  }
  // The recorded future beyond the playhead (after a seek back).
  const int lanesBottom = lanesTop() + static_cast<int>(lanes_.size() + (folded_ ? 1 : 0)) * kLane;
  if (past_ && end_ > playhead_) {
    const double x0 = xOf(playhead_), x1 = xOf(end_);
    p.setPen(Qt::NoPen);
    p.setBrush(QBrush(QColor(255, 255, 255, 150), Qt::BDiagPattern));
    p.drawRect(QRectF(x0, kAxis, x1 - x0, lanesBottom - kAxis));
  }
  p.setClipping(false);
  // Labels.
  p.setPen(palette().text().color());
  for (std::size_t lane = 0; lane < lanes_.size(); ++lane) {
    const QRect r = laneRect(lane);
    const QString name = a ? QString::fromStdString(a->parts[lanes_[lane]].name) : QString();
    p.drawText(QRect(4, r.top(), kLabel - 8, r.height()), Qt::AlignLeft | Qt::AlignVCenter,
               fm.elidedText(name, Qt::ElideRight, kLabel - 8));
  }
  if (folded_ > 0) {
    const QRect r = laneRect(lanes_.size());
    p.setPen(palette().placeholderText().color());
    p.drawText(QRect(4, r.top(), right, r.height()), Qt::AlignLeft | Qt::AlignVCenter,
               tr("%n part(s) without a state change (folded)", nullptr, static_cast<int>(folded_)));
  }
  // The playhead.
  const double xp = xOf(playhead_);
  if (xp >= kLabel && xp <= right) {
    p.setPen(QPen(QColor(220, 40, 40), 2.0));
    p.drawLine(QPointF(xp, 2), QPointF(xp, lanesBottom));
    p.setBrush(QColor(220, 40, 40));
    p.setPen(Qt::NoPen);
    QPainterPath head;
    head.moveTo(xp - 6, 2);
    head.lineTo(xp + 6, 2);
    head.lineTo(xp, 10);
    head.closeSubpath();
    p.drawPath(head);
  }
  // Legend (and the note about the future).
  int x = kLabel;
  const int y = std::max(lanesBottom + 4, area.height() - kLegend + 2);
  p.setPen(palette().text().color());
  for (const interact::PartState s : interact::kAllStates) {
    const QString label = stateName(s);
    p.fillRect(QRect(x, y + 4, 12, 12), toQColor(vaw::view::stateColor(s)));
    p.drawText(QPoint(x + 16, y + 14), label);
    x += 22 + fm.horizontalAdvance(label);
  }
  p.setPen(QPen(QColor(210, 30, 30), 2.0));
  p.drawLine(x, y + 6, x + 8, y + 14);
  p.drawLine(x, y + 14, x + 8, y + 6);
  p.setPen(palette().text().color());
  p.drawText(QPoint(x + 12, y + 14), tr("refused"));
  x += 20 + fm.horizontalAdvance(tr("refused"));
  if (past_ && end_ > playhead_) {
    p.setPen(QColor(160, 90, 0));
    p.drawText(QPoint(x + 8, y + 14), playback_ ? tr("hatched: recorded future; Play replays it")
                                                : tr("hatched: recorded future; Play from here discards it"));
  }
}

QString TimelineView::toolTipAt(const QPoint& pos) const {
  const double tolerance = 5.0;  // px
  if (pos.y() >= kAxis && pos.y() < kAxis + kEditLane) {
    for (const auto& e : model_->entries())
      if (e.kind == TimelineModel::Kind::Edit && std::abs(xOf(e.t) - pos.x()) <= tolerance) return model_->describe(e);
    return {};
  }
  for (std::size_t lane = 0; lane < lanes_.size(); ++lane) {
    if (!laneRect(lane).adjusted(0, -1, 0, 1).contains(pos)) continue;
    QStringList lines;
    for (const auto& e : model_->entries()) {
      if (std::abs(xOf(e.t) - pos.x()) > tolerance) continue;
      const vaw::PartId part = e.kind == TimelineModel::Kind::Transition ? model_->transitions()[e.index].part
                               : e.kind == TimelineModel::Kind::Refusal  ? model_->refusals()[e.index].part
                                                                         : static_cast<vaw::PartId>(-1);
      if (part == lanes_[lane]) lines << model_->describe(e);
    }
    return lines.join(QLatin1Char('\n'));
  }
  return {};
}

bool TimelineView::event(QEvent* e) {
  if (e->type() == QEvent::ToolTip) {
    const auto* help = static_cast<QHelpEvent*>(e);
    const QString text = toolTipAt(help->pos());
    if (text.isEmpty()) QToolTip::hideText();
    else QToolTip::showText(help->globalPos(), text, this);
    return true;
  }
  return QWidget::event(e);
}

void TimelineView::mousePressEvent(QMouseEvent* e) {
  dragStart_ = e->pos();
  dragT0_ = t0_;
  dragT1_ = t1_;
  const bool pan = e->button() == Qt::RightButton || e->button() == Qt::MiddleButton ||
                   (e->button() == Qt::LeftButton && (e->modifiers() & Qt::ShiftModifier));
  if (pan) {
    drag_ = Drag::Pan;
    followed_ = false;
  } else if (e->button() == Qt::LeftButton && e->pos().x() >= kLabel) {
    // On the axis, on the playhead or anywhere in the lanes: the playhead goes there.
    drag_ = Drag::Playhead;
    emit seekRequested(std::clamp(timeAt(e->position().x()), 0.0, std::max(end_, playhead_)));
  }
}

void TimelineView::mouseMoveEvent(QMouseEvent* e) {
  if (drag_ == Drag::Playhead) {
    emit seekRequested(std::clamp(timeAt(e->position().x()), 0.0, std::max(end_, playhead_)));
  } else if (drag_ == Drag::Pan) {
    const double w = std::max(1, width() - kLabel - 8);
    const double shift = (e->pos().x() - dragStart_.x()) / w * (dragT1_ - dragT0_);
    t0_ = dragT0_ - shift;
    t1_ = dragT1_ - shift;
    update();
  }
}

void TimelineView::mouseReleaseEvent(QMouseEvent*) { drag_ = Drag::None; }

void TimelineView::mouseDoubleClickEvent(QMouseEvent*) {
  // Fit the whole recording and follow the playhead again.
  t0_ = 0.0;
  t1_ = std::max({5.0, end_ * 1.05, playhead_ * 1.05});
  followed_ = true;
  update();
}

void TimelineView::wheelEvent(QWheelEvent* e) {
  const double factor = std::pow(0.85, e->angleDelta().y() / 120.0);
  const double at = timeAt(e->position().x());
  t0_ = at - (at - t0_) * factor;
  t1_ = at + (t1_ - at) * factor;
  if (t1_ - t0_ < 0.05) {
    const double mid = 0.5 * (t0_ + t1_);
    t0_ = mid - 0.025;
    t1_ = mid + 0.025;
  }
  followed_ = false;
  update();
  e->accept();
}

}  // namespace vaw::ui
