#pragma once
// The inside of vaw::sim::World, shared by the files that implement it one concern each:
//   world.cpp          the step, the base, transitions, edits, snapshots and the public API
//   world_hands.cpp    grabbing and letting go with the hands
//   world_tools.cpp    the hoist
//   world_flight.cpp   free flight (INSPACE)
//   world_on_base.cpp  recognition on release, and parts on the base (ONBASESLIDE, ONBASESTATIC)
//
// Everything that changes as the world steps lives in Snapshot::State, which World::Impl derives from, so a
// snapshot is a copy of that base and a restore an assignment to it. What Impl adds is fixed (the scene) or
// derived from the state (the collision world's poses, the list of awake parts) and rebuilt on restore.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "vaw/collision/collision_world.hpp"
#include "vaw/dynamics/free_flight.hpp"
#include "vaw/dynamics/hinge.hpp"
#include "vaw/sim/world.hpp"
#include "vaw/units.hpp"

namespace vaw::sim {

namespace detail {

inline constexpr std::size_t kMaxHistory = 64;  // hand pose samples kept for the release estimate

inline std::string fmt(const char* format, double a, double b = 0.0, double c = 0.0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  return buf;
}

inline double angleOf(const Eigen::Matrix3d& r) { return Eigen::AngleAxisd(r).angle(); }

}  // namespace detail

// What a part's current model needs beyond its PartRuntime coordinates.
struct PartModel {
  std::vector<interact::PoseSample> history;                 // hand-held: poses for the release velocity
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();  // holder frame -> part (hand, hoist)
  Eigen::Isometry3d inBase = Eigen::Isometry3d::Identity();  // part in base frame (PLACED, model reference)
  std::optional<dyn::Hinge> hinge;                           // cylindrical
  double clearance = 0.0;                                    // m, radial play of the fit (cylindrical)
  Eigen::Vector3d play = Eigen::Vector3d::Zero();            // base frame: where the play puts the part
  Eigen::Vector3d nb = Eigen::Vector3d::UnitZ(), e1b = Eigen::Vector3d::UnitX(), e2b = Eigen::Vector3d::UnitY();
  double radius = 0.0;                                       // largest distance from the axis (or CM)
  Eigen::Vector3d blockedDir = Eigen::Vector3d::Zero();     // base frame: the way it was last blocked
  double blockedRot = 0.0;                                   // sign of the rotation last blocked
  bool sliding = false;                                      // the slide's "moving" flag
  // Slid off the base's edge and still over it: the reduced model does not tip a part over the edge, so
  // its trailing side passes through the edge's corner for a few steps; that is not an impact with the base.
  bool clearing = false;
  dyn::Release release;
  Eigen::Vector3d gFree = Eigen::Vector3d::Zero();
  dyn::RotationModel rotation = dyn::RotationModel::ConstantOmega;
  std::optional<dyn::TorqueFree> torqueFree;
  // The motions on the base that can meet nothing (collision::FreeMotion), found at `slide` / `planeP` and
  // valid while the base keeps the pose `base` and no other object moves (`others`, Snapshot::State::moves).
  struct Free {
    bool valid = false;
    std::uint64_t others = 0;
    Eigen::Matrix4d base = Eigen::Matrix4d::Identity();
    double slide = 0.0;
    Eigen::Vector2d planeP = Eigen::Vector2d::Zero();
    collision::FreeMotion motion;
  } free;
};

// The logs are append-only. A snapshot seals what was appended since the last one into a chunk that
// points to the previous chunk, so snapshots share their history instead of copying it.
struct LogChunk {
  std::vector<TransitionRecord> transitions;
  std::vector<Refusal> refusals;
  std::vector<EditRecord> edits;
  std::shared_ptr<const LogChunk> previous;
};

struct Snapshot::State {
  Settings settings;                                    // as edited
  std::map<std::string, FrictionValues> materials;      // as edited
  std::vector<std::optional<FrictionValues>> overrides;  // per part
  std::vector<PartRuntime> parts;
  std::vector<PartModel> models;
  Eigen::Isometry3d basePose = Eigen::Isometry3d::Identity();
  std::array<Eigen::Vector3d, 3> baseTrail{};  // the base's last three positions (inertial forces)
  int baseTrailCount = 0;
  Eigen::Vector3d baseAcceleration = Eigen::Vector3d::Zero();
  bool prevGrab[2] = {false, false};
  std::optional<PartId> held[2];
  bool prevHoist = false;
  std::optional<PartId> onHoist;
  std::optional<Eigen::Isometry3d> hook;  // the hoist's hook frame after the last step
  Input lastInput;
  std::uint64_t stepIndex = 0;
  double t = 0.0;
  // Time is the step count over the rate, never a running sum; after a rate edit it counts on from the
  // step and time at which the rate changed.
  std::uint64_t rateStep = 0;
  double rateTime = 0.0;
  std::size_t active = 0;
  // Pose changes, of all parts and per part: a part's free motion stays valid while every change since it
  // was found is its own. State, so that a restored world reuses a free motion exactly when the original did.
  std::uint64_t moves = 0;
  std::vector<std::uint64_t> ownMoves;
  // The logs: sealed chunks up to the last snapshot, and how much of the live logs they hold.
  std::shared_ptr<const LogChunk> sealed;
  std::size_t sealedTransitions = 0, sealedRefusals = 0, sealedEdits = 0;
};

// One part's state as a snapshot holds it, shared by the snapshots in which it did not change.
struct PartSlot {
  PartRuntime runtime;
  PartModel model;
};

struct Snapshot::Stored {
  State state;  // without parts and models: those are the slots
  std::vector<std::shared_ptr<const PartSlot>> slots;
};

struct World::Impl : Snapshot::State {
  std::shared_ptr<const Scene> scene;
  const Assembly& assembly;
  collision::CollisionWorld collision;
  std::optional<Hoist> hoistTool;  // settings.hoist, else the scene's first hoist
  Eigen::Isometry3d baseLoad = Eigen::Isometry3d::Identity();
  std::optional<PartId> base;
  // The assembly's constraints with the partner's geometry in the base's frame (the base's own when the
  // partner is the base; a partner part's at its final pose, where it is when PLACED).
  std::vector<Constraint> inBaseFrame;
  std::vector<TransitionRecord> transitions;
  std::vector<Refusal> refusals;
  std::vector<EditRecord> edits;
  // Derived: per part, pose not yet given to the collision world; parts not STATIC (and not the base).
  std::vector<char> dirty;
  std::vector<PartId> dirtyList;
  std::vector<PartId> awake;
  std::size_t awakeStamp = static_cast<std::size_t>(-1);  // transitions.size() when `awake` was made
  // Per part: its state in the last snapshot, and whether anything may have written to it since (an event,
  // a pose, a step of its model, an edit). Marking is conservative: an unmarked part is unchanged, so the
  // next snapshot shares its slot.
  std::vector<std::shared_ptr<const PartSlot>> slots;
  std::vector<char> touched;

  Impl(std::shared_ptr<const Scene> s, Settings settings);

  // ---- world.cpp ----
  [[nodiscard]] double h() const { return settings.step(); }
  [[nodiscard]] const Part& def(PartId id) const { return assembly.parts[id]; }
  [[nodiscard]] FrictionValues friction(PartId id) const;
  [[nodiscard]] dyn::Friction slideFriction(PartId id) const {
    const FrictionValues f = friction(id);
    return {f.staticFriction, f.kineticFriction};
  }
  [[nodiscard]] Eigen::Vector3d comWorld(PartId id) const { return parts[id].pose * def(id).mass.centerOfMass; }
  [[nodiscard]] std::string objectName(const std::optional<collision::ObjectId>& o) const;
  [[nodiscard]] double endOfStep() const {
    return rateTime + static_cast<double>(stepIndex + 1 - rateStep) / settings.rate;
  }
  bool fireEvent(PartId id, interact::Event e, interact::Hands hands, const std::string& cause);
  // The first of the part's constraint partners that is not PLACED yet (empty: none).
  [[nodiscard]] std::string unplacedPartner(PartId id) const;
  // A moved part's pose reaches the collision world lazily: FCL's broad phase costs O(all objects) per
  // update (its tree height is recomputed), and a part's own queries pass its pose explicitly. So poses are
  // flushed only before a query by another part (or a grab, which reads bounds): with one active part the
  // step costs nothing per resting part.
  void setPose(PartId id, const Eigen::Isometry3d& pose);
  void flush(std::optional<PartId> except = std::nullopt);
  void moveBase(const std::optional<Eigen::Isometry3d>& pose);
  [[nodiscard]] Eigen::Vector3d gravity(double scale) const {
    return dyn::effectiveGravity(dyn::worldGravity() * scale, baseAcceleration, settings.inertialForces);
  }
  [[nodiscard]] std::string tiltCause(const Eigen::Vector3d& surfaceNormalWorld) const;
  [[nodiscard]] Eigen::Isometry3d inBaseOf(PartId id, double angle, double slide, const Eigen::Vector2d& p) const;
  [[nodiscard]] Eigen::Isometry3d currentInBase(PartId id) const {
    const PartRuntime& r = parts[id];
    return inBaseOf(id, r.angle, r.slide, r.planeP);
  }
  void step(const Input& in);
  std::string apply(const Edit& e);
  void rebaseFlight(PartId id);
  [[nodiscard]] Snapshot snapshot();
  void restore(const Snapshot& s);
  [[nodiscard]] std::uint64_t hash() const;

  // ---- world_hands.cpp ----
  [[nodiscard]] bool grabbable(PartId id) const;
  [[nodiscard]] double reachTo(PartId id, const Eigen::Vector3d& at) const;
  [[nodiscard]] std::optional<PartId> nearest(const Eigen::Vector3d& at, double reach, bool forTool) const;
  [[nodiscard]] std::optional<PartId> handTarget(const HandInput& hand) const;
  void hands(const Input& in);
  // `hand`: the input of the hand the part follows (its measured velocity, if any, is the release velocity).
  void letGo(PartId id, bool tool, interact::Hands hands, const HandInput* hand = nullptr);

  // ---- world_tools.cpp ----
  [[nodiscard]] Eigen::Isometry3d hoistFrame(const HoistInput& hi) const;
  void hoist(const HoistInput& hi);

  // ---- world_flight.cpp ----
  void enterFlight(PartId id, const Eigen::Vector3d& v, const Eigen::Vector3d& w, double t0);
  void stepFlight(PartId id, double t0, double t1);

  // ---- world_on_base.cpp ----
  struct Recognition {
    std::size_t constraint = 0;
    Eigen::Isometry3d pose;
    double distance = 0.0, angle = 0.0;
  };
  // The part's pose snapped onto constraint `ci` and how far it was off, whatever the limits.
  [[nodiscard]] Recognition measure(PartId id, std::size_t ci) const;
  // Whether a release at the part's pose would put it on that constraint: within the capture limits, on
  // its home side, and (checkTouch) touching its partner there.
  bool captures(PartId id, const Recognition& rec, bool checkTouch = true);
  std::optional<Recognition> recognize(PartId id);
  std::optional<CaptureHint> captureHint(PartId id);
  bool atFinalPose(PartId id, Eigen::Isometry3d& snapped) const;
  void enterOnBase(PartId id, std::size_t ci);
  void updatePlay(PartId id);
  [[nodiscard]] double torqueEps(PartId id) const {
    return 1e-6 * def(id).mass.mass * kStandardGravity * std::max(settings.gravity.rotation, 1e-12);
  }
  // `leaving`: the way (base frame) the part was last blocked, when it starts again away from it.
  void stepOnBase(PartId id, const Eigen::Vector3d& leaving = Eigen::Vector3d::Zero());
  void leaveBase(PartId id, const Eigen::Vector3d& v, const std::string& cause,
                 const Eigen::Vector3d& w = Eigen::Vector3d::Zero());
  void checkStart(PartId id);
  // The first fraction of an axial slide from s0 to s1 at which the part meets the plane of one of its mates
  // across the axis (a partner present: the base or PLACED), and that partner.
  [[nodiscard]] std::optional<std::pair<double, collision::ObjectId>> mateStop(PartId id, double angle, double s0, double s1) const;
  // With Settings::placeAtRest: a part come to rest on the base at its final pose is PLACED there.
  void placeIfHome(PartId id);
};

}  // namespace vaw::sim
