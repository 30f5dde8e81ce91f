// Whether a supported part is blocked at a pose, and what a part collides with there (docs/collision.md,
// "Blocked").
#include "collision_world_impl.hpp"

namespace vaw::collision {

using detail::Cull;
using detail::runQuery;

BlockResult CollisionWorld::blocked(const Support& s, std::size_t maxContacts) const {
  return blocked(s, impl_->get(ObjectId::part(s.part)).pose, maxContacts);
}

BlockResult CollisionWorld::blocked(const Support& s, const Eigen::Isometry3d& partPose, std::size_t maxContacts) const {
  BlockResult r;
  const ObjectId part = ObjectId::part(s.part), base = ObjectId::part(s.base);
  const Tolerances& tol = impl_->tol;
  Eigen::AlignedBox3d box = worldBounds(part, partPose);
  if (box.isEmpty()) return r;
  box.min().array() -= tol.distance;
  box.max().array() += tol.distance;
  for (const ObjectId& other : near(box, part)) {
    QueryOptions o;
    o.dropTouching = true;
    o.maxContacts = std::max<std::size_t>(1, maxContacts - std::min(maxContacts, r.contacts.size()));
    o.stopAtFirst = maxContacts <= 1;
    Eigen::Isometry3d pose = partPose;
    Cull cull;
    if (other == base) {
      const Eigen::Isometry3d& baseToWorld = impl_->get(base).pose;
      const SupportCache* cache = s.cache.get();
      if (s.kind == Support::Kind::Plane) {
        o.mode = FilterMode::SkipCoplanar;
        // Lift the part off the face it rests on by half the tolerance: exactly touching faces would
        // otherwise be visited pair by pair (tens of thousands of leaf tests on a fine mesh).
        const Eigen::Vector3d n = baseToWorld.linear() * s.basePlane.normal;
        pose.pretranslate(0.5 * tol.distance * n);
        // Skip the base's geometry below its face while the part is on its side of the face (FCL's
        // bounding boxes are about 1e-5 m loose, so the lift alone does not separate them).
        if (cache && cache->planeCull) {
          const Eigen::Isometry3d partToBase = baseToWorld.inverse() * pose;
          const Eigen::Vector3d np = partToBase.linear() * s.partPlane.normal;
          const double gap = s.basePlane.normal.dot(partToBase * s.partPlane.point - s.basePlane.point);
          const double sinTilt = s.basePlane.normal.cross(-np).norm();
          if (-np.dot(s.basePlane.normal) > 0.0 && gap - sinTilt * cache->partReach > 0.3 * tol.distance) cull.bBelow = &cache->baseBelow;
        }
      } else {
        o.mode = FilterMode::SkipCoaxial;
        cull.fit = &s.fitPairs;
        cull.fitClearance = s.clearance;
        if (cache && cache->axisCull) {
          // Every point of the part stays at least nearest - off - tilt * reach from the base's axis: no
          // closer than the shaft's surface (less a tenth of the tolerance), where only the fit can touch.
          const Eigen::Isometry3d partToBase = baseToWorld.inverse() * pose;
          const Eigen::Vector3d up = partToBase.linear() * s.partAxis.direction;
          Eigen::Vector3d off = partToBase * s.partAxis.point - s.baseAxis.point;
          off -= s.baseAxis.direction * s.baseAxis.direction.dot(off);
          const double sinTilt = up.cross(s.baseAxis.direction).norm();
          if (cache->partNearest - off.norm() - sinTilt * cache->partReach >= cache->fitRadius - 0.1 * tol.distance &&
              off.norm() <= s.clearance + 0.1 * tol.distance)
            cull.bBelow = &cache->baseInside;
        }
      }
    }
    QueryResult q = runQuery(impl_->tol, impl_->get(part), pose, impl_->get(other), o, cull);
    r.boundingVolumeTests += q.boundingVolumeTests;
    r.leafTests += q.leafTests;
    if (!q.contacts.empty() && !r.by) r.by = other;
    r.contacts.insert(r.contacts.end(), q.contacts.begin(), q.contacts.end());
    if (r.contacts.size() >= std::max<std::size_t>(1, maxContacts)) break;
  }
  r.blocked = !r.contacts.empty();
  return r;
}

BlockResult CollisionWorld::colliding(ObjectId id, const Eigen::Isometry3d& pose, bool countTouching) const {
  BlockResult r;
  Eigen::AlignedBox3d box = worldBounds(id, pose);
  if (box.isEmpty()) return r;
  box.min().array() -= impl_->tol.distance;
  box.max().array() += impl_->tol.distance;
  for (const ObjectId& other : near(box, id)) {
    QueryOptions o;
    o.dropTouching = !countTouching;
    o.maxContacts = 8;
    QueryResult q = query(id, pose, other, o);
    if (!q.contacts.empty() && !r.by) r.by = other;
    r.contacts.insert(r.contacts.end(), q.contacts.begin(), q.contacts.end());
  }
  r.blocked = !r.contacts.empty();
  return r;
}


}  // namespace vaw::collision
