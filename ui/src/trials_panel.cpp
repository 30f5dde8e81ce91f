// The panel's widgets, the design, participant and results-file form, and what the controls show in each
// phase of a session.
#include "vaw/ui/trials_panel.hpp"

#include <QAction>
#include <QApplication>
#include <QComboBox>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QGridLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QScrollArea>
#include <QStandardPaths>
#include <QTabWidget>
#include <QTimer>
#include <QVBoxLayout>
#include <stdexcept>
#include <utility>

#include "format.hpp"
#include "trials_panel_parts.hpp"
#include "vaw/paths.hpp"

namespace vaw::ui {

using detail::fsPath;
using detail::qPath;
using detail::str;

namespace {
// In the headset's adjustment, two hands closing within this time are one gesture: Accept.
constexpr int kPairWindow_ms = 300;
const QString kDesignSuffix = QStringLiteral(".vaw-trial.json");

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
  tabs_->addTab(createAnalysisTab(), tr("Analysis"));
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
  wireSession();
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

}  // namespace vaw::ui
