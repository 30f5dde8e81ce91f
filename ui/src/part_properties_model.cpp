#include "vaw/ui/part_properties_model.hpp"

#include <QBrush>
#include <QColor>
#include <QFont>

#include "format.hpp"

namespace vaw::ui {

namespace {

QString moments(const Eigen::Vector3d& m) {
  return QStringLiteral("%1, %2, %3 kg·m²")
      .arg(format::number(m.x()), format::number(m.y()), format::number(m.z()));
}

}  // namespace

PartPropertiesModel::PartPropertiesModel(QObject* parent) : QAbstractTableModel(parent) {}

void PartPropertiesModel::setPart(const vaw::Assembly* assembly, std::optional<vaw::PartId> part,
                                  const vaw::collision::ObjectInfo* collision) {
  beginResetModel();
  rows_.clear();
  part_.reset();
  if (assembly != nullptr && part && *part < assembly->parts.size()) {
    part_ = part;
    const vaw::Part& p = assembly->parts[*part];
    const auto add = [this](QString property, QString value, QString toolTip = {}, bool warn = false) {
      rows_.push_back(Row{std::move(property), std::move(value), std::move(toolTip), warn});
    };
    add(tr("Name"), format::str(p.name));
    if (assembly->base && *assembly->base == p.id) add(tr("Role"), tr("base (held in the left hand)"));
    add(tr("Category"), format::str(std::string(vaw::name(p.category.category))),
        format::str(p.category.reason));
    add(tr("Category reason"), format::str(p.category.reason));
    add(tr("Mass"), format::mass(p.mass.mass), tr("%1 kg").arg(p.mass.mass, 0, 'g', 10));
    const bool fromFile = p.massSource == vaw::MassSource::PropertyFile;
    add(tr("Mass source"),
        fromFile ? tr("property file") : tr("mesh and density"),
        fromFile ? format::str(p.propertyFile.string()) : QString());
    add(tr("Volume"), format::volume(p.mass.volume));
    if (p.mass.density > 0.0) add(tr("Density"), tr("%1 kg/m³").arg(format::number(p.mass.density)));
    add(tr("Centre of mass"), format::vectorMm(p.mass.centerOfMass), tr("in the part's own frame"));
    add(tr("Principal moments"), moments(p.principal.moments), tr("about the centre of mass, ascending"));
    add(tr("Largest extent"), format::lengthMm(p.extent), tr("along the principal axes"));
    if (p.mass.surfaceArea) add(tr("Surface area"), tr("%1 cm²").arg(format::number(*p.mass.surfaceArea * 1e4)));
    if (fromFile && p.meshMass) {
      add(tr("Mesh mass"), format::mass(p.meshMass->mass), tr("computed from the mesh and the density"));
    }
    if (p.disagreement) {
      const vaw::MassComparison& d = *p.disagreement;
      const double limit = 0.01;  // vaw::LoadOptions::massDisagreementWarning's default
      add(tr("File vs. mesh"),
          tr("mass %1, volume %2, CoM %3, inertia %4")
              .arg(format::percent(d.massRel), format::percent(d.volumeRel), format::lengthMm(d.comDistance),
                   format::percent(d.inertiaRel)),
          tr("relative differences between the property file and the mesh; worst %1")
              .arg(format::percent(d.worst())),
          d.worst() > limit);
    }
    add(tr("Triangles"), p.mesh ? QString::number(p.mesh->triangleCount()) : tr("none"));
    add(tr("Shape"), format::str(p.shapeSource));
    if (collision != nullptr) add(tr("Collision"), format::collision(*collision), format::str(collision->proxyReason));
    if (collision != nullptr && !collision->fit.empty())
      add(tr("Fit"), format::str(collision->fit), tr("how its constraints meet the base (a bore on a shaft: the clearance)"));
    add(tr("Material"), format::str(p.material));
    add(tr("Position"), format::vectorMm(p.pose.translation()), tr("part frame origin in the world"));
    if (!p.propertyFile.empty()) add(tr("Property file"), format::str(p.propertyFile.string()));
  }
  endResetModel();
}

QString PartPropertiesModel::value(const QString& property) const {
  for (const auto& row : rows_) {
    if (row.property == property) return row.value;
  }
  return {};
}

int PartPropertiesModel::rowCount(const QModelIndex& parent) const {
  return parent.isValid() ? 0 : static_cast<int>(rows_.size());
}

int PartPropertiesModel::columnCount(const QModelIndex& parent) const {
  return parent.isValid() ? 0 : ColumnCount;
}

QVariant PartPropertiesModel::data(const QModelIndex& index, int role) const {
  if (!checkIndex(index, CheckIndexOption::IndexIsValid | CheckIndexOption::ParentIsInvalid)) return {};
  const Row& row = rows_[static_cast<std::size_t>(index.row())];
  switch (role) {
    case Qt::DisplayRole: return index.column() == PropertyColumn ? row.property : row.value;
    case Qt::ToolTipRole: return row.toolTip.isEmpty() ? QVariant() : QVariant(row.toolTip);
    case Qt::ForegroundRole:
      return row.warn && index.column() == ValueColumn ? QVariant(QBrush(QColor(200, 60, 20))) : QVariant();
    case Qt::FontRole:
      if (index.column() == PropertyColumn) {
        QFont font;
        font.setBold(true);
        return font;
      }
      return {};
    default: return {};
  }
}

QVariant PartPropertiesModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (orientation != Qt::Horizontal || role != Qt::DisplayRole) return {};
  switch (section) {
    case PropertyColumn: return tr("Property");
    case ValueColumn: return tr("Value");
    default: return {};
  }
}

}  // namespace vaw::ui
