#pragma once
// The selected part's properties as a two-column table (property, value): mass, volume, centre of
// mass, principal moments, category and why, where the mass properties come from and how far the
// property file and the mesh disagree, triangle count and shape source. Copies what it shows.
#include <QAbstractTableModel>
#include <QString>
#include <optional>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/collision/collision_world.hpp"

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
  };
  std::vector<Row> rows_;
  std::optional<vaw::PartId> part_;
};

}  // namespace vaw::ui
