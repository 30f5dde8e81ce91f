#pragma once
// How close a carried part's path comes to everything else (docs/clearance.md): at every step of a span of
// a recording, the least distance from the part to each other part, the base, the table and the floor,
// with the two nearest points; the nearest object per step; each object's least clearance over the span;
// and the spans of near misses, contacts and interference, each naming the object. Distances are exact on
// the collision meshes (FCL's distance query); a box test first leaves out every object that cannot
// change an answer (docs/clearance.md, "Cost").
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "vaw/collision/collision_world.hpp"
#include "vaw/sim/session.hpp"

namespace vaw::sim {

class Scene;
class World;

struct ClearanceOptions {
  double threshold = 0.005;        // m: apart but closer than this is a near miss
  double reach = 0.05;             // m: objects never this close are left out of the table of objects
  std::optional<double> from, to;  // s: the span; unset: every step the part is INHAND or ONTOOL
};

// One step of the span: the object nearest the part.
struct ClearanceStep {
  double t = 0.0;
  collision::ObjectId nearest;
  double distance = 0.0;  // m; 0 when touching or interfering
  Eigen::Vector3d onPart = Eigen::Vector3d::Zero(), onOther = Eigen::Vector3d::Zero();  // world, m
  bool interfering = false;  // the part shares volume with `nearest` (beyond the touching tolerance)
};

// One object's least clearance over the span, where and when.
struct ObjectClearance {
  collision::ObjectId object;
  std::string name;
  double least = 0.0;  // m
  double t = 0.0;      // s, the first step at which it was least
  Eigen::Vector3d onPart = Eigen::Vector3d::Zero(), onOther = Eigen::Vector3d::Zero();
};

struct ClearanceSpan {
  enum class Kind { NearMiss, Contact, Interference };
  Kind kind = Kind::NearMiss;
  collision::ObjectId object;
  std::string name;
  double from = 0.0, to = 0.0;  // s: the first and the last step of it
};
std::string_view name(ClearanceSpan::Kind k);

struct ClearanceReport {
  PartId part = 0;
  double threshold = 0.0;
  std::vector<ClearanceStep> steps;      // in time order
  std::vector<ObjectClearance> objects;  // every object that came within `reach`, least clearance first
  std::vector<ClearanceSpan> spans;      // by start time
};

// Measures a part's clearance step by step, for a replay that feeds more than one measure
// (sweptVolumeAndClearance); clearanceAlong below is the one-measure replay. Construction throws
// vaw::InputError naming `file` for a part not in the scene or a threshold not a finite distance of 0
// or more; finish throws it when no step was in the span.
class ClearanceMeter {
 public:
  ClearanceMeter(const std::shared_ptr<const Scene>& scene, std::string file, PartId part, const ClearanceOptions& options);
  ~ClearanceMeter();
  ClearanceMeter(ClearanceMeter&&) noexcept;
  ClearanceMeter& operator=(ClearanceMeter&&) noexcept;

  void step(const World& w);
  [[nodiscard]] ClearanceReport finish();

 private:
  struct State;
  std::unique_ptr<State> s_;
};

// Replays `session` on `scene` and measures the part's clearance at every step of the span. Throws
// vaw::InputError (naming the session) when the span holds no step.
ClearanceReport clearanceAlong(const std::shared_ptr<const Scene>& scene, const Session& session, PartId part,
                               const ClearanceOptions& options = {});

}  // namespace vaw::sim
