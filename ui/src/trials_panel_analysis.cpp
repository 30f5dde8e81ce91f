// The analysis tab: results files read together, each participant's estimate and the pooled one, and the
// chart of the first condition.
#include "vaw/ui/trials_panel.hpp"

#include <QFileDialog>
#include <QFileInfo>
#include <QLabel>
#include <QMainWindow>
#include <QPushButton>
#include <QTabWidget>
#include <QVBoxLayout>
#include <QtCharts/QChart>
#include <QtCharts/QChartView>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "format.hpp"
#include "trials_panel_parts.hpp"
#include "vaw/trials/results.hpp"
#include "vaw/ui/trials_chart.hpp"

namespace vaw::ui {

using detail::fsPath;
using detail::kAnalysisWidth;
using detail::str;

namespace {
QString interval(const trials::Interval& i) {
  return QStringLiteral("[%1, %2]")
      .arg(i.lo > 0.0 ? format::number(i.lo, 3) : QStringLiteral("unbounded"),
           std::isfinite(i.hi) ? format::number(i.hi, 3) : QStringLiteral("unbounded"));
}
}  // namespace

QWidget* TrialsDock::createAnalysisTab() {
  auto* analysis = new QWidget(tabs_);
  auto* al = new QVBoxLayout(analysis);
  auto* analyze = new QPushButton(tr("Analyze Results…"), analysis);
  analyze->setObjectName(QStringLiteral("trialsAnalyze"));
  analyze->setToolTip(tr("Analyses one or more results files: each participant, and all of them pooled"));
  al->addWidget(analyze, 0, Qt::AlignLeft);
  summary_ = new QLabel(analysis);
  summary_->setObjectName(QStringLiteral("trialsSummary"));
  summary_->setWordWrap(true);
  summary_->setTextFormat(Qt::RichText);
  summary_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  al->addWidget(summary_);
  chartView_ = new QChartView(analysis);
  chartView_->setObjectName(QStringLiteral("trialsChart"));
  chartView_->setRenderHint(QPainter::Antialiasing);
  chartView_->setMinimumHeight(240);
  chartView_->hide();
  al->addWidget(chartView_, 1);
  al->addStretch(0);
  connect(analyze, &QPushButton::clicked, this, [this] {
    const QStringList files = QFileDialog::getOpenFileNames(this, tr("Analyze results files"), resultsPath(),
                                                            tr("Results (*.vaw-results.jsonl *.jsonl)"));
    if (!files.isEmpty()) analyzeFiles(files);
  });
  return analysis;
}

bool TrialsDock::analyzeFiles(const QStringList& paths) {
  std::vector<trials::ResultsFile> files;
  QStringList notes;
  for (const QString& p : paths) {
    try {
      files.push_back(trials::readResults(fsPath(p)));
    } catch (const std::exception& e) {
      showProblem(QString::fromUtf8(e.what()));
      return false;
    }
    if (const auto& torn = files.back().torn)
      notes << tr("%1: a torn last record at line %2 is left out.").arg(QFileInfo(p).fileName()).arg(torn->line);
  }
  if (!notes.isEmpty()) showNotice(notes.join(QLatin1Char(' ')));
  showProblem({});
  showAnalysis(files);
  return true;
}

void TrialsDock::showAnalysis(const std::vector<trials::ResultsFile>& files) {
  analysis_ = trials::analyze(files);
  QString html;
  for (const trials::ConditionAnalysis& c : analysis_) {
    const bool settings = c.condition.answers == trials::AnswerKind::Setting;
    html += tr("<p><b>%1, %2 scale</b> (%3)</p>")
                .arg(str(trials::name(c.condition.scenario)), str(trials::name(c.condition.motion)),
                     str(trials::name(c.condition.answers)));
    html += tr("<table cellspacing=6><tr><th align=left>participant</th><th align=left>method</th><th>trials</th>"
               "<th>%1</th><th align=left>95 % interval</th><th>caught</th></tr>")
                .arg(settings ? tr("setting (geometric mean)") : tr("PSE"));
    for (const trials::ParticipantResult& p : c.participants) {
      QStringList methods;
      for (const auto& m : p.methods) methods << QString::fromStdString(m);
      const auto estimate = p.estimate();
      QString why;
      if (!estimate) why = QString::fromStdString(p.fit ? p.fit->problem : p.settings ? p.settings->problem : std::string());
      html += QStringLiteral("<tr><td>%1</td><td>%2</td><td align=right>%3</td><td align=right><b>%4</b></td><td>%5</td>"
                             "<td align=right>%6/%3</td></tr>")
                  .arg(QString::fromStdString(p.participant).toHtmlEscaped(), methods.join(QStringLiteral(", ")))
                  .arg(p.trials)
                  .arg(estimate ? format::number(*estimate, 4) : tr("none"),
                       estimate ? interval(p.interval()) : why.toHtmlEscaped())
                  .arg(p.caught);
    }
    html += QStringLiteral("</table>");
    if (c.pooled)
      html += tr("<p>Pooled over participants (%1): <b>%2</b> %3</p>")
                  .arg(c.pooled->participants)
                  .arg(format::number(c.pooled->estimate, 4), interval(c.pooled->interval));
    if (c.predicted)
      html += tr("<p>Head-demand model for this viewing geometry: <b>%1</b> (largest scale within the %2 limit: %3)</p>")
                  .arg(format::number(c.predicted->recommendedScale, 4), QString::fromStdString(c.predicted->limitedBy),
                       format::number(c.predicted->maxScale, 4));
    for (const auto& n : c.notes) html += QStringLiteral("<p>%1</p>").arg(QString::fromStdString(n).toHtmlEscaped());
  }
  if (analysis_.size() > 1) html += tr("<p>The chart shows the first of %1 conditions.</p>").arg(analysis_.size());
  summary_->setText(html);
  QChart* old = chartView_->chart();
  if (!analysis_.empty()) {
    QChart* chart = makeTrialsChart(analysis_.front());
    // The summary above says what the title says; in a panel the room is the plot's, and a legend at the
    // side keeps its names whole where a row below would cut them.
    chart->setTitle(QString());
    chart->legend()->setAlignment(Qt::AlignRight);
    chartView_->setChart(chart);
    delete old;
  }
  chartView_->setVisible(!analysis_.empty());
  tabs_->setCurrentIndex(1);
  show();
  raise();
  // A chart needs room that a panel beside the 3D view does not have: widen the panel (the user can narrow
  // it again).
  if (auto* main = qobject_cast<QMainWindow*>(parentWidget()); main != nullptr && !isFloating())
    main->resizeDocks({this}, {std::max(width(), kAnalysisWidth)}, Qt::Horizontal);
}

}  // namespace vaw::ui
