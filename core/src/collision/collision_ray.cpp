// Ray casts against every object, exact against meshes and primitives (the drop line, picking).
#include "collision_world_impl.hpp"

namespace vaw::collision {

namespace {

// Möller-Trumbore: the ray parameter where it crosses the triangle, from either side.
std::optional<double> rayTriangle(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-300) return std::nullopt;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) / det;
  if (u < 0.0 || u > 1.0) return std::nullopt;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (v < 0.0 || u + v > 1.0) return std::nullopt;
  const double t = e2.dot(q) / det;
  return t >= 0.0 ? std::optional<double>(t) : std::nullopt;
}

// Ray against a primitive centred at the origin of its frame (o, d in that frame).
std::optional<double> rayPrimitive(const fcl::CollisionGeometryd& g, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  if (const auto* box = dynamic_cast<const fcl::Boxd*>(&g)) {
    const Eigen::Vector3d h = box->side / 2.0;
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) {
      if (std::abs(d[i]) < 1e-300) {
        if (std::abs(o[i]) > h[i]) return std::nullopt;
        continue;
      }
      double a = (-h[i] - o[i]) / d[i], b = (h[i] - o[i]) / d[i];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
      if (t0 > t1) return std::nullopt;
    }
    return t0;
  }
  if (const auto* sphere = dynamic_cast<const fcl::Sphered*>(&g)) {
    const double b = o.dot(d), c = o.squaredNorm() - sphere->radius * sphere->radius;
    const double disc = b * b - c;
    if (disc < 0.0) return std::nullopt;
    const double t = -b - std::sqrt(disc);
    return t >= 0.0 ? t : (c <= 0.0 ? std::optional<double>(0.0) : std::nullopt);
  }
  if (const auto* cyl = dynamic_cast<const fcl::Cylinderd*>(&g)) {
    const double r = cyl->radius, hz = cyl->lz / 2.0;
    std::optional<double> best;
    const auto consider = [&](double t) {
      if (t >= 0.0 && (!best || t < *best)) best = t;
    };
    const double a = d.x() * d.x() + d.y() * d.y();
    if (a > 1e-300) {
      const double b = o.x() * d.x() + o.y() * d.y(), c = o.x() * o.x() + o.y() * o.y() - r * r;
      const double disc = b * b - a * c;
      if (disc >= 0.0)
        for (double t : {(-b - std::sqrt(disc)) / a, (-b + std::sqrt(disc)) / a})
          if (std::abs(o.z() + t * d.z()) <= hz) consider(t);
    }
    if (std::abs(d.z()) > 1e-300)
      for (double z : {-hz, hz}) {
        const double t = (z - o.z()) / d.z();
        const Eigen::Vector3d p = o + t * d;
        if (p.x() * p.x() + p.y() * p.y() <= r * r) consider(t);
      }
    return best;
  }
  return std::nullopt;
}

}  // namespace

std::optional<CollisionWorld::RayHit> CollisionWorld::castRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                                              double length, std::optional<ObjectId> except) const {
  if (!(length > 0.0) || !origin.allFinite() || !direction.allFinite() || direction.norm() < 1e-12) return std::nullopt;
  const Eigen::Vector3d d = direction.normalized();
  Eigen::AlignedBox3d box(origin);
  box.extend(origin + d * length);
  // A thin box along the ray finds the triangles it may cross (FCL has no ray query).
  constexpr double kWidth = 1e-4;
  auto thin = std::make_shared<fcl::Boxd>(kWidth, kWidth, length);
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), d).toRotationMatrix();
  tf.translation() = origin + d * (length / 2.0);
  std::optional<RayHit> best;
  const auto consider = [&](ObjectId id, double t) {
    if (t <= length && (!best || t < best->distance)) best = RayHit{id, origin + d * t, t};
  };
  for (const ObjectId& id : near(box.extend(box.min() - Eigen::Vector3d::Constant(kWidth))
                                     .extend(box.max() + Eigen::Vector3d::Constant(kWidth)),
                                 except)) {
    const WorldObject& o = impl_->get(id);
    if (!o.geometry) continue;
    const Eigen::Isometry3d toGeometry = o.fclPose(o.pose).inverse();
    if (!o.bvh) {
      if (const auto t = rayPrimitive(*o.geometry, toGeometry * origin, toGeometry.linear() * d)) consider(id, *t);
      continue;
    }
    fcl::CollisionRequestd req(256, true);
    fcl::CollisionResultd res;
    fcl::collide(thin.get(), tf, o.geometry.get(), o.fclPose(o.pose), req, res);
    std::vector<fcl::Contactd> contacts;
    res.getContacts(contacts);
    const Eigen::Vector3d lo = o.pose.inverse() * origin, ld = o.pose.linear().transpose() * d;
    for (const fcl::Contactd& c : contacts) {
      const auto prim = static_cast<std::size_t>(c.o1 == thin.get() ? c.b2 : c.b1);
      if (prim >= o.bvhToMesh.size()) continue;
      const Eigen::Vector3i& tri = o.mesh->triangles[static_cast<std::size_t>(o.bvhToMesh[prim])];
      const auto& v = o.mesh->vertices;
      if (const auto t = rayTriangle(lo, ld, v[static_cast<std::size_t>(tri[0])], v[static_cast<std::size_t>(tri[1])],
                                     v[static_cast<std::size_t>(tri[2])]))
        consider(id, *t);
    }
  }
  return best;
}

}  // namespace vaw::collision
