// Running a session trial by trial: the scenario's scene, each presentation at its scale, the answers, and
// giving the scene back its own gravity when the session ends.
#include "vaw/ui/trials_panel.hpp"

#include <QAction>
#include <QFileDialog>
#include <QFileInfo>
#include <QLineEdit>
#include <QMainWindow>
#include <QPushButton>
#include <QTabWidget>
#include <QTimer>
#include <algorithm>
#include <stdexcept>
#include <utility>

#include "trials_panel_parts.hpp"
#include "vaw/paths.hpp"
#include "vaw/sim/edit.hpp"
#include "vaw/ui/assembly_controller.hpp"
#include "vaw/ui/simulation_controller.hpp"

namespace vaw::ui {

using detail::fsPath;
using detail::kSessionWidth;
using detail::qPath;
using detail::str;

namespace {
// A scripted hand that has not taken the part this long after the reset never will (a refused grab).
constexpr double kTakeBy_s = 0.3;
// Two-interval trials: the pause between the two presentations, so they read as two.
constexpr double kBetween_s = 0.6;
// Adjustment: one press changes the scale by this factor, the step of a staircase's finest rung.
constexpr double kAdjustFactor = 1.12;
}  // namespace

void TrialsDock::wireSession() {
  connect(start_, &QPushButton::clicked, this, &TrialsDock::start);
  connect(resumeFile_, &QPushButton::clicked, this, [this] {
    const QString file = QFileDialog::getOpenFileName(this, tr("Resume results file"), resultsPath(),
                                                      tr("Results (*.vaw-results.jsonl *.jsonl)"));
    if (!file.isEmpty()) resumeFile(file);
  });
  connect(pause_, &QPushButton::clicked, this, &TrialsDock::togglePause);
  connect(pauseKey_, &QAction::triggered, this, &TrialsDock::togglePause);
  connect(stop_, &QPushButton::clicked, this, &TrialsDock::stop);
  connect(replay_, &QPushButton::clicked, this, &TrialsDock::replay);
  connect(replayKey_, &QAction::triggered, this, &TrialsDock::replay);
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

}  // namespace vaw::ui
