#pragma once
// The part-state inspector: the selected part as a two-column table (property, value). First what it is
// doing now, updated as it moves (state and time in it, holder, motion model and method, the constraint it
// rests by, its model coordinates, world position, velocity, angular velocity, kinetic and potential
// energy, its last transition and refusal with their causes); then what it is (mass, volume, centre of
// mass, the full inertia tensor, principal moments and axes, category and why, where the mass properties
// come from and how far the property file and the mesh disagree, triangle count, shape, collision proxy).
// Live updates change only the cells whose text changed. Copies what it shows.
#include <QAbstractTableModel>
#include <QString>
#include <optional>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/collision/collision_world.hpp"
#include "vaw/sim/report.hpp"

namespace vaw::ui {

class PartPropertiesModel : public QAbstractTableModel {
  Q_OBJECT
 public:
  enum Column { PropertyColumn, ValueColumn, ColumnCount };

  explicit PartPropertiesModel(QObject* parent = nullptr);

  // Shows `part` of `assembly`; nothing when either is missing. `collision`: how the part collides.
  void setPart(const vaw::Assembly* assembly, std::optional<vaw::PartId> part,
               const vaw::collision::ObjectInfo* collision = nullptr);
  [[nodiscard]] std::optional<vaw::PartId> part() const { return part_; }
  // The live rows (added first on the first call, then updated in place).
  void updateLive(const vaw::sim::PartReport& report);
  [[nodiscard]] bool hasLive() const { return liveRows_ > 0; }
  // The volume the part's carried path swept (the Path panel), as a last row; empty removes it.
  void setSwept(const QString& value, const QString& toolTip = {});
  // The value shown for a property (by its label), empty if absent. For tests and tools.
  [[nodiscard]] QString value(const QString& property) const;

  [[nodiscard]] int rowCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] int columnCount(const QModelIndex& parent = {}) const override;
  [[nodiscard]] QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
  [[nodiscard]] QVariant headerData(int section, Qt::Orientation orientation,
                                    int role = Qt::DisplayRole) const override;

 private:
  struct Row {
    QString property;
    QString value;
    QString toolTip;
    bool warn = false;  // shown highlighted (e.g. a large file/mesh disagreement)
    bool live = false;  // part of the live section (shown on a tinted background)
  };
  std::vector<Row> rows_;
  std::size_t liveRows_ = 0;  // rows_[0, liveRows_) are the live section
  std::optional<vaw::PartId> part_;
};

}  // namespace vaw::ui
