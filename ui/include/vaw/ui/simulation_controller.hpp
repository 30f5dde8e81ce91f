#pragma once
// The one owner of the running simulation in the workbench: a vaw::sim::Recorder (the world and the
// session being recorded or played back) and the desktop's hands, base and hoist that drive it. Views never
// touch the world: they send commands (grab, move, tilt, edit, play, seek), which take effect at the next
// step boundary, and they read what the controller publishes: the current view::Frame after each batch of
// steps (frameReady) and the recording's logs (logChanged).
//
// It steps on the GUI thread (docs/architecture.md gives the measured step cost that makes that the simple
// and sufficient choice) at the world's fixed rate from a precise timer with an accumulator: wall time
// times the speed (0.1x to 2x) is turned into whole steps; a stall is caught up by at most kMaxCatchUp
// steps per tick and the rest is dropped, so the simulation slows down instead of running hundreds of
// steps at once.
#include <Eigen/Geometry>
#include <QElapsedTimer>
#include <QObject>
#include <QString>
#include <QTimer>
#include <deque>
#include <functional>
#include <memory>
#include <optional>

#include "vaw/sim/rate_meter.hpp"
#include "vaw/sim/recorder.hpp"
#include "vaw/view/frame.hpp"

namespace vaw::ui {

// The base as the left hand holds it: tilts about the world's x and y axes through the base's centre and a
// turn about the base's own vertical, in radians.
struct BaseAngles {
  double tiltX = 0.0, tiltY = 0.0, turn = 0.0;
  friend bool operator==(const BaseAngles&, const BaseAngles&) = default;
};

class SimulationController : public QObject {
  Q_OBJECT
 public:
  static constexpr int kMaxCatchUp = 5;             // steps per timer tick at most
  static constexpr double kMinSpeed = 0.1, kMaxSpeed = 2.0;
  static constexpr double kBaseRate = 30.0 * 3.14159265358979323846 / 180.0;  // rad/s the base turns at most

  explicit SimulationController(QObject* parent = nullptr);
  ~SimulationController() override;
  SimulationController(const SimulationController&) = delete;
  SimulationController& operator=(const SimulationController&) = delete;

  // A new recording of `scene`, paused at step 0. `sceneReference` is what a saved session names.
  void start(std::shared_ptr<const vaw::sim::Scene> scene, const QString& sceneReference,
             const vaw::sim::Settings& settings = {});
  // A recorded session on its scene, paused at step 0, playing its recorded inputs back. Throws
  // vaw::InputError when the session does not fit the scene.
  void startPlayback(std::shared_ptr<const vaw::sim::Scene> scene, vaw::sim::Session session);

  [[nodiscard]] bool hasWorld() const { return recorder_ != nullptr; }
  [[nodiscard]] const vaw::sim::Recorder& recorder() const { return *recorder_; }
  [[nodiscard]] const vaw::sim::World& world() const { return recorder_->world(); }
  [[nodiscard]] const vaw::view::SceneDescription& description() const { return description_; }
  [[nodiscard]] const vaw::view::Frame& frame() const { return frame_; }

  [[nodiscard]] bool isPlaying() const { return timer_.isActive(); }
  [[nodiscard]] double speed() const { return speed_; }
  // Following the recorded inputs (an opened session) rather than the desktop's hands.
  [[nodiscard]] bool isPlayback() const { return playback_; }
  // The world is before the end of the recording (after a seek back).
  [[nodiscard]] bool inPast() const { return recorder_ && !recorder_->atEnd(); }
  // CPU time of the last step (ns) and the parts it stepped.
  [[nodiscard]] qint64 lastStepNanoseconds() const { return lastStepNs_; }
  [[nodiscard]] std::optional<vaw::PartId> selected() const { return selected_; }

  // ---- the desktop's right hand (and both hands) ----
  // Closes the right hand (both hands with `bothHands`) on `part` at the world point `at`.
  void grab(vaw::PartId part, const Eigen::Vector3d& at, bool bothHands);
  void moveHand(const Eigen::Vector3d& at);
  void release();
  [[nodiscard]] bool handClosed() const { return handClosed_; }
  [[nodiscard]] Eigen::Vector3d handPosition() const { return hand_.translation(); }
  // Turning the held part while keys are held: its angular velocity (rad/s, world), about the hand.
  void setHandTurn(const Eigen::Vector3d& angularVelocity);

  // ---- the base in the left hand ----
  [[nodiscard]] BaseAngles baseAngles() const { return base_; }
  // The angles of the base as the world holds it now (a recording may have turned it).
  [[nodiscard]] BaseAngles worldBaseAngles() const;
  [[nodiscard]] BaseAngles baseTarget() const { return baseTarget_; }
  // Where the base goes; it moves there at kBaseRate at most (no jump, so inertial forces stay sane).
  void setBaseTarget(const BaseAngles& target);
  // While keys are held: the target moves at these rates (rad/s).
  void setBaseRates(const BaseAngles& rates);

  // ---- the hoist ----
  [[nodiscard]] const vaw::sim::HoistInput& hoist() const { return hoistInput_; }
  void setHoistEngaged(bool engaged);
  void setHoistHeight(double metres);
  void setHoistYaw(double radians);
  void setHoistRates(double metresPerSecond, double radiansPerSecond);

  // ---- another source of input (the headset's tracked hands) ----
  // When set, every live step takes its input from `source` instead of the desktop's mouse and keys; the
  // source is given the simulated time at the end of the step (s) so it can sample its hands for that
  // moment. Playback of a recording is unaffected. An empty function gives the desktop back its hands.
  using InputSource = std::function<vaw::sim::Input(double stepEndTime)>;
  void setInputSource(InputSource source);
  [[nodiscard]] bool hasInputSource() const { return static_cast<bool>(inputSource_); }

  // ---- a scripted presentation (the trials panel's, vaw/trials/stage.hpp) ----
  // When set, each live step's input, from the desktop or the source above, is handed to `script` with the
  // simulated time at the end of the step; it overrides what it drives (a hand until it lets go, the base)
  // and leaves the rest, so the desktop's mouse can still catch a part the script has let go. An empty
  // function ends it, and the desktop's hand and base go on from where the script left them.
  using Script = std::function<void(double stepEndTime, vaw::sim::Input& input)>;
  void setScript(Script script);
  [[nodiscard]] bool hasScript() const { return static_cast<bool>(script_); }

  // ---- pacing by another clock (the headset's frame loop) ----
  // While paced externally the timer steps nothing; play and pause still say whether time runs, and the
  // pacer calls advance() with the steps its clock owes (the headset: those that end by its next display
  // time). Turning it off restarts the timer's clock, so no time owed carries over either way.
  void setExternalPacing(bool on);
  [[nodiscard]] bool isPacedExternally() const { return externalPacing_; }
  // Runs `steps` live steps now (none while paused) and publishes one frame.
  void advance(int steps);

  // ---- the real rate ----
  // Simulated seconds per wall second over the last two seconds of play, and the share of that wall time
  // spent stepping; none while paused or until a second has passed. Behind: below the speed asked for
  // (vaw::sim::fallingBehind), which behindChanged announces.
  [[nodiscard]] std::optional<vaw::sim::RateMeter::Reading> realRate() const { return rateMeter_.reading(); }
  [[nodiscard]] bool isBehind() const { return behind_; }
  // The share of the timer's recent ticks that came on time and still owed more than kMaxCatchUp steps: near
  // 1 when the world's rate, not the machine, is what the timer cannot keep up with.
  [[nodiscard]] double cappedShare() const { return ticks_ > 0 ? static_cast<double>(cappedOnTime_) / ticks_ : 0.0; }

  // ---- memory ----
  // The machine's available memory in bytes (Linux: MemAvailable in /proc/meminfo); none where unknown.
  // Checked every `intervalMs` while playing: below kLowMemory the recording gives up its oldest snapshots
  // (vaw::sim::Recorder::giveUpOldest, half of what it holds) and pastGivenUp says up to when. Tests
  // replace the probe.
  static constexpr std::size_t kLowMemory = std::size_t{512} << 20;
  using MemoryProbe = std::function<std::optional<std::size_t>()>;
  void setMemoryProbe(MemoryProbe probe, int intervalMs = 5000);
  [[nodiscard]] static std::optional<std::size_t> availableMemory();

  // ---- edits (gravity, friction, method, rate) ----
  // Queued to the next step boundary; editApplied or editRefused says what came of it.
  void requestEdit(const vaw::sim::Edit& edit);

 public slots:
  void play();
  void pause();
  void togglePlay();
  void stepOnce();
  void setSpeed(double speed);
  void faster();
  void slower();
  // Back to the scene as loaded: a new, empty recording (an opened session is played again from its start).
  void reset();
  void seek(std::uint64_t step);
  void seekToEnd();
  void setSelected(std::optional<vaw::PartId> part);

 signals:
  void started();  // a new world (new scene, reset, session): views rebuild from description()
  void frameReady();
  void logChanged();
  void refused(const QString& message);  // a refusal of the world (a grab of a two-hand part...)
  void editApplied(const QString& description);
  void editRefused(const QString& reason);
  void playingChanged(bool playing);
  void speedChanged(double speed);
  void futureDiscarded(double fromSeconds);
  void behindChanged(bool behind);
  void pastGivenUp(double beforeSeconds);  // seeking before this time now replays from further back

 private:
  void tick();
  void runSteps(int n);
  void drainCommands();
  void stepOnceNow();
  [[nodiscard]] vaw::sim::Input nextInput();
  [[nodiscard]] Eigen::Isometry3d basePose(const BaseAngles& a) const;
  void publish();
  void meterRate();  // after each tick or paced advance
  void restartRate();
  void checkMemory();
  void reportNews(std::size_t transitionsBefore, std::size_t refusalsBefore);
  void takeOver();  // live input from the past or during playback: the recorded future goes
  void syncInputs();
  void resetInputs();

  std::unique_ptr<vaw::sim::Recorder> recorder_;
  std::optional<vaw::sim::Session> playbackSession_;  // to play again on reset
  vaw::view::SceneDescription description_;
  vaw::view::Frame frame_;
  std::optional<vaw::PartId> selected_;
  QTimer timer_;
  QElapsedTimer clock_;
  qint64 lastTickNs_ = 0;
  double accumulator_ = 0.0;  // s of simulated time owed
  double speed_ = 1.0;
  bool playback_ = false;
  qint64 lastStepNs_ = 0;
  std::deque<std::function<void()>> commands_;
  InputSource inputSource_;
  Script script_;
  bool externalPacing_ = false;
  vaw::sim::RateMeter rateMeter_;
  qint64 steppingNs_ = 0;  // spent stepping since the last sample
  bool behind_ = false;
  int ticks_ = 0, cappedOnTime_ = 0;
  MemoryProbe memoryProbe_ = &SimulationController::availableMemory;
  qint64 memoryCheckNs_ = 5'000'000'000;
  qint64 lastMemoryCheckNs_ = 0;

  // Desktop inputs, read at each step.
  Eigen::Isometry3d hand_ = Eigen::Isometry3d::Identity();
  std::deque<bool> grabEdges_;  // pending closes and opens, one per step so none is lost
  bool handClosed_ = false;     // as the last step saw it
  bool bothHands_ = false;
  std::optional<vaw::PartId> target_;
  Eigen::Vector3d handTurn_ = Eigen::Vector3d::Zero();
  BaseAngles base_, baseTarget_, baseRates_;
  Eigen::Vector3d basePivot_ = Eigen::Vector3d::Zero();
  Eigen::AlignedBox3d baseBox_;  // the base's own bounds; its lowest corner at load:
  double baseLowest_ = 0.0;
  Eigen::Isometry3d baseLoad_ = Eigen::Isometry3d::Identity();
  vaw::sim::HoistInput hoistInput_;
  double hoistRate_ = 0.0, hoistYawRate_ = 0.0;
};

}  // namespace vaw::ui
