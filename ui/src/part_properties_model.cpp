#include "vaw/ui/part_properties_model.hpp"

#include <algorithm>

#include <QBrush>
#include <QColor>
#include <QFont>

#include "format.hpp"

#include <QStringList>
#include <cmath>
#include <numbers>

namespace vaw::ui {

namespace {

QString moments(const Eigen::Vector3d& m) {
  return QStringLiteral("%1, %2, %3 kg·m²")
      .arg(format::number(m.x()), format::number(m.y()), format::number(m.z()));
}

QString vec(const Eigen::Vector3d& v, const QString& unit, double scale = 1.0) {
  const auto n = [scale](double x) { return format::number(std::abs(x * scale) < 1e-12 ? 0.0 : x * scale); };
  return QStringLiteral("(%1, %2, %3) %4").arg(n(v.x()), n(v.y()), n(v.z()), unit);
}

QString tensor(const Eigen::Matrix3d& m) {
  QStringList rows;
  for (int r = 0; r < 3; ++r)
    rows << QStringLiteral("%1  %2  %3").arg(format::number(m(r, 0)), format::number(m(r, 1)), format::number(m(r, 2)));
  return rows.join(QLatin1Char('\n')) + QStringLiteral("  kg·m²");
}

QString stateName(interact::PartState s) { return format::str(std::string(interact::name(s))); }

}  // namespace

PartPropertiesModel::PartPropertiesModel(QObject* parent) : QAbstractTableModel(parent) {}

void PartPropertiesModel::setPart(const vaw::Assembly* assembly, std::optional<vaw::PartId> part,
                                  const vaw::collision::ObjectInfo* collision) {
  beginResetModel();
  rows_.clear();
  liveRows_ = 0;
  part_.reset();
  if (assembly != nullptr && part && *part < assembly->parts.size()) {
    part_ = part;
    const vaw::Part& p = assembly->parts[*part];
    const auto add = [this](QString property, QString value, QString toolTip = {}, bool warn = false) {
      rows_.push_back(Row{std::move(property), std::move(value), std::move(toolTip), warn, false});
    };
    add(tr("Name"), format::str(p.name));
    if (!p.product.empty() && p.product != p.name) add(tr("Product"), format::str(p.product), tr("the CAD file's own name for the part"));
    if (assembly->base && *assembly->base == p.id) add(tr("Role"), tr("base (held in the left hand)"));
    add(tr("Category"), format::str(std::string(vaw::name(p.category.category))),
        format::str(p.category.reason));
    add(tr("Category reason"), format::str(p.category.reason));
    add(tr("Mass"), format::mass(p.mass.mass), tr("%1 kg").arg(p.mass.mass, 0, 'g', 10));
    const bool brep = p.massSource == vaw::MassSource::Brep;
    const bool fromFile = p.massSource == vaw::MassSource::PropertyFile || brep;
    add(tr("Mass source"),
        brep ? tr("exact B-rep and density") : fromFile ? tr("property file") : tr("mesh and density"),
        brep ? tr("integrated over the CAD file's boundary representation: %1").arg(format::str(assembly->cadFile.string()))
             : fromFile ? format::str(p.propertyFile.string()) : QString());
    add(tr("Volume"), format::volume(p.mass.volume));
    if (p.mass.density > 0.0) add(tr("Density"), tr("%1 kg/m³").arg(format::number(p.mass.density)));
    add(tr("Centre of mass"), format::vectorMm(p.mass.centerOfMass), tr("in the part's own frame"));
    add(tr("Inertia tensor"), tensor(p.mass.inertiaCm), tr("about the centre of mass, in the part's own axes"));
    add(tr("Principal moments"), moments(p.principal.moments), tr("about the centre of mass, ascending"));
    add(tr("Principal axes"),
        QStringLiteral("%1\n%2\n%3")
            .arg(vec(p.principal.axes.col(0), QString()), vec(p.principal.axes.col(1), QString()),
                 vec(p.principal.axes.col(2), QString())),
        tr("unit vectors in the part's own frame, in the order of the moments"));
    add(tr("Largest extent"), format::lengthMm(p.extent), tr("along the principal axes"));
    if (p.mass.surfaceArea) add(tr("Surface area"), tr("%1 cm²").arg(format::number(*p.mass.surfaceArea * 1e4)));
    if (fromFile && p.meshMass) {
      add(tr("Mesh mass"), format::mass(p.meshMass->mass), tr("computed from the mesh and the density"));
    }
    if (p.disagreement) {
      const vaw::MassComparison& d = *p.disagreement;
      const double limit = 0.01;  // vaw::LoadOptions::massDisagreementWarning's default
      add(brep ? tr("B-rep vs. mesh") : tr("File vs. mesh"),
          tr("mass %1, volume %2, CoM %3, inertia %4")
              .arg(format::percent(d.massRel), format::percent(d.volumeRel), format::lengthMm(d.comDistance),
                   format::percent(d.inertiaRel)),
          (brep ? tr("relative differences between the exact B-rep and its tessellation; worst %1")
                : tr("relative differences between the property file and the mesh; worst %1"))
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

void PartPropertiesModel::updateLive(const vaw::sim::PartReport& r) {
  if (!part_) return;
  std::vector<Row> live;
  const auto add = [&live](QString property, QString value, QString toolTip = {}, bool warn = false) {
    live.push_back(Row{std::move(property), std::move(value), std::move(toolTip), warn, true});
  };
  add(tr("State"), stateName(r.state));
  add(tr("Time in state"), tr("%1 s").arg(format::number(r.timeInState)));
  add(tr("Holder"), format::str(std::string(vaw::sim::name(r.holder))));
  add(tr("Motion model"), format::str(r.modelName));
  add(tr("Method"), r.method.empty() ? tr("—") : format::str(r.method));
  add(tr("Constraint"), r.constraint.empty() ? tr("—") : format::str(r.constraint));
  // Only a part turning on its shaft has a swing whose stability means something.
  if (r.stability && r.model == vaw::sim::Model::Cylindrical) {
    const bool warn = r.stability->level != vaw::sim::StabilityAdvice::Level::Stable;
    add(tr("Stability"), format::str(r.stability->text), format::str(r.stability->report.message), warn);
  }
  QString coordinates = tr("—");
  switch (r.model) {
    case vaw::sim::Model::Cylindrical:
      coordinates = tr("angle %1° at %2°/s; slide %3 mm at %4 mm/s")
                        .arg(format::number(r.angle * 180.0 / std::numbers::pi), format::number(r.omega * 180.0 / std::numbers::pi),
                             format::number(r.slide * 1e3), format::number(r.slideRate * 1e3));
      break;
    case vaw::sim::Model::Plane:
      coordinates = tr("(%1, %2) mm at (%3, %4) mm/s")
                        .arg(format::number(r.planePosition.x() * 1e3), format::number(r.planePosition.y() * 1e3),
                             format::number(r.planeVelocity.x() * 1e3), format::number(r.planeVelocity.y() * 1e3));
      break;
    default: break;
  }
  add(tr("Coordinates"), coordinates, tr("the coordinates of its state's model, in the base's frame"));
  add(tr("World position"), format::vectorMm(r.centreOfMass), tr("centre of mass, world"));
  add(tr("Velocity"), vec(r.velocity, QStringLiteral("m/s")),
      r.state == interact::PartState::InHand ? tr("what a release now would give it") : tr("centre of mass, world"));
  add(tr("Angular velocity"), vec(r.angularVelocity, QStringLiteral("°/s"), 180.0 / std::numbers::pi), tr("world axes"));
  add(tr("Kinetic energy"), tr("%1 J").arg(format::number(r.kineticEnergy)), tr("translation and rotation"));
  add(tr("Potential energy"), tr("%1 J").arg(format::number(r.potentialEnergy)),
      tr("m g z of the centre of mass, standard gravity, z = 0 at the world origin"));
  if (r.lastTransition) {
    const auto& t = *r.lastTransition;
    add(tr("Last transition"),
        tr("%1 → %2 (%3) at %4 s")
            .arg(stateName(t.from), stateName(t.to), format::str(std::string(interact::name(t.event))), format::number(t.t)),
        format::str(t.cause));
    add(tr("Cause"), format::str(t.cause));
  } else {
    add(tr("Last transition"), tr("none yet"));
    add(tr("Cause"), tr("—"));
  }
  add(tr("Last refusal"),
      r.lastRefusal ? tr("%1 at %2 s: %3")
                          .arg(format::str(std::string(interact::name(r.lastRefusal->event))),
                               format::number(r.lastRefusal->t), format::str(r.lastRefusal->reason))
                    : tr("none"),
      r.lastRefusal ? format::str(r.lastRefusal->reason) : QString(), r.lastRefusal.has_value());
  if (liveRows_ != 0 && liveRows_ != live.size()) {  // a row came or went (the stability of a swing)
    beginRemoveRows({}, 0, static_cast<int>(liveRows_) - 1);
    rows_.erase(rows_.begin(), rows_.begin() + static_cast<std::ptrdiff_t>(liveRows_));
    liveRows_ = 0;
    endRemoveRows();
  }
  if (liveRows_ == 0) {
    beginInsertRows({}, 0, static_cast<int>(live.size()) - 1);
    rows_.insert(rows_.begin(), live.begin(), live.end());
    liveRows_ = live.size();
    endInsertRows();
    return;
  }
  for (std::size_t i = 0; i < live.size() && i < liveRows_; ++i) {
    Row& row = rows_[i];
    if (row.value == live[i].value && row.toolTip == live[i].toolTip && row.warn == live[i].warn) continue;
    row = live[i];
    emit dataChanged(index(static_cast<int>(i), ValueColumn), index(static_cast<int>(i), ValueColumn));
  }
}

void PartPropertiesModel::setSwept(const QString& value, const QString& toolTip) {
  const QString label = tr("Swept volume");
  const auto it = std::find_if(rows_.begin(), rows_.end(), [&](const Row& r) { return r.property == label; });
  if (it == rows_.end()) {
    if (value.isEmpty() || !part_) return;
    const int at = static_cast<int>(rows_.size());
    beginInsertRows({}, at, at);
    rows_.push_back(Row{label, value, toolTip, false, false});
    endInsertRows();
  } else if (value.isEmpty()) {
    const int at = static_cast<int>(it - rows_.begin());
    beginRemoveRows({}, at, at);
    rows_.erase(it);
    endRemoveRows();
  } else {
    it->value = value;
    it->toolTip = toolTip;
    const int at = static_cast<int>(it - rows_.begin());
    emit dataChanged(index(at, 0), index(at, ColumnCount - 1));
  }
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
    case Qt::BackgroundRole: return row.live ? QVariant(QBrush(QColor(236, 244, 252))) : QVariant();
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
