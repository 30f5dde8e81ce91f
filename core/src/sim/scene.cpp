#include "vaw/sim/scene.hpp"

#include <cstdio>

#include "vaw/hash.hpp"
#include "vaw/primitives.hpp"
#include "vaw/scene_loader.hpp"

namespace vaw::sim {

namespace {

std::uint64_t add(std::uint64_t h, double v) { return fnv1a(&v, sizeof v, h); }
std::uint64_t add(std::uint64_t h, const Eigen::Vector3d& v) { return fnv1a(v.data(), sizeof(double) * 3, h); }
std::uint64_t add(std::uint64_t h, const Eigen::Matrix3d& m) { return fnv1a(m.data(), sizeof(double) * 9, h); }
std::uint64_t add(std::uint64_t h, const Eigen::Isometry3d& p) { return fnv1a(p.matrix().data(), sizeof(double) * 16, h); }
std::uint64_t add(std::uint64_t h, std::string_view s) {
  const std::size_t n = s.size();
  return fnv1a(s, fnv1a(&n, sizeof n, h));
}
std::uint64_t add(std::uint64_t h, const TriMesh* m) {
  if (m == nullptr) return add(h, std::string_view("no mesh"));
  const std::size_t counts[2] = {m->vertices.size(), m->triangles.size()};
  h = fnv1a(counts, sizeof counts, h);
  for (const auto& v : m->vertices) h = add(h, v);
  return fnv1a(m->triangles.data(), m->triangles.size() * sizeof(Eigen::Vector3i), h);
}

std::uint64_t hashOf(const Assembly& a) {
  std::uint64_t h = kFnvOffset;
  for (const auto& [name, m] : a.materials) {
    h = add(add(add(add(h, name), m.staticFriction), m.kineticFriction), m.rotationalFriction);
  }
  for (const Part& p : a.parts) {
    h = add(add(add(h, p.name), p.mesh.get()), p.pose);
    h = p.finalPose ? add(h, *p.finalPose) : add(h, std::string_view("no final pose"));
    h = add(add(add(add(h, p.material), p.mass.mass), p.mass.centerOfMass), p.mass.inertiaCm);
    h = add(h, static_cast<double>(p.category.category));
  }
  for (const auto& [id, f] : a.settings.partFriction)
    h = add(add(add(add(h, static_cast<double>(id)), f.staticFriction), f.kineticFriction), f.rotationalFriction);
  h = add(h, a.base ? static_cast<double>(*a.base) : -1.0);
  for (const EnvironmentObject& e : a.environment)
    if (!e.implied) h = add(add(add(h, e.name), e.mesh.get()), e.pose);
  for (const Constraint& c : a.constraints) {
    h = add(add(h, static_cast<double>(c.type)), static_cast<double>(c.part));
    if (c.partner) h = add(h, static_cast<double>(*c.partner));
    // Only the geometry of the constraint's type: the other members are never set (nor read).
    if (c.type == Constraint::Type::Insert) {
      for (const Axis* ax : {&c.partAxis, &c.baseAxis}) h = add(add(h, ax->point), ax->direction);
    } else {
      for (const Plane* pl : {&c.partPlane, &c.basePlane}) h = add(add(h, pl->point), pl->normal);
      h = add(h, c.offset);
    }
  }
  return h;
}

}  // namespace

void addDefaultFloor(Assembly& a) {
  for (const EnvironmentObject& e : a.environment)
    if (e.kind == "floor") return;
  Eigen::AlignedBox3d tables;
  for (const EnvironmentObject& e : a.environment) {
    if (e.kind != "table" || !e.mesh) continue;
    const Eigen::AlignedBox3d b = e.mesh->bounds();
    for (int c = 0; c < 8; ++c) tables.extend(e.pose * b.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
  }
  const Eigen::AlignedBox3d all = a.worldBounds();
  if (all.isEmpty()) return;
  const double top = (tables.isEmpty() ? all.min().z() : tables.max().z()) - kDefaultFloorDepth;
  const Eigen::Vector3d centre = tables.isEmpty() ? all.center() : tables.center();
  constexpr double thickness = 0.1;
  EnvironmentObject floor;
  floor.name = "floor";
  floor.kind = "floor";
  floor.implied = true;
  floor.mesh = std::make_shared<const TriMesh>(primitives::box({kDefaultFloorSize, kDefaultFloorSize, thickness}));
  floor.shapeSource = "box";
  floor.pose.translation() = Eigen::Vector3d(centre.x(), centre.y(), top - 0.5 * thickness);
  floor.color = Eigen::Vector3f(0.62f, 0.62f, 0.60f);
  a.environment.push_back(std::move(floor));
  TreeNode node;
  node.kind = TreeNode::Kind::Environment;
  node.name = "floor";
  node.index = a.environment.size() - 1;
  a.tree.children.push_back(std::move(node));
}

std::string hashText(std::uint64_t hash) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(hash));
  return buf;
}

Scene::Scene(Assembly assembly, collision::CollisionWorld collision)
    : assembly_(std::move(assembly)), collision_(std::move(collision)) {}

std::shared_ptr<const Scene> Scene::build(Assembly assembly, const ProgressFn& progress) {
  if (progress && !progress(0.0, "collision geometry")) throw LoadCancelled();
  addDefaultFloor(assembly);
  collision::CollisionWorld world(assembly);
  for (const auto& d : world.diagnostics()) assembly.warnings.push_back(d);
  std::shared_ptr<Scene> scene(new Scene(std::move(assembly), std::move(world)));
  for (const auto& id : scene->collision_.objects()) scene->collisionInfo_.push_back(scene->collision_.info(id));
  const auto& constraints = scene->assembly_.constraints;
  scene->supports_.reserve(constraints.size());
  for (std::size_t c = 0; c < constraints.size(); ++c) {
    if (progress && !progress(static_cast<double>(c) / static_cast<double>(constraints.size()), "constraint supports"))
      throw LoadCancelled();
    scene->supports_.push_back(scene->collision_.support(constraints[c], false));
  }
  scene->prepared_ = std::make_unique<std::once_flag[]>(constraints.size());
  scene->hash_ = hashOf(scene->assembly_);
  if (progress) progress(1.0, "scene ready");
  return scene;
}

const collision::Support& Scene::support(std::size_t c) const {
  collision::Support& s = supports_.at(c);
  std::call_once(prepared_[c], [&] { collision_.prepare(s); });
  return s;
}

const collision::ObjectInfo* Scene::collisionInfo(collision::ObjectId id) const {
  for (const auto& info : collisionInfo_)
    if (info.id == id) return &info;
  return nullptr;
}

}  // namespace vaw::sim
