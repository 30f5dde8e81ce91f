#include "vaw/ui/path_dock.hpp"

#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QPointer>
#include <QProgressBar>
#include <QPushButton>
#include <QSettings>
#include <QStandardItemModel>
#include <QTableView>
#include <QVBoxLayout>
#include <QtCharts/QChart>
#include <QtCharts/QChartView>
#include <QtCharts/QLineSeries>
#include <QtCharts/QScatterSeries>
#include <QtCharts/QValueAxis>
#include <QtConcurrent/QtConcurrentRun>
#include <algorithm>
#include <new>

#include "vaw/atomic_file.hpp"
#include "vaw/error.hpp"
#include "vaw/mesh_export.hpp"
#include "vaw/sim/recorder.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/ui/background.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/viewport.hpp"
#include "vaw/view/frame.hpp"

namespace vaw::ui {

namespace {
constexpr double kReach = 0.1;  // m: the table lists the objects the path came this close to
}  // namespace

PathDock::PathDock(SimulationController& simulation, Viewport& viewport, const vaw::ImporterRegistry& plugins, QWidget* parent)
    : QDockWidget(tr("Path"), parent), simulation_(simulation), viewport_(viewport), plugins_(plugins) {
  setObjectName(QStringLiteral("pathDock"));
  auto* body = new QWidget(this);
  auto* outer = new QVBoxLayout(body);
  outer->setContentsMargins(4, 4, 4, 4);
  // The outcome in one line over the whole panel: the controls' column is too narrow to hold it.
  summary_ = new QLabel(body);
  summary_->setObjectName(QStringLiteral("pathSummary"));
  summary_->setWordWrap(true);
  summary_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  outer->addWidget(summary_);
  auto* layout = new QHBoxLayout();
  outer->addLayout(layout, 1);

  auto* left = new QVBoxLayout();
  partLabel_ = new QLabel(tr("Select a part that was carried"), body);
  partLabel_->setObjectName(QStringLiteral("pathPart"));
  left->addWidget(partLabel_);
  auto* form = new QFormLayout();
  voxel_ = new QDoubleSpinBox(body);
  voxel_->setObjectName(QStringLiteral("pathVoxel"));
  voxel_->setRange(0.1, 50.0);
  voxel_->setDecimals(2);
  voxel_->setSingleStep(0.5);
  voxel_->setValue(1.0);
  voxel_->setSuffix(tr(" mm"));
  voxel_->setToolTip(tr("The voxels' edge: the volume holds the whole path and lies within about a voxel of it"));
  form->addRow(tr("Voxel"), voxel_);
  threshold_ = new QDoubleSpinBox(body);
  threshold_->setObjectName(QStringLiteral("pathThreshold"));
  threshold_->setRange(0.0, 1000.0);
  threshold_->setDecimals(1);
  threshold_->setValue(5.0);
  threshold_->setSuffix(tr(" mm"));
  threshold_->setToolTip(tr("Apart but closer than this is a near miss (red on the chart)"));
  form->addRow(tr("Near miss under"), threshold_);
  left->addLayout(form);
  relative_ = new QCheckBox(tr("Relative to the base"), body);
  relative_->setObjectName(QStringLiteral("pathRelative"));
  relative_->setToolTip(tr("The path in the base's frame: the space it needs on a base that turns"));
  left->addWidget(relative_);
  auto* buttons = new QHBoxLayout();
  sweep_ = new QPushButton(tr("Sweep"), body);
  sweep_->setObjectName(QStringLiteral("pathSweep"));
  sweep_->setToolTip(tr("The volume the part's carried path swept and its clearance, over the recording so far"));
  sweep_->setEnabled(false);
  export_ = new QPushButton(tr("Export..."), body);
  export_->setToolTip(tr("The swept volume as STL or as a STEP solid, in the scene's unit and frame"));
  export_->setObjectName(QStringLiteral("pathExport"));
  export_->setEnabled(false);
  stopExport_ = new QPushButton(tr("Stop"), body);
  stopExport_->setObjectName(QStringLiteral("pathStopExport"));
  stopExport_->setToolTip(tr("Stop writing the file: what was there stays"));
  stopExport_->hide();
  buttons->addWidget(sweep_);
  buttons->addWidget(export_);
  buttons->addWidget(stopExport_);
  left->addLayout(buttons);
  show_ = new QCheckBox(tr("Show the volume"), body);
  show_->setObjectName(QStringLiteral("pathShow"));
  show_->setChecked(true);
  left->addWidget(show_);
  busy_ = new QProgressBar(body);
  busy_->setObjectName(QStringLiteral("pathBusy"));
  busy_->setRange(0, 0);  // no fraction to tell: it moves while the worker runs
  busy_->setTextVisible(false);
  busy_->hide();
  left->addWidget(busy_);
  left->addStretch(1);
  layout->addLayout(left, 0);

  auto* chart = new QChart();
  chart->setObjectName(QStringLiteral("pathChart"));
  distance_ = new QLineSeries(chart);
  distance_->setName(tr("least clearance (mm)"));
  limit_ = new QLineSeries(chart);
  limit_->setName(tr("near-miss threshold"));
  limit_->setPen(QPen(QColor(200, 30, 30), 1.0, Qt::DashLine));
  near_ = new QScatterSeries(chart);
  near_->setName(tr("near miss, touching or in"));
  near_->setColor(QColor(235, 120, 0));
  near_->setBorderColor(QColor(235, 120, 0));
  near_->setMarkerSize(5.0);
  chart->addSeries(distance_);
  chart->addSeries(limit_);
  chart->addSeries(near_);
  timeAxis_ = new QValueAxis(chart);
  distanceAxis_ = new QValueAxis(chart);
  QFont small = timeAxis_->labelsFont();
  small.setPointSizeF(7.0);
  for (QValueAxis* a : {timeAxis_, distanceAxis_}) {
    a->setLabelsFont(small);
    a->setTickCount(5);
    a->setTitleVisible(false);
  }
  chart->addAxis(timeAxis_, Qt::AlignBottom);
  chart->addAxis(distanceAxis_, Qt::AlignLeft);
  for (auto* s : std::initializer_list<QXYSeries*>{distance_, limit_, near_}) {
    s->attachAxis(timeAxis_);
    s->attachAxis(distanceAxis_);
  }
  chart->setTitle(tr("Least clearance over time (s)"));
  chart->legend()->setAlignment(Qt::AlignBottom);
  chart->setMargins(QMargins(2, 2, 2, 2));
  chartView_ = new QChartView(chart, body);
  chartView_->setObjectName(QStringLiteral("pathChartView"));
  chartView_->setRenderHint(QPainter::Antialiasing);
  chartView_->setMinimumSize(320, 160);
  layout->addWidget(chartView_, 2);

  rows_ = new QStandardItemModel(0, 4, this);
  rows_->setHorizontalHeaderLabels({tr("Object"), tr("Least (mm)"), tr("At (s)"), tr("Where on the part (mm)")});
  table_ = new QTableView(body);
  table_->setObjectName(QStringLiteral("pathTable"));
  table_->setModel(rows_);
  table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  table_->setSelectionBehavior(QAbstractItemView::SelectRows);
  table_->setSelectionMode(QAbstractItemView::SingleSelection);
  table_->verticalHeader()->hide();
  table_->horizontalHeader()->setStretchLastSection(true);
  table_->setToolTip(tr("Every object the path came within %1 mm of, closest first; double-click a row to see that moment")
                         .arg(1e3 * kReach));
  layout->addWidget(table_, 2);
  setWidget(body);

  connect(sweep_, &QPushButton::clicked, this, &PathDock::sweep);
  connect(export_, &QPushButton::clicked, this, &PathDock::askExport);
  connect(threshold_, &QDoubleSpinBox::valueChanged, this, &PathDock::showThreshold);
  connect(show_, &QCheckBox::toggled, this, [this](bool on) {
    viewport_.showSweptVolume(on && result_ ? vaw::view::flatShaded(result_->swept.mesh) : nullptr);
  });
  connect(table_, &QTableView::activated, this, [this](const QModelIndex& index) {
    if (!result_ || !simulation_.hasWorld()) return;
    const double t = rows_->item(index.row(), 2)->data(Qt::UserRole).toDouble();
    simulation_.pause();
    simulation_.seek(simulation_.recorder().stepAt(t));
  });
  connect(&watcher_, &QFutureWatcher<Result>::finished, this, &PathDock::finished);
  connect(stopExport_, &QPushButton::clicked, this, &PathDock::stopExport);
  connect(&exportWatcher_, &QFutureWatcher<QString>::finished, this, [this] {
    exporting_ = false;
    stopExport_->hide();
    busy_->setRange(0, 0);
    busy_->setVisible(working_);
    export_->setEnabled(result_.has_value());
    const QString why = exportWatcher_.result();
    emit statusMessage(why.isEmpty() ? tr("Swept volume written to %1").arg(exportFile_) : tr("Not exported: %1").arg(why));
    if (!why.isEmpty()) summary_->setText(tr("Not exported: %1").arg(why));
    emit exported(exportFile_, why);
  });
}

PathDock::~PathDock() {
  watcher_.disconnect(this);
  watcher_.waitForFinished();
  exportWatcher_.disconnect(this);
  // A STEP write of a fine volume can take a minute: the window closing stops it instead of waiting.
  if (exportStopped_) exportStopped_->store(true);
  exportWatcher_.waitForFinished();
}

void PathDock::stopExport() {
  if (exporting_ && exportStopped_) exportStopped_->store(true);
}

void PathDock::setPart(std::optional<vaw::PartId> part) {
  part_ = part;
  if (part && simulation_.hasWorld() && *part < simulation_.recorder().scene().assembly().parts.size())
    partLabel_->setText(tr("Part: %1").arg(QString::fromStdString(simulation_.recorder().scene().assembly().parts[*part].name)));
  else
    partLabel_->setText(tr("Select a part that was carried"));
  sweep_->setEnabled(part.has_value() && !working_);
}

void PathDock::clear() {
  ++generation_;
  result_.reset();
  viewport_.showSweptVolume(nullptr);
  distance_->clear();
  limit_->clear();
  near_->clear();
  rows_->removeRows(0, rows_->rowCount());
  summary_->clear();
  export_->setEnabled(false);
  setPart(std::nullopt);
  emit cleared();
}

void PathDock::sweep() {
  if (working_ || !part_ || !simulation_.hasWorld()) return;
  // The worker takes copies: the recording goes on while it works.
  const vaw::sim::Recorder& rec = simulation_.recorder();
  vaw::sim::Session session = rec.session();
  const vaw::PartId part = *part_;
  vaw::sim::SweptVolumeOptions so;
  so.voxel = 1e-3 * voxel_->value();
  so.relativeToBase = relative_->isChecked();
  vaw::sim::ClearanceOptions co;
  co.threshold = 1e-3 * threshold_->value();
  co.reach = kReach;
  working_ = true;
  sweep_->setEnabled(false);
  busy_->show();
  summary_->setText(tr("Sweeping %1 over %2 recorded steps...")
                        .arg(QString::fromStdString(rec.scene().assembly().parts[part].name))
                        .arg(session.inputs.size()));
  emit statusMessage(summary_->text());
  watcher_.setFuture(QtConcurrent::run([scene = rec.scenePtr(), session = std::move(session), part, so, co, generation = generation_] {
    Result out;
    out.scene = scene;
    out.part = part;
    out.generation = generation;
    try {
      const BackgroundTask task("sweep");
      vaw::sim::SweptPathAndClearance both = vaw::sim::sweptVolumeAndClearance(scene, session, part, so, co);
      out.swept = std::move(both.swept);
      out.clearance = std::move(both.clearance);
    } catch (const std::bad_alloc&) {
      // Coming back through the watcher into a slot, any exception would end the window with the user's
      // unsaved session: each is said instead.
      out.error = QObject::tr("Not enough memory to sweep at %1 mm voxels: a larger voxel fits.").arg(1e3 * so.voxel);
    } catch (const std::exception& e) {  // vaw::InputError, and a grid too large for the voxel (with what fits)
      out.error = QString::fromStdString(e.what());
    }
    return out;
  }));
}

void PathDock::finished() {
  Result out = watcher_.result();
  working_ = false;
  busy_->setVisible(exporting_);
  sweep_->setEnabled(part_.has_value());
  // A result for a world that has since been replaced (a new scene, a reset, a session) is dropped.
  if (out.generation != generation_) {
    summary_->clear();
    emit finishedSweep();
    return;
  }
  if (!out.error.isEmpty()) {
    result_.reset();
    viewport_.showSweptVolume(nullptr);
    export_->setEnabled(false);
    summary_->setText(out.error);
    emit statusMessage(out.error);
    emit finishedSweep();
    return;
  }
  result_ = std::move(out);
  showResult();
  emit finishedSweep();
}

void PathDock::showResult() {
  const vaw::SweptVolume& sv = result_->swept;
  const vaw::sim::ClearanceReport& cr = result_->clearance;
  const vaw::Assembly& a = result_->scene->assembly();
  QString text = tr("%1 swept %2 cm³ (%3 voxels of %4 mm, t %5 to %6 s)")
                     .arg(QString::fromStdString(a.parts[result_->part].name))
                     .arg(1e6 * sv.volume, 0, 'f', 1)
                     .arg(QLocale().toString(static_cast<qulonglong>(sv.voxels)))
                     .arg(1e3 * sv.voxel, 0, 'g', 3)
                     .arg(sv.from, 0, 'f', 2)
                     .arg(sv.to, 0, 'f', 2);
  if (sv.relativeToBase) text += tr(", on %1").arg(QString::fromStdString(a.parts[*a.base].name));
  if (!cr.objects.empty())
    text += tr(". Nearest: %1, %2 mm at %3 s").arg(QString::fromStdString(cr.objects.front().name)).arg(1e3 * cr.objects.front().least, 0, 'f', 2).arg(cr.objects.front().t, 0, 'f', 2);
  int interference = 0, contact = 0;
  for (const auto& s : cr.spans) {
    if (s.kind == vaw::sim::ClearanceSpan::Kind::Interference) ++interference;
    if (s.kind == vaw::sim::ClearanceSpan::Kind::Contact) ++contact;
  }
  if (interference > 0 || contact > 0) text += tr("; %1 interference and %2 contact spans").arg(interference).arg(contact);
  summary_->setText(text + QLatin1Char('.'));
  emit statusMessage(summary_->text());
  export_->setEnabled(!exporting_);
  if (show_->isChecked()) viewport_.showSweptVolume(vaw::view::flatShaded(sv.mesh));

  QList<QPointF> points;
  points.reserve(static_cast<qsizetype>(cr.steps.size()));
  double most = 0.0;
  for (const auto& s : cr.steps) {
    points.append(QPointF(s.t, 1e3 * s.distance));
    most = std::max(most, 1e3 * s.distance);
  }
  distance_->replace(points);
  timeAxis_->setRange(cr.steps.empty() ? 0.0 : cr.steps.front().t, cr.steps.empty() ? 1.0 : std::max(cr.steps.back().t, cr.steps.front().t + 1e-3));
  distanceAxis_->setRange(0.0, std::max({most, threshold_->value() * 1.5, 1.0}));
  rows_->removeRows(0, rows_->rowCount());
  for (const auto& o : cr.objects) {
    QList<QStandardItem*> row;
    row << new QStandardItem(QString::fromStdString(o.name));
    row << new QStandardItem(QString::number(1e3 * o.least, 'f', 3));
    auto* at = new QStandardItem(QString::number(o.t, 'f', 3));
    at->setData(o.t, Qt::UserRole);
    row << at;
    row << new QStandardItem(QStringLiteral("%1, %2, %3").arg(1e3 * o.onPart.x(), 0, 'f', 1).arg(1e3 * o.onPart.y(), 0, 'f', 1).arg(1e3 * o.onPart.z(), 0, 'f', 1));
    rows_->appendRow(row);
  }
  table_->resizeColumnsToContents();
  showThreshold();
}

void PathDock::showThreshold() {
  limit_->clear();
  near_->clear();
  if (!result_) return;
  const auto& steps = result_->clearance.steps;
  if (steps.empty()) return;
  const double mm = threshold_->value();
  limit_->append(steps.front().t, mm);
  limit_->append(steps.back().t, mm);
  QList<QPointF> close;
  for (const auto& s : steps)
    if (1e3 * s.distance < mm || s.interfering) close.append(QPointF(s.t, 1e3 * s.distance));
  near_->replace(close);
}

void PathDock::exportVolume(const QString& file, bool faceted) {
  if (!result_ || exporting_) return;
  const vaw::Assembly& a = result_->scene->assembly();
  const std::string partName = a.parts[result_->part].name;
  const std::filesystem::path target = file.toStdString();
  const vaw::SolidExporter* step = QFileInfo(file).suffix().compare(QStringLiteral("stl"), Qt::CaseInsensitive) == 0
                                       ? nullptr
                                       : plugins_.exporterFor(target);
  if (step == nullptr && QFileInfo(file).suffix().compare(QStringLiteral("stl"), Qt::CaseInsensitive) != 0) {
    const QString why = tr("%1: vaw writes .stl, and .step or .stp with the STEP plugin installed").arg(file);
    summary_->setText(tr("Not exported: %1").arg(why));
    emit exported(file, why);
    return;
  }
  exporting_ = true;
  exportFile_ = file;
  export_->setEnabled(false);
  busy_->show();
  if (step != nullptr) {
    busy_->setRange(0, 100);
    busy_->setValue(0);
    stopExport_->show();
  }
  emit statusMessage(tr("Writing %1...").arg(file));
  // The STEP writer is held to the limits the reader is (File > STEP Settings).
  const QSettings settings;
  vaw::ExportOptions limits;
  limits.timeoutSeconds = settings.value(QStringLiteral("import/timeoutSeconds"), limits.timeoutSeconds).value<double>();
  limits.memoryMB = settings.value(QStringLiteral("import/readerMemoryMB"), limits.memoryMB).value<double>();
  limits.faceted = faceted;
  exportStopped_ = std::make_shared<std::atomic<bool>>(false);
  const QPointer<PathDock> self(this);
  const vaw::ProgressFn progress = [stopped = exportStopped_, self, file](double fraction, const std::string& stage) {
    QMetaObject::invokeMethod(
        self, [self, file, fraction, text = QString::fromStdString(stage)] {
          if (!self || !self->exporting_) return;
          self->busy_->setValue(static_cast<int>(100.0 * fraction));
          emit self->statusMessage(tr("Writing %1: %2").arg(file, text));
        },
        Qt::QueuedConnection);
    return !stopped->load();
  };
  // The worker takes its own copy of the mesh: a new sweep may replace the result meanwhile.
  exportWatcher_.setFuture(QtConcurrent::run([mesh = result_->swept.mesh, units = a.units, partName, target, step, limits, progress]() -> QString {
    try {
      const BackgroundTask task("export");
      if (step != nullptr) step->write(mesh, partName + " swept", units, target, limits, progress);
      else vaw::writeFileAtomically(target, vaw::binaryStl(mesh, 1.0 / vaw::toMetres(units), "vaw swept volume of " + partName + ", " + std::string(vaw::name(units))));
    } catch (const std::exception& e) {
      return failureText(e);
    }
    return {};
  }));
}

void PathDock::askExport() {
  if (!result_) return;
  QString filters = tr("STL (*.stl)");
  const QString faceted = tr("STEP faceted solid, about a third the size (*.step *.stp)");
  if (plugins_.exporterFor("x.step") != nullptr) filters += tr(";;STEP solid (*.step *.stp);;") + faceted;
  const QString name = QString::fromStdString(result_->scene->assembly().parts[result_->part].name) + QStringLiteral("-swept.stl");
  QString chosen;
  const QString file = QFileDialog::getSaveFileName(this, tr("Export the swept volume"), name, filters, &chosen);
  if (!file.isEmpty()) exportVolume(file, chosen == faceted);
}

}  // namespace vaw::ui
