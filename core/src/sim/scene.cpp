#include "vaw/sim/scene.hpp"

#include "vaw/primitives.hpp"
#include "vaw/scene_loader.hpp"

namespace vaw::sim {


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
  scene->hash_ = vaw::contentHash(scene->assembly_);
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
