#include "vaw/ui/trials_panel.hpp"

#include <QAction>
#include <QApplication>
#include <QComboBox>
#include <QDir>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QGridLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QMainWindow>
#include <QProgressBar>
#include <QPushButton>
#include <QScrollArea>
#include <QStandardPaths>
#include <QTabWidget>
#include <QTimer>
#include <QVBoxLayout>
#include <QtCharts/QChart>
#include <QtCharts/QChartView>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <system_error>
#include <utility>

#include "format.hpp"
#include "vaw/error.hpp"
#include "vaw/paths.hpp"
#include "vaw/sim/edit.hpp"
#include "vaw/trials/results.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/simulation_controller.hpp"
#include "vaw/ui/trials_chart.hpp"

namespace vaw::ui {

namespace {
// In the headset's adjustment, two hands closing within this time are one gesture: Accept.
constexpr int kPairWindow_ms = 300;
// A scripted hand that has not taken the part this long after the reset never will (a refused grab).
constexpr double kTakeBy_s = 0.3;
// Two-interval trials: the pause between the two presentations, so they read as two.
constexpr double kBetween_s = 0.6;
// Adjustment: one press changes the scale by this factor, the step of a staircase's finest rung.
constexpr double kAdjustFactor = 1.12;
// Wide enough for the analysis table and a readable chart; during a session the 3D view needs the room.
constexpr int kAnalysisWidth = 720, kSessionWidth = 420;
const QString kDesignSuffix = QStringLiteral(".vaw-trial.json");

QString str(std::string_view s) { return QString::fromUtf8(s.data(), static_cast<qsizetype>(s.size())); }
std::filesystem::path fsPath(const QString& p) { return std::filesystem::path(QFile::encodeName(p).toStdString()); }
QString qPath(const std::filesystem::path& p) { return QFile::decodeName(p.string().c_str()); }

QString interval(const trials::Interval& i) {
  return QStringLiteral("[%1, %2]")
      .arg(i.lo > 0.0 ? format::number(i.lo, 3) : QStringLiteral("unbounded"),
           std::isfinite(i.hi) ? format::number(i.hi, 3) : QStringLiteral("unbounded"));
}

QPushButton* bigButton(QWidget* parent, const char* name) {
  auto* b = new QPushButton(parent);
  b->setObjectName(QString::fromLatin1(name));
  b->setMinimumHeight(64);
  QFont f = b->font();
  f.setPointSizeF(f.pointSizeF() * 1.5);
  f.setBold(true);
  b->setFont(f);
  b->setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Fixed);
  return b;
}
}  // namespace

TrialsDock::TrialsDock(SimulationController& simulation, AssemblyController& assembly, QWidget* parent)
    : QDockWidget(tr("Trials"), parent), simulation_(simulation), assembly_(assembly) {
  setObjectName(QStringLiteral("trialsDock"));
  tabs_ = new QTabWidget(this);
  tabs_->setObjectName(QStringLiteral("trialsTabs"));
  auto* scroll = new QScrollArea(tabs_);
  scroll->setWidgetResizable(true);
  scroll->setFrameShape(QFrame::NoFrame);
  scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  auto* body = new QWidget(scroll);
  auto* layout = new QVBoxLayout(body);

  // ---- the design and where its answers go ----
  auto* setup = new QGroupBox(tr("Session"), body);
  auto* form = new QFormLayout(setup);
  auto* designRow = new QHBoxLayout();
  designField_ = new QLineEdit(setup);
  designField_->setObjectName(QStringLiteral("trialsDesign"));
  designField_->setReadOnly(true);
  designField_->setPlaceholderText(tr("no design"));
  openDesign_ = new QPushButton(tr("Open…"), setup);
  auto* openDesign = openDesign_;
  openDesign->setObjectName(QStringLiteral("trialsOpenDesign"));
  designRow->addWidget(designField_, 1);
  designRow->addWidget(openDesign);
  form->addRow(tr("Design"), designRow);
  examples_ = new QComboBox(setup);
  examples_->setObjectName(QStringLiteral("trialsExamples"));
  examples_->addItem(tr("Bundled examples…"));
  const QDir bundled(qPath(vaw::resourceDir() / "trials"));
  for (const QFileInfo& f : bundled.entryInfoList({QStringLiteral("*") + kDesignSuffix}, QDir::Files, QDir::Name))
    examples_->addItem(f.fileName(), f.absoluteFilePath());
  form->addRow(QString(), examples_);
  participant_ = new QLineEdit(setup);
  participant_->setObjectName(QStringLiteral("trialsParticipant"));
  participant_->setToolTip(tr("The participant's id: the analysis groups answers by it"));
  form->addRow(tr("Participant"), participant_);
  auto* resultsRow = new QHBoxLayout();
  results_ = new QLineEdit(setup);
  results_->setObjectName(QStringLiteral("trialsResults"));
  results_->setToolTip(tr("The results file: answers are appended and synced one by one; an existing file of the same "
                          "design is resumed"));
  chooseResults_ = new QPushButton(tr("…"), setup);
  auto* chooseResults = chooseResults_;
  chooseResults->setObjectName(QStringLiteral("trialsChooseResults"));
  resultsRow->addWidget(results_, 1);
  resultsRow->addWidget(chooseResults);
  form->addRow(tr("Results"), resultsRow);
  auto* buttons = new QGridLayout();
  start_ = new QPushButton(tr("Start / Resume"), setup);
  start_->setObjectName(QStringLiteral("trialsStart"));
  start_->setToolTip(tr("Runs the design; a results file with answers already is resumed at its first unanswered trial"));
  resumeFile_ = new QPushButton(tr("Resume File…"), setup);
  auto* resume = resumeFile_;
  resume->setObjectName(QStringLiteral("trialsResumeFile"));
  resume->setToolTip(tr("Resumes a results file with the design its header carries"));
  pause_ = new QPushButton(setup);
  pause_->setObjectName(QStringLiteral("trialsPause"));
  stop_ = new QPushButton(tr("Stop"), setup);
  stop_->setObjectName(QStringLiteral("trialsStop"));
  stop_->setToolTip(tr("Ends the session; every answer given is in the results file, and Start resumes it"));
  buttons->addWidget(start_, 0, 0);
  buttons->addWidget(resume, 0, 1);
  buttons->addWidget(pause_, 1, 0);
  buttons->addWidget(stop_, 1, 1);
  form->addRow(buttons);
  layout->addWidget(setup);

  // ---- the trial: the question, the progress and the answers ----
  auto* trial = new QGroupBox(tr("Trial"), body);
  auto* tl = new QVBoxLayout(trial);
  question_ = new QLabel(trial);
  question_->setObjectName(QStringLiteral("trialsQuestion"));
  question_->setWordWrap(true);
  QFont qf = question_->font();
  qf.setPointSizeF(qf.pointSizeF() * 1.25);
  question_->setFont(qf);
  tl->addWidget(question_);
  progress_ = new QProgressBar(trial);
  progress_->setObjectName(QStringLiteral("trialsProgress"));
  progress_->setTextVisible(true);
  progress_->setRange(0, 1);
  progress_->setValue(0);
  progress_->setFormat(tr("no session"));
  tl->addWidget(progress_);
  auto* answerRow = new QHBoxLayout();
  const char* names[3] = {"trialsAnswer1", "trialsAnswer2", "trialsAnswer3"};
  for (int i = 0; i < 3; ++i) {
    answers_[i] = bigButton(trial, names[i]);
    answerRow->addWidget(answers_[i]);
    // The keys work wherever the keyboard is in the window, the 3D view included (it forwards them).
    answerKeys_[i] = new QAction(this);
    answerKeys_[i]->setShortcut(QKeySequence(Qt::Key_1 + i));
    answerKeys_[i]->setShortcutContext(Qt::WindowShortcut);
    addAction(answerKeys_[i]);
    connect(answerKeys_[i], &QAction::triggered, answers_[i], &QPushButton::click);
  }
  tl->addLayout(answerRow);
  replay_ = new QPushButton(tr("Replay  [R]"), trial);
  replay_->setObjectName(QStringLiteral("trialsReplay"));
  replay_->setToolTip(tr("Plays this trial again"));
  tl->addWidget(replay_);
  replayKey_ = new QAction(this);
  replayKey_->setShortcut(QKeySequence(Qt::Key_R));
  addAction(replayKey_);
  pairTimer_ = new QTimer(this);
  pairTimer_->setSingleShot(true);
  pairTimer_->setInterval(kPairWindow_ms);
  connect(pairTimer_, &QTimer::timeout, this, [this] {
    const auto hand = std::exchange(pairedHand_, std::nullopt);
    if (hand && running() && phase_ == Phase::Answering && !paused_) answers_[*hand]->click();
  });
  pauseKey_ = new QAction(this);
  pauseKey_->setShortcut(QKeySequence(Qt::Key_P));
  addAction(pauseKey_);
  notice_ = new QLabel(trial);
  notice_->setObjectName(QStringLiteral("trialsNotice"));
  notice_->setWordWrap(true);
  tl->addWidget(notice_);
  problem_ = new QLabel(trial);
  problem_->setObjectName(QStringLiteral("trialsProblem"));
  problem_->setWordWrap(true);
  problem_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  problem_->setStyleSheet(QStringLiteral("color: rgb(180, 40, 20);"));
  tl->addWidget(problem_);
  layout->addWidget(trial);
  layout->addStretch(1);
  scroll->setWidget(body);
  tabs_->addTab(scroll, tr("Session"));

  // ---- the analysis ----
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
  tabs_->addTab(analysis, tr("Analysis"));
  setWidget(tabs_);

  connect(openDesign, &QPushButton::clicked, this, [this] {
    const QString start = designPath_.isEmpty() ? QString() : QFileInfo(designPath_).absolutePath();
    const QString file = QFileDialog::getOpenFileName(this, tr("Open trial design"), start,
                                                      tr("Trial designs (*.vaw-trial.json);;JSON files (*.json)"));
    if (!file.isEmpty()) loadDesign(file);
  });
  connect(examples_, &QComboBox::activated, this, [this](int index) {
    if (index > 0) loadDesign(examples_->itemData(index).toString());
    examples_->setCurrentIndex(0);
  });
  // The default results file follows the participant; one the user chose stays.
  connect(participant_, &QLineEdit::textEdited, this, [this] {
    if (!resultsChosen_) setResultsPath({});
  });
  connect(results_, &QLineEdit::textEdited, this, [this] { resultsChosen_ = true; });
  connect(chooseResults, &QPushButton::clicked, this, [this] {
    const QString file = QFileDialog::getSaveFileName(this, tr("Results file"), resultsPath(),
                                                      tr("Results (*.vaw-results.jsonl)"), nullptr,
                                                      QFileDialog::DontConfirmOverwrite);
    if (!file.isEmpty()) setResultsPath(file);
  });
  connect(start_, &QPushButton::clicked, this, &TrialsDock::start);
  connect(resume, &QPushButton::clicked, this, [this] {
    const QString file = QFileDialog::getOpenFileName(this, tr("Resume results file"), resultsPath(),
                                                      tr("Results (*.vaw-results.jsonl *.jsonl)"));
    if (!file.isEmpty()) resumeFile(file);
  });
  connect(pause_, &QPushButton::clicked, this, &TrialsDock::togglePause);
  connect(pauseKey_, &QAction::triggered, this, &TrialsDock::togglePause);
  connect(stop_, &QPushButton::clicked, this, &TrialsDock::stop);
  connect(replay_, &QPushButton::clicked, this, &TrialsDock::replay);
  connect(replayKey_, &QAction::triggered, this, &TrialsDock::replay);
  connect(analyze, &QPushButton::clicked, this, [this] {
    const QStringList files = QFileDialog::getOpenFileNames(this, tr("Analyze results files"), resultsPath(),
                                                            tr("Results (*.vaw-results.jsonl *.jsonl)"));
    if (!files.isEmpty()) analyzeFiles(files);
  });
  connect(answers_[0], &QPushButton::clicked, this, [this] {
    if (!design_) return;
    switch (design_->question.answers) {
      case trials::AnswerKind::TooFastTooSlow: answer(trials::Judgement::TooSlow); break;
      case trials::AnswerKind::TwoInterval: answer(trials::Judgement::First); break;
      case trials::AnswerKind::Setting: adjust(1.0 / kAdjustFactor); break;
    }
  });
  connect(answers_[1], &QPushButton::clicked, this, [this] {
    if (!design_) return;
    switch (design_->question.answers) {
      case trials::AnswerKind::TooFastTooSlow: answer(trials::Judgement::TooFast); break;
      case trials::AnswerKind::TwoInterval: answer(trials::Judgement::Second); break;
      case trials::AnswerKind::Setting: adjust(kAdjustFactor); break;
    }
  });
  connect(answers_[2], &QPushButton::clicked, this, [this] { answer(trials::Setting{setting_}); });

  // The scenario's scene: the window's load handler starts its world first, then the session goes on.
  connect(&assembly_, &AssemblyController::assemblyLoaded, this,
          [this] {
            if (phase_ != Phase::LoadingScene) return;
            // Another file opened meanwhile is not the scenario's scene, whose part the trials drop.
            if (QFileInfo(assembly_.currentPath()).canonicalFilePath() !=
                QFileInfo(scenePath(design_->scenario)).canonicalFilePath()) {
              showProblem(tr("Another file was opened instead of the scenario's scene; the session is stopped."));
              endSession();
              return;
            }
            sceneLoaded();
          },
          Qt::QueuedConnection);
  const auto notOpened = [this] {
    if (phase_ != Phase::LoadingScene) return;
    showProblem(tr("The scenario's scene was not opened (see Messages); the session is stopped."));
    endSession();
  };
  connect(&assembly_, &AssemblyController::loadFailed, this, notOpened);
  connect(&assembly_, &AssemblyController::loadCancelled, this, notOpened);
  connect(&simulation_, &SimulationController::frameReady, this, &TrialsDock::frameReady);
  connect(&simulation_, &SimulationController::editRefused, this, [this](const QString& reason) {
    if (running()) showProblem(tr("The world refused the trial's scale: %1").arg(reason));
  });
  updateControls();
}

TrialsDock::~TrialsDock() = default;

QString TrialsDock::problem() const { return problem_->text(); }
QString TrialsDock::notice() const { return notice_->text(); }
QString TrialsDock::resultsPath() const { return results_->text(); }

void TrialsDock::showProblem(const QString& text) { problem_->setText(text); }
void TrialsDock::showNotice(const QString& text) { notice_->setText(text); }

bool TrialsDock::loadDesign(const QString& path) {
  if (running()) return false;
  try {
    design_ = trials::loadDesign(fsPath(path));
  } catch (const std::exception& e) {
    showProblem(QString::fromUtf8(e.what()));
    return false;
  }
  designPath_ = QFileInfo(path).absoluteFilePath();
  designField_->setText(designPath_);
  designField_->setToolTip(QString::fromStdString(design_->name));
  participant_->setText(QString::fromStdString(design_->participant));
  setResultsPath({});
  showProblem({});
  showNotice(tr("%1: %2, %3 scale, %4.")
                 .arg(QString::fromStdString(design_->name), str(trials::name(design_->scenario)),
                      str(trials::name(design_->motion)), str(trials::methodName(design_->method))));
  updateControls();
  return true;
}

void TrialsDock::setParticipant(const QString& id) {
  participant_->setText(id);
  if (!resultsChosen_) setResultsPath({});
}

void TrialsDock::setResultsPath(const QString& path) {
  resultsChosen_ = !path.isEmpty();
  if (!path.isEmpty() || designPath_.isEmpty()) {
    results_->setText(path);
    return;
  }
  // Next to the design, named from the participant; a bundled design's folder is not the user's to write
  // in, so its results go to the documents folder.
  const QFileInfo design(designPath_);
  QString stem = design.fileName();
  if (stem.endsWith(kDesignSuffix)) stem.chop(kDesignSuffix.size());
  const QString participant = participant_->text().trimmed().isEmpty() ? tr("participant") : participant_->text().trimmed();
  QString folder = design.absolutePath();
  if (!QFileInfo(folder).isWritable())
    folder = QStandardPaths::writableLocation(QStandardPaths::DocumentsLocation);
  results_->setText(QDir(folder).filePath(QStringLiteral("%1-%2.vaw-results.jsonl").arg(participant, stem)));
}

void TrialsDock::start() {
  if (running()) return;
  if (!design_) {
    showProblem(tr("Open a design first."));
    return;
  }
  if (results_->text().trimmed().isEmpty()) {
    showProblem(tr("Choose a results file first."));
    return;
  }
  trials::Design design = *design_;
  if (!participant_->text().trimmed().isEmpty()) design.participant = participant_->text().trimmed().toStdString();
  try {
    begin(std::make_unique<trials::Runner>(trials::Runner::open(design, fsPath(results_->text().trimmed()))));
  } catch (const std::exception& e) {
    showProblem(QString::fromUtf8(e.what()));
  }
}

void TrialsDock::resumeFile(const QString& path) {
  if (running()) return;
  try {
    auto runner = std::make_unique<trials::Runner>(trials::Runner::resume(fsPath(path)));
    design_ = runner->design();
    designPath_.clear();
    designField_->setText(tr("(from %1)").arg(QFileInfo(path).fileName()));
    participant_->setText(QString::fromStdString(design_->participant));
    setResultsPath(path);
    begin(std::move(runner));
  } catch (const std::exception& e) {
    showProblem(QString::fromUtf8(e.what()));
  }
}

void TrialsDock::begin(std::unique_ptr<trials::Runner> runner) {
  const QString scene = scenePath(runner->design().scenario);
  if (!QFileInfo::exists(scene)) {
    showProblem(tr("The scene of the scenario \"%1\" is missing: %2 (is vaw installed whole?)")
                    .arg(str(trials::name(runner->design().scenario)), scene));
    return;
  }
  runner_ = std::move(runner);
  design_ = runner_->design();
  show();
  raise();  // the participant answers here, and its keys work only while it is shown
  // After the layout has settled on the raised dock (an analysis may have widened it).
  QTimer::singleShot(0, this, [this] {
    if (auto* main = qobject_cast<QMainWindow*>(parentWidget()); main != nullptr && !isFloating() && width() > kSessionWidth)
      main->resizeDocks({this}, {kSessionWidth}, Qt::Horizontal);
  });
  tabs_->setCurrentIndex(0);
  showProblem({});
  QStringList notes;
  if (const auto& torn = runner_->recovered())
    notes << tr("Cut off a torn record at line %1 (%2 bytes, a write cut short by a crash); that trial is asked again.")
                 .arg(torn->line)
                 .arg(static_cast<qulonglong>(torn->bytes));
  if (runner_->answered() > 0)
    notes << tr("Resumed at trial %1 of %2.").arg(runner_->answered() + 1).arg(runner_->plannedTrials());
  showNotice(notes.join(QLatin1Char(' ')));
  paused_ = false;
  const bool sameScene = simulation_.hasWorld() &&
                         QFileInfo(assembly_.currentPath()).canonicalFilePath() == QFileInfo(scene).canonicalFilePath();
  if (sameScene) {
    sceneLoaded();
  } else {
    phase_ = Phase::LoadingScene;
    updateControls();
    emit openSceneRequested(scene);
  }
}

QString TrialsDock::scenePath(trials::Scenario scenario) const {
  return qPath(vaw::resourceDir() / "scenes" / std::string(trials::Stage::sceneFile(scenario)));
}

void TrialsDock::sceneLoaded() {
  if (!running() || !simulation_.hasWorld()) return;
  try {
    stage_.emplace(design_->scenario, simulation_.world().assembly());
  } catch (const std::exception& e) {
    showProblem(QString::fromUtf8(e.what()));
    endSession();
    return;
  }
  gravityBefore_ = simulation_.world().settings().gravity;
  blinded_ = design_->blind;
  if (blinded_) emit blindingChanged(true);
  startTrial();
}

void TrialsDock::startTrial() {
  const auto& t = runner_->next();
  if (!t) {
    finish();
    return;
  }
  presentations_.clear();
  if (t->referenceScale) {
    presentations_ = t->referenceFirst ? std::vector{*t->referenceScale, t->scale} : std::vector{t->scale, *t->referenceScale};
  } else {
    setting_ = t->scale;
    presentations_ = {t->scale};
  }
  presenting_ = 0;
  caught_ = false;
  regrasp_.reset();
  present(presentations_[0]);
}

void TrialsDock::present(double scale) {
  simulation_.reset();
  // In the headset the world takes its hands from the tracker: a drop or a throw is the participant's own,
  // and for the others the script's hand and base move while the participant watches. The desktop's view
  // follows the head there; on the desktop it frames the whole motion, the same at every scale.
  const bool headset = simulation_.hasInputSource();
  participantActs_ = headset && stage_->participantActs();
  if (participantActs_) {
    simulation_.setScript({});
  } else {
    simulation_.setScript([stage = *stage_](double t, vaw::sim::Input& in) { stage.script(t, in); });
  }
  if (!headset) emit viewRequested(stage_->eye(), stage_->centre());
  simulation_.requestEdit(vaw::sim::GravityEdit{trials::withScale(*gravityBefore_, design_->motion, scale)});
  phase_ = Phase::Holding;
  if (!paused_) simulation_.play();
  updateControls();
}

void TrialsDock::frameReady() {
  if (!running() || !stage_ || !simulation_.hasWorld()) return;
  const vaw::sim::World& w = simulation_.world();
  const vaw::sim::PartRuntime& p = w.part(stage_->part());
  const double t = w.time();
  const bool held = p.holder != vaw::sim::Holder::None;
  // The measures belong to the presentation of the trial's own scale (the other of two is the reference's).
  const bool ownScale = presentations_.size() < 2 || presenting_ == (runner_->next()->referenceFirst ? 1u : 0u);
  switch (phase_) {
    case Phase::Holding:
      if (participantActs_) {
        if (p.state == vaw::interact::PartState::InSpace) {
          releasedAt_ = t;
          phase_ = Phase::Moving;
        }
      } else if (!held && t >= stage_->releaseTime()) {
        releasedAt_ = stage_->releaseTime();
        phase_ = Phase::Moving;
      } else if (!held && t > kTakeBy_s) {
        showProblem(tr("The hand could not take the part: the session is stopped."));
        endSession();
      }
      break;
    case Phase::Moving: {
      if (held && ownScale && !regrasp_) {
        caught_ = true;  // taken back before the presentation was over
        regrasp_ = t - releasedAt_;
      }
      if (!stage_->over(w, t - releasedAt_)) break;
      if (presenting_ + 1 < presentations_.size()) {
        phase_ = Phase::Between;
        betweenUntil_ = t + kBetween_s;
      } else {
        phase_ = Phase::Answering;
        updateControls();
      }
      break;
    }
    case Phase::Between:
      if (t >= betweenUntil_) present(presentations_[++presenting_]);
      break;
    case Phase::Answering:
      // Taken back after the presentation: a re-grasp, though not a catch.
      if (held && ownScale && !regrasp_) regrasp_ = t - releasedAt_;
      break;
    default: break;
  }
}

void TrialsDock::headsetAnswer(int hand) {
  if (!running() || phase_ != Phase::Answering || paused_ || hand < 0 || hand > 1) return;
  if (design_->question.answers != trials::AnswerKind::Setting) {
    answers_[hand]->click();
    return;
  }
  // Adjusting: both hands closing together accept; one hand alone is slower or faster once it is clear
  // that the other is not following.
  if (pairedHand_ && *pairedHand_ != hand) {
    pairTimer_->stop();
    pairedHand_.reset();
    answers_[2]->click();
    return;
  }
  pairedHand_ = hand;
  pairTimer_->start();
}

void TrialsDock::replay() {
  if (!running() || paused_ || (phase_ != Phase::Answering && phase_ != Phase::Moving)) return;
  presenting_ = 0;
  caught_ = false;
  regrasp_.reset();
  present(presentations_[0]);
}

void TrialsDock::adjust(double factor) {
  if (phase_ != Phase::Answering || paused_ || !runner_->next()->adjustable) return;
  const trials::ScaleRange range = *runner_->next()->adjustable;
  setting_ = std::clamp(setting_ * factor, range.min, range.max);
  presentations_ = {setting_};
  presenting_ = 0;
  present(setting_);
}

void TrialsDock::answer(const std::variant<trials::Judgement, trials::Setting>& response) {
  if (!running() || phase_ != Phase::Answering || paused_) return;
  try {
    runner_->answer(trials::Answer{response, trials::Measures{caught_, regrasp_}});
  } catch (const std::exception& e) {
    // Not recorded: the trial stays, and may be answered again.
    showProblem(tr("The answer was not recorded: %1").arg(QString::fromUtf8(e.what())));
    return;
  }
  showProblem({});
  startTrial();
}

void TrialsDock::togglePause() {
  if (!running()) return;
  paused_ = !paused_;
  if (paused_) simulation_.pause();
  else simulation_.play();
  updateControls();
  // The answers are disabled while paused: the keyboard stays on the one button that goes on.
  if (paused_) pause_->setFocus(Qt::OtherFocusReason);
}

void TrialsDock::stop() {
  if (!running()) return;
  const int answered = runner_->answered();
  const QString file = qPath(runner_->path());
  endSession();
  showNotice(tr("Stopped with %1 trials answered; they are in %2, and Start resumes it.").arg(answered).arg(file));
}

void TrialsDock::finish() {
  const QString file = qPath(runner_->path());
  const int answered = runner_->answered();
  endSession();
  phase_ = Phase::Done;
  showNotice(tr("Session complete: %1 trials answered, in %2.").arg(answered).arg(file));
  analyzeFiles({file});
  updateControls();
}

void TrialsDock::endSession() {
  runner_.reset();  // closes the results file and lets go of its lock
  simulation_.setScript({});
  stage_.reset();
  phase_ = Phase::Idle;
  paused_ = false;
  restoreGravity();
  if (blinded_) emit blindingChanged(false);
  blinded_ = false;
  updateControls();
}

void TrialsDock::restoreGravity() {
  if (gravityBefore_ && simulation_.hasWorld()) {
    // Applied now, not at the next step: a session started at once on the same scene takes the world's
    // gravity as the scene's own, and must not find the last trial's scale there.
    const bool playing = simulation_.isPlaying();
    simulation_.pause();
    simulation_.requestEdit(vaw::sim::GravityEdit{*gravityBefore_});
    if (playing) simulation_.play();
  }
  gravityBefore_.reset();
}

void TrialsDock::updateControls() {
  const bool session = running();
  const bool answering = session && phase_ == Phase::Answering && !paused_;
  start_->setEnabled(!session && design_.has_value());
  openDesign_->setEnabled(!session);
  resumeFile_->setEnabled(!session);
  examples_->setEnabled(!session && examples_->count() > 1);
  pause_->setEnabled(session);
  pause_->setText(paused_ ? tr("Continue  [P]") : tr("Pause  [P]"));
  pauseKey_->setEnabled(session);
  stop_->setEnabled(session);
  replay_->setEnabled(answering);
  replayKey_->setEnabled(answering);
  participant_->setEnabled(!session);
  results_->setEnabled(!session);
  chooseResults_->setEnabled(!session);
  const trials::AnswerKind kind = design_ ? design_->question.answers : trials::AnswerKind::TooFastTooSlow;
  QString labels[3];
  switch (kind) {
    case trials::AnswerKind::TooFastTooSlow: labels[0] = tr("Too slow"), labels[1] = tr("Too fast"); break;
    case trials::AnswerKind::TwoInterval: labels[0] = tr("First was faster"), labels[1] = tr("Second was faster"); break;
    case trials::AnswerKind::Setting:
      labels[0] = tr("Slower"), labels[1] = tr("Faster"), labels[2] = tr("Accept");
      break;
  }
  for (int i = 0; i < 3; ++i) {
    answers_[i]->setText(tr("%1\n[%2]").arg(labels[i]).arg(i + 1));
    answers_[i]->setVisible(!labels[i].isEmpty());
    answers_[i]->setEnabled(answering);
    answerKeys_[i]->setEnabled(answering && !labels[i].isEmpty());
  }

  QString question = design_ ? QString::fromStdString(design_->question.text) : tr("Open a design to run a session.");
  if (session) {
    const auto& t = runner_->next();
    if (paused_) question = tr("Paused. Press Continue or P to go on.");
    else if (phase_ == Phase::LoadingScene) question = tr("Opening the scenario's scene…");
    else if (phase_ == Phase::Holding && participantActs_)
      question = design_->scenario == trials::Scenario::Throw ? tr("Take the block and toss it up.")
                                                              : tr("Take the block and let it go.");
    else if (phase_ != Phase::Answering) question = tr("Watch the part.") + QStringLiteral(" ") + question;
    // An unblinded design may show the scale (a demonstration, a pilot).
    if (t && !t->blinded)
      question += tr(" (scale %1)").arg(format::number(kind == trials::AnswerKind::Setting ? setting_ : t->scale, 3));
    const int planned = runner_->plannedTrials();
    progress_->setRange(0, planned);
    progress_->setValue(runner_->answered());
    const bool exact = !std::holds_alternative<trials::Staircase>(runner_->design().method);
    progress_->setFormat(exact ? tr("trial %1 of %2").arg(runner_->answered() + 1).arg(planned)
                               : tr("trial %1 of at most %2").arg(runner_->answered() + 1).arg(planned));
  } else if (phase_ == Phase::Done) {
    progress_->setValue(progress_->maximum());
    progress_->setFormat(tr("complete"));
  } else {
    progress_->setRange(0, 1);
    progress_->setValue(0);
    progress_->setFormat(tr("no session"));
  }
  question_->setText(question);
  if (answering && !answers_[0]->hasFocus() && !answers_[1]->hasFocus() && !answers_[2]->hasFocus() &&
      isVisible() && QApplication::activeWindow() == window())
    answers_[0]->setFocus(Qt::OtherFocusReason);  // the keys reach the answers, not a field being edited
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
