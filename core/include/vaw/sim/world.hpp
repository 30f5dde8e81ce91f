#pragma once
// The simulation world: joins the part states (interaction/states.hpp), the reduced motion models
// (dynamics/*) and the collision checks (collision/*) into one deterministic, fixed-step simulation.
//
// One way for data to flow: an Input per step (hands, the base as held in the left hand, the hoist) goes in
// through step(); the parts' runtime state, the transition log and the refusals come out. A part's state
// changes only through interact::fire(), and every accepted transition and every refusal is logged.
// Nothing reads a clock or global state: the same scene, settings and inputs give bit-identical states.
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/dynamics/gravity.hpp"
#include "vaw/dynamics/integrators.hpp"
#include "vaw/interaction/release.hpp"
#include "vaw/interaction/states.hpp"

namespace vaw::sim {

struct Settings {
  double rate = 90.0;                       // Hz, the fixed step is 1 / rate
  dyn::GravityScales gravity;               // free flight 0.25, slide 1, rotation 1
  dyn::Method rotationMethod = dyn::Method::RK4;
  interact::ReleaseSettings release;        // windowed fit by default
  double recognizeDistance = 0.01;          // m: a released part this near its mate is put on it
  double recognizeAngle = 10.0;             // deg
  double placeDistance = 0.002;             // m: released this near its final pose it is PLACED
  double placeAngle = 2.0;                  // deg
  double grabReach = 0.05;                  // m: from the hand to the part's world bounds
  bool inertialForces = false;              // the hand-held base's acceleration (off, as in the paper)
  double rotationModelTolerance = 1.0;      // deg: constant-omega flight when its predicted error is below
  // The hoist (a tool): its hook hangs at a fixed (x, y); it takes a tool part within this reach.
  Eigen::Vector2d hoistXY = Eigen::Vector2d::Zero();  // m, world
  double hoistReach = 0.05;                 // m, from the hook to the part's world bounds

  [[nodiscard]] double step() const { return 1.0 / rate; }
};

struct HandInput {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // world
  bool grab = false;
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

class World {
 public:
  World(const Assembly& assembly, Settings settings = {});
  ~World();
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  void step(const Input& input);

  [[nodiscard]] double time() const;
  [[nodiscard]] std::uint64_t stepCount() const;
  [[nodiscard]] const Settings& settings() const;
  [[nodiscard]] const Assembly& assembly() const;
  [[nodiscard]] const std::vector<PartRuntime>& parts() const;
  [[nodiscard]] const PartRuntime& part(PartId id) const;
  [[nodiscard]] Eigen::Isometry3d basePose() const;
  [[nodiscard]] const std::vector<TransitionRecord>& transitions() const;
  [[nodiscard]] const std::vector<Refusal>& refusals() const;
  // Parts that cost a model step this step (INHAND, ONTOOL, ONBASESLIDE, INSPACE, and ONBASESTATIC checks).
  [[nodiscard]] std::size_t activeParts() const;
  // FNV-1a over the bytes of every part's state, pose and model coordinates, and the time.
  [[nodiscard]] std::uint64_t stateHash() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// FNV-1a 64 over raw bytes (exposed for tests).
std::uint64_t fnv1a(const void* data, std::size_t size, std::uint64_t h = 0xcbf29ce484222325ULL);

}  // namespace vaw::sim
