#include "vaw/evaluation/way_clearance.hpp"

#include <algorithm>
#include <compare>
#include <map>
#include <cmath>
#include <limits>
#include <string>

#include "vaw/collision/collision_world.hpp"
#include "vaw/error.hpp"
#include "vaw/sim/swept_volume.hpp"
#include "case_key.hpp"

namespace vaw::eval {

namespace {

using collision::ObjectId;

// The least distance from `mover` to `other` over the way, the mover at home + s * out for s in [from,
// length]. Distance is 1-Lipschitz in s (no point moves farther than s changes), and so is the gap between
// the two bounding boxes, which never exceeds it: from a point where either is d, nothing within d - b
// can be nearer than b. Stepping by that much, at least by the accuracy, with b the least found so far
// (capped at `reach`), misses no value below b by more than the accuracy: `tolerance`, or 5 % of how far
// b lies beyond the threshold when that is more, so that whether a pass is a near miss is decided to the
// tolerance while far passes take long steps. The box gap, checked first, spares the exact query where the
// boxes are far apart. Once the mover's box has passed the other's along the way every distance only
// grows, so the walk ends there.
std::optional<WayObject> leastAlong(collision::CollisionWorld& cw, PartId mover, PartId other, const Eigen::Isometry3d& home,
                                    const Eigen::Vector3d& out, double from, double end, const WayClearanceOptions& o) {
  const ObjectId a = ObjectId::part(mover), b = ObjectId::part(other);
  const Eigen::AlignedBox3d moverBox = cw.worldBounds(a, home), otherBox = cw.worldBounds(b);
  std::optional<WayObject> best;
  // The last nearest points, the mover's carried along with it: they bound the next search.
  std::optional<collision::CollisionWorld::Nearest> hint;
  double hintAt = 0.0;
  // The least found so far, capped at the reach, and how finely the walk must look for anything below it.
  const auto bound = [&] { return best ? std::min(best->least, o.reach) : o.reach; };
  const auto accuracy = [&](double least) { return std::max(o.tolerance, 0.05 * (least - o.threshold)); };
  double s = from;
  for (;;) {
    const Eigen::AlignedBox3d box(moverBox.min() + s * out, moverBox.max() + s * out);
    double d = box.exteriorDistance(otherBox);
    if (d - bound() < accuracy(bound())) {
      Eigen::Isometry3d pose = home;
      pose.pretranslate(s * out);
      cw.setPose(a, pose);
      if (hint) hint->onA += (s - hintAt) * out;
      const collision::CollisionWorld::Nearest n = cw.nearest(a, b, hint ? &*hint : nullptr);
      if (!std::isfinite(n.distance)) return std::nullopt;
      if (n.distance < o.reach && (!best || n.distance < best->least)) best = WayObject{other, n.distance, s, n.onA, n.onB};
      if (n.distance > 0.0) hint = n;
      else hint.reset();
      hintAt = s;
      d = n.distance;
    }
    if (s >= end) break;
    s = std::min(end, s + std::max(d - bound(), accuracy(bound())));
  }
  return best;
}

// Products repeat their parts: a walk is decided by the two shapes and their case (case_key.hpp), so each
// case is walked once and its answer, in the mover's frame, reused, as the order search does with its sweeps.
class Walks {
 public:
  Walks(collision::CollisionWorld& cw, const Assembly& a, const std::vector<Eigen::Isometry3d>& home, const WayClearanceOptions& o)
      : cw_(cw), a_(a), home_(home), o_(o) {}

  struct Pass {
    bool seat = false;               // touching at home
    std::optional<WayObject> least;  // within reach along the way (for a seat, from the threshold out)
  };

  Pass pass(PartId mover, PartId other, const Eigen::Vector3d& out, double length) {
    const Eigen::Isometry3d& h = home_[mover];
    const Key key = keyOf(mover, other, out, length);
    if (const auto it = done_.find(key); it != done_.end()) {
      Pass p = it->second;  // in the mover's home frame
      if (p.least) {
        p.least->part = other;
        p.least->onPart = h * p.least->onPart;
        p.least->onOther = h * p.least->onOther;
      }
      return p;
    }
    const ObjectId a = ObjectId::part(mover), b = ObjectId::part(other);
    cw_.setPose(a, h);
    Pass p;
    p.seat = cw_.distance(a, b) <= cw_.tolerances().distance;
    const double from = std::min(p.seat ? o_.threshold + o_.tolerance : 0.0, length);
    // Once the mover's box has passed the other's along the way, every distance only grows.
    const double end = std::clamp(extentAlong(cw_.worldBounds(b), out).second - extentAlong(cw_.worldBounds(a, h), out).first, from, length);
    p.least = leastAlong(cw_, mover, other, h, out, from, end, o_);
    cw_.setPose(a, h);
    Pass local = p;
    if (local.least) {
      local.least->onPart = h.inverse() * local.least->onPart;
      local.least->onOther = h.inverse() * local.least->onOther;
    }
    done_.emplace(key, local);
    return p;
  }

 private:
  struct Key {
    const void* mover;
    const void* other;
    detail::CaseGeometry geometry;
    auto operator<=>(const Key&) const = default;
  };

  [[nodiscard]] Key keyOf(PartId mover, PartId other, const Eigen::Vector3d& out, double length) const {
    return Key{a_.parts[mover].mesh.get(), a_.parts[other].mesh.get(), detail::caseGeometry(home_[mover], home_[other], out, length)};
  }

  collision::CollisionWorld& cw_;
  const Assembly& a_;
  const std::vector<Eigen::Isometry3d>& home_;
  const WayClearanceOptions& o_;
  std::map<Key, Pass> done_;
};

}  // namespace

std::vector<WayClearance> wayClearances(const Assembly& assembly, const SequencePlan& plan, const WayClearanceOptions& options,
                                        const ProgressFn& progress) {
  const std::string file = assembly.source.string();
  const auto length = [&](const char* field, double v, bool positive) {
    if (!std::isfinite(v) || v < 0.0 || (positive && v == 0.0))
      fail(file, field, positive ? "a finite length above 0" : "a finite length of 0 or more", std::to_string(v));
  };
  length("threshold", options.threshold, false);
  length("reach", options.reach, false);
  length("tolerance", options.tolerance, true);
  length("voxel", options.voxel, false);

  const std::vector<Eigen::Isometry3d> home = homePoses(assembly);
  Assembly together = assembly;
  for (PartId p = 0; p < together.parts.size(); ++p) together.parts[p].pose = home[p];
  collision::CollisionWorld cw(together);
  Walks walks(cw, assembly, home, options);

  std::vector<WayClearance> ways;
  std::vector<bool> in(assembly.parts.size(), false);
  for (std::size_t i = 0; i < plan.order.size(); ++i) {
    const PartId p = plan.order[i];
    const int k = plan.way[i];
    const PartCheck* check = plan.checkOf(p);
    if (k < 0 || check == nullptr || (options.only && p != *options.only)) {  // the base, or a way not asked for
      in[p] = true;
      continue;
    }
    if (progress && !progress(static_cast<double>(i) / static_cast<double>(plan.order.size()), "clearance of the way home: " + assembly.parts[p].name))
      throw LoadCancelled();
    const Direction& d = check->directions[static_cast<std::size_t>(k)];
    WayClearance w;
    w.part = p;
    w.way = k;
    w.out = d.out;
    w.length = d.length;
    const ObjectId mover = ObjectId::part(p);
    Eigen::AlignedBox3d box = cw.worldBounds(mover, home[p]);
    box.extend(box.min() + d.length * d.out).extend(box.max() + d.length * d.out);
    box.min().array() -= options.reach;
    box.max().array() += options.reach;
    // The partners of its inserts whose axis is this way.
    for (const Constraint& c : assembly.constraints) {
      if (c.part != p || c.type != Constraint::Type::Insert) continue;
      const PartId partner = c.partner ? *c.partner : *assembly.base;
      if (std::abs((home[partner].linear() * c.homeDirection).normalized().dot(d.out)) > 1.0 - 1e-9 && in[partner])
        w.guides.push_back(partner);
    }
    std::sort(w.guides.begin(), w.guides.end());
    w.guides.erase(std::unique(w.guides.begin(), w.guides.end()), w.guides.end());
    for (const ObjectId& o : cw.near(box, mover)) {
      if (o.kind != ObjectId::Kind::Part || !in[o.index] || std::binary_search(w.guides.begin(), w.guides.end(), o.index)) continue;
      const Walks::Pass pass = walks.pass(p, o.index, d.out, d.length);
      if (pass.seat) w.seatedOn.push_back(o.index);
      if (pass.least && (!pass.seat || pass.least->least < options.threshold)) w.objects.push_back(*pass.least);
    }
    std::sort(w.seatedOn.begin(), w.seatedOn.end());
    std::sort(w.objects.begin(), w.objects.end(), [](const WayObject& x, const WayObject& y) {
      return x.least != y.least ? x.least < y.least : x.part < y.part;
    });
    if (options.voxel > 0.0) {
      Eigen::Isometry3d start = home[p];
      start.pretranslate(d.length * d.out);
      try {
        w.swept = sweep(*assembly.parts[p].mesh, {{start, home[p]}}, options.voxel, kMaxSweepVoxels, sim::tessellationSag(assembly.parts[p]));
        w.swept->mesh = TriMesh();
      } catch (const std::invalid_argument& e) {
        fail(file, "voxel", "a grid vaw can hold for " + assembly.parts[p].name + "'s way home", e.what());
      }
    }
    ways.push_back(std::move(w));
    in[p] = true;
  }
  return ways;
}

}  // namespace vaw::eval
