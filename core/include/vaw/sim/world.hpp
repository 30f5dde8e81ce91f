#pragma once
// The simulation world: joins the part states (interaction/states.hpp), the reduced motion models
// (dynamics/*) and the collision checks (collision/*) into one deterministic, fixed-step simulation
// (docs/simulation.md).
//
// One way for data to flow: an Input per step (hands, the base as held in the left hand, the hoist) goes in
// through step(), edits (gravity, friction, method, rate) through apply() between steps; the parts' runtime
// state, the transition log, the refusals and the edit log come out. A part's state changes only through
// interact::fire(), and every accepted transition and every refusal is logged. Nothing reads a clock or
// global state: the same scene, settings, inputs and edits give bit-identical states.
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_set>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/dynamics/gravity.hpp"
#include "vaw/dynamics/stability.hpp"
#include "vaw/dynamics/free_flight.hpp"
#include "vaw/dynamics/integrators.hpp"
#include "vaw/hash.hpp"
#include "vaw/interaction/release.hpp"
#include "vaw/interaction/states.hpp"
#include "vaw/sim/edit.hpp"
#include "vaw/sim/scene.hpp"

namespace vaw::sim {

// Where a hoist stands when a session or script places it itself (sessions recorded before scenes could
// declare their hoist); otherwise the scene's first hoist is used.
struct HoistPlacement {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // m, world x, y of the hook's vertical line
  double reach = 0.05;                                 // m, from the hook to the part's world bounds
};

struct Settings {
  double rate = 90.0;                       // Hz, the fixed step is 1 / rate
  dyn::GravityScales gravity;               // free flight 0.25, slide 1, rotation 1
  dyn::Method rotationMethod = dyn::Method::RK4;
  interact::ReleaseSettings release;        // windowed fit by default
  double recognizeDistance = 0.01;          // m: a released part this near its mate is put on it
  double recognizeAngle = 10.0;             // deg
  double placeDistance = 0.002;             // m: released this near its final pose it is PLACED
  double placeAngle = 2.0;                  // deg
  // A part on the base that comes to rest (stopped or blocked) this near its final pose is PLACED too:
  // on for CAD assemblies, whose parts slide home along their constraints (docs/physics.md, "Parts on
  // parts"); off for earlier scenes, whose recorded sessions replay as they were.
  bool placeAtRest = false;
  double grabReach = 0.05;                  // m: from the hand to the part's world bounds
  bool inertialForces = false;              // the hand-held base's acceleration (off, as in the paper)
  double rotationModelTolerance = 1.0;      // deg: constant-omega flight when its predicted error is below
  std::optional<HoistPlacement> hoist;      // none: the scene's hoist (Assembly::hoists)

  [[nodiscard]] double step() const { return 1.0 / rate; }
};

// The defaults with what the scene's "settings" block sets (rate, gravity scales, rotation method).
Settings settingsFor(const Assembly& assembly);

struct HandInput {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // world
  bool grab = false;
  // The part this hand closes on, when the hand knows it (the desktop's mouse picks it); none: the
  // nearest grabbable part within reach (tracked hands). Read on the step the grab starts.
  std::optional<PartId> target;
  // The hand's own velocity at its pose's origin (world), when a tracker measures it (a headset's hand
  // joints or controller); none: the release velocity is estimated from the held part's recent poses
  // (Settings::release). Read on the step the hand lets go.
  std::optional<interact::Twist> velocity{};  // initialised here, so inputs written as {pose, grab, target} stay complete
};

struct HoistInput {
  bool engaged = false;  // the hook is closed
  double height = 1.0;   // m, world z of the hook (the attachment frame's origin)
  double yaw = 0.0;      // rad about world z
};

// Everything that drives one step.
struct Input {
  HandInput left, right;
  std::optional<Eigen::Isometry3d> base;  // the base's pose this step (held in the left hand); none: unchanged
  HoistInput hoist;
};

enum class Holder : std::uint8_t { None, Left, Right, Both, Hoist };

// What a part is doing, and the coordinates of its state's model.
enum class Model : std::uint8_t { None, Kinematic, Free, Cylindrical, Plane };

struct PartRuntime {
  PartId id = 0;
  interact::PartState state = interact::PartState::Static;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // part frame -> world
  Model model = Model::None;
  Holder holder = Holder::None;
  std::optional<std::size_t> constraint;  // the constraint it rests by (ONBASE*), index into Assembly::constraints
  // Model coordinates: cylindrical (angle, omega, slide, slide rate) or plane (x, y, vx, vy) in the base.
  double angle = 0.0, omega = 0.0, slide = 0.0, slideRate = 0.0;
  Eigen::Vector2d planeP = Eigen::Vector2d::Zero(), planeV = Eigen::Vector2d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // CM, world (free flight; last known elsewhere)
  Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();  // world
};

struct TransitionRecord {
  std::uint64_t step = 0;
  double t = 0.0;  // s, the time at the end of the step in which it happened
  PartId part = 0;
  interact::PartState from{}, to{};
  interact::Event event{};
  std::string cause;  // e.g. "tilt=16.9deg", "blocked by base", "hit table"
};

struct Refusal {
  std::uint64_t step = 0;
  double t = 0.0;
  PartId part = 0;
  interact::PartState state{};
  interact::Event event{};
  std::string reason;
};

// The whole runtime state of a world at the end of a step (Jolt's SaveState, MuJoCo's mj_getState): parts,
// models, hands, settings and materials as edited, and the logs up to that step. Immutable and cheap to keep:
// the logs are shared between snapshots, and so is each part's state while it does not change (a part at
// rest is stored once however many snapshots hold it), so a recording keeps one every second and seeks
// from the nearest.
class Snapshot {
 public:
  [[nodiscard]] std::uint64_t step() const;  // steps run before it was taken
  [[nodiscard]] double time() const;
  [[nodiscard]] bool valid() const { return stored_ != nullptr; }
  // Heap bytes it holds, counting each part's state it shares with other snapshots only when it is not in
  // `counted` yet (which it then joins): over all snapshots of a recording, what they hold together.
  [[nodiscard]] std::size_t bytes(std::unordered_set<const void*>& counted) const;

 private:
  friend class World;
  struct State;
  struct Stored;
  std::shared_ptr<const Stored> stored_;
};

// How near a carried part is to being put on its mate when let go (the status bar and the viewport show it
// while a part is carried near its mate): the nearest of its constraints whose partner is placed.
struct CaptureHint {
  std::size_t constraint = 0;  // index into Assembly::constraints
  Constraint::Type type = Constraint::Type::Insert;
  double distance = 0.0;  // m off the mate's axis (insert) or plane (mate)
  double angle = 0.0;     // rad between the part's axis or face and the mate's
  bool captures = false;  // let go now, it goes onto the mate (within the limits and touching its partner there)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();      // world: on the mate's axis or plane, nearest the part's
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ(); // world: the axis, or the plane's normal
};

class World {
 public:
  explicit World(std::shared_ptr<const Scene> scene, Settings settings = {});
  // Builds a Scene of its own first (tests and one-off runs).
  explicit World(const Assembly& assembly, Settings settings = {});
  ~World();
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  void step(const Input& input);

  // Applies an edit before the next step and logs it; refused (nothing changes) when validate() finds it
  // breaks a rule: the reason is returned, empty on success.
  [[nodiscard]] std::string apply(const Edit& edit);

  [[nodiscard]] Snapshot snapshot() const;
  // Puts the world back exactly as it was when `s` was taken (logs included). `s` must come from a world
  // of the same scene.
  void restore(const Snapshot& s);

  [[nodiscard]] double time() const;
  [[nodiscard]] std::uint64_t stepCount() const;
  [[nodiscard]] const Settings& settings() const;
  [[nodiscard]] const Assembly& assembly() const;
  [[nodiscard]] const std::shared_ptr<const Scene>& scene() const;
  // The friction a part slides and turns with now (its override, else its material's, as edited).
  [[nodiscard]] FrictionValues friction(PartId id) const;
  [[nodiscard]] FrictionValues materialFriction(const std::string& material) const;
  // The part's own friction when it has an override (even one equal to its material's), else none.
  [[nodiscard]] std::optional<FrictionValues> frictionOverride(PartId id) const;
  [[nodiscard]] const std::vector<PartRuntime>& parts() const;
  [[nodiscard]] const PartRuntime& part(PartId id) const;
  [[nodiscard]] Eigen::Isometry3d basePose() const;
  [[nodiscard]] const std::vector<TransitionRecord>& transitions() const;
  [[nodiscard]] const std::vector<Refusal>& refusals() const;
  [[nodiscard]] const std::vector<EditRecord>& edits() const;
  // The input of the last step (what the hands and the hoist did), for views.
  [[nodiscard]] const Input& lastInput() const;
  // The hoist in use (position and reach) and its hook's frame after the last step; none without a hoist.
  [[nodiscard]] std::optional<Hoist> hoist() const;
  [[nodiscard]] std::optional<Eigen::Isometry3d> hookPose() const;
  // The part each hand (0 left, 1 right) holds, and the part on the hoist.
  [[nodiscard]] std::optional<PartId> held(int hand) const;
  [[nodiscard]] std::optional<PartId> onHoist() const;
  // What the release estimator would give for a held part if it were let go now.
  [[nodiscard]] std::optional<interact::Twist> releaseVelocity(PartId id) const;
  // None when the part has no constraint whose partner is placed, or the scene no base.
  [[nodiscard]] std::optional<CaptureHint> captureHint(PartId id) const;
  // The linear stability of the rotation method at the current rate for a part that turns on a shaft: the
  // hinge it is on now, or, for a part with an insert constraint that is not on it yet, the hinge it would
  // be on at its assembled pose, under the base's current orientation and the rotation's gravity. The
  // workbench warns with it before a part explodes (dynamics/stability.hpp). None for other parts.
  [[nodiscard]] std::optional<dyn::StabilityReport> rotationStability(PartId id) const;
  // The free-flight rotation model chosen at release, for a part in flight.
  [[nodiscard]] std::optional<dyn::RotationModel> flightRotation(PartId id) const;
  // The first surface straight below `point` (world) within `depth` (m), ignoring part `except`: a point
  // on a part, the base or an environment object. For views (the drop line under a lifted part).
  [[nodiscard]] std::optional<Eigen::Vector3d> surfaceBelow(const Eigen::Vector3d& point, double depth,
                                                            std::optional<PartId> except) const;
  // Parts that cost a model step this step (INHAND, ONTOOL, ONBASESLIDE, INSPACE, and ONBASESTATIC checks).
  [[nodiscard]] std::size_t activeParts() const;
  // FNV-1a over the bytes of every part's state, pose and model coordinates, and the time.
  [[nodiscard]] std::uint64_t stateHash() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vaw::sim
