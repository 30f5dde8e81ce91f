#include "vaw/assembly.hpp"

namespace vaw {

std::string_view name(Constraint::Type t) {
  switch (t) {
    case Constraint::Type::Mate: return "mate";
    case Constraint::Type::Align: return "align";
    case Constraint::Type::Insert: return "insert";
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

}  // namespace vaw
