#pragma once
// The loaded scene: an assembly together with everything derived from it once, at load, and never
// changed afterwards: its collision geometry (hierarchies, surface patches, proxies), the supports of its
// constraints and a content hash. It is built on a loading thread and then shared, read-only, by every
// consumer: the workbench's panels and viewport, each simulation World, the headless runner.
//
// Building the collision geometry of a large assembly takes hundreds of milliseconds; a World made from
// a Scene only takes an instance of it (collision::CollisionWorld::instance), so a reset, a replay or a
// second world costs almost nothing.
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "vaw/assembly.hpp"
#include "vaw/collision/collision_world.hpp"
#include "vaw/importer.hpp"

namespace vaw::sim {

// A scene that declares no floor gets one a desk's height below its table's top (below its lowest point
// when it has no table), so that a part thrown off the table comes to rest instead of falling forever
// (docs/physics.md, "The floor").
inline constexpr double kDefaultFloorDepth = 0.72;  // m below the table's top
inline constexpr double kDefaultFloorSize = 20.0;   // m, square, centred under the scene
// Adds the default floor (an environment object of kind "floor", `implied`, with its tree node) unless
// the assembly has an environment object of kind "floor". Scene::build calls it.
void addDefaultFloor(Assembly& assembly);

class Scene {
 public:
  // Adds the default floor, builds the collision geometry and the supports. The collision geometry's
  // problems join the assembly's warnings. `progress` may cancel (vaw::LoadCancelled).
  static std::shared_ptr<const Scene> build(Assembly assembly, const ProgressFn& progress = {});

  [[nodiscard]] const Assembly& assembly() const { return assembly_; }
  // The collision geometry with every object at its load pose. Worlds take instances of it.
  [[nodiscard]] const collision::CollisionWorld& collision() const { return collision_; }
  [[nodiscard]] const std::vector<collision::ObjectInfo>& collisionInfo() const { return collisionInfo_; }
  [[nodiscard]] const collision::ObjectInfo* collisionInfo(collision::ObjectId id) const;
  // How the part of constraint `c` rests on the base (index into Assembly::constraints). Prepared when
  // first asked for (by any thread): a product of a thousand parts has thousands of supports, most never
  // used in a session, each a pass over its base's mesh.
  [[nodiscard]] const collision::Support& support(std::size_t c) const;
  // FNV-1a over what the simulation reads from the assembly (geometry, poses, mass properties,
  // materials, constraints, tools): equal hashes replay equally; a changed mesh or file changes it.
  [[nodiscard]] std::uint64_t contentHash() const { return hash_; }

 private:
  Scene(Assembly assembly, collision::CollisionWorld collision);
  Assembly assembly_;
  collision::CollisionWorld collision_;
  std::vector<collision::ObjectInfo> collisionInfo_;
  mutable std::vector<collision::Support> supports_;
  std::unique_ptr<std::once_flag[]> prepared_;
  std::uint64_t hash_ = 0;
};

}  // namespace vaw::sim
