#include "vaw/ui/trials_chart.hpp"

#include <QtCharts/QAreaSeries>
#include <QtCharts/QChartView>
#include <QtCharts/QLegendMarker>
#include <QtCharts/QLineSeries>
#include <QtCharts/QLogValueAxis>
#include <QtCharts/QScatterSeries>
#include <QtCharts/QValueAxis>
#include <QtGui/QPainter>
#include <QtWidgets/QApplication>
#include <algorithm>
#include <cmath>
#include <memory>

namespace vaw::ui {

namespace {

using trials::AnswerKind;

QString number(double v) { return QString::number(v, 'g', 3); }

QString title(const trials::ConditionAnalysis& a) {
  const auto& c = a.condition;
  QString t = QString::fromStdString(std::string(trials::name(c.scenario)) + ", " + std::string(trials::name(c.motion)) + " scale: ");
  if (c.answers == AnswerKind::Setting) t += "adjusted settings";
  else if (c.answers == AnswerKind::TwoInterval) t += "judged faster than the reference at " + number(*c.referenceScale);
  else t += "judged too fast";
  t += QString(" (%1 participant%2)").arg(a.participants.size()).arg(a.participants.size() == 1 ? "" : "s");
  if (a.allAnswersFit && a.allAnswersFit->ok)
    t += QString("<br>curve: every answer in one fit, PSE %1, spread %2 (ln), lapse %3 (fixed)")
             .arg(number(a.allAnswersFit->pse), number(a.allAnswersFit->sigmaLog), number(a.allAnswersFit->lapse));
  if (a.predicted)
    t += QString("<br>head-demand model: peak %1 deg/s at 1 g; the %2 limit %3 deg/s allows up to %4, so %5")
             .arg(number(a.predicted->atFullGravity.peakRate_deg_s), QString::fromStdString(a.predicted->limitedBy),
                  number(a.predicted->rateLimit_deg_s), number(a.predicted->maxScale), number(a.predicted->recommendedScale));
  return t;
}

void attach(QChart* chart, QAbstractSeries* s, QAbstractAxis* x, QAbstractAxis* y) {
  chart->addSeries(s);
  s->attachAxis(x);
  s->attachAxis(y);
}

QLineSeries* verticalLine(double x, const QString& name, const QColor& color, Qt::PenStyle style) {
  auto* line = new QLineSeries();
  line->setName(name);
  QPen pen(color);
  pen.setWidthF(2.0);
  pen.setStyle(style);
  line->setPen(pen);
  line->append(x, 0.0);
  line->append(x, 1.0);
  return line;
}

}  // namespace

QChart* makeTrialsChart(const trials::ConditionAnalysis& a) {
  auto* chart = new QChart();
  chart->setTitle(title(a));
  chart->legend()->setAlignment(Qt::AlignBottom);
  const bool settings = a.condition.answers == AnswerKind::Setting;

  // The x range holds every tested scale, the pooled interval and the model's scale.
  std::vector<double> xs;
  for (const auto& s : a.perScale) xs.push_back(s.scale);
  if (a.pooled) {
    xs.push_back(a.pooled->estimate);
    if (a.pooled->interval.lo > 0) xs.push_back(a.pooled->interval.lo);
    if (std::isfinite(a.pooled->interval.hi)) xs.push_back(a.pooled->interval.hi);
  }
  if (a.predicted) xs.push_back(a.predicted->recommendedScale);
  const double xMin = *std::min_element(xs.begin(), xs.end()) / 1.25, xMax = *std::max_element(xs.begin(), xs.end()) * 1.25;

  auto* x = new QLogValueAxis();
  x->setTitleText("gravity scale (log axis)");
  // Base 2: a label at every doubling, which is how far apart the scales a study tests usually are.
  x->setLabelFormat("%.3g");
  x->setBase(2.0);
  x->setMinorTickCount(1);
  x->setRange(xMin, xMax);
  auto* y = new QValueAxis();
  y->setTitleText(settings ? "share of settings at or below the scale" : "share of answers \"faster\"");
  // A margin above 1 and below 0, so the answers at those shares (most of them, at the ends of the range)
  // are whole points rather than halves cut by the plot's edge; the labels stay at 0, 0.2, ..., 1.
  y->setRange(-0.05, 1.05);
  y->setTickType(QValueAxis::TicksDynamic);
  y->setTickAnchor(0.0);
  y->setTickInterval(0.2);
  chart->addAxis(x, Qt::AlignBottom);
  chart->addAxis(y, Qt::AlignLeft);

  // The pooled interval as a band, drawn first so that everything else lies on top of it.
  if (a.pooled) {
    const double lo = std::max(a.pooled->interval.lo, xMin), hi = std::min(a.pooled->interval.hi, xMax);
    auto* upper = new QLineSeries();
    auto* lower = new QLineSeries();
    upper->append(lo, 1.0);
    upper->append(hi, 1.0);
    lower->append(lo, 0.0);
    lower->append(hi, 0.0);
    auto* band = new QAreaSeries(upper, lower);
    upper->setParent(band);
    lower->setParent(band);
    band->setName(QString("interval %1 - %2").arg(number(a.pooled->interval.lo), number(a.pooled->interval.hi)));
    band->setColor(QColor(31, 119, 180, 45));
    band->setBorderColor(Qt::transparent);
    attach(chart, band, x, y);
  }

  // Answers: the share at each scale; settings: their empirical distribution.
  auto* points = new QScatterSeries();
  points->setMarkerSize(9);
  points->setColor(QColor("#333333"));
  QLineSeries* curve = nullptr;
  if (settings) {
    points->setName("settings");
    int total = 0, below = 0;
    double sum = 0.0, sumSq = 0.0;
    for (const auto& s : a.perScale) total += s.trials;
    for (const auto& s : a.perScale) {
      below += s.trials;
      points->append(s.scale, static_cast<double>(below) / total);
      sum += s.trials * std::log(s.scale);
      sumSq += s.trials * std::log(s.scale) * std::log(s.scale);
    }
    const double mean = sum / total, sd = std::sqrt(std::max(sumSq / total - mean * mean, 1e-12));
    curve = new QLineSeries();
    curve->setName("log-normal fit");
    for (int i = 0; i <= 200; ++i) {
      const double s = xMin * std::pow(xMax / xMin, i / 200.0);
      curve->append(s, 0.5 * std::erfc(-(std::log(s) - mean) / (sd * std::sqrt(2.0))));
    }
  } else {
    points->setName("answers at each scale");
    for (const auto& s : a.perScale) points->append(s.scale, static_cast<double>(s.faster) / s.trials);
    if (a.allAnswersFit && a.allAnswersFit->ok) {
      const auto& f = *a.allAnswersFit;
      curve = new QLineSeries();
      curve->setName("fitted curve");
      for (int i = 0; i <= 200; ++i) {
        const double s = xMin * std::pow(xMax / xMin, i / 200.0);
        curve->append(s, trials::psychometric(s, f.pse, f.sigmaLog, f.lapse));
      }
    }
  }
  if (curve) {
    QPen pen(QColor("#1f77b4"));
    pen.setWidthF(2.5);
    curve->setPen(pen);
    attach(chart, curve, x, y);
  }
  attach(chart, points, x, y);

  auto* each = new QScatterSeries();
  each->setName("participants");
  each->setMarkerShape(QScatterSeries::MarkerShapeRectangle);
  each->setMarkerSize(8);
  each->setColor(QColor("#ff7f0e"));
  for (const auto& p : a.participants)
    if (const auto e = p.estimate()) each->append(*e, 0.5);
  if (a.participants.size() > 1 && each->count() > 0) attach(chart, each, x, y);
  else delete each;

  if (a.pooled)
    attach(chart,
           verticalLine(a.pooled->estimate, QString(a.pooled->participants > 1 ? "pooled " : "") + (settings ? "mean setting " : "PSE ") + number(a.pooled->estimate),
                        QColor("#1f77b4"), Qt::SolidLine),
           x, y);
  if (a.predicted) {
    const auto& p = *a.predicted;
    attach(chart,
           verticalLine(p.recommendedScale, "head-demand model " + number(p.recommendedScale), QColor("#d62728"), Qt::DashLine),
           x, y);
  }
  return chart;
}

std::vector<std::filesystem::path> writeTrialsCharts(const std::vector<trials::ConditionAnalysis>& analyses,
                                                     const std::filesystem::path& png, int argc, char** argv) {
  std::unique_ptr<QApplication> app;
  if (!QApplication::instance()) {
    if (qEnvironmentVariableIsEmpty("DISPLAY") && qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM"))
      qputenv("QT_QPA_PLATFORM", "offscreen");
    app = std::make_unique<QApplication>(argc, argv);
  }
  std::vector<std::filesystem::path> written;
  for (std::size_t i = 0; i < analyses.size(); ++i) {
    QChartView view(makeTrialsChart(analyses[i]));
    view.setRenderHint(QPainter::Antialiasing);
    view.resize(1100, 700);
    std::filesystem::path file = png;
    if (i > 0) file.replace_filename(png.stem().string() + "-" + std::to_string(i + 1) + png.extension().string());
    if (!view.grab().save(QString::fromStdString(file.string()), "PNG")) continue;
    written.push_back(file);
  }
  return written;
}

}  // namespace vaw::ui
