#pragma once
// The state-transition timeline: one lane per part that has changed state (the others folded into one
// line), coloured state segments with a legend, event markers with their cause on hover, refusals marked,
// edits on a lane of their own, zoom (wheel) and pan (drag with the right or middle button, or Shift+drag),
// and a playhead that follows the simulation. Dragging the playhead (or clicking the time axis) asks to
// seek there; the recorded future beyond the playhead is hatched, with a note that playing from the past
// discards it. Exports as PNG and as CSV (the columns of `vaw-sim run`'s transitions.csv).
//
// TimelineModel holds the recording's log as a table (one row per transition, refusal or edit, in time
// order); TimelineView draws it.
#include <QAbstractTableModel>
#include <QWidget>
#include <optional>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/sim/world.hpp"

namespace vaw::ui {

class TimelineModel : public QAbstractTableModel {
  Q_OBJECT
 public:
  enum Column { StepColumn, TimeColumn, PartColumn, FromColumn, ToColumn, EventColumn, CauseColumn, ColumnCount };
  enum class Kind { Transition, Refusal, Edit };
  struct Entry {
    Kind kind = Kind::Transition;
    std::size_t index = 0;  // into transitions(), refusals() or edits()
    double t = 0.0;
  };

  explicit TimelineModel(QObject* parent = nullptr);

  // The recording's log. Appends become row insertions; anything else (a discarded future) a reset.
  void setLog(const vaw::Assembly* assembly, const std::vector<vaw::sim::TransitionRecord>& transitions,
              const std::vector<vaw::sim::Refusal>& refusals, const std::vector<vaw::sim::EditRecord>& edits);
  void clear();

  [[nodiscard]] const vaw::Assembly* assembly() const { return assembly_; }
  [[nodiscard]] const std::vector<vaw::sim::TransitionRecord>& transitions() const { return transitions_; }
  [[nodiscard]] const std::vector<vaw::sim::Refusal>& refusals() const { return refusals_; }
  [[nodiscard]] const std::vector<vaw::sim::EditRecord>& edits() const { return edits_; }
  [[nodiscard]] const std::vector<Entry>& entries() const { return entries_; }
  // One line for a tooltip or a message.
  [[nodiscard]] QString describe(const Entry& e) const;
  // Writes the transitions and refusals as CSV (vaw::sim::writeTransitionsCsv). Throws vaw::InputError.
  void writeCsv(const QString& file) const;

  [[nodiscard]] int rowCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] int columnCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
  [[nodiscard]] QVariant headerData(int section, Qt::Orientation orientation, int role = Qt::DisplayRole) const override;

 private:
  static std::vector<Entry> entriesOf(const std::vector<vaw::sim::TransitionRecord>& transitions,
                                      const std::vector<vaw::sim::Refusal>& refusals,
                                      const std::vector<vaw::sim::EditRecord>& edits);
  const vaw::Assembly* assembly_ = nullptr;
  std::vector<vaw::sim::TransitionRecord> transitions_;
  std::vector<vaw::sim::Refusal> refusals_;
  std::vector<vaw::sim::EditRecord> edits_;
  std::vector<Entry> entries_;
};

class TimelineView : public QWidget {
  Q_OBJECT
 public:
  explicit TimelineView(TimelineModel* model, QWidget* parent = nullptr);

  // The playhead and the recording's span (s), whether the world is before the recording's end, and whether
  // Play replays the recording (an opened session) rather than recording anew from the playhead.
  void setTimes(double playhead, double end, bool past, bool playback = false);
  [[nodiscard]] double playhead() const { return playhead_; }
  [[nodiscard]] double visibleStart() const { return t0_; }
  [[nodiscard]] double visibleEnd() const { return t1_; }
  void setVisibleRange(double start, double end);
  // Lanes shown, top to bottom: the parts that changed state (by id).
  [[nodiscard]] const std::vector<vaw::PartId>& lanes() const { return lanes_; }
  // Where things are drawn (widget coordinates), for tests and tools.
  [[nodiscard]] double xOf(double t) const;
  [[nodiscard]] double timeAt(double x) const;
  [[nodiscard]] QRect laneRect(std::size_t lane) const;
  [[nodiscard]] int axisHeight() const { return kAxis; }
  // The whole timeline as an image (what File > Export Timeline writes).
  [[nodiscard]] QImage render(qreal scale = 2.0) const;

  [[nodiscard]] QSize sizeHint() const override;
  [[nodiscard]] QSize minimumSizeHint() const override;

 signals:
  void seekRequested(double seconds);

 protected:
  void paintEvent(QPaintEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void mouseDoubleClickEvent(QMouseEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;
  bool event(QEvent* event) override;

 private:
  static constexpr int kLabel = 130, kAxis = 22, kLane = 20, kLegend = 22, kEditLane = 14;
  void relayout();
  void draw(QPainter& p, const QRect& area) const;
  [[nodiscard]] QString toolTipAt(const QPoint& pos) const;
  [[nodiscard]] int lanesTop() const { return kAxis + kEditLane; }

  TimelineModel* model_;
  std::vector<vaw::PartId> lanes_;
  std::size_t folded_ = 0;  // parts without a transition
  double playhead_ = 0.0, end_ = 0.0;
  bool past_ = false;
  bool playback_ = false;
  double t0_ = 0.0, t1_ = 5.0;  // visible time range (s)
  bool followed_ = true;        // the view follows the playhead until the user zooms or pans
  enum class Drag { None, Playhead, Pan } drag_ = Drag::None;
  QPoint dragStart_;
  double dragT0_ = 0.0, dragT1_ = 0.0;
};

}  // namespace vaw::ui
