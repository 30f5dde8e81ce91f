// Bought-in units (cad_units.hpp): which sub-assemblies come apart on their own, and one solid for those
// that do not.
#include "cad_units.hpp"

#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>

#include "../input/load_detail.hpp"
#include "vaw/cad_assembly.hpp"
#include "vaw/collision/collision_world.hpp"
#include "vaw/constraint_recognition.hpp"
#include "vaw/hash.hpp"
#include "vaw/kept_results.hpp"

namespace vaw::detail {

namespace {

// Within this of its home a part that meets another cannot be moved out (m): a tenth of a millimetre.
constexpr double kAtOnce = 1e-4;

struct Member {
  std::shared_ptr<const CadSolid> solid;
  Eigen::Isometry3d location;  // in the sub-assembly's frame
  std::string name;
};

// Every part under `n` (units count as parts), placed in `n`'s frame.
void collectMembers(const ImportedNode& n, const Eigen::Isometry3d& at, std::vector<Member>& out) {
  for (const ImportedNode& c : n.children) {
    const Eigen::Isometry3d here = at * c.location;
    if (c.solid) out.push_back({c.solid, here, c.name.empty() ? c.solid->product : c.name});
    else collectMembers(c, here, out);
  }
}

// Identical sub-assemblies (every instance of one product, and the copies some exporters write of it as
// products of their own) have the same parts placed alike: decided once. A part by its shape's measures.
std::string signature(const std::vector<Member>& members) {
  std::string key;
  for (const Member& m : members) {
    char text[160];
    const CadSolid& s = *m.solid;
    std::snprintf(text, sizeof text, "%.9g,%.9g,%.9g,%.9g,%zu,%zu", s.volume, s.centroid.x(), s.centroid.y(), s.centroid.z(), s.faces.size(),
                  s.mesh.triangles.size());
    key += text;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) {
        const double v = m.location.matrix()(r, c);
        std::snprintf(text, sizeof text, ",%.9f", std::abs(v) < 5e-10 ? 0.0 : v);  // no "-0.000000000"
        key += text;
      }
    key += ";";
  }
  return key;
}

// Why the parts, on their own, do not come apart (an order of disassembly leaves some in: trapped), or
// empty when they do. The same pipeline as a whole assembly's: constraints found, the part they stand on
// as base, the order search.
std::string trapped(const std::vector<Member>& members, SolidMeshes& meshes) {
  Assembly a;
  std::vector<Eigen::Isometry3d> poses;
  std::vector<RecognitionPart> rec;
  for (std::size_t i = 0; i < members.size(); ++i) {
    const Member& m = members[i];
    Part p;
    p.id = i;
    p.name = m.name;
    p.mesh = meshes.of(m.solid).mesh;
    p.cad = m.solid;
    p.mass.volume = m.solid->volume;
    p.mass.mass = m.solid->volume;  // density 1: only which is heavier matters here
    p.mass.centerOfMass = m.solid->centroid;
    p.mass.inertiaCm = m.solid->inertiaUnitDensity;
    p.pose = m.location;
    p.finalPose = m.location;
    poses.push_back(m.location);
    rec.push_back({m.solid, m.location});
    a.parts.push_back(std::move(p));
  }
  const std::vector<FoundConstraint> found = recognizeConstraints(rec);
  const PartId base = chooseBase(a.parts, poses, found).base;
  a.base = base;
  a.parts[base].finalPose.reset();
  a.constraints = constraintsFromFound(found, a.parts, base, poses);
  // Held fast by each other: two parts that share volume beyond a designed fit (a rotor modelled through its
  // housing, screws in a dummy servo without holes), or a part in no constraint with the others that meets
  // one of them within a tenth of a millimetre whichever way it moves (a ball between its races). A part that
  // could move a little before it meets another (a bracket on a rod through its bore) is not held so: such
  // parts come apart in a fitter's hands, whatever order a search finds, and the sub-assembly is no unit.
  const collision::CollisionWorld world(a);
  collision::QueryOptions clash;
  clash.dropTouching = true;
  clash.skipDesigned = true;
  clash.stopAtFirst = true;
  std::vector<std::string> held;
  for (PartId p = 0; p < a.parts.size() && held.size() <= 3; ++p)
    for (const collision::ObjectId& q : world.near(world.worldBounds(collision::ObjectId::part(p)), collision::ObjectId::part(p)))
      if (q.kind == collision::ObjectId::Kind::Part && q.index > p && !world.query(collision::ObjectId::part(p), q, clash).contacts.empty()) {
        held.push_back(a.parts[p].name + " drawn into " + a.parts[q.index].name);
        break;
      }
  std::vector<bool> constrained(a.parts.size(), false);
  for (const FoundConstraint& f : found) constrained[f.a] = constrained[f.b] = true;
  for (PartId p = 0; p < a.parts.size() && held.size() <= 3; ++p) {
    if (constrained[p]) continue;
    bool fast = true;
    for (int k = 0; k < 6 && fast; ++k) {
      Eigen::Isometry3d moved = poses[p];
      moved.pretranslate((k % 2 == 0 ? kAtOnce : -kAtOnce) * Eigen::Vector3d::Unit(k / 2));
      fast = !world.colliding(collision::ObjectId::part(p), moved).contacts.empty();
    }
    if (fast) held.push_back(a.parts[p].name + " held whichever way it moves");
  }
  if (held.empty()) return {};
  std::string why;
  for (std::size_t k = 0; k < held.size() && k < 3; ++k) why += (k == 0 ? "" : "; ") + held[k];
  if (held.size() > 3) why += "; ...";
  return "its parts do not come apart on their own (" + why + ")";
}

// One solid holding every member, in the sub-assembly's frame: meshes and faces side by side, mass
// properties combined (parallel axis), the colour of the largest member.
std::shared_ptr<const CadSolid> unitSolid(const std::vector<Member>& members, const std::string& name) {
  auto u = std::make_shared<CadSolid>();
  u->product = name;
  double volume = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  double largest = -1.0;
  for (const Member& m : members) {
    const CadSolid& s = *m.solid;
    volume += s.volume;
    moment += s.volume * (m.location * s.centroid);
    u->surfaceArea += s.surfaceArea;
    u->deflection = std::max(u->deflection, s.deflection);
    if (s.volume > largest && s.color) {
      largest = s.volume;
      u->color = s.color;
    }
    const auto first = static_cast<int>(u->mesh.vertices.size());
    const std::size_t firstTriangle = u->mesh.triangles.size();
    for (const auto& v : s.mesh.vertices) u->mesh.vertices.push_back(m.location * v);
    for (const auto& t : s.mesh.triangles) u->mesh.triangles.push_back(t + Eigen::Vector3i::Constant(first));
    for (CadFace f : s.faces) {
      f.point = m.location * f.point;
      f.direction = (m.location.linear() * f.direction).normalized();
      f.firstTriangle += firstTriangle;
      u->faces.push_back(f);
    }
  }
  u->volume = volume;
  u->centroid = volume > 0.0 ? Eigen::Vector3d(moment / volume) : Eigen::Vector3d::Zero();
  for (const Member& m : members) {
    const CadSolid& s = *m.solid;
    const Eigen::Matrix3d R = m.location.linear();
    const Eigen::Vector3d d = m.location * s.centroid - u->centroid;
    u->inertiaUnitDensity += R * s.inertiaUnitDensity * R.transpose() + s.volume * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  return u;
}

struct Joiner {
  const std::set<std::string>& split;
  const std::set<std::string>& join;
  const ProgressFn& progress;
  SolidMeshes& meshes;
  // Whether a sub-assembly comes apart takes a second of sweeps for a thirty-part servo: kept between
  // sessions like the reader's results, under the signature and vaw's build (docs/step.md, "Reopening a file").
  std::optional<KeptResults> kept;
  std::map<std::string, std::pair<std::shared_ptr<const CadSolid>, std::string>> decided;  // by signature
  std::map<std::string, std::string> units;

  std::string decide(const std::vector<Member>& members, const std::string& key) {
    const std::string file = ResultKey(buildIdentity(reinterpret_cast<const void*>(&joinUnits))).add(key).text();
    if (kept)
      if (const auto data = kept->find(file); data && !data->empty() && (*data)[0] == 'U')
        return std::string(data->begin() + 1, data->end());
    const std::string why = trapped(members, meshes);
    if (kept) {
      std::vector<std::uint8_t> data{'U'};
      data.insert(data.end(), why.begin(), why.end());
      try {
        kept->store(file, data);
      } catch (const OutputError&) {
        // A folder that cannot be written only costs the next open its sweeps.
      }
    }
    return why;
  }

  void visit(ImportedNode& n, bool root) {
    for (ImportedNode& c : n.children)
      if (!c.solid && !c.children.empty()) visit(c, false);
    if (root || split.count(n.name)) return;
    std::vector<Member> members;
    collectMembers(n, Eigen::Isometry3d::Identity(), members);
    if (members.size() < 2) return;
    const std::string key = signature(members) + (join.count(n.name) ? "joined" : "");
    auto it = decided.find(key);
    if (it == decided.end()) {
      if (progress && !progress(0.0, "units: " + n.name)) throw LoadCancelled();
      const std::string why = join.count(n.name) ? std::string("joined as one unit") : decide(members, key);
      it = decided.emplace(key, std::pair{why.empty() ? nullptr : unitSolid(members, n.name), why}).first;
    }
    if (!it->second.first) return;
    n.solid = it->second.first;
    units.emplace(n.name, it->second.second);
  }
};

}  // namespace

std::map<std::string, std::string> joinUnits(ImportedNode& root, const std::set<std::string>& split, const std::set<std::string>& join,
                                             const ImportOptions& import, SolidMeshes& meshes, const ProgressFn& progress) {
  Joiner j{split, join, progress, meshes, KeptResults::under(import.resultCache, import.resultCacheMB, "units"), {}, {}};
  j.visit(root, true);
  return std::move(j.units);
}

}  // namespace vaw::detail
