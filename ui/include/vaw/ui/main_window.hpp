#pragma once
// The workbench window: composes the viewport and the docks, the menus, the simulation toolbar and the
// status bar, and wires them to the two controllers (the loaded scene's and the running simulation's). It
// holds no assembly or simulation state of its own.
#include <QElapsedTimer>
#include <QFutureWatcher>
#include <QMainWindow>
#include <QTimer>
#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/importer.hpp"
#include "vaw/sim/edit.hpp"
#include "vaw/sim/report.hpp"
#include "vaw/video/video.hpp"

class QAction;
class QDockWidget;
class QLabel;
class QMenu;
class QProgressDialog;
class QUndoStack;

namespace vaw::ui {

class AssemblyController;
class SimulationController;
class Viewport;
class SceneDock;
class PartDock;
class MessagesDock;
class ControlsDock;
class TimelineDock;
class LoadFeedback;
class GravityDock;
class FrictionDock;
class MethodsDock;
class MotionChartDock;
class WorkPrecisionDock;
class TrialsDock;
class ConstraintsDock;
class SequenceDock;
class InterferenceDock;
class PathDock;
class XrController;
class BackgroundExport;

class MainWindow : public QMainWindow {
  Q_OBJECT
 public:
  explicit MainWindow(AssemblyController& controller, QWidget* parent = nullptr);
  ~MainWindow() override;

  [[nodiscard]] Viewport* viewport() const { return viewport_; }
  [[nodiscard]] SceneDock* sceneDock() const { return sceneDock_; }
  [[nodiscard]] PartDock* partDock() const { return partDock_; }
  [[nodiscard]] MessagesDock* messagesDock() const { return messagesDock_; }
  [[nodiscard]] ControlsDock* controlsDock() const { return controlsDock_; }
  [[nodiscard]] TimelineDock* timelineDock() const { return timelineDock_; }
  [[nodiscard]] LoadFeedback* loadFeedback() const { return loadFeedback_; }
  [[nodiscard]] GravityDock* gravityDock() const { return gravityDock_; }
  [[nodiscard]] FrictionDock* frictionDock() const { return frictionDock_; }
  [[nodiscard]] MethodsDock* methodsDock() const { return methodsDock_; }
  [[nodiscard]] MotionChartDock* motionDock() const { return motionDock_; }
  [[nodiscard]] WorkPrecisionDock* workPrecisionDock() const { return workPrecisionDock_; }
  [[nodiscard]] TrialsDock* trialsDock() const { return trialsDock_; }
  [[nodiscard]] ConstraintsDock* constraintsDock() const { return constraintsDock_; }
  [[nodiscard]] SequenceDock* sequenceDock() const { return sequenceDock_; }
  [[nodiscard]] InterferenceDock* interferenceDock() const { return interferenceDock_; }
  [[nodiscard]] PathDock* pathDock() const { return pathDock_; }
  [[nodiscard]] QUndoStack* undoStack() const { return undoStack_; }
  // The stability warning of the status bar (empty when the selected part's swing is stable).
  [[nodiscard]] QString stabilityWarning() const;
  // Whether the tuning was changed since the scene was opened or saved.
  [[nodiscard]] bool hasUnsavedChanges() const;
  [[nodiscard]] SimulationController& simulation() const { return *simulation_; }
  [[nodiscard]] XrController& xr() const { return *xr_; }
  // The permanent status text: time, step cost, active parts, speed, mode.
  [[nodiscard]] QString statusText() const;
  // The real rate when it is behind the speed asked for, and what holds it back: "0.78× of real time, rendering is the bottleneck".
  [[nodiscard]] QString rateText() const;
  QString captureText_;  // the status bar's capture hint, empty when no part is carried near its mate
  // Whether a newly opened scene starts running at once (the workbench does; tests that step by hand
  // turn it off).
  void setAutoPlay(bool on) { autoPlay_ = on; }

 public slots:
  void openFileDialog();
  void saveSessionDialog();
  // Writes the running session (what `vaw-sim run --replay` reads). Returns false and says why on failure.
  bool saveSession(const QString& file);
  bool exportTimelinePng(const QString& file);
  bool exportTimelineCsv(const QString& file);
  // File > Export Report: the folder asked for, then exportReport.
  void exportReportDialog();
  // The evaluation report (vaw::report::writeReport) into `dir`, with this window's session when it has
  // steps. Without an order yet, the Sequence panel finds one first and the report follows it. The session's
  // replay and the pictures run off the GUI thread, shown in a progress window with Stop (reportProgress).
  void exportReport(const QString& dir);
  // True from the moment a report is started until what came of it was said.
  [[nodiscard]] bool writingReport() const { return reportCancel_ != nullptr; }
  [[nodiscard]] QProgressDialog* reportProgress() const { return reportProgress_; }
  // File > Export Video: the size, frame rate and camera asked for (videoDialog), then the file; exportVideo.
  void exportVideoDialog();
  // The recording so far as an MP4 video (vaw::video::writeSessionVideo: the scene as the viewport shows
  // it, with a caption line) written off the window's thread in a progress window with Stop
  // (videoProgress); the window goes on simulating meanwhile. Says where it wrote it, or why not.
  void exportVideo(const QString& file, const vaw::video::VideoOptions& options);
  [[nodiscard]] bool exportingVideo() const;
  [[nodiscard]] QProgressDialog* videoProgress() const;
  // File > Export glTF: the file asked for, then exportGltf.
  void exportGltfDialog();
  // The recording so far, or the scene at rest when nothing is recorded, as one glTF 2.0 binary
  // (vaw::report::writeGlb; docs/sharing.md), off the window's thread like a video.
  void exportGltf(const QString& file);
  [[nodiscard]] bool exportingGltf() const;
  // A pause at each of the report's progress reports, so that a short replay lasts long enough for a GUI
  // test to click during it on any machine; 0 (no pause) unless a test sets it.
  void setReportPace(int milliseconds) { reportPaceMs_ = milliseconds; }
  // File > Save: the scene with the tuning as edited (vaw::sim::saveScene); Save As when the file opened is
  // not a scene. Returns false, having said why, when nothing was saved.
  bool save();
  bool saveAs();
  bool saveScene(const QString& file);
  // File > STEP Settings: the chordal deflection of STEP parts as a fraction of each part's size and the
  // reader's limits (time, memory, part instances), kept between runs; an open STEP assembly is read again
  // with a new tessellation.
  void stepSettingsDialog();
  void setStepSettings(const vaw::ImportOptions& import);
  // Opens `path` after asking about unsaved tuning (which may cancel).
  void openFile(const QString& path);
  // Asks whether to save unsaved tuning: true when it was saved or may be dropped, false to cancel.
  bool maybeSave();
  // True, having said why, while a trials session runs: its world plays the trial's scale, which must not
  // be saved as the scene's tuning.
  bool savingWaitsForTrials();

 protected:
  void closeEvent(QCloseEvent* event) override;
  void dragEnterEvent(QDragEnterEvent* event) override;
  void dropEvent(QDropEvent* event) override;

 private:
  // main_window.cpp: the docks in their places.
  void createDocks();
  void message(int severity, const QString& text, const QString& detail = {});
  // main_window_docks.cpp: each dock's wiring, with the handlers that serve it alone.
  void wireViewport();
  void showSelection(std::optional<vaw::PartId> part);
  void wirePart();
  void wireControls();
  void wireMotion();
  void wireTimeline();
  void logChanged();
  void wireTrials();
  // A blinded trials session: the gravity panel, the Messages log and the timeline's edit lane keep the
  // trial's scale to themselves, and the panels that show the fall's speed or duration close until it ends.
  void setBlinded(bool blinded);
  void wireConstraints();
  // The viewport's right-click menu: "Put this face down" on a flat face of a CAD assembly's base.
  void showViewportMenu(const QPoint& windowPos);
  void wireSequence();
  void wirePath();
  // The part panel's swept-volume row: the Path panel's result when it is the shown part's.
  void showSwept();
  // Writes the report with the order found; says where, or why not.
  void writeReport(const QString& dir);
  void wireXr();
  // main_window_tuning.cpp
  void wireTuning();
  // A tuning edit from a panel: refused with the rule it breaks, or pushed on the undo stack.
  void requestTuning(const vaw::sim::Edit& edit, int mergeKey);
  void updateTuning(const std::optional<vaw::sim::StabilityAdvice>& advice);
  // main_window_simulation.cpp
  void wireSimulation();
  void simulationStarted();
  void frameReady();
  void updateLive();
  // main_window_status.cpp
  void createStatusBar();
  // While the mouse's hand carries a part near its mate: the capture zone in the viewport and, in the
  // status bar, how near a release must be.
  void updateCapture();
  void updateStatus();
  // main_window_files.cpp
  void wireLoading();
  void assemblyLoaded();
  void updateTitle();
  // main_window_menus.cpp
  void createMenus();
  void addRecent(const QString& path);
  void updateRecentMenu();
  void showAbout();
  void showBindings();

  AssemblyController& controller_;
  SimulationController* simulation_ = nullptr;
  XrController* xr_ = nullptr;
  Viewport* viewport_ = nullptr;
  SceneDock* sceneDock_ = nullptr;
  PartDock* partDock_ = nullptr;
  MessagesDock* messagesDock_ = nullptr;
  ControlsDock* controlsDock_ = nullptr;
  TimelineDock* timelineDock_ = nullptr;
  LoadFeedback* loadFeedback_ = nullptr;
  QAction* reloadAction_ = nullptr;
  QAction* playAction_ = nullptr;
  QAction* saveAction_ = nullptr;
  QAction* saveAsAction_ = nullptr;
  QMenu* recentMenu_ = nullptr;
  QUndoStack* undoStack_ = nullptr;
  GravityDock* gravityDock_ = nullptr;
  FrictionDock* frictionDock_ = nullptr;
  MethodsDock* methodsDock_ = nullptr;
  MotionChartDock* motionDock_ = nullptr;
  WorkPrecisionDock* workPrecisionDock_ = nullptr;
  TrialsDock* trialsDock_ = nullptr;
  ConstraintsDock* constraintsDock_ = nullptr;
  SequenceDock* sequenceDock_ = nullptr;
  InterferenceDock* interferenceDock_ = nullptr;
  PathDock* pathDock_ = nullptr;
  QString pendingReport_;  // the folder a report waits for the order to be written into
  // The report being written in the background: where, and what came of it.
  struct ReportOutcome {
    QString dir, html, error, session;
    bool cancelled = false;
  };
  void reportFinished();
  QFutureWatcher<ReportOutcome> reportWatcher_;
  std::shared_ptr<std::atomic<bool>> reportCancel_;  // set while a report is being written
  BackgroundExport* videoExport_ = nullptr;  // the video being written, its progress window
  BackgroundExport* gltfExport_ = nullptr;   // the glTF file being written
  // A BackgroundExport for `task`, made at its first use, whose outcome is said as "<what> FILE".
  BackgroundExport* exporter(BackgroundExport*& slot, const char* task, const QString& title, const QString& what);
  QProgressDialog* reportProgress_ = nullptr;
  int reportPaceMs_ = 0;
  QString reportHeading_;
  bool blinded_ = false;
  std::vector<QDockWidget*> closedForBlinding_;
  bool motionStale_ = true;  // a new world: the motion chart replays it when next shown
  QLabel* stabilityStatus_ = nullptr;
  QString scenePath_;  // where File > Save writes: the scene file opened or last saved as
  QLabel* status_ = nullptr;
  bool autoPlay_ = true;
  // Live views are refreshed at most this often while the simulation runs (the viewport every frame).
  QElapsedTimer lastLive_;
  QTimer liveTimer_;
  bool axesShown_ = false;
  // Kept across File > Reload: the selected part's name and the file it came from.
  std::string selectedName_;
  QString selectedFrom_;
};

}  // namespace vaw::ui
