#include "vaw/ui/constraints_dock.hpp"
#include "format.hpp"

#include <QActionGroup>
#include <QFont>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QItemSelectionModel>
#include <QLabel>
#include <QMainWindow>
#include <QMenu>
#include <QPushButton>
#include <QShortcut>
#include <QStandardItemModel>
#include <QStatusBar>
#include <QTableView>
#include <QTreeView>
#include <QUndoStack>
#include <QVBoxLayout>
#include <QtConcurrent/QtConcurrentRun>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "vaw/constraint_recognition.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/background.hpp"
#include "vaw/ui/docks.hpp"
#include "vaw/ui/scene_tree_model.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/viewport.hpp"

namespace vaw::ui {

namespace {

using format::str;

// Where a constraint's partner stands when the assembly is assembled: its final pose, or the base's pose.
Eigen::Isometry3d assembledPose(const vaw::Assembly& a, vaw::PartId id) {
  const vaw::Part& p = a.parts[id];
  return p.finalPose.value_or(p.pose);
}

vaw::PartId partnerOf(const vaw::Assembly& a, const vaw::Constraint& c) { return c.partner ? *c.partner : a.base.value_or(0); }

// "-0.0" reads as a sign that means something.
QString fixed(double value, int decimals) {
  QString s = QString::number(value, 'f', decimals);
  if (s.startsWith(QLatin1Char('-')) && s.mid(1).remove(QLatin1Char('0')).remove(QLatin1Char('.')).isEmpty()) s.remove(0, 1);
  return s;
}

QString mm(double metres) { return fixed(metres * 1000.0, 1); }

QString pointMm(const Eigen::Vector3d& p) { return QStringLiteral("(%1, %2, %3) mm").arg(mm(p.x()), mm(p.y()), mm(p.z())); }

QString direction(const Eigen::Vector3d& d) {
  const auto c = [](double x) {
    if (std::abs(x) < 5e-4) x = 0.0;
    return QString::number(x, 'g', 3);
  };
  return QStringLiteral("(%1, %2, %3)").arg(c(d.x()), c(d.y()), c(d.z()));
}

// An insert's fit as a fitter names it ("threaded M6", "clearance, counterbore"); a mate has none unless it
// holds a part between two faces (a key).
QString fitText(const vaw::Constraint& c) {
  if (c.type == vaw::Constraint::Type::Mate && c.found && c.found->keyWidth > 0.0)
    return QObject::tr("prismatic, %1 mm wide").arg(fixed(c.found->keyWidth * 1000.0, 1));
  if (c.type != vaw::Constraint::Type::Insert || !c.found) return QStringLiteral("—");
  QString text = str(vaw::name(c.found->fit));
  if (!c.found->thread.empty()) text += QLatin1Char(' ') + str(c.found->thread);
  if (c.found->seat != vaw::Constraint::Found::Seat::None) text += QStringLiteral(", ") + str(vaw::name(c.found->seat));
  return text;
}

QString geometryText(const vaw::Assembly& a, const vaw::Constraint& c) {
  const Eigen::Isometry3d Q = assembledPose(a, partnerOf(a, c));
  if (c.type == vaw::Constraint::Type::Insert) {
    return QObject::tr("axis through %1 along %2")
        .arg(pointMm(Q * c.baseAxis.point), direction((Q.linear() * c.baseAxis.direction).normalized()));
  }
  const Eigen::Vector3d n = (Q.linear() * c.basePlane.normal).normalized();
  const Eigen::Vector3d p = Q * c.basePlane.point;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(n[k]) > 1.0 - 1e-9) {
      static const char* axes[3] = {"x", "y", "z"};
      return QObject::tr("plane %1 = %2 mm, normal %3").arg(QLatin1String(axes[k]), mm(p[k]), direction(n));
    }
  }
  return QObject::tr("plane through %1, normal %2").arg(pointMm(p), direction(n));
}

// Whether two constraints tie the same two parts by the same faces, either way round: the same axis (and
// radii, where measured) or the same plane, compared in world terms at the assembled poses.
bool sameConstraint(const vaw::Assembly& a, const vaw::Constraint& c, const vaw::Constraint& d) {
  const vaw::PartId cp = partnerOf(a, c), dp = partnerOf(a, d);
  if (c.type != d.type || !((c.part == d.part && cp == dp) || (c.part == dp && cp == d.part))) return false;
  const double near = 1e-6;  // m; recognition's own tolerance is 1e-5 m, exports round at ~1e-6 m
  const Eigen::Isometry3d P = assembledPose(a, cp), Q = assembledPose(a, dp);
  if (c.type == vaw::Constraint::Type::Insert) {
    const Eigen::Vector3d u = (P.linear() * c.baseAxis.direction).normalized(),
                          v = (Q.linear() * d.baseAxis.direction).normalized();
    const Eigen::Vector3d rel = Q * d.baseAxis.point - P * c.baseAxis.point;
    if (u.cross(v).norm() > near || (rel - u * u.dot(rel)).norm() > near) return false;
    if (!c.found || !d.found) return true;
    const auto radii = [](const vaw::Constraint::Found& f) -> std::pair<double, double> {
      return std::minmax(f.partRadius, f.partnerRadius);
    };
    const auto [c0, c1] = radii(*c.found);
    const auto [d0, d1] = radii(*d.found);
    return std::abs(c0 - d0) < near && std::abs(c1 - d1) < near;
  }
  const Eigen::Vector3d n = (P.linear() * c.basePlane.normal).normalized(), m = (Q.linear() * d.basePlane.normal).normalized();
  return std::abs(n.dot(m)) > 1.0 - 1e-9 && std::abs(n.dot(Q * d.basePlane.point - P * c.basePlane.point)) < near;
}

QString faceText(const vaw::CadFace& f) {
  switch (f.surface) {
    case vaw::CadFace::Surface::Plane: return QObject::tr("a flat face");
    case vaw::CadFace::Surface::Cylinder:
      return f.convex ? QObject::tr("a shaft of radius %1 mm").arg(fixed(f.radius * 1000.0, 2))
                      : QObject::tr("a hole of radius %1 mm").arg(fixed(f.radius * 1000.0, 2));
    case vaw::CadFace::Surface::Cone:
      return f.convex ? QObject::tr("a cone of %1 degrees (a countersunk head)")
                            .arg(fixed(2.0 * f.halfAngle * 180.0 / std::numbers::pi, 0))
                      : QObject::tr("a countersink of %1 degrees").arg(fixed(2.0 * f.halfAngle * 180.0 / std::numbers::pi, 0));
    case vaw::CadFace::Surface::Other: break;
  }
  return QObject::tr("a curved face");
}

}  // namespace

vaw::Constraint swapped(const vaw::Constraint& c, const vaw::Assembly& assembly) {
  vaw::Constraint s = c;
  const vaw::PartId oldPart = c.part, oldPartner = c.partner.value();
  s.part = oldPartner;
  s.partner = oldPart;
  // Each member holds its own part's geometry in that part's frame: exchanging the parts exchanges them.
  std::swap(s.partAxis, s.baseAxis);
  std::swap(s.partPlane, s.basePlane);
  if (s.found) std::swap(s.found->partRadius, s.found->partnerRadius);
  // The offset is measured along the partner's normal: a mate's normals are opposed, so it reads the same
  // from either side; an align's are equal, so it changes sign.
  if (c.type == vaw::Constraint::Type::Align) s.offset = -c.offset;
  // The old part came home along -h relative to the old partner; seen from the old part, the old partner
  // comes home along +h. In world terms at the assembled poses that is -(Q h), expressed in P's frame.
  const Eigen::Isometry3d P = assembledPose(assembly, oldPart), Q = assembledPose(assembly, oldPartner);
  s.homeDirection = (P.linear().transpose() * (Q.linear() * -c.homeDirection)).normalized();
  // A generated name says which part goes on which: it follows the swap. A name the user gave is kept.
  const std::string kind(vaw::name(c.type));
  const std::string prefix = kind + " " + assembly.parts[oldPart].name + " on " + assembly.parts[oldPartner].name;
  if (c.name.rfind(prefix, 0) == 0)
    s.name = kind + " " + assembly.parts[oldPartner].name + " on " + assembly.parts[oldPart].name + c.name.substr(prefix.size());
  return s;
}

ConstraintsModel::ConstraintsModel(QObject* parent) : QAbstractTableModel(parent) {}

void ConstraintsModel::setScene(std::shared_ptr<const vaw::sim::Scene> scene) {
  beginResetModel();
  scene_ = std::move(scene);
  endResetModel();
}

std::vector<vaw::Constraint> ConstraintsModel::constraints() const {
  return scene_ ? scene_->assembly().constraints : std::vector<vaw::Constraint>{};
}

int ConstraintsModel::rowCount(const QModelIndex& parent) const {
  return parent.isValid() || !scene_ ? 0 : static_cast<int>(scene_->assembly().constraints.size());
}

int ConstraintsModel::columnCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : ColumnCount; }

QVariant ConstraintsModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (orientation != Qt::Horizontal) return {};
  if (role == Qt::DisplayRole) {
    switch (section) {
      case PartColumn: return tr("Part");
      case PartnerColumn: return tr("Partner");
      case KindColumn: return tr("Kind");
      case FitColumn: return tr("Fit");
      case GeometryColumn: return tr("Geometry");
      case ClearanceColumn: return tr("Clearance");
      case OverlapColumn: return tr("Overlap");
      case StatusColumn: return tr("Status");
      default: return {};
    }
  }
  if (role == Qt::ToolTipRole) {
    switch (section) {
      case PartColumn: return tr("The part the constraint guides home");
      case PartnerColumn: return tr("What it goes onto: another part, or the base");
      case FitColumn:
        return tr(
            "How an insert's shaft sits in its bore: with play (clearance), a screw at its nominal size in a hole "
            "modelled at its tap drill (threaded), a press fit; a head in a counterbore or a countersink; and a key in its "
            "slot (prismatic)");
      case GeometryColumn:
        return tr(
            "The partner's axis (insert) or face plane (mate, align), in world coordinates with the partner at "
            "its assembled pose");
      case ClearanceColumn: return tr("Radial play between the shaft and the bore (inserts)");
      case OverlapColumn: return tr("Area the two faces share (mates), length the shaft sits in the bore (inserts)");
      case StatusColumn: return tr("found: recognised, not reviewed yet; accepted: confirmed, and saved so");
      default: return {};
    }
  }
  return {};
}

QVariant ConstraintsModel::data(const QModelIndex& index, int role) const {
  if (!scene_ || !index.isValid() || index.row() >= rowCount()) return {};
  const vaw::Assembly& a = scene_->assembly();
  const vaw::Constraint& c = a.constraints[static_cast<std::size_t>(index.row())];
  const bool insert = c.type == vaw::Constraint::Type::Insert;
  const vaw::PartId partner = partnerOf(a, c);
  const QString notMeasured = tr("Not measured: read from the scene file (what recognition measured is not saved)");
  if (role == Qt::DisplayRole) {
    switch (index.column()) {
      case PartColumn: return str(a.parts[c.part].name);
      case PartnerColumn: return c.partner ? str(a.parts[partner].name) : tr("%1 (base)").arg(str(a.parts[partner].name));
      case KindColumn: return str(vaw::name(c.type));
      case FitColumn: return fitText(c);
      case GeometryColumn: return geometryText(a, c);
      case ClearanceColumn:
        if (!insert || !c.found) return QStringLiteral("—");
        return tr("%1 mm").arg(fixed(c.found->clearance * 1000.0, 3));
      case OverlapColumn:
        if (!c.found) return QStringLiteral("—");
        return insert ? tr("%1 mm").arg(mm(c.found->overlap)) : tr("%1 mm²").arg(fixed(c.found->overlap * 1e6, 1));
      case StatusColumn:
        if (c.accepted) return tr("accepted");
        return c.found || !a.cadFile.empty() ? tr("found") : tr("declared");
      default: return {};
    }
  }
  if (role == Qt::ToolTipRole) {
    switch (index.column()) {
      case PartColumn:
      case PartnerColumn:
      case KindColumn: return str(c.name);
      case FitColumn:
        if (c.found && c.found->keyWidth > 0.0)
          return tr("A prismatic fit: two parallel faces %1 mm apart between two faces of the other part, free only along "
                    "them (a key in its keyway or in a hub's slot, a tongue in its groove)")
              .arg(fixed(c.found->keyWidth * 1000.0, 3));
        if (!insert || !c.found) return {};
        if (c.found->seat == vaw::Constraint::Found::Seat::Counterbore)
          return tr("The head sits in a counterbore of radius %1 mm, on its floor; the shank's fit is the tighter of the two")
              .arg(fixed(c.found->seatRadius * 1000.0, 3));
        if (c.found->seat == vaw::Constraint::Found::Seat::Countersink)
          return tr("The head's cone lies in a countersink of %1 degrees and radius %2 mm; the shank's fit is %3")
              .arg(fixed(2.0 * c.found->seatAngle * 180.0 / std::numbers::pi, 0), fixed(c.found->seatRadius * 1000.0, 3),
                   str(vaw::name(c.found->fit)));
        if (c.found->fit == vaw::Constraint::Found::Fit::Threaded)
          return tr("Modelled at the tap drill: the shaft is %1 mm larger in radius than the hole, a thread's depth").arg(fixed(c.found->interference * 1000.0, 3));
        if (c.found->fit == vaw::Constraint::Found::Fit::Press)
          return tr("A press fit: the shaft is %1 mm larger in radius than the bore").arg(fixed(c.found->interference * 1000.0, 3));
        return tr("Radial play %1 mm").arg(fixed(c.found->clearance * 1000.0, 3));
      case GeometryColumn:
        return tr("%1\nWorld coordinates, %2 at its assembled pose.").arg(geometryText(a, c), str(a.parts[partner].name));
      case ClearanceColumn:
        if (insert && c.found)
          return tr("Shaft radius %1 mm in a bore of %2 mm (%3 is the %4)")
              .arg(fixed(std::min(c.found->partRadius, c.found->partnerRadius) * 1000.0, 3),
                   fixed(std::max(c.found->partRadius, c.found->partnerRadius) * 1000.0, 3), str(a.parts[c.part].name),
                   c.found->partRadius <= c.found->partnerRadius ? tr("shaft") : tr("bore"));
        return insert ? QVariant(notMeasured) : QVariant(tr("Mates have no clearance"));
      case OverlapColumn: return c.found ? QVariant() : QVariant(notMeasured);
      case StatusColumn: {
        QString text = c.accepted                      ? tr("Accepted: saved with the scene as confirmed.")
                       : c.found || !a.cadFile.empty() ? tr("Found in the geometry, not reviewed yet.")
                                                       : tr("Declared in the scene file.");
        if (c.found && c.found->fromSpline)
          text += tr("\nOne of its faces is a B-spline surface recognised as a %1.").arg(insert ? tr("cylinder") : tr("plane"));
        return text;
      }
      default: return {};
    }
  }
  if (role == Qt::TextAlignmentRole && (index.column() == ClearanceColumn || index.column() == OverlapColumn))
    return QVariant::fromValue(Qt::AlignRight | Qt::AlignVCenter);
  if (role == Qt::FontRole && index.column() == StatusColumn && c.found && c.found->fromSpline) {
    QFont f;
    f.setItalic(true);
    return f;
  }
  return {};
}

ConstraintsCommand::ConstraintsCommand(Apply apply, std::vector<vaw::Constraint> before, std::vector<vaw::Constraint> after,
                                       const QString& text)
    : QUndoCommand(text), apply_(std::move(apply)), before_(std::move(before)), after_(std::move(after)) {}

ConstraintsDock::ConstraintsDock(AssemblyController& controller, SimulationController& simulation, Viewport& viewport,
                                 QUndoStack& undoStack, QWidget* parent)
    : QDockWidget(tr("Constraints"), parent),
      controller_(controller),
      simulation_(simulation),
      viewport_(viewport),
      undoStack_(undoStack) {
  setObjectName(QStringLiteral("constraintsDock"));
  auto* body = new QWidget(this);
  auto* layout = new QVBoxLayout(body);
  layout->setContentsMargins(4, 4, 4, 4);
  model_ = new ConstraintsModel(this);
  view_ = new QTableView(body);
  view_->setObjectName(QStringLiteral("constraintsView"));
  view_->setModel(model_);
  view_->setSelectionBehavior(QAbstractItemView::SelectRows);
  view_->setSelectionMode(QAbstractItemView::ExtendedSelection);
  view_->setAlternatingRowColors(true);
  view_->verticalHeader()->hide();
  view_->verticalHeader()->setDefaultSectionSize(view_->fontMetrics().height() + 6);
  view_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  view_->horizontalHeader()->setSectionResizeMode(ConstraintsModel::GeometryColumn, QHeaderView::Stretch);
  layout->addWidget(view_);
  auto* buttons = new QHBoxLayout;
  const auto button = [&](const QString& text, const char* name, const QString& tip) {
    auto* b = new QPushButton(text, body);
    b->setObjectName(QString::fromLatin1(name));
    b->setToolTip(tip);
    buttons->addWidget(b);
    return b;
  };
  accept_ = button(tr("Accept"), "constraintAccept", tr("Mark the selected constraints as confirmed (saved with the scene)"));
  reject_ = button(tr("Reject"), "constraintReject", tr("Remove the selected constraints from the assembly"));
  swap_ = button(tr("Swap"), "constraintSwap", tr("Exchange part and partner: the partner goes onto the part instead"));
  addFromFaces_ = button(tr("Add from faces…"), "constraintAddFromFaces",
                         tr("Add a constraint by clicking a face on each of two parts in the viewport: a shaft and its bore "
                            "(insert) or two faces that meet (mate). Esc or this button again cancels."));
  addFromFaces_->setCheckable(true);
  hint_ = new QLabel(body);
  hint_->setObjectName(QStringLiteral("constraintsHint"));
  hint_->setWordWrap(true);
  buttons->addWidget(hint_, 1);
  layout->addLayout(buttons);
  nearTitle_ = new QLabel(body);
  nearTitle_->setObjectName(QStringLiteral("nearMissTitle"));
  nearTitle_->setToolTip(tr("Coaxial cylinders or facing planes that a test refused as a fit: a constraint you may have "
                            "expected and why it is not there"));
  layout->addWidget(nearTitle_);
  near_ = new QStandardItemModel(0, 3, this);
  near_->setHorizontalHeaderLabels({tr("Parts"), tr("Kind"), tr("Not taken because")});
  nearView_ = new QTableView(body);
  nearView_->setObjectName(QStringLiteral("nearMissView"));
  nearView_->setModel(near_);
  nearView_->setSelectionBehavior(QAbstractItemView::SelectRows);
  nearView_->setSelectionMode(QAbstractItemView::SingleSelection);
  nearView_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  nearView_->verticalHeader()->hide();
  nearView_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  nearView_->horizontalHeader()->setStretchLastSection(true);
  nearView_->setMaximumHeight(4 * (nearView_->fontMetrics().height() + 8));
  layout->addWidget(nearView_);
  setWidget(body);
  connect(&nearWatcher_, &QFutureWatcher<NearMisses>::finished, this, &ConstraintsDock::showNearMisses);
  // A row selects its first part, as a row of the constraints does.
  connect(nearView_->selectionModel(), &QItemSelectionModel::currentRowChanged, this, [this](const QModelIndex& current) {
    if (!current.isValid()) return;
    const QVariant part = near_->index(current.row(), 0).data(Qt::UserRole);
    if (part.isValid()) viewport_.selectPart(static_cast<vaw::PartId>(part.toULongLong()));
  });

  connect(accept_, &QPushButton::clicked, this, &ConstraintsDock::acceptSelected);
  connect(reject_, &QPushButton::clicked, this, &ConstraintsDock::rejectSelected);
  connect(swap_, &QPushButton::clicked, this, &ConstraintsDock::swapSelected);
  connect(addFromFaces_, &QPushButton::clicked, this, [this](bool on) {
    if (on) startPicking();
    else stopPicking(tr("Adding from faces cancelled."));
  });
  // Esc where the main window has the keyboard; the viewport reports its own (its 3D view is a window of its
  // own). Only while picking, so that Esc keeps its meaning elsewhere.
  cancelPicking_ = new QShortcut(
      QKeySequence(Qt::Key_Escape), this, this, [this] { stopPicking(tr("Adding from faces cancelled.")); }, Qt::WindowShortcut);
  cancelPicking_->setEnabled(false);
  connect(&viewport_, &Viewport::facePicked, this, &ConstraintsDock::facePicked);
  connect(&viewport_, &Viewport::facePickCancelled, this, [this] { stopPicking(tr("Adding from faces cancelled.")); });
  connect(view_->selectionModel(), &QItemSelectionModel::selectionChanged, this, &ConstraintsDock::selectionChanged);
  connect(view_->selectionModel(), &QItemSelectionModel::currentChanged, this, &ConstraintsDock::showGeometry);
  connect(&controller_, &AssemblyController::assemblyLoaded, this, &ConstraintsDock::assemblyLoaded);
  // Queued: a new world rebuilds the viewport's scene (which drops overlays) after this is told.
  connect(&simulation_, &SimulationController::started, this, &ConstraintsDock::showGeometry, Qt::QueuedConnection);
  connect(this, &QDockWidget::visibilityChanged, this, &ConstraintsDock::showGeometry);
  // The prompts are in this panel: picking on while it cannot be seen would leave clicks unexplained.
  connect(this, &QDockWidget::visibilityChanged, this, [this](bool visible) {
    if (!visible) stopPicking();
  });
  updateButtons();
}

ConstraintsDock::~ConstraintsDock() {
  nearWatcher_.disconnect(this);
  nearWatcher_.waitForFinished();
}

QString ConstraintsDock::nearMissKey(const vaw::Assembly& a) {
  return QStringLiteral("%1|%2|%3|%4|%5")
      .arg(str(a.cadFile.string()), str(a.cadHash), str(a.cadUp), a.base ? QString::number(*a.base) : QString())
      .arg(a.parts.size());
}

void ConstraintsDock::showNearMisses() {
  if (nearWatcher_.future().isValid() && nearWatcher_.future().isFinished() && nearWatcher_.future().resultCount() > 0)
    nearFound_ = nearWatcher_.result();
  near_->removeRows(0, near_->rowCount());
  nearTitle_->clear();
  const vaw::Assembly* a = model_->assembly();
  if (a == nullptr || a->cadFile.empty()) return;
  const QString key = nearMissKey(*a);
  if (!nearFound_ || nearFound_->of != key) {
    // Looked for once per geometry, one search at a time: a search for another assembly ends first.
    nearTitle_->setText(tr("Looking for near misses..."));
    if (nearWatcher_.isRunning()) return;
    nearWatcher_.setFuture(QtConcurrent::run([scene = controller_.scene(), key] {
      NearMisses out;
      out.of = key;
      try {
        const BackgroundTask task("near misses");
        out.misses = vaw::nearMisses(scene->assembly());
      } catch (const std::exception& e) {
        // Only a hint beside the constraints: the panel says why there is none, the table stays.
        out.error = failureText(e);
      }
      return out;
    }));
    return;
  }
  if (!nearFound_->error.isEmpty()) {
    nearTitle_->setText(tr("Near misses could not be looked for: %1").arg(nearFound_->error));
    return;
  }
  for (const vaw::NearMiss& m : nearFound_->misses) {
    auto* parts = new QStandardItem(tr("%1 and %2").arg(str(a->parts[m.a].name), str(a->parts[m.b].name)));
    parts->setData(QVariant::fromValue<qulonglong>(m.b), Qt::UserRole);
    near_->appendRow({parts, new QStandardItem(str(vaw::name(m.type))), new QStandardItem(str(m.why))});
  }
  nearTitle_->setText(nearFound_->misses.empty() ? tr("No near misses: every pair of coaxial cylinders and facing planes is a fit or apart.")
                                                 : tr("%1 near miss%2: faces that look like a fit and were not taken")
                                                       .arg(nearFound_->misses.size())
                                                       .arg(nearFound_->misses.size() == 1 ? QString() : QStringLiteral("es")));
}

void ConstraintsDock::assemblyLoaded() {
  const QStringList keep = controller_.currentPath() == keepFrom_ ? keepSelected_ : QStringList();
  keepFrom_ = controller_.currentPath();
  // Another scene (or this one rebuilt) may not have the parts the first face was picked on.
  stopPicking();
  model_->setScene(controller_.scene());
  hint_->clear();
  // After an edit (or File > Reload) the rows that were selected, by name, stay selected.
  const vaw::Assembly* a = model_->assembly();
  if (a != nullptr && !keep.isEmpty()) {
    QItemSelection selection;
    int current = -1;
    for (int row = 0; row < model_->rowCount(); ++row) {
      if (!keep.contains(str(a->constraints[static_cast<std::size_t>(row)].name))) continue;
      selection.select(model_->index(row, 0), model_->index(row, ConstraintsModel::ColumnCount - 1));
      if (current < 0) current = row;
    }
    if (current >= 0) {
      view_->selectionModel()->setCurrentIndex(model_->index(current, 0), QItemSelectionModel::NoUpdate);
      view_->selectionModel()->select(selection, QItemSelectionModel::ClearAndSelect);
    }
  }
  selectionChanged();
  // The near misses of a CAD assembly: recognition's tests again on every pair whose boxes meet, off the
  // window's thread, once per geometry (an edit of the table keeps them).
  showNearMisses();
}

std::vector<int> ConstraintsDock::selectedRows() const {
  std::vector<int> rows;
  for (const QModelIndex& i : view_->selectionModel()->selectedRows()) rows.push_back(i.row());
  std::sort(rows.begin(), rows.end());
  return rows;
}

void ConstraintsDock::selectionChanged() {
  keepSelected_.clear();
  if (const vaw::Assembly* a = model_->assembly())
    for (int row : selectedRows()) keepSelected_ << str(a->constraints[static_cast<std::size_t>(row)].name);
  updateButtons();
  showGeometry();
}

void ConstraintsDock::updateButtons() {
  const vaw::Assembly* a = model_->assembly();
  const std::vector<int> rows = selectedRows();
  bool anyOpen = false, allOnParts = !rows.empty();
  for (int row : rows) {
    const vaw::Constraint& c = a->constraints[static_cast<std::size_t>(row)];
    anyOpen = anyOpen || !c.accepted;
    allOnParts = allOnParts && c.partner.has_value();
  }
  accept_->setEnabled(anyOpen);
  reject_->setEnabled(!rows.empty());
  swap_->setEnabled(allOnParts);
  const bool hasFaces =
      a != nullptr && std::any_of(a->parts.begin(), a->parts.end(), [](const vaw::Part& p) { return p.cad != nullptr; });
  addFromFaces_->setEnabled(hasFaces);
  addFromFaces_->setToolTip(
      hasFaces ? tr("Add a constraint by clicking a face on each of two parts in the viewport: a shaft and its bore (insert) or "
                    "two faces that meet (mate). Esc or this button again cancels.")
               : tr("Only a CAD assembly (STEP) has the exact faces a constraint is made from"));
  swap_->setToolTip(!rows.empty() && !allOnParts
                        ? tr("The base cannot be the constrained part: only constraints between two parts can be swapped")
                        : tr("Exchange part and partner: the partner goes onto the part instead"));
}

void ConstraintsDock::showGeometry() {
  const vaw::Assembly* a = model_->assembly();
  QModelIndex current = view_->selectionModel()->currentIndex();
  if (!current.isValid() || !view_->selectionModel()->isRowSelected(current.row(), {})) {
    const auto rows = view_->selectionModel()->selectedRows();
    current = rows.isEmpty() ? QModelIndex() : rows.front();
  }
  if (a == nullptr || !current.isValid() || !isVisible()) {
    viewport_.hideConstraintGeometry();
    return;
  }
  const vaw::Constraint& c = a->constraints[static_cast<std::size_t>(current.row())];
  Viewport::ConstraintGeometry g;
  g.partner = partnerOf(*a, c);
  const vaw::Part& partner = a->parts[g.partner];
  // Sized by the larger of the two, so an axis sticks out of the stud it runs through and of the bracket
  // that goes over it, and a plane shows round both faces.
  const double extent = std::max({partner.extent, a->parts[c.part].extent, 0.01});
  if (c.type == vaw::Constraint::Type::Insert) {
    g.kind = Viewport::ConstraintGeometry::Kind::Axis;
    // From the partner's middle along its axis, mostly out to the side the part comes home from (a stud
    // standing on the table would hide the other half in it).
    const Eigen::Vector3d d = c.baseAxis.direction.normalized();
    const double side = d.dot(c.homeDirection) < 0.0 ? -1.0 : 1.0;
    g.size = 1.5 * extent;
    g.point = c.baseAxis.point + d * d.dot(partner.mass.centerOfMass - c.baseAxis.point) + side * 0.25 * g.size * d;
    g.direction = d;
  } else {
    g.kind = Viewport::ConstraintGeometry::Kind::Plane;
    g.point = c.basePlane.point;
    g.direction = c.basePlane.normal;
    g.size = 0.5 * extent;
  }
  viewport_.showConstraintGeometry(g);
}

void ConstraintsDock::change(std::vector<vaw::Constraint> after, const QString& text) {
  if (model_->assembly() == nullptr) return;
  undoStack_.push(new ConstraintsCommand([this](const std::vector<vaw::Constraint>& list) { apply(list); }, model_->constraints(),
                                         std::move(after), text));
}

void ConstraintsDock::apply(const std::vector<vaw::Constraint>& constraints) {
  QString why;
  if (!controller_.setConstraints(constraints, simulation_.hasWorld() ? &simulation_.world() : nullptr, &why))
    hint_->setText(tr("Not applied: %1").arg(why));
}

void ConstraintsDock::acceptSelected() {
  std::vector<vaw::Constraint> list = model_->constraints();
  int count = 0;
  for (int row : selectedRows()) {
    auto& c = list[static_cast<std::size_t>(row)];
    if (!c.accepted) ++count;
    c.accepted = true;
  }
  if (count == 0) return;
  change(std::move(list), count == 1 ? tr("Accept constraint") : tr("Accept %1 constraints").arg(count));
}

void ConstraintsDock::rejectSelected() {
  const std::vector<int> rows = selectedRows();
  if (rows.empty()) return;
  std::vector<vaw::Constraint> list = model_->constraints();
  for (auto it = rows.rbegin(); it != rows.rend(); ++it) list.erase(list.begin() + *it);
  change(std::move(list), rows.size() == 1 ? tr("Reject constraint") : tr("Reject %1 constraints").arg(rows.size()));
}

void ConstraintsDock::swapSelected() {
  const vaw::Assembly* a = model_->assembly();
  const std::vector<int> rows = selectedRows();
  if (a == nullptr || rows.empty()) return;
  std::vector<vaw::Constraint> list = model_->constraints();
  for (int row : rows) {
    auto& c = list[static_cast<std::size_t>(row)];
    if (!c.partner) return;  // the button is disabled for these
    c = swapped(c, *a);
  }
  // The selection follows the swapped rows under their new names.
  keepSelected_.clear();
  for (int row : rows) keepSelected_ << str(list[static_cast<std::size_t>(row)].name);
  change(std::move(list), rows.size() == 1 ? tr("Swap part and partner") : tr("Swap %1 constraints").arg(rows.size()));
}

void ConstraintsDock::tell(const QString& message) {
  hint_->setText(message);
  // The status bar is where the window says what just happened; the dock may float, so look up its parents.
  for (QWidget* w = parentWidget(); w != nullptr; w = w->parentWidget())
    if (auto* main = qobject_cast<QMainWindow*>(w)) {
      main->statusBar()->showMessage(message, 10000);
      break;
    }
}

void ConstraintsDock::startPicking() {
  if (model_->assembly() == nullptr) {
    addFromFaces_->setChecked(false);
    return;
  }
  picking_ = true;
  firstFace_.reset();
  addFromFaces_->setChecked(true);
  cancelPicking_->setEnabled(true);
  viewport_.setPickingFaces(true);
  hint_->setText(tr("Click a face of the part that goes on (Esc cancels)"));
}

void ConstraintsDock::stopPicking(const QString& message) {
  if (!picking_) return;
  picking_ = false;
  firstFace_.reset();
  addFromFaces_->setChecked(false);
  cancelPicking_->setEnabled(false);
  viewport_.setPickingFaces(false);
  if (message.isEmpty()) hint_->clear();
  else tell(message);
}

void ConstraintsDock::facePicked(vaw::PartId part, const Eigen::Vector3d& at) {
  const vaw::Assembly* a = model_->assembly();
  if (!picking_ || a == nullptr || part >= a->parts.size()) return;
  const vaw::Part& p = a->parts[part];
  const QString name = str(p.name);
  const auto pose = viewport_.partPose(part);
  if (!p.cad || !pose) {
    hint_->setText(tr("%1 has no CAD faces to pick: click another part").arg(name));
    return;
  }
  // The click is where the part is drawn now, perhaps waiting on the table: its own frame does not care.
  const Eigen::Vector3d local = pose->inverse() * at;
  Eigen::AlignedBox3d bounds;
  for (const auto& v : p.cad->mesh.vertices) bounds.extend(v);
  const auto face = vaw::faceAt(*p.cad, local, 0.01 * bounds.diagonal().norm());
  if (!face) {
    hint_->setText(tr("No face of %1 found there: click on a face").arg(name));
    return;
  }
  const vaw::CadFace& f = p.cad->faces[*face];
  if (f.surface == vaw::CadFace::Surface::Other) {
    hint_->setText(
        tr("That face of %1 is neither flat, a cylinder nor a cone: constraints are made from those. Click another").arg(name));
    return;
  }
  if (!firstFace_) {
    firstFace_ = {part, *face};
    hint_->setText(tr("Click the face of its partner (%1: %2)").arg(name, faceText(f)));
    return;
  }
  if (firstFace_->first == part) {
    hint_->setText(tr("Click the face of its partner: another part than %1").arg(name));
    return;
  }
  const auto [firstPart, firstFace] = *firstFace_;
  stopPicking();
  addFromFaces(firstPart, firstFace, part, *face);
}

void ConstraintsDock::addFromFaces(vaw::PartId partA, std::size_t faceA, vaw::PartId partB, std::size_t faceB) {
  const vaw::Assembly* a = model_->assembly();
  if (a == nullptr) return;
  // The faces must fit where the parts end up, not where they wait.
  std::vector<vaw::RecognitionPart> rec;
  std::vector<Eigen::Isometry3d> poses;
  for (vaw::PartId id = 0; id < a->parts.size(); ++id) {
    poses.push_back(assembledPose(*a, id));
    rec.push_back({a->parts[id].cad, poses.back()});
  }
  const vaw::FacePairResult result = vaw::constraintFromFaces(rec, partA, faceA, partB, faceB);
  const QString pair = tr("%1 and %2").arg(str(a->parts[partA].name), str(a->parts[partB].name));
  if (!result.found) {
    tell(tr("Not a constraint between %1: %2.").arg(pair, str(result.why)));
    return;
  }
  // Part and partner by the assembly order the other constraints give, as recognition orders them.
  std::vector<std::pair<vaw::PartId, vaw::PartId>> contacts;
  for (const vaw::Constraint& c : a->constraints) contacts.emplace_back(c.part, partnerOf(*a, c));
  std::vector<vaw::Constraint> made = vaw::constraintsFromFound({*result.found}, a->parts, a->base.value_or(0), poses, contacts);
  if (made.size() != 1) return;
  vaw::Constraint c = std::move(made.front());
  std::vector<vaw::Constraint> list = model_->constraints();
  for (const vaw::Constraint& existing : list)
    if (sameConstraint(*a, existing, c)) {
      tell(tr("Not added: \"%1\" is there already.").arg(str(existing.name)));
      return;
    }
  c.accepted = true;  // the user made it: nothing left to review
  const auto taken = [&list](const std::string& n) {
    return std::any_of(list.begin(), list.end(), [&n](const vaw::Constraint& x) { return x.name == n; });
  };
  const std::string base = c.name;
  for (int k = 2; taken(c.name); ++k) c.name = base + " " + std::to_string(k);
  // Where recognition would have put it: with its part's others, inserts before mates (a released part is
  // tried on its axes first).
  const bool insert = c.type == vaw::Constraint::Type::Insert;
  const auto at = std::find_if(list.begin(), list.end(), [&](const vaw::Constraint& x) {
    return x.part > c.part || (x.part == c.part && insert && x.type != vaw::Constraint::Type::Insert);
  });
  const QString name = str(c.name);
  list.insert(at, std::move(c));
  keepSelected_ = QStringList{name};
  change(std::move(list), tr("Add constraint"));
  if (const vaw::Assembly* now = model_->assembly();
      now != nullptr && std::any_of(now->constraints.begin(), now->constraints.end(),
                                    [&](const vaw::Constraint& x) { return str(x.name) == name; }))
    tell(tr("Added \"%1\", accepted.").arg(name));
}

namespace {

// The name of the sub-assembly (a group of the file's tree below its root) that holds `part`, if any.
std::optional<std::string> subAssemblyOf(const vaw::TreeNode& node, vaw::PartId part, bool root = true) {
  for (const vaw::TreeNode& c : node.children) {
    if (c.kind == vaw::TreeNode::Kind::Part && c.index == part)
      return !root && node.kind == vaw::TreeNode::Kind::Group ? std::optional(node.name) : std::nullopt;
    if (c.kind == vaw::TreeNode::Kind::Group)
      if (auto found = subAssemblyOf(c, part, false)) return found;
  }
  return std::nullopt;
}

}  // namespace

QMenu* ConstraintsDock::baseMenu(vaw::PartId part, QWidget* parent) {
  auto* menu = new QMenu(parent);
  menu->setObjectName(QStringLiteral("sceneTreeMenu"));
  menu->setToolTipsVisible(true);
  QAction* makeBase = menu->addAction(tr("Make this the base"));
  makeBase->setObjectName(QStringLiteral("makeBaseAction"));
  const vaw::Assembly* a = controller_.assembly();
  if (a == nullptr || part >= a->parts.size()) {
    makeBase->setEnabled(false);
    return menu;
  }
  const QString name = str(a->parts[part].name);
  QString tip;
  if (a->cadFile.empty()) {
    makeBase->setEnabled(false);
    tip =
        tr("Only a CAD assembly (STEP) can change its base: its constraints are found again relative to the new one. "
           "A scene file names its base and constraints itself.");
  } else if (a->base == part) {
    makeBase->setEnabled(false);
    tip = tr("%1 is the base already").arg(name);
  } else {
    tip = tr("Reopen the assembly with %1 as the base: the constraints are found again relative to it").arg(name);
  }
  makeBase->setToolTip(tip);
  makeBase->setStatusTip(tip);
  connect(makeBase, &QAction::triggered, this, [this, name] { emit baseRequested(name); });
  // Units (docs/step.md, "Units"): a unit taken apart; a part of a sub-assembly joins it as one.
  if (!a->cadFile.empty()) {
    const vaw::Part& p = a->parts[part];
    if (!p.unitMembers.empty()) {
      QAction* apart = menu->addAction(tr("Handle as parts"));
      apart->setObjectName(QStringLiteral("unitApartAction"));
      apart->setToolTip(tr("Reopen the assembly with the %1 parts of %2 each its own part").arg(p.unitMembers.size()).arg(name));
      connect(apart, &QAction::triggered, this, [this, name] { emit unitRequested(name, false); });
    } else if (const auto group = subAssemblyOf(a->tree, part)) {
      QAction* join = menu->addAction(tr("Handle %1 as one unit").arg(str(*group)));
      join->setObjectName(QStringLiteral("unitJoinAction"));
      join->setToolTip(tr("Reopen the assembly with the sub-assembly %1 ordered, carried and placed as one rigid part").arg(str(*group)));
      connect(join, &QAction::triggered, this, [this, g = str(*group)] { emit unitRequested(g, true); });
    }
  }
  // Which way is up (docs/step.md): the automatic choice or one of the file's axes, the current one ticked.
  if (!a->cadFile.empty()) {
    QMenu* up = menu->addMenu(tr("Which way is up"));
    up->setObjectName(QStringLiteral("upMenu"));
    up->setToolTipsVisible(true);
    auto* group = new QActionGroup(up);
    const std::pair<const char*, QString> choices[] = {
        {"auto", tr("Automatic: the base on its most stable face")},
        {"+z", tr("The file's +Z up")}, {"-z", tr("The file's -Z up")}, {"+y", tr("The file's +Y up")},
        {"-y", tr("The file's -Y up")}, {"+x", tr("The file's +X up")}, {"-x", tr("The file's -X up")}};
    for (const auto& [key, text] : choices) {
      QAction* act = up->addAction(text);
      act->setObjectName(QStringLiteral("up") + QString::fromLatin1(key));
      act->setCheckable(true);
      act->setChecked(a->cadUp == key);
      act->setActionGroup(group);
      act->setToolTip(tr("Reopen the assembly standing this way; the constraints keep their parts"));
      const QString choice = QString::fromLatin1(key);
      connect(act, &QAction::triggered, this, [this, choice, current = str(a->cadUp)] {
        if (choice != current) emit upRequested(choice);
      });
    }
    // A face put down in the viewport that is square to no file axis: its direction, ticked.
    if (std::none_of(std::begin(choices), std::end(choices), [&](const auto& c) { return a->cadUp == c.first; })) {
      const Eigen::Vector3d d = a->cadUpAxis;
      QAction* act = up->addAction(tr("A face put down in the view: the file's (%1, %2, %3) up")
                                       .arg(d.x(), 0, 'f', 3)
                                       .arg(d.y(), 0, 'f', 3)
                                       .arg(d.z(), 0, 'f', 3));
      act->setObjectName(QStringLiteral("upface"));
      act->setCheckable(true);
      act->setChecked(true);
      act->setActionGroup(group);
    }
  }
  return menu;
}

void ConstraintsDock::attachBaseMenu(SceneDock* scene) {
  QTreeView* tree = scene->view();
  tree->setContextMenuPolicy(Qt::CustomContextMenu);
  connect(tree, &QWidget::customContextMenuRequested, this, [this, scene, tree](const QPoint& at) {
    const auto part = scene->model()->partAt(tree->indexAt(at));
    if (!part) return;
    QMenu* menu = baseMenu(*part, tree);
    menu->setAttribute(Qt::WA_DeleteOnClose);
    menu->popup(tree->viewport()->mapToGlobal(at));
  });
}

}  // namespace vaw::ui
