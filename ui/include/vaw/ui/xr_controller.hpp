#pragma once
// VR mode (docs/vr.md): moves the running session into an OpenXR headset and back. It loads the OpenXR plugin
// (libvaw_xr_openxr.so, behind ui/include/vaw/ui/xr.hpp) when VR is first asked for, gives it a GLX OpenGL context of its
// own, and runs the headset's frame loop on the GUI thread: each frame the runtime's xrWaitFrame paces it,
// the SimulationController runs the steps that end by the frame's display time (its own timer is set aside,
// setExternalPacing), each step takes its whole input from the tracked hands sampled at the step's end time
// (setInputSource, through HandMapper), and the frame is drawn into both eyes. The desktop keeps every panel
// live and its viewport follows the wearer's head.
//
// Failures (no plugin, no runtime, no headset, an unsuitable OpenGL context, the session or the runtime lost)
// end in failed() with a message that says which; the workbench is then back on the desktop with the world as
// the last step left it (paused when the headset went away by itself), the recording intact.
#include <QObject>
#include <QPointer>
#include <QString>
#include <QTimer>
#include <QVector3D>
#include <cstdint>
#include <memory>
#include <array>
#include <optional>

#include "vaw/ui/xr.hpp"
#include "vaw/ui/xr_input.hpp"

class QAction;
class QLabel;
class QMenuBar;
class QOffscreenSurface;
class QOpenGLContext;
class QStatusBar;

namespace vaw::ui {

class SimulationController;
class Viewport;

class XrController : public QObject {
  Q_OBJECT
 public:
  enum class Mode { Desktop, Starting, Headset };

  // `mirror`, if given, shows the wearer's view while in the headset.
  XrController(SimulationController& simulation, Viewport* mirror, QObject* parent = nullptr);
  ~XrController() override;
  XrController(const XrController&) = delete;
  XrController& operator=(const XrController&) = delete;

  // Adds the VR menu (Enter VR / Leave VR, Ctrl+Shift+V) to `bar` and the runtime's line to `status`.
  void install(QMenuBar* bar, QStatusBar* status);

  [[nodiscard]] Mode mode() const { return mode_; }
  [[nodiscard]] bool inHeadset() const { return mode_ != Mode::Desktop; }
  [[nodiscard]] xr::SessionState sessionState() const { return state_; }
  // The runtime of the current or last session: its name, version and system; empty before any.
  [[nodiscard]] const xr::RuntimeInfo& runtime() const { return runtime_; }
  [[nodiscard]] QString statusText() const;
  [[nodiscard]] QAction* enterAction() const { return enterAction_; }
  [[nodiscard]] QAction* recenterAction() const { return recenterAction_; }
  // The last frame the headset showed (its timings and head pose), and how many it has shown.
  [[nodiscard]] const xr::FrameResult& lastFrame() const { return lastFrame_; }
  [[nodiscard]] std::uint64_t framesShown() const { return framesShown_; }
  // The thresholds of the hands, read from the settings' "vr" group when VR starts.
  [[nodiscard]] const xr::InputSettings& inputSettings() const { return inputSettings_; }

 public slots:
  void enter();
  // Asks the runtime to end the session; the headset winds down over the next frames.
  void leave();
  void toggle();
  // VR > Recenter (Ctrl+Shift+C): the table in front of where the wearer stands and looks now
  // (xr::Backend::recenter); only in the headset.
  void recenter();

 signals:
  void modeChanged(bool inHeadset);
  void sessionStateChanged(vaw::xr::SessionState state);
  void failed(vaw::xr::Failure failure, const QString& message);
  // What the runtime or the plugin said that the user should know (hands or controllers, validation).
  void notice(const QString& text, bool warning);
  void frameShown();
  // A hand (0 left, 1 right) closed: a pinch, a grip or a controller's select began. Emitted inside a
  // simulation step, so a receiver that resets or edits the world must connect queued.
  void handClosed(int hand);

 private:
  void loop();
  bool loadPlugin(QString& why);
  bool makeCurrent(QString& why);
  void startDriving();
  void stopDriving();
  const vaw::view::Frame* simulate(const xr::FrameTiming& timing);
  vaw::sim::Input inputAt(double stepEndTime);
  void mirror(const xr::FrameResult& frame);
  void sceneChanged();
  // The desktop's swept volume, drawn in the headset too.
  void overlayChanged();
  void finish(std::optional<xr::Event> failure);
  void updateUi();

  QPointer<SimulationController> simulation_;
  QPointer<Viewport> mirror_;
  QAction* enterAction_ = nullptr;
  QAction* recenterAction_ = nullptr;
  QLabel* status_ = nullptr;
  Mode mode_ = Mode::Desktop;
  xr::SessionState state_ = xr::SessionState::Unknown;
  xr::RuntimeInfo runtime_;
  xr::InputSettings inputSettings_;

  void* library_ = nullptr;
  VawXrCreateFn create_ = nullptr;
  std::unique_ptr<QOpenGLContext> context_;
  std::unique_ptr<QOffscreenSurface> surface_;
  std::unique_ptr<xr::Backend> backend_;
  std::optional<xr::HandMapper> hands_;
  std::array<bool, 2> handsClosed_{};  // as the last step saw them, across resets (a new mapper starts open)
  QTimer timer_;
  bool driving_ = false;

  // The simulation's clock against the headset's: steps that end by a display time run before it is drawn.
  bool anchored_ = false;
  std::int64_t anchorXr_ = 0;  // ns, runtime clock
  std::uint64_t anchorStep_ = 0, expectedStep_ = 0;
  double anchorSim_ = 0.0, anchorSpeed_ = 1.0, anchorRate_ = 0.0;

  xr::FrameResult lastFrame_;
  std::uint64_t framesShown_ = 0;
  struct Camera {
    QVector3D position, viewCenter, up;
    float fov = 0.0f;
  };
  std::optional<Camera> desktopCamera_;
};

}  // namespace vaw::ui
