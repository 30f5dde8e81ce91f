#include "vaw/evaluation/way_clearance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "vaw/collision/collision_world.hpp"
#include "vaw/error.hpp"

namespace vaw::eval {

namespace {

using collision::ObjectId;

// The least distance from `mover` to `other` over the way, the mover at home + s * out for s in [0, length]:
// distance is 1-Lipschitz in s (no point moves farther than s changes), so from a point at distance d
// nothing within d - b of it can be nearer than b. Stepping by that much (and at least `tolerance`) with b
// the least found so far (capped at `reach`) misses no value below it by more than `tolerance`. Parallel
// runs near the least step by `tolerance`; far-off parts take a few long steps.
std::optional<WayObject> leastAlong(collision::CollisionWorld& cw, PartId mover, PartId other, const Eigen::Isometry3d& home,
                                    const Eigen::Vector3d& out, double from, double length, const WayClearanceOptions& o) {
  const ObjectId a = ObjectId::part(mover), b = ObjectId::part(other);
  std::optional<WayObject> best;
  // The last nearest points, the mover's carried along with it: they bound the next search.
  std::optional<collision::CollisionWorld::Nearest> hint;
  double s = std::min(from, length);
  for (;;) {
    Eigen::Isometry3d pose = home;
    pose.pretranslate(s * out);
    cw.setPose(a, pose);
    const collision::CollisionWorld::Nearest n = cw.nearest(a, b, hint ? &*hint : nullptr);
    if (!std::isfinite(n.distance)) return std::nullopt;
    if (n.distance < o.reach && (!best || n.distance < best->least)) best = WayObject{other, n.distance, s, n.onA, n.onB};
    if (s >= length) break;
    const double bound = best ? std::min(best->least, o.reach) : o.reach;
    const double next = std::min(length, s + std::max(n.distance - bound, o.tolerance));
    if (n.distance > 0.0) hint = collision::CollisionWorld::Nearest{n.distance, n.onA + (next - s) * out, n.onB};
    else hint.reset();
    s = next;
  }
  return best;
}

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
  const double touching = cw.tolerances().distance;

  std::vector<WayClearance> ways;
  std::vector<bool> in(assembly.parts.size(), false);
  for (std::size_t i = 0; i < plan.order.size(); ++i) {
    const PartId p = plan.order[i];
    const int k = plan.way[i];
    const PartCheck* check = plan.checkOf(p);
    if (k < 0 || check == nullptr) {  // the base
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
      cw.setPose(mover, home[p]);
      const bool seat = cw.distance(mover, ObjectId::part(o.index)) <= touching;
      if (seat) w.seatedOn.push_back(o.index);
      auto least = leastAlong(cw, p, o.index, home[p], d.out, seat ? options.threshold + options.tolerance : 0.0, d.length, options);
      if (least && (!seat || least->least < options.threshold)) w.objects.push_back(*least);
    }
    cw.setPose(mover, home[p]);
    std::sort(w.seatedOn.begin(), w.seatedOn.end());
    std::sort(w.objects.begin(), w.objects.end(), [](const WayObject& x, const WayObject& y) {
      return x.least != y.least ? x.least < y.least : x.part < y.part;
    });
    if (options.voxel > 0.0) {
      Eigen::Isometry3d start = home[p];
      start.pretranslate(d.length * d.out);
      try {
        w.swept = sim::sweep(*assembly.parts[p].mesh, {{start, home[p]}}, options.voxel);
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
