#include "vaw/ui/tuning.hpp"

#include <QBrush>
#include <QCheckBox>
#include <QColor>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QPushButton>
#include <QSettings>
#include <QSignalBlocker>
#include <QSlider>
#include <QSpinBox>
#include <QTableView>
#include <QVBoxLayout>
#include <cmath>
#include <numbers>

#include "format.hpp"
#include "vaw/human/head_demand.hpp"
#include "vaw/units.hpp"
#include "vaw/ui/simulation_controller.hpp"

namespace vaw::ui {

namespace {
using vaw::kDeg;
constexpr int kSliderSteps = 200;       // the slider covers scales 0 to 2 in steps of 0.01
constexpr double kSliderMax = 2.0;
const QColor kProblemColour(255, 205, 200);

double angleDeg(double coefficient) { return std::atan(coefficient) / kDeg; }
}  // namespace

// ---- EditCommand ----

EditCommand::EditCommand(SimulationController& simulation, vaw::sim::Edit before, vaw::sim::Edit after,
                         const QString& text, int mergeKey)
    : simulation_(simulation), before_(std::move(before)), after_(std::move(after)), mergeKey_(mergeKey) {
  setText(text);
}

void EditCommand::redo() { simulation_.requestEdit(after_); }
void EditCommand::undo() { simulation_.requestEdit(before_); }

bool EditCommand::mergeWith(const QUndoCommand* other) {
  if (other->id() != id() || id() < 0) return false;
  after_ = static_cast<const EditCommand*>(other)->after_;
  setText(other->text());
  return true;
}

// ---- FrictionModel ----

FrictionModel::FrictionModel(QObject* parent) : QAbstractTableModel(parent) {}

void FrictionModel::showWorld(const vaw::sim::World* world, std::optional<vaw::PartId> selected) {
  world_ = world;
  std::vector<Row> rows;
  if (world != nullptr) {
    for (const auto& [name, material] : world->assembly().materials)
      rows.push_back(Row{name, std::nullopt, QString::fromStdString(name), world->materialFriction(name), false});
    if (selected && *selected < world->assembly().parts.size()) {
      const vaw::Part& p = world->assembly().parts[*selected];
      rows.push_back(Row{p.material, selected, tr("%1 (part)").arg(QString::fromStdString(p.name)), world->friction(*selected),
                         world->frictionOverride(*selected).has_value()});
    }
  }
  const bool sameRows = rows.size() == rows_.size() &&
                        std::equal(rows.begin(), rows.end(), rows_.begin(), [](const Row& a, const Row& b) {
                          return a.material == b.material && a.part == b.part;
                        });
  if (!sameRows) {
    beginResetModel();
    rows_ = std::move(rows);
    problems_.clear();
    endResetModel();
    return;
  }
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].values == rows_[i].values && rows[i].overridden == rows_[i].overridden) continue;
    rows_[i] = rows[i];
    const int r = static_cast<int>(i);
    for (int c = StaticColumn; c <= RotationalColumn; ++c) problems_.erase({r, c});
    emit dataChanged(index(r, 0), index(r, ColumnCount - 1));
  }
}

int FrictionModel::materialRow(const std::string& material) const {
  for (std::size_t i = 0; i < rows_.size(); ++i)
    if (!rows_[i].part && rows_[i].material == material) return static_cast<int>(i);
  return -1;
}

int FrictionModel::partRow() const { return !rows_.empty() && rows_.back().part ? static_cast<int>(rows_.size()) - 1 : -1; }

QString FrictionModel::problem(int row, int column) const {
  const auto it = problems_.find({row, column});
  return it == problems_.end() ? QString() : it->second;
}

int FrictionModel::rowCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : static_cast<int>(rows_.size()); }
int FrictionModel::columnCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : ColumnCount; }

QVariant FrictionModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (orientation != Qt::Horizontal) return {};
  if (role == Qt::DisplayRole) {
    switch (section) {
      case NameColumn: return tr("Material");
      case StaticColumn: return tr("Static f_s");
      case KineticColumn: return tr("Kinetic f_d");
      case RotationalColumn: return tr("Rotational f_r");
      case StaticAngleColumn: return tr("Static angle");
      case KineticAngleColumn: return tr("Kinetic angle");
      default: return {};
    }
  }
  if (role == Qt::ToolTipRole) {
    switch (section) {
      case StaticColumn: return tr("Static friction coefficient: a part at rest starts to slide beyond its friction angle");
      case KineticColumn: return tr("Kinetic (sliding) friction coefficient, no larger than the static one");
      case RotationalColumn: return tr("Viscous friction of a rotation on a shaft, N m s");
      case StaticAngleColumn: return tr("atan(f_s): the tilt at which a part at rest starts to slide");
      case KineticAngleColumn: return tr("atan(f_d): the tilt at which a sliding part keeps its speed");
      default: return {};
    }
  }
  return {};
}

Qt::ItemFlags FrictionModel::flags(const QModelIndex& index) const {
  if (!index.isValid()) return Qt::NoItemFlags;
  Qt::ItemFlags f = Qt::ItemIsEnabled | Qt::ItemIsSelectable;
  const Row& row = rows_[static_cast<std::size_t>(index.row())];
  if (row.part && index.column() == NameColumn) f |= Qt::ItemIsUserCheckable;
  const bool valueColumn = index.column() >= StaticColumn && index.column() <= RotationalColumn;
  if (valueColumn && (!row.part || row.overridden)) f |= Qt::ItemIsEditable;
  return f;
}

QVariant FrictionModel::data(const QModelIndex& index, int role) const {
  if (!index.isValid() || index.row() >= static_cast<int>(rows_.size())) return {};
  const Row& row = rows_[static_cast<std::size_t>(index.row())];
  const vaw::FrictionValues& v = row.values;
  const int col = index.column();
  const auto value = [&]() -> double {
    switch (col) {
      case StaticColumn: return v.staticFriction;
      case KineticColumn: return v.kineticFriction;
      case RotationalColumn: return v.rotationalFriction;
      case StaticAngleColumn: return angleDeg(v.staticFriction);
      case KineticAngleColumn: return angleDeg(v.kineticFriction);
      default: return 0.0;
    }
  };
  switch (role) {
    case Qt::DisplayRole:
      if (col == NameColumn) return row.name;
      if (col >= StaticAngleColumn) return tr("%1°").arg(QString::number(value(), 'f', 2));
      // A refused entry keeps the value and says so in the cell itself (visible even when selected).
      return problem(index.row(), col).isEmpty() ? QString::number(value(), 'g', 6)
                                                 : tr("%1 ⚠").arg(QString::number(value(), 'g', 6));
    case Qt::EditRole:
      if (col == NameColumn) return row.name;
      return QString::number(value(), 'g', 10);
    case Qt::CheckStateRole:
      if (row.part && col == NameColumn) return row.overridden ? Qt::Checked : Qt::Unchecked;
      return {};
    case Qt::BackgroundRole:
      if (!problem(index.row(), col).isEmpty()) return QBrush(kProblemColour);
      return {};
    case Qt::ForegroundRole:
      if (row.part && !row.overridden && col != NameColumn) return QBrush(QColor(140, 140, 140));
      return {};
    case Qt::ToolTipRole: {
      const QString p = problem(index.row(), col);
      if (!p.isEmpty()) return tr("Refused: %1").arg(p);
      if (row.part && col == NameColumn)
        return row.overridden ? tr("This part has its own friction; uncheck to follow its material (%1) again")
                                    .arg(QString::fromStdString(row.material))
                              : tr("Check to give this part its own friction instead of its material's (%1)")
                                    .arg(QString::fromStdString(row.material));
      return {};
    }
    default: return {};
  }
}

bool FrictionModel::setData(const QModelIndex& index, const QVariant& value, int role) {
  if (!index.isValid() || world_ == nullptr) return false;
  const int r = index.row(), col = index.column();
  Row& row = rows_[static_cast<std::size_t>(r)];
  if (role == Qt::CheckStateRole && row.part && col == NameColumn) {
    const bool on = value.toInt() == Qt::Checked;
    if (on == row.overridden) return false;
    emit editRequested(vaw::sim::PartFrictionEdit{*row.part, on ? std::optional(row.values) : std::nullopt});
    return true;
  }
  if (role != Qt::EditRole || col < StaticColumn || col > RotationalColumn) return false;
  const auto refuse = [&](const QString& rule) {
    problems_[{r, col}] = rule;
    emit dataChanged(index, index);
    emit refused(rule);
    return false;
  };
  bool ok = false;
  const double x = value.toString().trimmed().toDouble(&ok);
  if (!ok || !std::isfinite(x)) return refuse(tr("\"%1\" is not a number").arg(value.toString()));
  vaw::FrictionValues f = row.values;
  (col == StaticColumn ? f.staticFriction : col == KineticColumn ? f.kineticFriction : f.rotationalFriction) = x;
  const std::string rule = vaw::sim::validateFriction(f);
  if (!rule.empty()) return refuse(QString::fromStdString(rule));
  problems_.erase({r, col});
  emit dataChanged(index, index);
  if (f == row.values) return true;
  if (row.part) emit editRequested(vaw::sim::PartFrictionEdit{*row.part, f});
  else emit editRequested(vaw::sim::MaterialFrictionEdit{row.material, f});
  return true;
}

// ---- GravityDock ----

GravityDock::GravityDock(QWidget* parent) : QDockWidget(tr("Gravity"), parent) {
  setObjectName(QStringLiteral("gravityDock"));
  auto* body = new QWidget(this);
  auto* layout = new QVBoxLayout(body);
  auto* scalesBox = new QGroupBox(tr("Gravity scales"), body);
  auto* grid = new QFormLayout(scalesBox);
  const QString names[3] = {QStringLiteral("FreeFlight"), QStringLiteral("Slide"), QStringLiteral("Rotation")};
  const QString labels[3] = {tr("Free flight"), tr("Slide"), tr("Rotation")};
  const QString tips[3] = {tr("Gravity for parts flying after a release (the source paper found 0.2-0.3 felt real in a headset)"),
                           tr("Gravity for parts sliding on the base, on a plane or along a shaft"),
                           tr("Gravity for parts swinging about a shaft")};
  for (int i = 0; i < 3; ++i) {
    scales_[i] = makeScale(names[i], FreeFlightScaleKey + i, scalesBox);
    auto* row = new QHBoxLayout();
    row->addWidget(scales_[i].slider, 1);
    row->addWidget(scales_[i].factor);
    row->addWidget(scales_[i].metres);
    for (QWidget* w : {static_cast<QWidget*>(scales_[i].slider), static_cast<QWidget*>(scales_[i].factor),
                       static_cast<QWidget*>(scales_[i].metres)})
      w->setToolTip(tips[i]);
    grid->addRow(labels[i], row);
  }
  auto* presets = new QHBoxLayout();
  auto* real = new QPushButton(tr("All 1.0 (real)"), scalesBox);
  real->setObjectName(QStringLiteral("gravityPresetReal"));
  auto* paper = new QPushButton(tr("Paper: free flight 0.25"), scalesBox);
  paper->setObjectName(QStringLiteral("gravityPresetPaper"));
  paper->setToolTip(tr("The scale the source paper's users found natural for a falling part in a headset; slide and rotation at 1"));
  presets->addWidget(real);
  presets->addWidget(paper);
  grid->addRow(tr("Presets"), presets);
  layout->addWidget(scalesBox);
  scalesBox_ = scalesBox;
  blindNote_ = new QLabel(tr("The gravity scales are hidden while a blinded trials session runs (Trials panel)."), body);
  blindNote_->setObjectName(QStringLiteral("gravityBlindNote"));
  blindNote_->setWordWrap(true);
  blindNote_->hide();
  layout->addWidget(blindNote_);
  connect(real, &QPushButton::clicked, this, [this] { emit editRequested(vaw::sim::GravityEdit{{1.0, 1.0, 1.0}}, -1); });
  connect(paper, &QPushButton::clicked, this, [this] { emit editRequested(vaw::sim::GravityEdit{{0.25, 1.0, 1.0}}, -1); });

  // The head-tracking demand of following a falling part (docs/head-demand.md).
  auto* demandBox = new QGroupBox(tr("Head-tracking demand of a fall"), body);
  auto* form = new QFormLayout(demandBox);
  const auto spin = [demandBox](const char* name, double lo, double hi, double value, int decimals, const QString& suffix) {
    auto* s = new QDoubleSpinBox(demandBox);
    s->setObjectName(QString::fromLatin1(name));
    s->setRange(lo, hi);
    s->setDecimals(decimals);
    s->setValue(value);
    s->setSuffix(suffix);
    s->setKeyboardTracking(false);
    return s;
  };
  QSettings settings;
  distance_ = spin("headDistance", 0.1, 20.0, settings.value(QStringLiteral("gravity/distance"), 0.6).toDouble(), 2, tr(" m"));
  fallHeight_ = spin("headFallHeight", 0.05, 20.0, settings.value(QStringLiteral("gravity/fallHeight"), 0.8).toDouble(), 2, tr(" m"));
  const human::HeadLimits defaults;
  pitchLimit_ = spin("headPitchLimit", 10.0, 2000.0,
                     settings.value(QStringLiteral("gravity/pitchLimit"), defaults.pitchRate_deg_s).toDouble(), 0, tr(" °/s"));
  accelLimit_ = spin("headAccelLimit", 10.0, 100000.0, settings.value(QStringLiteral("gravity/accelLimit"), 3000.0).toDouble(), 0,
                     tr(" °/s²"));
  useAccel_ = new QCheckBox(tr("Limit the acceleration too"), demandBox);
  useAccel_->setObjectName(QStringLiteral("headUseAccel"));
  useAccel_->setChecked(settings.value(QStringLiteral("gravity/useAccel"), false).toBool());
  useAccel_->setToolTip(tr("The source of the rate limits gives no acceleration limit: set one only with a figure for "
                           "your headset and users"));
  distance_->setToolTip(tr("Horizontally from the eye to the falling part"));
  fallHeight_->setToolTip(tr("From eye level down to where the fall ends (a table, the floor)"));
  pitchLimit_->setToolTip(tr("The fastest a person pitches the head (Durlach et al. 1995: 300 °/s; a helmet lowers it)"));
  form->addRow(tr("Viewing distance"), distance_);
  form->addRow(tr("Fall height"), fallHeight_);
  form->addRow(tr("Head pitch limit"), pitchLimit_);
  form->addRow(useAccel_, accelLimit_);
  demand_ = new QLabel(demandBox);
  demand_->setObjectName(QStringLiteral("headDemandResult"));
  demand_->setWordWrap(true);
  demand_->setTextFormat(Qt::RichText);
  form->addRow(demand_);
  apply_ = new QPushButton(demandBox);
  apply_->setObjectName(QStringLiteral("headApply"));
  form->addRow(QString(), apply_);
  layout->addWidget(demandBox);
  demandBox_ = demandBox;
  layout->addStretch(1);
  setWidget(body);
  for (QDoubleSpinBox* s : {distance_, fallHeight_, pitchLimit_, accelLimit_})
    connect(s, &QDoubleSpinBox::valueChanged, this, &GravityDock::updateDemand);
  connect(useAccel_, &QCheckBox::toggled, this, &GravityDock::updateDemand);
  connect(apply_, &QPushButton::clicked, this, [this] { request(FreeFlightScaleKey, recommended_); });
  updateDemand();
}

GravityDock::Scale GravityDock::makeScale(const QString& name, int key, QWidget* parent) {
  Scale s;
  s.slider = new QSlider(Qt::Horizontal, parent);
  s.slider->setObjectName(QStringLiteral("gravity%1Slider").arg(name));
  s.slider->setRange(0, kSliderSteps);
  s.slider->setPageStep(25);
  s.factor = new QDoubleSpinBox(parent);
  s.factor->setObjectName(QStringLiteral("gravity%1").arg(name));
  s.factor->setRange(0.0, vaw::sim::kMaxGravityScale);
  s.factor->setDecimals(3);
  s.factor->setSingleStep(0.05);
  s.factor->setPrefix(QStringLiteral("× "));
  s.factor->setKeyboardTracking(false);
  s.metres = new QDoubleSpinBox(parent);
  s.metres->setObjectName(QStringLiteral("gravity%1Ms2").arg(name));
  s.metres->setRange(0.0, vaw::sim::kMaxGravityScale * kStandardGravity);
  s.metres->setDecimals(3);
  s.metres->setSingleStep(0.1);
  s.metres->setSuffix(tr(" m/s²"));
  s.metres->setKeyboardTracking(false);
  // A slider sends while dragged only when it is let go; clicks and keys send at once.
  connect(s.slider, &QSlider::valueChanged, this, [this, key, slider = s.slider](int v) {
    if (!slider->isSliderDown()) request(key, kSliderMax * v / kSliderSteps);
  });
  connect(s.slider, &QSlider::sliderReleased, this,
          [this, key, slider = s.slider] { request(key, kSliderMax * slider->value() / kSliderSteps); });
  connect(s.factor, &QDoubleSpinBox::valueChanged, this, [this, key](double v) { request(key, v); });
  connect(s.metres, &QDoubleSpinBox::valueChanged, this, [this, key](double v) { request(key, v / kStandardGravity); });
  return s;
}

void GravityDock::request(int key, double factor) {
  vaw::dyn::GravityScales g = shown_;
  double& target = key == FreeFlightScaleKey ? g.freeFlight : key == SlideScaleKey ? g.slide : g.rotation;
  if (std::abs(target - factor) < 1e-12) return;
  target = factor;
  emit editRequested(vaw::sim::GravityEdit{g}, key);
}

void GravityDock::setBlinded(bool blinded) {
  blinded_ = blinded;
  scalesBox_->setVisible(!blinded);
  blindNote_->setVisible(blinded);
  demandBox_->setEnabled(!blinded);
}

void GravityDock::showWorld(const vaw::sim::World& world) {
  if (blinded_) return;
  shown_ = world.settings().gravity;
  const double values[3] = {shown_.freeFlight, shown_.slide, shown_.rotation};
  for (int i = 0; i < 3; ++i) {
    const Scale& s = scales_[i];
    const QSignalBlocker b1(s.slider), b2(s.factor), b3(s.metres);
    if (!s.slider->isSliderDown())
      s.slider->setValue(static_cast<int>(std::lround(std::min(values[i], kSliderMax) / kSliderMax * kSliderSteps)));
    if (!s.factor->hasFocus()) s.factor->setValue(values[i]);
    if (!s.metres->hasFocus()) s.metres->setValue(values[i] * kStandardGravity);
  }
}

void GravityDock::updateDemand() {
  QSettings settings;
  settings.setValue(QStringLiteral("gravity/distance"), distance_->value());
  settings.setValue(QStringLiteral("gravity/fallHeight"), fallHeight_->value());
  settings.setValue(QStringLiteral("gravity/pitchLimit"), pitchLimit_->value());
  settings.setValue(QStringLiteral("gravity/accelLimit"), accelLimit_->value());
  settings.setValue(QStringLiteral("gravity/useAccel"), useAccel_->isChecked());
  accelLimit_->setEnabled(useAccel_->isChecked());
  human::HeadLimits limits;
  limits.pitchRate_deg_s = pitchLimit_->value();
  if (useAccel_->isChecked()) limits.acceleration_deg_s2 = accelLimit_->value();
  const human::ViewingGeometry geometry{distance_->value(), fallHeight_->value()};
  const human::ScaleRecommendation r = human::recommendScale(geometry, limits);
  const human::HeadDemand& d = r.atFullGravity;
  recommended_ = r.recommendedScale;
  demand_->setText(tr("At full gravity the part falls in %1 s; following it takes up to <b>%2 °/s</b> (at %3 s) and "
                      "<b>%4 °/s²</b> (at release).<br>The largest scale within the limits is %5 (limited by %6): "
                      "<b>recommended free-flight scale %7</b>.")
                       .arg(format::number(d.fallTime_s, 3), format::number(d.peakRate_deg_s, 4),
                            format::number(d.peakRateTime_s, 3), format::number(d.peakAcceleration_deg_s2, 4),
                            format::number(r.maxScale, 3), QString::fromStdString(r.limitedBy),
                            format::number(r.recommendedScale, 3)));
  apply_->setText(tr("Apply free-flight scale %1").arg(format::number(r.recommendedScale, 3)));
}

// ---- FrictionDock ----

FrictionDock::FrictionDock(QWidget* parent) : QDockWidget(tr("Friction"), parent) {
  setObjectName(QStringLiteral("frictionDock"));
  auto* body = new QWidget(this);
  auto* layout = new QVBoxLayout(body);
  model_ = new FrictionModel(this);
  view_ = new QTableView(body);
  view_->setObjectName(QStringLiteral("frictionTable"));
  view_->setModel(model_);
  view_->verticalHeader()->hide();
  view_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  view_->horizontalHeader()->setStretchLastSection(true);
  view_->setEditTriggers(QAbstractItemView::DoubleClicked | QAbstractItemView::EditKeyPressed |
                         QAbstractItemView::AnyKeyPressed);
  layout->addWidget(view_, 1);
  problem_ = new QLabel(body);
  problem_->setObjectName(QStringLiteral("frictionProblem"));
  problem_->setWordWrap(true);
  problem_->setStyleSheet(QStringLiteral("color: rgb(180, 40, 20);"));
  layout->addWidget(problem_);
  auto* hint = new QLabel(tr("Double-click a value to edit it. The last row is the selected part: check it to give it "
                             "its own friction. Ctrl+Z undoes."),
                          body);
  hint->setWordWrap(true);
  layout->addWidget(hint);
  setWidget(body);
  connect(model_, &FrictionModel::refused, problem_, [this](const QString& rule) { problem_->setText(tr("Refused: %1").arg(rule)); });
  connect(model_, &FrictionModel::editRequested, problem_, [this] { problem_->clear(); });
}

// ---- MethodsDock ----

MethodsDock::MethodsDock(QWidget* parent) : QDockWidget(tr("Methods"), parent) {
  setObjectName(QStringLiteral("methodsDock"));
  auto* body = new QWidget(this);
  auto* layout = new QVBoxLayout(body);
  auto* box = new QGroupBox(tr("Integration"), body);
  auto* form = new QFormLayout(box);
  auto* flight = new QLabel(tr("closed form (translation); rotation at constant ω or torque-free, chosen at each release "
                               "from its predicted error"),
                            box);
  flight->setWordWrap(true);
  auto* slide = new QLabel(tr("closed form, with the stop found inside the step"), box);
  slide->setWordWrap(true);
  rotation_ = new QComboBox(box);
  rotation_->setObjectName(QStringLiteral("rotationMethod"));
  for (const vaw::dyn::Method m : vaw::dyn::kAllMethods)
    if (vaw::sim::rotationSupports(m))
      rotation_->addItem(QString::fromLatin1(vaw::dyn::name(m).data(), static_cast<int>(vaw::dyn::name(m).size())),
                         static_cast<int>(m));
  rotation_->setToolTip(tr("How a part swinging on a shaft is integrated (its torque depends on the angle: there is no "
                           "closed form)"));
  rate_ = new QSpinBox(box);
  rate_->setObjectName(QStringLiteral("stepRate"));
  rate_->setRange(static_cast<int>(vaw::sim::kMinRate), static_cast<int>(vaw::sim::kMaxRate));
  rate_->setSuffix(tr(" Hz"));
  rate_->setKeyboardTracking(false);
  rate_->setToolTip(tr("The world's fixed step rate (a headset refreshes at 72, 90 or 120 Hz)"));
  form->addRow(tr("Free flight"), flight);
  form->addRow(tr("Slide"), slide);
  form->addRow(tr("Rotation on a shaft"), rotation_);
  form->addRow(tr("Step rate"), rate_);
  layout->addWidget(box);
  auto* stabilityBox = new QGroupBox(tr("Stability of the selected part"), body);
  auto* sl = new QVBoxLayout(stabilityBox);
  stability_ = new QLabel(tr("Select a part that turns on a shaft."), stabilityBox);
  stability_->setObjectName(QStringLiteral("stabilityWarning"));
  stability_->setWordWrap(true);
  sl->addWidget(stability_);
  suggestion_ = new QPushButton(stabilityBox);
  suggestion_->setObjectName(QStringLiteral("applyStabilitySuggestion"));
  suggestion_->hide();
  sl->addWidget(suggestion_);
  layout->addWidget(stabilityBox);
  layout->addStretch(1);
  setWidget(body);
  connect(rotation_, &QComboBox::activated, this, [this](int index) {
    emit editRequested(vaw::sim::MethodEdit{static_cast<vaw::dyn::Method>(rotation_->itemData(index).toInt())}, -1);
  });
  connect(rate_, &QSpinBox::valueChanged, this, [this](int hz) { emit editRequested(vaw::sim::RateEdit{double(hz)}, RateKey); });
  connect(suggestion_, &QPushButton::clicked, this, [this] {
    if (!advice_) return;
    if (advice_->safeMethod) emit editRequested(vaw::sim::MethodEdit{*advice_->safeMethod}, -1);
    else if (advice_->safeRate) emit editRequested(vaw::sim::RateEdit{*advice_->safeRate}, -1);
  });
}

void MethodsDock::showWorld(const vaw::sim::World& world, const std::optional<vaw::sim::StabilityAdvice>& advice,
                            const QString& partName) {
  {
    const QSignalBlocker b1(rotation_), b2(rate_);
    const int i = rotation_->findData(static_cast<int>(world.settings().rotationMethod));
    if (i >= 0) rotation_->setCurrentIndex(i);
    if (!rate_->hasFocus()) rate_->setValue(static_cast<int>(std::lround(world.settings().rate)));
  }
  advice_ = advice;
  if (!advice) {
    stability_->setText(partName.isEmpty() ? tr("Select a part that turns on a shaft.")
                                           : tr("%1 does not turn on a shaft.").arg(partName));
    stability_->setStyleSheet({});
    suggestion_->hide();
    return;
  }
  const bool ok = advice->level == vaw::sim::StabilityAdvice::Level::Stable;
  stability_->setText(QStringLiteral("%1: %2").arg(partName, QString::fromStdString(advice->text)));
  stability_->setStyleSheet(ok ? QString() : QStringLiteral("color: rgb(180, 40, 20); font-weight: bold;"));
  suggestion_->setVisible(!ok && (advice->safeMethod || advice->safeRate));
  if (advice->safeMethod)
    suggestion_->setText(tr("Use %1").arg(QString::fromLatin1(vaw::dyn::name(*advice->safeMethod).data())));
  else if (advice->safeRate)
    suggestion_->setText(tr("Use %1 Hz").arg(QString::number(*advice->safeRate, 'g', 6)));
}

}  // namespace vaw::ui
