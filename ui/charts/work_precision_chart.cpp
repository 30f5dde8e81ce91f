#include "vaw/ui/work_precision_chart.hpp"

#include <QtCharts/QChartView>
#include <QtCharts/QLegendMarker>
#include <QtCharts/QLineSeries>
#include <QtCharts/QLogValueAxis>
#include <QtCharts/QScatterSeries>
#include <QtGui/QPainter>
#include <QtSvg/QSvgGenerator>
#include <QtWidgets/QApplication>
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>

namespace vaw::ui {

namespace {

// Round-off errors (1e-15) and exact zeros have no place on a log axis; show them on a floor line.
constexpr double kErrorFloor = 1e-16;
// A diverged run's error is not a number worth plotting to scale.
constexpr double kErrorCeiling = 1e3;

QString title(const std::string& scenario) {
  static const std::map<std::string, QString> titles{
      {"slide-with-stop", "Slide with stop: block on an 8 degree incline, v0 = 1.5 m/s, f_s 0.3, f_d 0.2 (error in m; paper-explicit lies under exact)"},
      {"gear-pendulum", "Gear pendulum, undamped: r 0.05 m, m 0.3 kg, CM 0.02 m off the axis, 60 degrees (error in rad)"},
      {"gear-pendulum-damped", "Gear pendulum, damped: f_r = 0.0005 N m s, 60 degrees (error in rad)"},
      {"tumbling-block", "Tumbling block: 0.2 x 0.1 x 0.05 m steel, w = (3, 1, 5) rad/s (orientation error in rad)"}};
  auto it = titles.find(scenario);
  return it == titles.end() ? QString::fromStdString(scenario) : it->second;
}

QColor colorFor(const std::string& method) {
  static const std::map<std::string, QColor> colors{
      {"paper-explicit", QColor("#d62728")},   {"semi-implicit-euler", QColor("#1f77b4")},
      {"velocity-verlet", QColor("#2ca02c")},  {"rk4", QColor("#9467bd")},
      {"exact", QColor("#000000")},            {"constant-omega", QColor("#d62728")},
      {"torque-free-rk4", QColor("#9467bd")},  {"bullet", QColor("#ff7f0e")},
      {"ode", QColor("#8c564b")}};
  auto it = colors.find(method);
  return it == colors.end() ? QColor("#7f7f7f") : it->second;
}

}  // namespace

QChart* makeWorkPrecisionChart(const std::vector<dyn::Record>& records, const std::string& scenario) {
  auto* chart = new QChart();
  chart->setTitle(title(scenario));
  chart->legend()->setAlignment(Qt::AlignRight);
  auto* x = new QLogValueAxis();
  x->setTitleText("CPU seconds per simulated second (median)");
  x->setLabelFormat("%.0e");
  x->setMinorTickCount(-1);
  auto* y = new QLogValueAxis();
  y->setTitleText("max error against the reference");
  y->setLabelFormat("%.0e");
  y->setMinorTickCount(-1);
  chart->addAxis(x, Qt::AlignBottom);
  chart->addAxis(y, Qt::AlignLeft);

  std::vector<std::string> methods;
  for (const auto& r : records)
    if (r.scenario == scenario && std::find(methods.begin(), methods.end(), r.method) == methods.end()) methods.push_back(r.method);

  double xMin = 1e300, xMax = 0, yMin = 1e300, yMax = 0;
  auto* unstable = new QScatterSeries();
  unstable->setName("unstable at this step");
  unstable->setMarkerShape(QScatterSeries::MarkerShapeRectangle);
  unstable->setMarkerSize(13);
  unstable->setColor(Qt::transparent);
  unstable->setBorderColor(QColor("#d62728"));
  for (const auto& method : methods) {
    auto* line = new QLineSeries();
    line->setName(QString::fromStdString(method));
    QPen pen(colorFor(method));
    pen.setWidthF(2.0);
    if (method == "bullet" || method == "ode") pen.setStyle(Qt::DashLine);
    line->setPen(pen);
    line->setPointsVisible(true);
    std::vector<const dyn::Record*> rows;
    for (const auto& r : records)
      if (r.scenario == scenario && r.method == method) rows.push_back(&r);
    std::sort(rows.begin(), rows.end(), [](auto* a, auto* b) { return a->stepRate < b->stepRate; });
    for (const auto* r : rows) {
      const double cx = r->cpuPerSimSecond, cy = std::clamp(r->error, kErrorFloor, kErrorCeiling);
      line->append(cx, cy);
      if (!r->stable) unstable->append(cx, cy);
      xMin = std::min(xMin, cx);
      xMax = std::max(xMax, cx);
      yMin = std::min(yMin, cy);
      yMax = std::max(yMax, cy);
    }
    chart->addSeries(line);
    line->attachAxis(x);
    line->attachAxis(y);
  }
  chart->addSeries(unstable);
  unstable->attachAxis(x);
  unstable->attachAxis(y);
  if (unstable->count() == 0) chart->legend()->markers(unstable).front()->setVisible(false);
  if (xMax > 0) {
    x->setRange(std::pow(10.0, std::floor(std::log10(xMin))), std::pow(10.0, std::ceil(std::log10(xMax))));
    y->setRange(std::pow(10.0, std::floor(std::log10(yMin))), std::pow(10.0, std::ceil(std::log10(yMax))));
  }
  return chart;
}

std::vector<std::filesystem::path> writeWorkPrecisionCharts(const std::vector<dyn::Record>& records,
                                                            const std::filesystem::path& dir, int argc, char** argv) {
  std::unique_ptr<QApplication> app;
  if (!QApplication::instance()) {
    if (qEnvironmentVariableIsEmpty("DISPLAY") && qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM"))
      qputenv("QT_QPA_PLATFORM", "offscreen");
    app = std::make_unique<QApplication>(argc, argv);
  }
  std::set<std::string> scenarios;
  for (const auto& r : records) scenarios.insert(r.scenario);
  std::vector<std::filesystem::path> written;
  for (const auto& scenario : scenarios) {
    QChartView view(makeWorkPrecisionChart(records, scenario));
    view.setRenderHint(QPainter::Antialiasing);
    view.resize(1100, 650);
    const auto png = dir / ("work-precision-" + scenario + ".png");
    view.grab().save(QString::fromStdString(png.string()), "PNG");
    const auto svg = dir / ("work-precision-" + scenario + ".svg");
    QSvgGenerator gen;
    gen.setFileName(QString::fromStdString(svg.string()));
    gen.setSize(view.size());
    gen.setViewBox(QRect(QPoint(0, 0), view.size()));
    gen.setTitle(title(scenario));
    QPainter painter(&gen);
    view.render(&painter);
    painter.end();
    written.push_back(png);
    written.push_back(svg);
  }
  return written;
}

}  // namespace vaw::ui
