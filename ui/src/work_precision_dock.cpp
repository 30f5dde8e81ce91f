#include "vaw/ui/work_precision_dock.hpp"

#include <QComboBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QMetaObject>
#include <QProgressBar>
#include <QPushButton>
#include <QThread>
#include <QVBoxLayout>
#include <QtCharts/QChart>
#include <QtCharts/QChartView>
#include <QtCharts/QLogValueAxis>
#include <QtCharts/QScatterSeries>
#include <QtCharts/QValueAxis>
#include <algorithm>
#include <cmath>
#include <exception>

#include "vaw/peers/peers.hpp"
#include "vaw/sim/world.hpp"
#include "vaw/ui/work_precision_chart.hpp"

namespace vaw::ui {

namespace {

QString scenarioLabel(const std::string& s) {
  if (s == "slide-with-stop") return QObject::tr("Slide (a block on an incline, stopping)");
  if (s == "gear-pendulum") return QObject::tr("Rotation about an axis (gear pendulum)");
  if (s == "gear-pendulum-damped") return QObject::tr("Rotation about an axis, with rotational friction");
  if (s == "tumbling-block") return QObject::tr("Free flight (tumbling block)");
  if (s == "tennis-racket") return QObject::tr("Free flight about the intermediate axis (tennis racket)");
  return QString::fromStdString(s);
}

// A rate the measurement can use: a whole number of steps per 0.1 s sample.
bool sampledRate(double rate) {
  const double steps = rate * vaw::dyn::kSampleInterval;
  return rate >= 1.0 && std::abs(steps - std::round(steps)) < 1e-9;
}

}  // namespace

WorkPrecisionDock::WorkPrecisionDock(QWidget* parent) : QDockWidget(tr("Work-precision"), parent) {
  setObjectName(QStringLiteral("workPrecisionDock"));
  auto* body = new QWidget(this);
  auto* layout = new QVBoxLayout(body);
  layout->setContentsMargins(4, 4, 4, 4);
  auto* row = new QHBoxLayout();
  scenarioBox_ = new QComboBox(body);
  scenarioBox_->setObjectName(QStringLiteral("workPrecisionScenario"));
  for (const char* s : vaw::dyn::kScenarios) scenarioBox_->addItem(scenarioLabel(s), QString::fromLatin1(s));
  scenarioBox_->setToolTip(tr("The motion to measure; follows the selected part's model"));
  computeButton_ = new QPushButton(tr("Compute"), body);
  computeButton_->setObjectName(QStringLiteral("workPrecisionCompute"));
  computeButton_->setToolTip(tr("Run every method at every step rate on this motion, against its reference solution"));
  cancelButton_ = new QPushButton(tr("Cancel"), body);
  cancelButton_->setObjectName(QStringLiteral("workPrecisionCancel"));
  cancelButton_->setEnabled(false);
  progress_ = new QProgressBar(body);
  progress_->setObjectName(QStringLiteral("workPrecisionProgress"));
  progress_->setRange(0, 1);
  progress_->setValue(0);
  progress_->setTextVisible(true);
  layout->addWidget(scenarioBox_);
  row->addWidget(computeButton_);
  row->addWidget(cancelButton_);
  row->addWidget(progress_, 1);
  layout->addLayout(row);
  note_ = new QLabel(tr("Compute to measure each method's cost and error on the selected part's motion."), body);
  note_->setObjectName(QStringLiteral("workPrecisionNote"));
  note_->setWordWrap(true);
  layout->addWidget(note_);
  auto* empty = new QChart();
  empty->setTitle(tr("Not computed yet"));
  view_ = new QChartView(empty, body);
  view_->setRenderHint(QPainter::Antialiasing);
  view_->setMinimumHeight(260);
  layout->addWidget(view_, 1);
  setWidget(body);
  connect(computeButton_, &QPushButton::clicked, this, &WorkPrecisionDock::compute);
  connect(cancelButton_, &QPushButton::clicked, this, &WorkPrecisionDock::cancel);
  connect(scenarioBox_, &QComboBox::currentIndexChanged, this, [this] { draw(); });
}

WorkPrecisionDock::~WorkPrecisionDock() {
  // The measurement holds nothing of the window's; it only has to stop before the dock goes.
  if (thread_) {
    stop_->store(true);
    thread_->wait();
  }
}

std::string WorkPrecisionDock::scenario() const { return scenarioBox_->currentData().toString().toStdString(); }

QChart* WorkPrecisionDock::chart() const { return view_->chart(); }

std::string WorkPrecisionDock::scenarioFor(const vaw::sim::World& world, vaw::PartId part) {
  const vaw::sim::PartRuntime& r = world.part(part);
  if (r.model == vaw::sim::Model::Cylindrical)
    return world.friction(part).rotationalFriction > 0.0 ? "gear-pendulum-damped" : "gear-pendulum";
  if (r.model == vaw::sim::Model::Plane) return "slide-with-stop";
  return "tumbling-block";
}

std::string WorkPrecisionDock::methodFor(const std::string& scenario, const vaw::sim::World& world) {
  if (scenario == "slide-with-stop") return "exact";  // the slides' closed form within each step
  if (scenario == "gear-pendulum" || scenario == "gear-pendulum-damped")
    return std::string(vaw::dyn::name(world.settings().rotationMethod));
  return "torque-free";  // free flight: the closed form, or constant-omega where that is within tolerance
}

void WorkPrecisionDock::showWorld(const vaw::sim::World& world, std::optional<vaw::PartId> part) {
  // The list follows the part's model when the selection or the model changes; a scenario picked by hand
  // stays until then.
  if (part && !busy()) {
    const std::string follows = scenarioFor(world, *part);
    if (part != part_ || follows != followed_) {
      const int index = scenarioBox_->findData(QString::fromStdString(follows));
      if (index >= 0 && index != scenarioBox_->currentIndex()) scenarioBox_->setCurrentIndex(index);
      followed_ = follows;
    }
  }
  part_ = part;
  const std::string method = methodFor(scenario(), world);
  const double rate = world.settings().rate;
  if (method == method_ && rate == rate_) return;
  method_ = method;
  rate_ = rate;
  draw();
}

void WorkPrecisionDock::compute() {
  cancel();
  vaw::dyn::WorkPrecisionOptions options;
  options.repeats = 3;
  options.scenarios = {scenario()};
  options.rates.assign(vaw::dyn::kStepRates.begin(), vaw::dyn::kStepRates.end());
  const int current = static_cast<int>(std::lround(rate_));
  if (sampledRate(rate_) && std::find(options.rates.begin(), options.rates.end(), current) == options.rates.end()) {
    options.rates.push_back(current);
    std::sort(options.rates.begin(), options.rates.end());
  }
  stop_ = std::make_shared<std::atomic<bool>>(false);
  progress_->setRange(0, 0);  // busy until the first report gives the total
  computeButton_->setEnabled(false);
  cancelButton_->setEnabled(true);
  scenarioBox_->setEnabled(false);
  note_->setText(tr("Measuring %1…").arg(scenarioLabel(scenario())));
  auto stop = stop_;
  const int generation = ++generation_;
  // The worker reports through queued calls only; the dock outlives it (the destructor waits).
  thread_ = QThread::create([this, options, stop, generation] {
    std::vector<vaw::dyn::Record> records;
    QString error;
    try {
      records = vaw::dyn::runWorkPrecision(options, [this, stop](int done, int total) {
        QMetaObject::invokeMethod(this, [this, done, total] {
          progress_->setRange(0, total);
          progress_->setValue(done);
        }, Qt::QueuedConnection);
        return !stop->load();
      });
      if (!stop->load()) {
        const auto peers = vaw::peers::runPeers(options, [this, stop](const std::string& what) {
          QMetaObject::invokeMethod(this, [this, what] { note_->setText(tr("Measuring the peer %1…").arg(QString::fromStdString(what))); },
                                    Qt::QueuedConnection);
          return !stop->load();
        });
        records.insert(records.end(), peers.begin(), peers.end());
      }
    } catch (const std::exception& e) {
      error = QString::fromUtf8(e.what());
    }
    const bool cancelled = stop->load();
    QMetaObject::invokeMethod(this, [this, records = std::move(records), cancelled, error, generation]() mutable {
      if (generation == generation_) finish(std::move(records), cancelled, error);
    }, Qt::QueuedConnection);
  });
  thread_->start();
}

void WorkPrecisionDock::endMeasurement(bool complete) {
  thread_->wait();
  delete thread_;
  thread_ = nullptr;
  computeButton_->setEnabled(true);
  cancelButton_->setEnabled(false);
  scenarioBox_->setEnabled(true);
  progress_->setRange(0, 1);
  progress_->setValue(complete ? 1 : 0);
}

void WorkPrecisionDock::cancel() {
  if (!thread_) return;
  stop_->store(true);
  ++generation_;  // its last report is queued; what it found is dropped with it
  endMeasurement(false);
  note_->setText(tr("Cancelled."));
}

void WorkPrecisionDock::finish(std::vector<vaw::dyn::Record> records, bool cancelled, const QString& error) {
  endMeasurement(!cancelled);
  if (!error.isEmpty()) {
    note_->setText(tr("The measurement failed: %1").arg(error));
  } else if (!cancelled) {
    records_ = std::move(records);
  }
  draw();
  if (!error.isEmpty()) note_->setText(tr("The measurement failed: %1").arg(error));
  emit finished();
}

std::optional<vaw::dyn::Record> WorkPrecisionDock::highlighted() const {
  for (const auto& r : records_)
    if (r.scenario == scenario() && r.method == method_ && r.stepRate == rate_) return r;
  return std::nullopt;
}

void WorkPrecisionDock::draw() {
  const std::string s = scenario();
  const bool have = std::any_of(records_.begin(), records_.end(), [&](const auto& r) { return r.scenario == s; });
  if (!have) {
    auto* empty = new QChart();
    empty->setTitle(tr("%1: not computed yet").arg(scenarioLabel(s)));
    QChart* old = view_->chart();
    view_->setChart(empty);
    delete old;
    if (!busy()) note_->setText(tr("Compute to measure each method's cost and error on this motion (%1 at %2 Hz is what the world uses now).")
                                    .arg(QString::fromStdString(method_), QString::number(rate_, 'g', 6)));
    return;
  }
  QChart* chart = makeWorkPrecisionChart(records_, s);
  // A dock is short: the list names the scenario and the line below the axes, so the plot gets the height.
  chart->setTitle(QString());
  chart->legend()->setAlignment(Qt::AlignBottom);
  QFont small = chart->titleFont();
  small.setPointSizeF(7.5);
  for (QAbstractAxis* a : chart->axes()) {
    a->setLabelsFont(small);
    a->setTitleVisible(false);
  }
  // A label per decade does not fit a dock's height when the errors span many: one per two decades then.
  for (QAbstractAxis* a : chart->axes(Qt::Vertical))
    if (auto* log = qobject_cast<QLogValueAxis*>(a); log && log->max() > 1e4 * log->min()) log->setBase(100.0);
  chart->legend()->setFont(small);
  chart->setMargins(QMargins(2, 2, 2, 2));
  const auto now = highlighted();
  QString text;
  if (now) {
    auto* mark = new QScatterSeries(chart);
    mark->setName(tr("now: %1 at %2 Hz").arg(QString::fromStdString(method_), QString::number(rate_, 'g', 6)));
    mark->setMarkerShape(QScatterSeries::MarkerShapeCircle);
    mark->setMarkerSize(18);
    mark->setColor(Qt::transparent);
    QPen ring(QColor(230, 120, 0));
    ring.setWidthF(3.0);
    mark->setPen(ring);
    mark->append(now->cpuPerSimSecond, std::clamp(now->error, 1e-16, 1e3));
    chart->addSeries(mark);
    for (QAbstractAxis* a : chart->axes()) mark->attachAxis(a);
    text = tr("Now: %1 at %2 Hz, error %3 %4 for %5 s of CPU per simulated second%6.")
               .arg(QString::fromStdString(method_), QString::number(rate_, 'g', 6), QString::number(now->error, 'g', 3),
                    QString::fromStdString(now->errorUnit), QString::number(now->cpuPerSimSecond, 'g', 3),
                    now->stable ? QString() : tr(" (unstable at this step)"));
  } else if (!sampledRate(rate_)) {
    text = tr("The world's rate of %1 Hz is not a whole number of steps per 0.1 s sample, so it has no point here.")
               .arg(QString::number(rate_, 'g', 6));
  } else {
    text = tr("%1 at %2 Hz was not measured: compute again to add it.").arg(QString::fromStdString(method_), QString::number(rate_, 'g', 6));
  }
  const bool peers = std::any_of(records_.begin(), records_.end(), [&](const auto& r) {
    return r.scenario == s && (r.method == "bullet" || r.method == "ode");
  });
  if (!peers && (s == "slide-with-stop" || s.starts_with("gear-pendulum")))
    text += tr(" No peer engine was built in (Bullet, ODE).");
  const auto unit = std::find_if(records_.begin(), records_.end(), [&](const auto& r) { return r.scenario == s; })->errorUnit;
  note_->setText(tr("Across: CPU seconds per simulated second; up: largest error against the reference (%1). ")
                     .arg(QString::fromStdString(unit)) + text);
  QChart* old = view_->chart();
  view_->setChart(chart);
  delete old;
}

}  // namespace vaw::ui
