#include "vaw/assembly.hpp"

#include "vaw/hash.hpp"

namespace vaw {

std::string_view name(Constraint::Type t) {
  switch (t) {
    case Constraint::Type::Mate: return "mate";
    case Constraint::Type::Align: return "align";
    case Constraint::Type::Insert: return "insert";
  }
  return "?";
}

std::string_view name(Constraint::Found::Seat s) {
  switch (s) {
    case Constraint::Found::Seat::None: return "none";
    case Constraint::Found::Seat::Counterbore: return "counterbore";
    case Constraint::Found::Seat::Countersink: return "countersink";
  }
  return "none";
}

std::string_view name(Constraint::Found::Fit f) {
  switch (f) {
    case Constraint::Found::Fit::Clearance: return "clearance";
    case Constraint::Found::Fit::Threaded: return "threaded";
    case Constraint::Found::Fit::Press: return "press";
  }
  return "?";
}

std::optional<PartId> Assembly::findPart(std::string_view partName) const {
  for (const auto& p : parts)
    if (p.name == partName) return p.id;
  return std::nullopt;
}

std::size_t Assembly::totalTriangles() const {
  std::size_t n = 0;
  for (const auto& p : parts) n += p.mesh ? p.mesh->triangleCount() : 0;
  for (const auto& e : environment) n += e.mesh ? e.mesh->triangleCount() : 0;
  return n;
}

Eigen::AlignedBox3d Assembly::worldBounds() const {
  Eigen::AlignedBox3d box;
  auto add = [&](const TriMesh* m, const Eigen::Isometry3d& pose) {
    if (!m) return;
    const auto b = m->bounds();
    if (b.isEmpty()) return;
    for (int c = 0; c < 8; ++c) box.extend(pose * b.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
  };
  for (const auto& p : parts) add(p.mesh.get(), p.pose);
  for (const auto& e : environment) add(e.mesh.get(), e.pose);
  return box;
}

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

}  // namespace

std::uint64_t contentHash(const Assembly& a) {
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


}  // namespace vaw
