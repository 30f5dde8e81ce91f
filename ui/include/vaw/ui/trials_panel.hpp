#pragma once
// "Trials": runs a gravity-scale trial design (vaw::trials::Runner) trial by trial in the workbench and
// analyses results files (docs/trials.md, "The trials panel").
//
// Each trial resets the scenario's bundled scene, sets the trial's scale for the design's motion kind
// through the simulation controller's queue (never the undo stack: a trial is not a user's tuning), plays
// the scenario's script (vaw/trials/stage.hpp: a drop, a throw, a slide off the tilted base or the gear's
// swing) and then takes one answer from large buttons or their keys. While a blinded session runs the panel asks the window to hide every place that
// would show the scale (blindingChanged). Every answer is on disk before the next trial starts (the
// runner fsyncs it), so pausing needs no saving and a session killed at any moment resumes where it was.
#include <Eigen/Core>
#include <QDockWidget>
#include <QString>
#include <QStringList>
#include <memory>
#include <optional>
#include <variant>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/dynamics/gravity.hpp"
#include "vaw/trials/analysis.hpp"
#include "vaw/trials/design.hpp"
#include "vaw/trials/runner.hpp"
#include "vaw/trials/stage.hpp"

class QAction;
class QComboBox;
class QLabel;
class QLineEdit;
class QProgressBar;
class QPushButton;
class QTabWidget;
class QTimer;

QT_BEGIN_NAMESPACE
class QChartView;
QT_END_NAMESPACE

namespace vaw::ui {

class AssemblyController;
class SimulationController;

class TrialsDock : public QDockWidget {
  Q_OBJECT
 public:
  // What the panel waits for within a trial.
  // Holding: before the part leaves the hand; Moving: from then until the presentation is over.
  enum class Phase { Idle, LoadingScene, Holding, Moving, Between, Answering, Done };

  TrialsDock(SimulationController& simulation, AssemblyController& assembly, QWidget* parent = nullptr);
  ~TrialsDock() override;

  // Loads a design (the design field shows it); false, with the error shown in the panel, when it is bad.
  bool loadDesign(const QString& path);
  void setParticipant(const QString& id);
  void setResultsPath(const QString& path);
  [[nodiscard]] QString resultsPath() const;
  [[nodiscard]] bool running() const { return runner_ != nullptr; }
  [[nodiscard]] Phase phase() const { return phase_; }
  [[nodiscard]] bool paused() const { return paused_; }
  [[nodiscard]] const trials::Runner* runner() const { return runner_.get(); }
  // The last error or notice the panel shows (empty when none).
  [[nodiscard]] QString problem() const;
  [[nodiscard]] QString notice() const;
  // The analysis shown (empty until a session completes or files are analysed).
  [[nodiscard]] const std::vector<trials::ConditionAnalysis>& analysis() const { return analysis_; }
  [[nodiscard]] QChartView* chartView() const { return chartView_; }

  // Analyses results files together (per participant and pooled) and shows the result.
  bool analyzeFiles(const QStringList& paths);

 public slots:
  // Starts the loaded design on the results file, or resumes it when the file has answers already.
  void start();
  // Resumes a results file from its header alone (the design it carries).
  void resumeFile(const QString& path);
  void togglePause();
  // Ends the session (its answers are on disk already) and gives the window back its tuning.
  void stop();
  void replay();
  // In the headset: the left hand closing answers as the first button (or key 1), the right as the second;
  // in the adjustment method both hands closing within 0.3 s of each other answer Accept (key 3).
  void headsetAnswer(int hand);

 signals:
  // The scenario's scene must be opened (the window asks about unsaved tuning first).
  void openSceneRequested(const QString& path);
  // A blinded session starts (true) or ends (false): the window hides and shows the scale.
  void blindingChanged(bool blinded);
  // Where the 3D view should look from for the trial (world, m): the whole fall in view.
  void viewRequested(const Eigen::Vector3d& eye, const Eigen::Vector3d& centre);

 private:
  // trials_panel.cpp: the form and what the controls show.
  void showProblem(const QString& text);
  void showNotice(const QString& text);
  void updateControls();
  // trials_panel_session.cpp: the session's buttons and keys, and the controllers it follows.
  void wireSession();
  void begin(std::unique_ptr<trials::Runner> runner);
  [[nodiscard]] QString scenePath(trials::Scenario scenario) const;
  void sceneLoaded();
  void startTrial();
  void present(double scale);
  void frameReady();
  void answer(const std::variant<trials::Judgement, trials::Setting>& response);
  void adjust(double factor);
  void finish();
  void endSession();
  void restoreGravity();
  // trials_panel_analysis.cpp
  QWidget* createAnalysisTab();
  void showAnalysis(const std::vector<trials::ResultsFile>& files);

  SimulationController& simulation_;
  AssemblyController& assembly_;

  std::optional<trials::Design> design_;
  QString designPath_;
  bool resultsChosen_ = false;  // the results file was chosen, not named from the participant
  std::unique_ptr<trials::Runner> runner_;
  Phase phase_ = Phase::Idle;
  bool paused_ = false;
  bool blinded_ = false;
  // In the headset a drop or a throw is the participant's own: their hand takes the part and lets it go.
  bool participantActs_ = false;
  std::optional<vaw::dyn::GravityScales> gravityBefore_;  // the scene's tuning before the session
  std::optional<trials::Stage> stage_;                     // the scenario's script on the loaded scene
  std::vector<double> presentations_;                      // the scales this trial plays, in order
  std::size_t presenting_ = 0;                             // the one playing
  double setting_ = 1.0;                                   // adjustment: the scale the participant set
  double releasedAt_ = 0.0, betweenUntil_ = 0.0;           // world time, s
  bool caught_ = false;
  std::optional<double> regrasp_;
  std::vector<trials::ConditionAnalysis> analysis_;

  QTabWidget* tabs_ = nullptr;
  QComboBox* examples_ = nullptr;
  QLineEdit* designField_ = nullptr;
  QLineEdit* participant_ = nullptr;
  QLineEdit* results_ = nullptr;
  QPushButton *openDesign_ = nullptr, *resumeFile_ = nullptr, *chooseResults_ = nullptr;
  QPushButton *start_ = nullptr, *pause_ = nullptr, *stop_ = nullptr, *replay_ = nullptr;
  QLabel* question_ = nullptr;
  QProgressBar* progress_ = nullptr;
  QLabel* problem_ = nullptr;
  QLabel* notice_ = nullptr;
  QPushButton* answers_[3] = {nullptr, nullptr, nullptr};
  QAction* answerKeys_[3] = {nullptr, nullptr, nullptr};
  QAction* pauseKey_ = nullptr;
  QTimer* pairTimer_ = nullptr;        // the headset's Accept: waits for the other hand
  std::optional<int> pairedHand_;      // the hand that closed first
  QAction* replayKey_ = nullptr;
  QLabel* summary_ = nullptr;
  QChartView* chartView_ = nullptr;
};

}  // namespace vaw::ui
