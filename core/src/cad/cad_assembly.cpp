#include "vaw/cad_assembly.hpp"

#include <algorithm>
#include <chrono>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <locale>
#include <map>
#include <memory>
#include <new>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <utility>

#include "../collision/geometry2d.hpp"
#include "vaw/collision/surface_patches.hpp"
#include "cad_units.hpp"
#include "../input/load_detail.hpp"
#include "vaw/cad_faces.hpp"
#include "vaw/categories.hpp"
#include "vaw/hash.hpp"
#include "vaw/kept_results.hpp"
#include "vaw/constraint_recognition.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/primitives.hpp"
#include "vaw/scene_loader.hpp"

#include <xxhash.h>

namespace vaw {

namespace {

namespace g2 = collision::geom2;

// Who goes first takes seconds of sweeps on a product of a thousand parts (docs/step.md, "Reopening a
// file"). Its answer depends only on the parts' shapes and exact faces at their file poses, the base, the
// constraints found and vaw's own build, so it is kept beside the reader's results under a hash of those.
class KeptPrecedence {
 public:
  // At this point every part stands at its file pose, which the content hash covers; the exact faces,
  // which it does not, are hashed once per product.
  KeptPrecedence(const Assembly& a, const ImportOptions& import)
      : kept_(KeptResults::under(import.resultCache, import.resultCacheMB, "who-goes-first")) {
    if (!kept_) return;
    ResultKey key(buildIdentity(reinterpret_cast<const void*>(&eval::geometricPrecedence)));
    key.add(contentHash(a));
    std::set<const CadSolid*> solids;
    for (const Part& p : a.parts)
      if (p.cad && solids.insert(p.cad.get()).second)
        for (const CadFace& f : p.cad->faces) {
          const double fields[] = {static_cast<double>(f.surface), f.point.x(), f.point.y(), f.point.z(),
                                   f.direction.x(), f.direction.y(), f.direction.z(), f.radius,
                                   f.convex ? 1.0 : 0.0, f.axialMin, f.axialMax, f.halfAngle,
                                   static_cast<double>(f.firstTriangle), static_cast<double>(f.triangleCount)};
          key.add(fields);
        }
    key_ = key.text();
  }

  // The pairs kept for these parts, when there are and they name parts that exist.
  [[nodiscard]] std::optional<std::vector<std::pair<PartId, PartId>>> find(std::size_t parts) const {
    if (!kept_) return std::nullopt;
    const auto data = kept_->find(key_);
    if (!data || data->size() % (2 * sizeof(std::uint32_t)) != 0) return std::nullopt;
    std::vector<std::pair<PartId, PartId>> out;
    for (std::size_t k = 0; k < data->size(); k += 2 * sizeof(std::uint32_t)) {
      std::uint32_t ids[2];
      std::memcpy(ids, data->data() + k, sizeof ids);
      if (ids[0] >= parts || ids[1] >= parts || ids[0] == ids[1]) return std::nullopt;
      out.emplace_back(ids[0], ids[1]);
    }
    return out;
  }
  // Keeps the answer; a folder that cannot be written only costs the next open its sweeps.
  void store(const std::vector<std::pair<PartId, PartId>>& first) const {
    if (!kept_) return;
    std::vector<std::uint8_t> data;
    for (const auto& [p, q] : first) {
      const std::uint32_t ids[2] = {static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(q)};
      const auto* b = reinterpret_cast<const std::uint8_t*>(ids);
      data.insert(data.end(), b, b + sizeof ids);
    }
    try {
      kept_->store(key_, data);
    } catch (const OutputError&) {
    }
  }

 private:
  std::optional<KeptResults> kept_;
  std::string key_;
};

struct Instance {
  const ImportedNode* node = nullptr;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // file's assembled pose, metres
  std::string name;
};

void checkCancel(const ProgressFn& progress, double f, const std::string& stage) {
  if (progress && !progress(std::clamp(f, 0.0, 1.0), stage)) throw LoadCancelled();
}

// Records how long each stage of an open takes, when asked (LoadOptions::timings).
class StageClock {
 public:
  explicit StageClock(std::vector<std::pair<std::string, double>>* out) : out_(out), last_(std::chrono::steady_clock::now()) {}
  // The time since the last mark is the stage `name`'s.
  void mark(const char* name) {
    const auto now = std::chrono::steady_clock::now();
    if (out_) out_->emplace_back(name, std::chrono::duration<double>(now - last_).count());
    last_ = now;
  }

 private:
  std::vector<std::pair<std::string, double>>* out_;
  std::chrono::steady_clock::time_point last_;
};

// The parts of a unit as the tree shows them: names, no geometry of their own.
TreeNode unitTree(const ImportedNode& n) {
  TreeNode t;
  t.kind = TreeNode::Kind::MeshNode;
  t.name = !n.name.empty() ? n.name : n.solid ? n.solid->product : std::string("(unnamed)");
  for (const auto& c : n.children) t.children.push_back(unitTree(c));
  return t;
}

// Walks the file's tree: sub-assemblies become groups, solid instances parts (in file order). A part is
// named by its instance, else its product, else the nearest named ancestor (`ancestor`); the STEP reader
// never passes on the names Open CASCADE makes up for unnamed labels.
TreeNode walk(const ImportedNode& n, const Eigen::Isometry3d& parent, std::vector<Instance>& out, std::set<std::string>& names,
              const std::string& ancestor = {}) {
  const Eigen::Isometry3d pose = parent * n.location;
  const std::string& own = n.name;
  TreeNode t;
  if (n.solid) {
    std::string name = !own.empty() ? own : n.solid->product;
    if (name.empty()) name = ancestor;
    if (name.empty()) name = "part";
    // Part names identify parts in scenes and sessions, so repeated instance names get a number.
    if (!names.insert(name).second) {
      int k = 2;
      while (!names.insert(name + " #" + std::to_string(k)).second) ++k;
      name += " #" + std::to_string(k);
    }
    t.kind = TreeNode::Kind::Part;
    t.name = name;
    t.index = out.size();
    // A unit's parts (cad_units.hpp), by name only: it moves as one.
    for (const auto& c : n.children) t.children.push_back(unitTree(c));
    out.push_back({&n, pose, name});
    return t;
  }
  t.kind = TreeNode::Kind::Group;
  t.name = own;
  for (const auto& c : n.children) {
    TreeNode child = walk(c, pose, out, names, own.empty() ? ancestor : own);
    if (child.kind == TreeNode::Kind::Part || !child.children.empty()) t.children.push_back(std::move(child));
  }
  return t;
}

}  // namespace

namespace {

// Height of the centre of mass over the table and whether it lies over the support, in orientation R.
std::pair<bool, double> restOn(const TriMesh& mesh, const Eigen::Vector3d& com, const Eigen::Matrix3d& R) {
  const double size = std::max(mesh.bounds().diagonal().norm(), 1e-9);
  double low = std::numeric_limits<double>::infinity();
  for (const auto& v : mesh.vertices) low = std::min(low, (R * v).z());
  std::vector<g2::P> support;
  for (const auto& v : mesh.vertices) {
    const Eigen::Vector3d w = R * v;
    if (w.z() <= low + 1e-6 * size) support.emplace_back(w.x(), w.y());
  }
  const std::vector<g2::P> hull = g2::convexHull(support);
  const Eigen::Vector3d c = R * com;
  // Stable: the centre of mass above the support polygon, a little inside its edge.
  const bool stable = hull.size() >= 3 && g2::signedDistanceConvex({c.x(), c.y()}, hull) > 1e-4 * size;
  return std::pair{stable, c.z() - low};
}

// The file's axis named by "+x", "-y", ...; none for anything else.
std::optional<Eigen::Vector3d> namedAxis(const std::string& text) {
  if (text.size() != 2 || (text[0] != '+' && text[0] != '-')) return std::nullopt;
  const double sign = text[0] == '+' ? 1.0 : -1.0;
  switch (text[1]) {
    case 'x': return Eigen::Vector3d(sign, 0, 0);
    case 'y': return Eigen::Vector3d(0, sign, 0);
    case 'z': return Eigen::Vector3d(0, 0, sign);
    default: return std::nullopt;
  }
}

// The turn that makes `from` (unit) point along `to` (unit); about x when they are opposite, so that "-z"
// turns the file over about its own x axis rather than about some axis Eigen happens to pick.
Eigen::Matrix3d turnOnto(const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  if (from.dot(to) < -1.0 + 1e-12) {
    const Eigen::Vector3d axis = std::abs(from.x()) < 0.9 ? from.cross(Eigen::Vector3d::UnitX()).normalized()
                                                          : from.cross(Eigen::Vector3d::UnitY()).normalized();
    return Eigen::AngleAxisd(std::numbers::pi, axis).toRotationMatrix();
  }
  return Eigen::Quaterniond::FromTwoVectors(from, to).toRotationMatrix();
}

}  // namespace

std::optional<Eigen::Vector3d> upDirection(const std::string& up) {
  if (const auto axis = namedAxis(up)) return axis;
  // Three numbers, as upForFaceDown writes them.
  std::istringstream in(up);
  in.imbue(std::locale::classic());
  Eigen::Vector3d d;
  if (!(in >> d.x() >> d.y() >> d.z())) return std::nullopt;
  in >> std::ws;
  if (!in.eof() || !d.allFinite() || !(d.norm() > 1e-9)) return std::nullopt;
  return d.normalized();
}

bool validUpChoice(const std::string& up) { return up == "auto" || upDirection(up).has_value(); }

std::optional<std::string> upForFaceDown(const Assembly& a, const Eigen::Vector3d& normal) {
  if (!a.base || a.cadFile.empty() || !(normal.norm() > 1e-12)) return std::nullopt;
  const Eigen::Vector3d up = -(a.cadTurn.transpose() * (a.parts[*a.base].pose.linear() * normal.normalized()));
  const char* names[] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    if (std::abs(std::abs(up[i]) - 1.0) < 1e-9) return std::string(up[i] > 0.0 ? "+" : "-") + names[i];
  // to_chars: the C locale's point whatever the process's locale (Qt applies the user's, where printf would
  // write "0,5" and upDirection's stream would not read it back).
  std::string text;
  for (int i = 0; i < 3; ++i) {
    char digits[32];
    const auto r = std::to_chars(digits, digits + sizeof digits, up[i], std::chars_format::general, 9);
    text.append(i == 0 ? "" : " ").append(digits, r.ptr);
  }
  return text;
}

Eigen::Matrix3d assemblyUp(const Part& base, const Eigen::Isometry3d& basePose, const Eigen::Vector3d& assemblyCentre,
                           const std::string& up, const std::optional<Eigen::Vector3d>& footing) {
  if (const auto axis = upDirection(up)) return turnOnto(*axis, Eigen::Vector3d::UnitZ());
  const Eigen::Matrix3d L = basePose.linear();
  const TriMesh& mesh = *base.mesh;
  const Eigen::Vector3d& com = base.mass.centerOfMass;
  // The base was chosen for the footing it stands on: so it stands, where it is stable there.
  if (footing && footing->norm() > 0.5) {
    const Eigen::Matrix3d turn = turnOnto(footing->normalized(), -Eigen::Vector3d::UnitZ());
    if (restOn(mesh, com, turn * L).first) return turn;
  }
  const double size = std::max(mesh.bounds().diagonal().norm(), 1e-9);
  // Candidate faces down, in the base's own frame: its planar faces (largest first), then its principal axes.
  std::vector<Eigen::Vector3d> downs;
  if (base.cad) {
    std::vector<const CadFace*> planes;
    for (const auto& f : base.cad->faces)
      if (f.surface == CadFace::Surface::Plane) planes.push_back(&f);
    std::stable_sort(planes.begin(), planes.end(), [](const CadFace* a, const CadFace* b) { return a->area > b->area; });
    for (const CadFace* f : planes) downs.push_back(f->direction.normalized());
  }
  for (int k = 0; k < 3; ++k) {
    downs.push_back(base.principal.axes.col(k));
    downs.push_back(-base.principal.axes.col(k));
  }
  // The rest of the assembly stands on the base: of two faces equally low (a plate's top and bottom), the
  // one facing away from the other parts goes down.
  const Eigen::Vector3d towardsRest = L.transpose() * (assemblyCentre - basePose * com);
  const auto rest = [&](const Eigen::Vector3d& down) {
    return restOn(mesh, com, Eigen::Quaterniond::FromTwoVectors(down, -Eigen::Vector3d::UnitZ()).toRotationMatrix());
  };
  std::optional<Eigen::Vector3d> best;
  double bestHeight = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& d : downs) {
    if (!d.allFinite() || d.norm() < 0.5) continue;
    const auto [stable, height] = rest(d);
    if (!stable) continue;
    const bool lower = height < bestHeight - 1e-3 * size;
    const bool tie = !lower && height <= bestHeight + 1e-3 * size;
    if (lower || (tie && best && d.dot(towardsRest) < best->dot(towardsRest) - 1e-9)) {
      best = d;
      bestHeight = std::min(bestHeight, height);
    }
  }
  if (!best) return Eigen::Matrix3d::Identity();
  // The file's own orientation stands when it is as low and the rest of the assembly is not below the base.
  const Eigen::Vector3d fileDown = L.transpose() * -Eigen::Vector3d::UnitZ();
  const auto [stableAsIs, heightAsIs] = restOn(mesh, com, L);
  if (stableAsIs && heightAsIs <= bestHeight + 0.01 * size && fileDown.dot(towardsRest) <= best->dot(towardsRest) + 1e-9)
    return Eigen::Matrix3d::Identity();
  return turnOnto((L * *best).normalized(), -Eigen::Vector3d::UnitZ());
}

BaseChoice chooseBase(const std::vector<Part>& parts, const std::vector<Eigen::Isometry3d>& poses, const std::vector<FoundConstraint>& found) {
  BaseChoice best;
  if (parts.empty()) return best;
  std::vector<std::size_t> links(parts.size(), 0);
  for (const FoundConstraint& f : found) {
    ++links[f.a];
    ++links[f.b];
  }
  const bool anyLinked = std::any_of(links.begin(), links.end(), [](std::size_t n) { return n > 0; });
  std::vector<Eigen::AlignedBox3d> boxes(parts.size());
  for (PartId p = 0; p < parts.size(); ++p)
    if (parts[p].mesh)
      for (const auto& v : parts[p].mesh->vertices) boxes[p].extend(poses[p] * v);
  // The footing of `p` facing `down` (a file axis, k and its sign): the area of its planar faces' triangles
  // facing down whose middles have no other part's box below them.
  const auto footing = [&](PartId p, int k, double sign) {
    const Part& part = parts[p];
    if (!part.cad) return 0.0;
    const Eigen::Vector3d down = sign * Eigen::Vector3d::Unit(k);
    const int u = (k + 1) % 3, v = (k + 2) % 3;
    // The boxes over its shadow that reach lower than its highest point: what could cover a face of it.
    std::vector<const Eigen::AlignedBox3d*> below;
    for (PartId q = 0; q < parts.size(); ++q) {
      if (q == p || boxes[q].isEmpty()) continue;
      const Eigen::AlignedBox3d& b = boxes[q];
      if (b.max()[u] < boxes[p].min()[u] || b.min()[u] > boxes[p].max()[u] || b.max()[v] < boxes[p].min()[v] || b.min()[v] > boxes[p].max()[v])
        continue;
      if ((sign > 0 ? b.max()[k] : -b.min()[k]) > (sign > 0 ? boxes[p].min()[k] : -boxes[p].max()[k])) below.push_back(&b);
    }
    double area = 0.0;
    const CadSolid& s = *part.cad;
    for (const CadFace& f : s.faces) {
      if (f.surface != CadFace::Surface::Plane || (poses[p].linear() * f.direction).dot(down) < 1.0 - 1e-6) continue;
      for (std::size_t t = f.firstTriangle; t < f.firstTriangle + f.triangleCount && t < s.mesh.triangles.size(); ++t) {
        const auto& tri = s.mesh.triangles[t];
        const Eigen::Vector3d a = poses[p] * s.mesh.vertices[static_cast<std::size_t>(tri[0])];
        const Eigen::Vector3d b = poses[p] * s.mesh.vertices[static_cast<std::size_t>(tri[1])];
        const Eigen::Vector3d c = poses[p] * s.mesh.vertices[static_cast<std::size_t>(tri[2])];
        const Eigen::Vector3d mid = (a + b + c) / 3.0;
        const bool covered = std::any_of(below.begin(), below.end(), [&](const Eigen::AlignedBox3d* box) {
          return mid[u] > box->min()[u] && mid[u] < box->max()[u] && mid[v] > box->min()[v] && mid[v] < box->max()[v] &&
                 (sign > 0 ? box->max()[k] > mid[k] + 1e-9 : box->min()[k] < mid[k] - 1e-9);
        });
        if (!covered) area += 0.5 * (b - a).cross(c - a).norm();
      }
    }
    return area;
  };
  struct Down {
    int k;
    double sign;
    const char* name;
  };
  const Down downs[] = {{2, -1.0, "-z"}, {1, -1.0, "-y"}, {2, 1.0, "+z"}, {1, 1.0, "+y"}, {0, -1.0, "-x"}, {0, 1.0, "+x"}};
  struct Found {
    PartId part = 0;
    double area = 0.0;
  };
  std::vector<Found> byDown;
  for (const Down& d : downs) {
    Found f;
    for (PartId p = 0; p < parts.size(); ++p) {
      if (anyLinked && links[p] == 0) continue;
      const double area = footing(p, d.k, d.sign);
      const bool larger = area > f.area * 1.05;
      const bool tie = !larger && area >= f.area * 0.95 && area > 0.0;
      if (larger || (tie && parts[p].mass.mass > parts[f.part].mass.mass)) f = {p, area};
    }
    byDown.push_back(f);
  }
  // Z up or Y up, as the file was modelled, where either has a footing worth the name (a quarter of the best
  // of all six); otherwise the best of all six.
  double most = 0.0;
  for (const Found& f : byDown) most = std::max(most, f.area);
  std::size_t chosen = byDown[0].area >= byDown[1].area ? 0 : 1;
  if (byDown[chosen].area < 0.25 * most)
    for (std::size_t i = 0; i < byDown.size(); ++i)
      if (byDown[i].area > byDown[chosen].area) chosen = i;
  if (!(byDown[chosen].area > 0.0)) {
    // No planar footing anywhere (meshes of curved parts): the heaviest, as before.
    for (PartId p = 1; p < parts.size(); ++p)
      if (parts[p].mass.mass > parts[best.base].mass.mass) best.base = p;
    best.reason = "the heaviest part (no part has a flat face the assembly could stand on)";
    return best;
  }
  best.base = byDown[chosen].part;
  best.footing = byDown[chosen].area;
  best.down = downs[chosen].sign * Eigen::Vector3d::Unit(downs[chosen].k);
  char text[160];
  std::snprintf(text, sizeof text, "the part the assembly stands on: %.0f mm\u00b2 of its faces at the bottom facing the file's %s, in %zu constraint%s",
                best.footing * 1e6, downs[chosen].name, links[best.base], links[best.base] == 1 ? "" : "s");
  best.reason = text;
  return best;
}

Eigen::Matrix3d restingOrientation(const TriMesh& mesh, const Eigen::Vector3d& com, const Principal& principal, const CadSolid* solid,
                                   const std::optional<Eigen::Matrix3d>& preferred) {
  const double size = std::max(mesh.bounds().diagonal().norm(), 1e-9);
  const auto rest = [&](const Eigen::Matrix3d& R) { return restOn(mesh, com, R); };
  if (preferred && rest(*preferred).first) return *preferred;
  std::vector<Eigen::Vector3d> downs;
  if (solid) {
    // The larger planar faces first: a part rests on a face it has, when it has one.
    std::vector<const CadFace*> planes;
    for (const auto& f : solid->faces)
      if (f.surface == CadFace::Surface::Plane) planes.push_back(&f);
    std::stable_sort(planes.begin(), planes.end(), [](const CadFace* a, const CadFace* b) { return a->area > b->area; });
    for (const CadFace* f : planes) downs.push_back(f->direction.normalized());
  }
  for (int k = 0; k < 3; ++k) {
    downs.push_back(principal.axes.col(k));
    downs.push_back(-principal.axes.col(k));
  }
  Eigen::Matrix3d best = Eigen::Matrix3d::Identity();
  double bestHeight = std::numeric_limits<double>::infinity();
  bool bestStable = false;
  for (const Eigen::Vector3d& d : downs) {
    if (!d.allFinite() || d.norm() < 0.5) continue;
    const Eigen::Matrix3d R = Eigen::Quaterniond::FromTwoVectors(d, -Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const auto [stable, height] = rest(R);
    if ((stable && !bestStable) || (stable == bestStable && height < bestHeight - 1e-9 * size)) {
      best = R;
      bestHeight = height;
      bestStable = stable;
    }
  }
  return best;
}

namespace {

// The base's bounds where it stands, and every pose a layout gives: the base's own, the rest to be set.
std::pair<Eigen::AlignedBox3d, std::vector<Eigen::Isometry3d>> layoutStart(const std::vector<Part>& parts, PartId base) {
  std::vector<Eigen::Isometry3d> poses(parts.size(), Eigen::Isometry3d::Identity());
  Eigen::AlignedBox3d baseBox;
  for (const auto& v : parts[base].mesh->vertices) baseBox.extend(parts[base].pose * v);
  poses[base] = parts[base].pose;
  return {baseBox, std::move(poses)};
}

}  // namespace

std::vector<Eigen::Isometry3d> layOutBeside(const std::vector<Part>& parts, PartId base, const std::vector<Eigen::Matrix3d>& orientations,
                                            double tableTop, double gap) {
  auto [baseBox, poses] = layoutStart(parts, base);
  const double depthLimit = std::max(baseBox.sizes().y(), 0.3);
  double columnX = baseBox.max().x() + gap, columnWidth = 0.0, y = baseBox.min().y();
  for (PartId id = 0; id < parts.size(); ++id) {
    if (id == base) continue;
    const Eigen::Matrix3d& R = orientations[id];
    Eigen::AlignedBox3d box;
    for (const auto& v : parts[id].mesh->vertices) box.extend(R * v);
    const Eigen::Vector3d size = box.sizes();
    if (y > baseBox.min().y() && y + size.y() > baseBox.min().y() + depthLimit) {
      columnX += columnWidth + gap;
      columnWidth = 0.0;
      y = baseBox.min().y();
    }
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = R;
    pose.translation() = Eigen::Vector3d(columnX, y, tableTop) - box.min();
    poses[id] = pose;
    columnWidth = std::max(columnWidth, size.x());
    y += size.y() + gap;
  }
  return poses;
}

std::vector<Eigen::Isometry3d> layOutAround(const std::vector<Part>& parts, PartId base, const std::vector<Eigen::Matrix3d>& orientations,
                                            double tableTop, double gap) {
  auto [baseBox, poses] = layoutStart(parts, base);
  // Sides: 0 +y, 1 -y (rows along x), 2 +x, 3 -x (rows along y).
  struct Item {
    PartId id;
    double t;            // where it goes, along its side
    Eigen::Vector3d min;  // its box in its resting orientation
    double along, across, spacing;
  };
  std::array<std::vector<Item>, 4> sides;
  for (PartId id = 0; id < parts.size(); ++id) {
    if (id == base) continue;
    Eigen::AlignedBox3d box;
    for (const auto& v : parts[id].mesh->vertices) box.extend(orientations[id] * v);
    const Eigen::Vector3d goes = parts[id].finalPose ? Eigen::Vector3d(*parts[id].finalPose * parts[id].mass.centerOfMass) : baseBox.center();
    const double to[4] = {baseBox.max().y() - goes.y(), goes.y() - baseBox.min().y(), baseBox.max().x() - goes.x(), goes.x() - baseBox.min().x()};
    const int side = static_cast<int>(std::min_element(std::begin(to), std::end(to)) - std::begin(to));
    const bool rowAlongX = side < 2;
    const Eigen::Vector3d size = box.sizes();
    const double along = rowAlongX ? size.x() : size.y(), across = rowAlongX ? size.y() : size.x();
    // Room for fingers between neighbours, more for larger parts.
    const double spacing = std::clamp(0.5 * std::max(size.x(), size.y()), 0.01, gap);
    sides[static_cast<std::size_t>(side)].push_back({id, rowAlongX ? goes.x() : goes.y(), box.min(), along, across, spacing});
  }
  for (int side = 0; side < 4; ++side) {
    auto& items = sides[static_cast<std::size_t>(side)];
    if (items.empty()) continue;
    std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.t != b.t ? a.t < b.t : a.id < b.id; });
    const bool rowAlongX = side < 2;
    const double a0 = rowAlongX ? baseBox.min().x() : baseBox.min().y(), a1 = rowAlongX ? baseBox.max().x() : baseBox.max().y();
    double needed = 0.0;
    for (const Item& it : items) needed += it.along + it.spacing;
    // As few rows as hold them with some slack; each part in the row that takes it nearest where it goes.
    struct Row {
      double cursor, depth = 0.0;
      std::vector<std::pair<std::size_t, double>> placed;  // item, position along the side
    };
    const auto rowsWanted = static_cast<std::size_t>(std::max(1.0, std::ceil(needed / (0.8 * std::max(a1 - a0, 1e-3)))));
    std::vector<Row> rows(rowsWanted, Row{a0, 0.0, {}});
    for (std::size_t i = 0; i < items.size(); ++i) {
      const Item& it = items[i];
      bool done = false;
      for (std::size_t k = 0; k < rows.size() && !done; ++k) {
        Row& row = rows[(i + k) % rows.size()];
        const double at = std::max(row.cursor, it.t - 0.5 * it.along);
        if (at + it.along > a1 && row.cursor > a0) continue;
        row.placed.emplace_back(i, at);
        row.cursor = at + it.along + it.spacing;
        row.depth = std::max(row.depth, it.across);
        done = true;
      }
      if (!done) {
        Row row{a0, 0.0, {}};
        const double at = std::max(a0, std::min(it.t - 0.5 * it.along, a1 - it.along));
        row.placed.emplace_back(i, at);
        row.cursor = at + it.along + it.spacing;
        row.depth = it.across;
        rows.push_back(std::move(row));
      }
    }
    double offset = gap;
    for (const Row& row : rows) {
      if (row.placed.empty()) continue;
      for (const auto& [i, at] : row.placed) {
        const Item& it = items[i];
        Eigen::Vector3d corner;  // where the box's minimum corner goes
        switch (side) {
          case 0: corner = {at, baseBox.max().y() + offset, tableTop}; break;
          case 1: corner = {at, baseBox.min().y() - offset - it.across, tableTop}; break;
          case 2: corner = {baseBox.max().x() + offset, at, tableTop}; break;
          default: corner = {baseBox.min().x() - offset - it.across, at, tableTop}; break;
        }
        Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
        pose.linear() = orientations[it.id];
        pose.translation() = corner - it.min;
        poses[it.id] = pose;
      }
      double rowSpacing = 0.0;
      for (const auto& [i, at] : row.placed) rowSpacing = std::max(rowSpacing, items[i].spacing);
      offset += row.depth + rowSpacing;
    }
  }
  return poses;
}

std::shared_ptr<const CadSolid> cadSolidFromMesh(const TriMesh& mesh, const std::string& product, Eigen::Vector3d& centroid) {
  const VolumeIntegrals vi = integrateVolume(mesh);
  centroid = vi.centroid;
  TriMesh local = mesh;
  for (auto& v : local.vertices) v -= centroid;
  const collision::SurfacePatches patches = collision::classifySurfaces(local);

  auto solid = std::make_shared<CadSolid>();
  solid->product = product;
  solid->volume = vi.volume;
  solid->centroid = Eigen::Vector3d::Zero();
  solid->inertiaUnitDensity = vi.inertiaUnitDensity;
  solid->surfaceArea = vi.surfaceArea;
  solid->mesh.vertices = local.vertices;
  std::vector<bool> taken(local.triangles.size(), false);
  const auto triangleArea = [&](int t) {
    const Eigen::Vector3i& tri = local.triangles[static_cast<std::size_t>(t)];
    return 0.5 * (local.vertices[tri[1]] - local.vertices[tri[0]]).cross(local.vertices[tri[2]] - local.vertices[tri[0]]).norm();
  };
  const auto addFace = [&](CadFace f, const std::vector<int>& triangles) {
    f.firstTriangle = solid->mesh.triangles.size();
    f.area = 0.0;
    for (int t : triangles) {
      if (taken[static_cast<std::size_t>(t)]) continue;
      taken[static_cast<std::size_t>(t)] = true;
      solid->mesh.triangles.push_back(local.triangles[static_cast<std::size_t>(t)]);
      f.area += triangleArea(t);
    }
    f.triangleCount = solid->mesh.triangles.size() - f.firstTriangle;
    if (f.triangleCount > 0) solid->faces.push_back(f);
  };
  for (const auto& c : patches.cylinders) {
    CadFace f;
    f.surface = CadFace::Surface::Cylinder;
    f.point = c.point;
    f.direction = c.direction;
    f.radius = c.radius;
    f.convex = c.convex;
    f.axialMin = 0.0;
    f.axialMax = c.length;
    addFace(f, c.triangles);
  }
  for (const auto& p : patches.planes) {
    CadFace f;
    f.surface = CadFace::Surface::Plane;
    f.point = p.origin;
    f.direction = p.normal;
    addFace(f, p.triangles);
  }
  std::vector<int> rest;
  for (std::size_t t = 0; t < taken.size(); ++t)
    if (!taken[t]) rest.push_back(static_cast<int>(t));
  addFace(CadFace{}, rest);
  // A cylinder or plane interrupted (by a groove, a slot) is found as several patches: assemblyFromCad makes
  // them one, as it does a CAD file's split faces.
  return solid;
}

namespace {

// Every byte of `file` to `add`, a megabyte at a time.
template <class Add>
void eachBlock(const std::filesystem::path& file, Add add) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file.string(), "", "a readable file", "cannot open it");
  std::vector<char> buf(1 << 20);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    add(buf.data(), static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) fail(file.string(), "", "a file that can be read to its end", std::strerror(errno));
}

}  // namespace

std::string fileContentHash(const std::filesystem::path& file) {
  const std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> state(XXH3_createState(), &XXH3_freeState);
  if (!state || XXH3_64bits_reset(state.get()) != XXH_OK) throw std::bad_alloc();
  eachBlock(file, [&](const char* data, std::size_t n) { XXH3_64bits_update(state.get(), data, n); });
  return "xxh3:" + hashText(XXH3_64bits_digest(state.get()));
}

std::string fileContentHashFnv(const std::filesystem::path& file) {
  std::uint64_t h = kFnvOffset;
  eachBlock(file, [&](const char* data, std::size_t n) { h = fnv1a(data, n, h); });
  return "fnv1a64:" + hashText(h);
}

namespace {

// Each distinct solid under `root` replaced by a copy with its split faces merged (mergeSplitFaces); the
// instances of one solid keep sharing one copy.
void mergeEverySolidsFaces(ImportedNode& root) {
  std::map<const CadSolid*, std::shared_ptr<const CadSolid>> merged;
  const std::function<void(ImportedNode&)> visit = [&](ImportedNode& n) {
    if (n.solid) {
      auto [it, fresh] = merged.try_emplace(n.solid.get());
      if (fresh) {
        auto copy = std::make_shared<CadSolid>(*n.solid);
        mergeSplitFaces(*copy);
        it->second = std::move(copy);
      }
      n.solid = it->second;
    }
    for (ImportedNode& c : n.children) visit(c);
  };
  visit(root);
}

}  // namespace

namespace {

// A choice naming no sub-assembly of the file (renamed in the CAD system since it was saved) is said.
void warnOfChoicesNamingNone(Assembly& a, const ImportedNode& root, const LoadOptions& options, const std::string& fileStr) {
  std::set<std::string> subAssemblies;
  const std::function<void(const ImportedNode&)> collect = [&](const ImportedNode& n) {
    for (const ImportedNode& c : n.children) {
      if (!c.children.empty()) subAssemblies.insert(c.name);
      collect(c);
    }
  };
  collect(root);
  for (const auto& [field, chosen] : {std::pair{"units_apart", &options.cadSplit}, std::pair{"units_joined", &options.cadJoin}})
    for (const std::string& n : *chosen)
      if (!subAssemblies.count(n))
        a.warnings.push_back({Diagnostic::Severity::Warning, fileStr, field, "the instance name of a sub-assembly in the file",
                              "\"" + n + "\", which names none: that choice is left out"});
}

// A part per instance: one welded mesh and one set of mass properties per product, shared by its instances.
void addParts(Assembly& a, const std::vector<Instance>& instances, detail::SolidMeshes& meshes, const std::map<std::string, std::string>& units,
              const std::filesystem::path& file, const LoadOptions& options, const ProgressFn& progress, MassSource massSource) {
  const std::string fileStr = file.string();
  Material mat;
  mat.name = "default";
  mat.density = options.bareMeshDensity;
  a.materials.emplace(mat.name, mat);
  const double rho = options.bareMeshDensity;

  struct Shared {
    std::shared_ptr<const TriMesh> mesh;
    MassProperties brep, mesh_;
  };
  std::map<const CadSolid*, Shared> shared;
  for (std::size_t i = 0; i < instances.size(); ++i) {
    const Instance& in = instances[i];
    checkCancel(progress, 0.1 + 0.5 * static_cast<double>(i) / static_cast<double>(instances.size()), "parts: " + in.name);
    const CadSolid& solid = *in.node->solid;
    auto it = shared.find(&solid);
    if (it == shared.end()) {
      // The B-rep is closed (the reader keeps no other); a tessellation that stays open after the reader's
      // retries and the repair costs this part its exact collision, not the file.
      const detail::SolidMeshes::Checked& checked = meshes.of(in.node->solid);
      const MeshCheck& check = checked.check;
      // Open edges only: a unit's parts that touch share edges between four triangles, which is no gap.
      if (check.boundaryEdges > 0)
        a.warnings.push_back({Diagnostic::Severity::Warning, fileStr, "product " + solid.product,
                              "a closed tessellation (every edge shared by two triangles)",
                              check.summary() + "; kept: its mass properties are the exact B-rep's, but its collision mesh "
                                                "has gaps a part could pass through there"});
      Shared s;
      s.mesh = checked.mesh;
      if (!(solid.volume > 0.0) || !std::isfinite(solid.volume))
        fail(fileStr, "product " + solid.product, "a solid with a positive, finite volume", std::to_string(solid.volume) + " m^3");
      s.brep.volume = solid.volume;
      s.brep.density = rho;
      s.brep.mass = rho * solid.volume;
      s.brep.centerOfMass = solid.centroid;
      s.brep.inertiaCm = rho * solid.inertiaUnitDensity;
      s.brep.surfaceArea = solid.surfaceArea;
      s.mesh_ = massPropertiesFromMesh(*s.mesh, rho);
      it = shared.emplace(&solid, std::move(s)).first;
    }
    Part p;
    p.id = i;
    p.name = in.name;
    p.product = solid.product;
    p.material = mat.name;
    p.shapeSource = file.filename().string() + (solid.product.empty() ? "" : " (" + solid.product + ")");
    p.mesh = it->second.mesh;
    p.cad = in.node->solid;
    p.color = in.node->color ? in.node->color : solid.color;
    p.meshMass = it->second.mesh_;
    p.massSource = massSource;
    if (massSource == MassSource::Brep) {
      p.fileMass = it->second.brep;
      p.mass = it->second.brep;
      p.disagreement = compare(*p.fileMass, *p.meshMass, p.mesh->bounds().diagonal().norm());
    } else {
      p.mass = it->second.mesh_;
    }
    if (p.disagreement && p.disagreement->worst() > options.massDisagreementWarning) {
      std::ostringstream s;
      s << "mass " << 100.0 * p.disagreement->massRel << " %, centre of mass " << 1000.0 * p.disagreement->comDistance
        << " mm, inertia " << 100.0 * p.disagreement->inertiaRel << " % (the tessellation is coarse: lower the deflection)";
      a.warnings.push_back({Diagnostic::Severity::Warning, fileStr, "part " + p.name,
                            "the tessellation's mass properties within " + std::to_string(100.0 * options.massDisagreementWarning) +
                                " % of the B-rep's",
                            s.str()});
    }
    if (const std::string problem = inertiaProblem(p.mass.inertiaCm, 1e-6); !problem.empty())
      fail(fileStr, "part " + p.name, "mass properties with a physically valid inertia", problem);
    p.principal = principalMoments(p.mass.inertiaCm);
    p.extent = principalExtent(*p.mesh, p.principal.axes);
    p.category = categorize(p.mass.mass, p.extent, options.categories);
    p.pose = in.pose;
    if (!in.node->children.empty()) {
      for (const ImportedNode& c : in.node->children) p.unitMembers.push_back(c.name.empty() && c.solid ? c.solid->product : c.name);
      if (const auto u = units.find(in.node->name); u != units.end()) p.unitReason = u->second;
    }
    a.parts.push_back(std::move(p));
  }
}

// The base: named, else the part the assembly stands on (docs/step.md, "The base"); `footing` the way down
// it stands, when it was chosen for its footing.
PartId chooseTheBase(Assembly& a, const std::vector<Eigen::Isometry3d>& filePoses, const std::vector<FoundConstraint>& found,
                     const LoadOptions& options, const std::string& fileStr, std::optional<Eigen::Vector3d>& footing) {
  if (options.cadBase) {
    const auto id = a.findPart(*options.cadBase);
    if (!id) fail(fileStr, "base", "the name of a part in the file", "\"" + *options.cadBase + "\"");
    a.baseReason = "chosen";
    return *id;
  }
  const BaseChoice choice = chooseBase(a.parts, filePoses, found);
  a.baseReason = choice.reason;
  if (choice.footing > 0.0) footing = choice.down;
  return choice.base;
}

// The base stands on its most stable face (or the way the user chose) with its footprint centred at the
// origin; the whole assembly turns with it, so every final pose keeps its place relative to the base. The
// other parts wait on the table beside it, and a table goes under all of it, its top at z = 0.
void layOutOnTheTable(Assembly& a, PartId base, const std::vector<Eigen::Isometry3d>& filePoses, const std::optional<Eigen::Vector3d>& baseFooting,
                      const LoadOptions& options, const std::string& fileStr) {
  a.cadUp = options.cadUp.value_or("auto");
  if (!validUpChoice(a.cadUp)) fail(fileStr, "up", kUpChoices, "\"" + a.cadUp + "\"");
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double total = 0.0;
  for (PartId id = 0; id < a.parts.size(); ++id) {
    centre += a.parts[id].mass.mass * (filePoses[id] * a.parts[id].mass.centerOfMass);
    total += a.parts[id].mass.mass;
  }
  if (total > 0.0) centre /= total;
  const Eigen::Matrix3d turn = assemblyUp(a.parts[base], filePoses[base], centre, a.cadUp, baseFooting);
  a.cadTurn = turn;
  a.cadUpAxis = (turn.transpose() * Eigen::Vector3d::UnitZ()).normalized();
  Eigen::Isometry3d shift = Eigen::Isometry3d::Identity();
  shift.linear() = turn;
  Eigen::AlignedBox3d baseBox;
  for (const auto& v : a.parts[base].mesh->vertices) baseBox.extend(shift * filePoses[base] * v);
  // The assembly as built stands on the table: a bolt's end and its nut under the plate hold the base up
  // by their length, so that they can be put in place under it (the base is held, not resting).
  double lowest = baseBox.min().z();
  for (PartId id = 0; id < a.parts.size(); ++id)
    for (const auto& v : a.parts[id].mesh->vertices) lowest = std::min(lowest, (shift * filePoses[id] * v).z());
  shift.pretranslate(-Eigen::Vector3d(baseBox.center().x(), baseBox.center().y(), lowest));
  baseBox.translate(-Eigen::Vector3d(baseBox.center().x(), baseBox.center().y(), lowest));
  for (PartId id = 0; id < a.parts.size(); ++id) a.parts[id].finalPose = shift * filePoses[id];
  a.parts[base].pose = shift * filePoses[base];
  a.parts[base].finalPose.reset();
  std::vector<Eigen::Matrix3d> orientations;
  for (const Part& p : a.parts)
    orientations.push_back(restingOrientation(*p.mesh, p.mass.centerOfMass, p.principal, p.cad.get(),
                                              p.finalPose ? std::optional<Eigen::Matrix3d>(p.finalPose->linear()) : std::nullopt));
  const double gap = std::clamp(0.1 * baseBox.sizes().maxCoeff(), 0.01, 0.05);
  std::vector<Eigen::Isometry3d> poses = layOutBeside(a.parts, base, orientations, 0.0, gap);
  // Beside the base while that stays within reach of it; a product too large for that (hundreds of parts
  // would run metres down the table) waits all round the base, each part by the side it goes nearest.
  double farthest = baseBox.max().x();
  for (PartId id = 0; id < a.parts.size(); ++id)
    if (id != base)
      for (const auto& v : a.parts[id].mesh->vertices) farthest = std::max(farthest, (poses[id] * v).x());
  if (farthest - baseBox.max().x() > std::max(baseBox.sizes().head<2>().maxCoeff(), 1.0))
    poses = layOutAround(a.parts, base, orientations, 0.0, gap);
  for (PartId id = 0; id < a.parts.size(); ++id) a.parts[id].pose = poses[id];

  Eigen::AlignedBox3d all = a.worldBounds();
  const double margin = std::max(0.1, gap * 2.0);
  EnvironmentObject table;
  table.name = "table";
  table.kind = "table";
  const Eigen::Vector3d size(all.sizes().x() + 2.0 * margin, all.sizes().y() + 2.0 * margin, 0.04);
  table.mesh = std::make_shared<const TriMesh>(primitives::box(size));
  table.shapeSource = "box";
  table.pose.translation() = Eigen::Vector3d(all.center().x(), all.center().y(), -0.02);
  table.color = Eigen::Vector3f(0.48f, 0.36f, 0.24f);
  a.environment.push_back(std::move(table));
  TreeNode tableNode;
  tableNode.kind = TreeNode::Kind::Environment;
  tableNode.name = "table";
  tableNode.index = 0;
  a.tree.children.push_back(std::move(tableNode));
}

}  // namespace

Assembly assemblyFromCad(ImportedMesh imported, const std::filesystem::path& file, const LoadOptions& options, const ProgressFn& progress,
                         MassSource massSource) {
  const std::string fileStr = file.string();
  Assembly a;
  a.source = file;
  a.cadFile = file;
  a.cadHash = imported.contentHash.empty() ? fileContentHash(file) : imported.contentHash;
  a.name = imported.root.name.empty() ? file.stem().string() : imported.root.name;
  a.units = LengthUnit::Metre;
  a.categorySettings = options.categories;
  for (const auto& w : imported.warnings) a.warnings.push_back({Diagnostic::Severity::Warning, fileStr, "", "", w});
  if (imported.declaredUnit)
    a.warnings.push_back({Diagnostic::Severity::Warning, fileStr, "unit", "a length unit the file declares",
                          *imported.declaredUnit + " (converted to metres)"});

  StageClock clock(options.timings);
  // One face per surface, whatever importer read the file: a cylinder an exporter split at its seams (or a
  // mesh's patches interrupted by a groove) is one here, before units join solids and recognition reads them.
  mergeEverySolidsFaces(imported.root);
  // Bought-in units (a bearing, a motor) become one part each before anything else sees them.
  detail::SolidMeshes meshes(fileStr);
  const std::map<std::string, std::string> units =
      detail::joinUnits(imported.root, options.cadSplit, options.cadJoin, options.import, meshes, progress);
  a.cadSplit = options.cadSplit;
  a.cadJoin = options.cadJoin;
  warnOfChoicesNamingNone(a, imported.root, options, fileStr);
  clock.mark("units");
  std::vector<Instance> instances;
  std::set<std::string> names;
  a.tree = walk(imported.root, Eigen::Isometry3d::Identity(), instances, names);
  a.tree.kind = TreeNode::Kind::Assembly;
  a.tree.name = a.name;
  if (instances.empty()) fail(fileStr, "", "a STEP file with at least one solid part", "no solid");

  addParts(a, instances, meshes, units, file, options, progress, massSource);

  clock.mark("parts, meshes and mass properties");
  checkCancel(progress, 0.65, "recognising constraints");
  std::vector<Eigen::Isometry3d> filePoses;
  std::vector<RecognitionPart> rec;
  for (const Part& p : a.parts) {
    filePoses.push_back(p.pose);
    rec.push_back({p.cad, p.pose});
  }
  // Progress names the pair at hand: recognition and who goes first take seconds on a thousand parts.
  const auto pairStage = [&](const char* stage, double from, double to) -> PairProgress {
    if (!progress) return {};
    return [&a, &progress, stage, from, to](double f, std::size_t i, std::size_t j) {
      return progress(from + (to - from) * f, std::string(stage) + ": " + a.parts[i].name + " and " + a.parts[j].name);
    };
  };
  const std::vector<FoundConstraint> found = recognizeConstraints(rec, {}, pairStage("recognising constraints", 0.65, 0.75));

  clock.mark("recognising constraints");
  std::optional<Eigen::Vector3d> baseFooting;
  const PartId base = chooseTheBase(a, filePoses, found, options, fileStr, baseFooting);
  a.base = base;
  a.constraints = constraintsFromFound(found, a.parts, base, filePoses);
  // Who goes first, from how the parts can move (docs/step.md, "Who goes first"); the rule above for
  // the pairs the geometry leaves open.
  clock.mark("the base");
  checkCancel(progress, 0.75, "which part goes first");
  const KeptPrecedence kept(a, options.import);
  std::optional<std::vector<std::pair<PartId, PartId>>> first = kept.find(a.parts.size());
  if (!first) {
    first = eval::geometricPrecedence(a, filePoses, {}, nullptr, pairStage("which part goes first", 0.75, 0.85));
    kept.store(*first);
  }
  if (!first->empty()) a.constraints = constraintsFromFound(found, a.parts, base, filePoses, {}, *first);
  // Parts come home along their constraints and are PLACED where they come to rest there.
  a.settings.placeAtRest = true;

  clock.mark("which part goes first");
  checkCancel(progress, 0.85, "laying the parts out on the table");
  layOutOnTheTable(a, base, filePoses, baseFooting, options, fileStr);

  clock.mark("layout");
  checkCancel(progress, 1.0, "done");
  return a;
}

}  // namespace vaw
