#pragma once
// The workbench window: composes the viewport and the docks, the menus, the simulation toolbar and the
// status bar, and wires them to the two controllers (the loaded scene's and the running simulation's). It
// holds no assembly or simulation state of its own.
#include <QElapsedTimer>
#include <QMainWindow>
#include <QTimer>
#include <optional>
#include <string>

#include "vaw/assembly.hpp"

class QAction;
class QLabel;

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
class XrController;

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
  [[nodiscard]] SimulationController& simulation() const { return *simulation_; }
  [[nodiscard]] XrController& xr() const { return *xr_; }
  // The permanent status text: time, step cost, active parts, speed, mode.
  [[nodiscard]] QString statusText() const;
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

 private:
  void createMenus();
  void assemblyLoaded();
  void simulationStarted();
  void showSelection(std::optional<vaw::PartId> part);
  void frameReady();
  void updateLive();
  void updateStatus();
  void logChanged();
  void message(int severity, const QString& text, const QString& detail = {});

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
