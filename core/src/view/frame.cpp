#include "vaw/view/frame.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace vaw::view {

using interact::PartState;

namespace {

Rgb toRgb(const Eigen::Vector3f& c) {
  const auto ch = [](float v) { return std::clamp(v, 0.0f, 1.0f); };
  return {ch(c.x()), ch(c.y()), ch(c.z())};
}

Rgb mix(const Rgb& a, const Rgb& b, float t) {
  return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
}

Eigen::AlignedBox3d worldBox(const Eigen::AlignedBox3d& local, const Eigen::Isometry3d& pose) {
  Eigen::AlignedBox3d box;
  if (local.isEmpty()) return box;
  for (int corner = 0; corner < 8; ++corner) box.extend(pose * local.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)));
  return box;
}

// How far below a lifted part the drop line looks for a surface (m).
constexpr double kDropDepth = 20.0;

}  // namespace

Eigen::AlignedBox3d boundsOf(const Drawable& d) {
  const Eigen::AlignedBox3d box = worldBox(d.mesh ? d.mesh->bounds : Eigen::AlignedBox3d(), d.pose);
  if (!d.backdrop || box.isEmpty()) return box;
  const Eigen::Vector3d top(box.center().x(), box.center().y(), box.max().z());
  return Eigen::AlignedBox3d(top, top);
}

std::shared_ptr<const MeshBuffer> flatShaded(const TriMesh& mesh) {
  auto out = std::make_shared<MeshBuffer>();
  out->vertices.reserve(mesh.triangles.size() * 3 * kFloatsPerVertex);
  const auto n = static_cast<int>(mesh.vertices.size());
  for (const Eigen::Vector3i& t : mesh.triangles) {
    if (t.minCoeff() < 0 || t.maxCoeff() >= n) continue;  // the loader rejects these; draw nothing
    const Eigen::Vector3d& a = mesh.vertices[static_cast<std::size_t>(t.x())];
    const Eigen::Vector3d& b = mesh.vertices[static_cast<std::size_t>(t.y())];
    const Eigen::Vector3d& c = mesh.vertices[static_cast<std::size_t>(t.z())];
    if (!a.allFinite() || !b.allFinite() || !c.allFinite()) continue;
    Eigen::Vector3d normal = (b - a).cross(c - a);
    const double length = normal.norm();
    normal = length > 0.0 ? Eigen::Vector3d(normal / length) : Eigen::Vector3d::UnitZ();
    const Eigen::Vector3f nf = normal.cast<float>();
    for (const Eigen::Vector3d* p : {&a, &b, &c}) {
      const Eigen::Vector3f pf = p->cast<float>();
      out->vertices.insert(out->vertices.end(), {pf.x(), pf.y(), pf.z(), nf.x(), nf.y(), nf.z()});
      out->bounds.extend(*p);
    }
  }
  out->vertexCount = out->vertices.size() / kFloatsPerVertex;
  return out;
}

SceneDescription describe(const Assembly& assembly) {
  SceneDescription d;
  std::unordered_map<const TriMesh*, std::shared_ptr<const MeshBuffer>> buffers;
  const auto bufferOf = [&](const TriMesh& m) {
    auto [it, added] = buffers.try_emplace(&m, nullptr);
    if (added) it->second = flatShaded(m);
    return it->second;
  };
  d.partDrawable.resize(assembly.parts.size());
  for (const Part& p : assembly.parts) {
    if (!p.mesh) continue;
    Drawable dr;
    dr.kind = assembly.base && *assembly.base == p.id ? DrawableKind::Base : DrawableKind::Part;
    dr.index = p.id;
    dr.name = p.name;
    dr.mesh = bufferOf(*p.mesh);
    const auto it = assembly.materials.find(p.material);
    dr.color = p.color ? toRgb(*p.color) : it != assembly.materials.end() ? toRgb(it->second.color) : Rgb{0.698f, 0.698f, 0.722f};
    dr.pose = p.pose;
    d.partDrawable[p.id] = d.drawables.size();
    const Eigen::AlignedBox3d box = worldBox(dr.mesh->bounds, p.pose);
    d.partsBounds.extend(box);
    d.allBounds.extend(box);
    d.drawables.push_back(std::move(dr));
  }
  for (std::size_t i = 0; i < assembly.environment.size(); ++i) {
    const EnvironmentObject& e = assembly.environment[i];
    if (!e.mesh) continue;
    Drawable dr;
    dr.kind = DrawableKind::Environment;
    dr.index = i;
    dr.name = e.name;
    dr.mesh = bufferOf(*e.mesh);
    dr.color = toRgb(e.color);
    dr.pose = e.pose;
    dr.backdrop = e.implied;
    d.allBounds.extend(boundsOf(dr));
    d.drawables.push_back(std::move(dr));
  }
  d.hoists = assembly.hoists;
  for (const Hoist& h : d.hoists) {
    d.allBounds.extend(Eigen::Vector3d(h.position.x(), h.position.y(), h.lowest));
    d.allBounds.extend(Eigen::Vector3d(h.position.x(), h.position.y(), h.highest));
  }
  return d;
}

Rgb stateColor(PartState s) {
  switch (s) {
    case PartState::InHand: return {0.263f, 0.627f, 0.278f};       // green
    case PartState::OnTool: return {0.557f, 0.141f, 0.667f};       // purple
    case PartState::OnBaseSlide: return {0.984f, 0.753f, 0.176f};  // amber
    case PartState::OnBaseStatic: return {0.0f, 0.537f, 0.482f};   // teal
    case PartState::InSpace: return {0.118f, 0.533f, 0.898f};      // blue
    case PartState::Static: return {0.62f, 0.62f, 0.62f};          // grey
    case PartState::Placed: return {0.427f, 0.298f, 0.255f};       // brown
  }
  return {0.5f, 0.5f, 0.5f};
}

Rgb displayColor(const Rgb& own, PartState state, bool selected) {
  Rgb c = own;
  switch (state) {
    case PartState::InHand:
    case PartState::OnTool:
    case PartState::OnBaseSlide:
    case PartState::InSpace: c = mix(c, stateColor(state), 0.35f); break;
    default: break;
  }
  return selected ? mix(c, kHighlight, 0.45f) : c;
}

void makeFrame(const sim::World& world, const SceneDescription& scene, const FrameOptions& options, Frame& out) {
  const Assembly& a = world.assembly();
  out.step = world.stepCount();
  out.t = world.time();
  out.basePose = world.basePose();
  out.parts.resize(a.parts.size());
  out.drops.clear();
  for (PartId id = 0; id < a.parts.size(); ++id) {
    const sim::PartRuntime& r = world.part(id);
    PartFrame& p = out.parts[id];
    p.pose = r.pose;
    p.state = r.state;
    p.holder = r.holder;
    p.selected = options.selected == id;
    const auto drawable = id < scene.partDrawable.size() ? scene.partDrawable[id] : std::nullopt;
    p.color = displayColor(drawable ? scene.drawables[*drawable].color : Rgb{}, r.state, p.selected);
    const bool lifted = r.state == PartState::InHand || r.state == PartState::OnTool || r.state == PartState::InSpace;
    if (options.drops && lifted) {
      const Eigen::Vector3d com = r.pose * a.parts[id].mass.centerOfMass;
      if (const auto below = world.surfaceBelow(com, kDropDepth, id)) out.drops.push_back({id, com, *below});
    }
  }
  const sim::Input& in = world.lastInput();
  const sim::HandInput* hands[2] = {&in.left, &in.right};
  for (int k = 0; k < 2; ++k) out.hands[static_cast<std::size_t>(k)] = {hands[k]->pose, hands[k]->grab, world.held(k)};
  out.hoists.clear();
  if (const auto hook = world.hookPose()) {
    const auto hoist = world.hoist();
    out.hoists.push_back({*hook, std::isfinite(hoist->highest) ? hoist->highest : hook->translation().z() + 1.0,
                          in.hoist.engaged, world.onHoist()});
  }
}

}  // namespace vaw::view
