#include "vaw/evaluation/sequence.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <compare>
#include <cstdint>
#include <cstdio>
#include <map>
#include <mutex>
#include <optional>
#include <set>

#include "vaw/collision/collision_world.hpp"
#include "vaw/collision/interference.hpp"
#include "vaw/collision/time_of_impact.hpp"
#include "../base/on_cores.hpp"
#include "case_key.hpp"

namespace vaw::eval {

namespace {

using collision::ObjectId;

// A part held within this of home in every way by what it wraps (m).
constexpr double kWrapReach = 1e-3;

// A closed surface with a hole through it (genus one or more: a belt, a ring, a spring), from its Euler
// characteristic V - E + F = 2 - 2 g per connected piece, on the welded mesh.
bool ring(const TriMesh& mesh) {
  std::set<std::pair<int, int>> edges;
  std::set<int> used;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      edges.emplace(std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3]));
      used.insert(t[k]);
    }
  const auto chi = static_cast<long>(used.size()) - static_cast<long>(edges.size()) + static_cast<long>(mesh.triangles.size());
  return chi <= 0;
}

std::vector<Direction> directionsOf(const Assembly& a, PartId p, const std::vector<Eigen::Isometry3d>& home) {
  std::vector<Direction> dirs;
  auto add = [&](Eigen::Vector3d out, std::string from, std::optional<std::size_t> constraint, bool axis) {
    out.normalize();
    for (auto& d : dirs)
      if (d.out.dot(out) > 1.0 - 1e-9) {
        d.alongAxis = d.alongAxis || axis;
        return;
      }
    dirs.push_back({out, std::move(from), constraint, axis, {}});
  };
  struct Insert {
    Eigen::Vector3d out;
    std::string from;
    std::size_t constraint;
  };
  std::vector<Insert> otherEnds;
  for (std::size_t i = 0; i < a.constraints.size(); ++i) {
    const Constraint& c = a.constraints[i];
    if (c.part != p) continue;
    const PartId partner = c.partner ? *c.partner : *a.base;
    const Eigen::Vector3d out = home[partner].linear() * c.homeDirection;
    const std::string from = std::string(name(c.type)) + " on " + a.parts[partner].name;
    add(out, from, i, c.type == Constraint::Type::Insert);
    if (c.type == Constraint::Type::Insert) otherEnds.push_back({-out, from + " (other end)", i});
  }
  for (const Insert& e : otherEnds) add(e.out, e.from, e.constraint, true);
  if (dirs.empty()) {
    const std::pair<Eigen::Vector3d, const char*> axes[] = {{Eigen::Vector3d::UnitZ(), "world +z"}, {-Eigen::Vector3d::UnitZ(), "world -z"},
                                                            {Eigen::Vector3d::UnitX(), "world +x"}, {-Eigen::Vector3d::UnitX(), "world -x"},
                                                            {Eigen::Vector3d::UnitY(), "world +y"}, {-Eigen::Vector3d::UnitY(), "world -y"}};
    for (const auto& [v, label] : axes) add(v, label, std::nullopt, false);
  }
  return dirs;
}

// Where `mover` (at home[mover]) moving out along `out` first meets `obstacle`, if anywhere before it has
// passed it; the block's distance, or flagged undecided. `whole`: the span to check at most.
//
// Products repeat their parts (every bolt of a kind in every bracket of a kind, every copy of a
// sub-assembly): a check is decided by the two shapes, where one stands relative to the other, the way out
// in the mover's frame and the length swept, so each such case is swept once and its answer reused
// (rounded to a nanometre, far below the check's own tolerance).
struct PairChecks {
  PairChecks(const Assembly& a, const collision::CollisionWorld& w, const std::vector<Eigen::Isometry3d>& h, const SequenceOptions& options)
      : assembly(a), world(w), home(h) {
    toi.tolerance = options.tolerance;
    toi.maxStep = options.maxStep;
  }

  const Assembly& assembly;
  const collision::CollisionWorld& world;
  const std::vector<Eigen::Isometry3d>& home;
  collision::ToiOptions toi;
  // Sweeps may run on several threads at once (onCores): the counts and the cases decided are shared.
  std::atomic<int> runs = 0, evaluations = 0, undecided = 0, reused = 0;

  struct Case {
    const void* moverShape;
    const void* obstacleShape;
    bool alongAxis;
    detail::CaseGeometry geometry;
    auto operator<=>(const Case&) const = default;
  };
  std::map<Case, std::optional<double>> decided;  // the block's distance (none: free); undecided not kept
  std::map<Case, collision::MotionEvent> ahead;    // by runAhead, not yet taken by block()
  std::mutex deciding;                             // guards `decided` and `ahead`

  // How far a check of `mover` past `obstacle` goes, and its case; none when it cannot block. Only as far as
  // the obstacle can be met: until the trailing side passes its leading side. An obstacle no farther ahead
  // than the tolerance is behind the mover: at most touching it (a nut under the plate it is screwed
  // against, moved down), it cannot block, and the check of such a pair in contact was among the costliest
  // there are (a third of a thousand-part product's order).
  struct Planned {
    double length;
    std::optional<Case> key;
  };
  [[nodiscard]] std::optional<Planned> plan(PartId mover, PartId obstacle, const Eigen::Vector3d& out, bool alongAxis, double whole) const {
    const Eigen::AlignedBox3d box = world.worldBounds(ObjectId::part(mover));
    const double gap = extentAlong(world.worldBounds(ObjectId::part(obstacle)), out).second - extentAlong(box, out).first;
    if (gap <= toi.tolerance) return std::nullopt;
    const double length = std::min(gap + 2.0 * toi.tolerance, whole);
    return Planned{length, caseOf(mover, obstacle, out, alongAxis, length)};
  }

  [[nodiscard]] collision::MotionEvent run(PartId mover, PartId obstacle, const Eigen::Vector3d& out, bool alongAxis, double length) const {
    return collision::firstBlockBy(world, ObjectId::part(mover), ObjectId::part(obstacle), collision::translation(home[mover], out, length),
                                   alongAxis ? collision::FilterMode::SkipCoaxial : collision::FilterMode::SkipCoplanar, toi);
  }

  std::optional<Blocker> block(PartId mover, PartId obstacle, const Eigen::Vector3d& out, bool alongAxis, double whole) {
    const std::optional<Planned> planned = plan(mover, obstacle, out, alongAxis, whole);
    if (!planned) return std::nullopt;
    const std::optional<Case>& key = planned->key;
    std::optional<collision::MotionEvent> done;
    if (key) {
      const std::lock_guard<std::mutex> lock(deciding);
      if (const auto it = decided.find(*key); it != decided.end()) {
        ++reused;
        if (!it->second) return std::nullopt;
        return Blocker{obstacle, *it->second, false};
      }
      if (const auto it = ahead.find(*key); it != ahead.end()) {
        done = it->second;
        ahead.erase(it);
      }
    }
    const collision::MotionEvent ev = done ? *done : run(mover, obstacle, out, alongAxis, planned->length);
    ++runs;
    evaluations += ev.evaluations;
    if (ev.undecided) {
      ++undecided;
      return Blocker{obstacle, ev.s, true};
    }
    const std::optional<double> distance =
        ev.kind != collision::EventKind::Blocked ? std::nullopt : std::optional<double>(ev.initiallyBlocked ? 0.0 : ev.s);
    if (key) {
      const std::lock_guard<std::mutex> lock(deciding);
      decided.emplace(*key, distance);
    }
    if (!distance) return std::nullopt;
    return Blocker{obstacle, *distance, false};
  }

  // Sweeps, on every core, the cases of the calls of block() that are to come in this order, each the way
  // its first call would; those calls then take the results as if they had swept, so the answers and the
  // counts are the same whatever the cores. `report` (the share done; false: stop) is called on the
  // caller's thread.
  struct Call {
    PartId mover, obstacle;
    Eigen::Vector3d out;
    bool alongAxis;
    double whole;
  };
  void runAhead(const std::vector<Call>& calls, const std::function<bool(double)>& report) {
    std::vector<std::pair<const Call*, Planned>> pending;
    std::set<Case> met;
    for (const Call& c : calls)
      if (auto planned = plan(c.mover, c.obstacle, c.out, c.alongAxis, c.whole);
          planned && planned->key && !decided.count(*planned->key) && !ahead.count(*planned->key) && met.insert(*planned->key).second)
        pending.emplace_back(&c, std::move(*planned));
    std::vector<collision::MotionEvent> events(pending.size());
    vaw::detail::onCores(pending.size(), [&](std::size_t k, bool onCaller) {
      if (onCaller && report && !report(static_cast<double>(k) / static_cast<double>(pending.size()))) throw LoadCancelled();
      const Call& c = *pending[k].first;
      events[k] = run(c.mover, c.obstacle, c.out, c.alongAxis, pending[k].second.length);
    });
    for (std::size_t k = 0; k < pending.size(); ++k) ahead.emplace(*pending[k].second.key, events[k]);
  }

  // None for parts without a shape of their own (none in a loaded assembly): those are always swept.
  [[nodiscard]] std::optional<Case> caseOf(PartId mover, PartId obstacle, const Eigen::Vector3d& out, bool alongAxis, double length) const {
    const Part& m = assembly.parts[mover];
    const Part& o = assembly.parts[obstacle];
    if (!m.mesh || !o.mesh) return std::nullopt;
    return Case{m.mesh.get(), o.mesh.get(), alongAxis, detail::caseGeometry(home[mover], home[obstacle], out, length)};
  }
};

}  // namespace

std::vector<std::pair<PartId, PartId>> geometricPrecedence(const Assembly& assembly, const std::vector<Eigen::Isometry3d>& home,
                                                           const SequenceOptions& options, int* pairChecks, const PairProgress& progress) {
  std::vector<std::pair<PartId, PartId>> out;
  if (!assembly.base || home.size() != assembly.parts.size()) return out;
  const PartId base = *assembly.base;
  const std::size_t n = assembly.parts.size();
  // Every way out a part has from the constraints it is in, on either side.
  struct Way {
    Eigen::Vector3d out;
    bool axis;
  };
  std::vector<std::vector<Way>> ways(n);
  auto add = [&](PartId p, Eigen::Vector3d d, bool axis) {
    d.normalize();
    for (Way& w : ways[p])
      if (w.out.dot(d) > 1.0 - 1e-9) {
        w.axis = w.axis || axis;
        return;
      }
    ways[p].push_back({d, axis});
  };
  for (const Constraint& c : assembly.constraints) {
    const PartId partner = c.partner.value_or(base);
    if (c.part >= n || partner >= n || c.part == partner) continue;
    const Eigen::Vector3d d = home[partner].linear() * c.homeDirection;
    const bool axis = c.type == Constraint::Type::Insert;
    add(c.part, d, axis);
    if (partner != base) add(partner, -d, axis);
    if (axis) {
      add(c.part, -d, true);
      if (partner != base) add(partner, d, true);
    }
  }
  if (std::none_of(assembly.constraints.begin(), assembly.constraints.end(),
                   [&](const Constraint& c) { return c.partner && *c.partner != base; }))
    return out;

  Assembly together = assembly;
  for (PartId p = 0; p < n; ++p) together.parts[p].pose = home[p];
  const collision::CollisionWorld world(together);
  Eigen::AlignedBox3d all;
  for (PartId p = 0; p < n; ++p) all.extend(world.worldBounds(ObjectId::part(p)));
  PairChecks checks(assembly, world, home, options);
  const auto whole = [&](PartId p, const Eigen::Vector3d& d) {
    return extentAlong(all, d).second - extentAlong(world.worldBounds(ObjectId::part(p)), d).first + 2.0 * options.tolerance;
  };
  // Per part and way: does the base block it (-1 not swept yet); swept only when it decides something.
  std::vector<std::vector<int>> baseBlocks(n);
  std::mutex baseLock;  // the pairs are checked on several cores
  const auto blockedByBase = [&](PartId p, std::size_t k) {
    {
      const std::lock_guard<std::mutex> lock(baseLock);
      if (baseBlocks[p].empty()) baseBlocks[p].assign(ways[p].size(), -1);
      if (baseBlocks[p][k] >= 0) return baseBlocks[p][k] == 1;
    }
    const bool b = checks.block(p, base, ways[p][k].out, ways[p][k].axis, whole(p, ways[p][k].out)).has_value();
    const std::lock_guard<std::mutex> lock(baseLock);
    baseBlocks[p][k] = b ? 1 : 0;
    return b;
  };
  // True when every way `p` has past the base is blocked by `q` in place (every way at all, when the base
  // blocks them all): p must come before q. The short checks against q come first; the base's only where
  // they leave the answer open.
  const auto needsAbsent = [&](PartId p, PartId q) {
    if (ways[p].empty()) return false;
    std::vector<std::size_t> byQ;
    for (std::size_t k = 0; k < ways[p].size(); ++k) {
      if (checks.block(p, q, ways[p][k].out, ways[p][k].axis, whole(p, ways[p][k].out))) byQ.push_back(k);
      else if (!blockedByBase(p, k)) return false;  // a way out past both
    }
    if (byQ.size() == ways[p].size()) return true;
    // Some ways only the base blocks: q decides only if one of its ways is not the base's too.
    return std::any_of(byQ.begin(), byQ.end(), [&](std::size_t k) { return !blockedByBase(p, k); });
  };
  // Only where the geometry says otherwise than the partner the constraints already name: the part that
  // needs its partner absent, while the partner does not need it absent, goes first.
  std::set<std::pair<PartId, PartId>> checked;
  std::vector<std::pair<std::size_t, std::pair<PartId, PartId>>> pairs;  // with the constraint naming it
  for (std::size_t k = 0; k < assembly.constraints.size(); ++k) {
    const Constraint& c = assembly.constraints[k];
    const PartId partner = c.partner.value_or(base);
    if (partner == base || c.part >= n || partner >= n || c.part == partner) continue;
    if (checked.emplace(std::min(c.part, partner), std::max(c.part, partner)).second) pairs.push_back({k, {c.part, partner}});
  }
  std::vector<char> first(pairs.size(), 0);
  vaw::detail::onCores(pairs.size(), [&](std::size_t i, bool onCaller) {
    const auto [k, pq] = pairs[i];
    if (onCaller && progress &&
        !progress(static_cast<double>(k) / static_cast<double>(assembly.constraints.size()), pq.first, pq.second))
      throw LoadCancelled();
    first[i] = needsAbsent(pq.first, pq.second) && !needsAbsent(pq.second, pq.first);
  });
  for (std::size_t i = 0; i < pairs.size(); ++i)
    if (first[i]) out.push_back(pairs[i].second);
  if (pairChecks) *pairChecks = checks.runs;
  return out;
}

std::string travelText(const Eigen::Vector3d& out) {
  const Eigen::Vector3d in = -out;
  const char* axes[] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    if (std::abs(std::abs(in[i]) - 1.0) < 1e-6) {
      if (i == 2) return in[i] < 0 ? "down" : "up";
      return std::string(in[i] < 0 ? "along -" : "along +") + axes[i];
    }
  char buf[80];
  std::snprintf(buf, sizeof buf, "along (%.3f, %.3f, %.3f)", in.x(), in.y(), in.z());
  return buf;
}

const PartCheck* SequencePlan::checkOf(PartId p) const {
  for (const auto& c : checks)
    if (c.part == p) return &c;
  return nullptr;
}

const Direction* SequencePlan::wayOf(PartId p) const {
  const auto it = std::find(order.begin(), order.end(), p);
  if (it == order.end()) return nullptr;
  const int k = way[static_cast<std::size_t>(it - order.begin())];
  const PartCheck* c = checkOf(p);
  return c && k >= 0 ? &c->directions[static_cast<std::size_t>(k)] : nullptr;
}

const SequencePlan::Wrap* SequencePlan::wrapOf(PartId p) const {
  for (const Wrap& w : wraps)
    if (w.part == p) return &w;
  return nullptr;
}

const SequencePlan::SubAssembly* SequencePlan::subAssemblyOf(PartId p) const {
  const auto it = std::find(order.begin(), order.end(), p);
  if (it == order.end()) return nullptr;
  const std::size_t i = static_cast<std::size_t>(it - order.begin());
  return i < subAssembly.size() && subAssembly[i] >= 0 ? &subAssemblies[static_cast<std::size_t>(subAssembly[i])] : nullptr;
}

std::pair<double, double> extentAlong(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& direction) {
  const double c = box.center().dot(direction);
  const double r = (0.5 * box.sizes()).dot(direction.cwiseAbs());
  return {c - r, c + r};
}

std::vector<Eigen::Isometry3d> homePoses(const Assembly& assembly) {
  std::vector<Eigen::Isometry3d> home(assembly.parts.size());
  for (PartId p = 0; p < assembly.parts.size(); ++p) {
    const Part& part = assembly.parts[p];
    home[p] = (assembly.base && p == *assembly.base) || !part.finalPose ? part.pose : *part.finalPose;
  }
  return home;
}

SequencePlan planSequence(const Assembly& assembly, const SequenceOptions& options, const ProgressFn& progress) {
  if (!assembly.base) fail(assembly.source.string(), "base", "an assembly with a base part (the sequence starts from it)", "none");
  // The assembly put together: every part at its final pose (the base where it stands).
  Assembly together = assembly;
  const std::vector<Eigen::Isometry3d> home = homePoses(assembly);
  for (PartId p = 0; p < assembly.parts.size(); ++p) together.parts[p].pose = home[p];
  return planSequence(assembly, collision::CollisionWorld(together), options, progress);
}

SequencePlan planSequence(const Assembly& assembly, const collision::CollisionWorld& world, const SequenceOptions& options,
                          const ProgressFn& progress) {
  if (!assembly.base) fail(assembly.source.string(), "base", "an assembly with a base part (the sequence starts from it)", "none");
  SequencePlan plan;
  plan.base = assembly.base;
  const PartId base = *assembly.base;
  const std::size_t n = assembly.parts.size();
  const std::vector<Eigen::Isometry3d> home = homePoses(assembly);
  std::vector<bool> inSequence(n, false);
  for (PartId p = 0; p < n; ++p) {
    inSequence[p] = p == base || assembly.parts[p].finalPose.has_value();
    if (!inSequence[p]) plan.skipped.push_back(p);
  }
  Eigen::AlignedBox3d all;
  for (PartId p = 0; p < n; ++p)
    if (inSequence[p]) all.extend(world.worldBounds(ObjectId::part(p)));

  PairChecks checks(assembly, world, home, options);
  // Two parts that share volume at home beyond a designed fit (a modelling error: a dowel drawn larger than
  // its hole) would each block the other at once in every way. Each comes home through the other along the
  // ways its constraints give it, and the way says so. Asked only of a pair blocked where it stands (a
  // check's distance 0): parts that only touch there are blocked a tolerance on, if at all.
  std::map<std::pair<PartId, PartId>, bool> clashing;
  const auto clash = [&](PartId p, PartId q) {
    const auto key = std::minmax(p, q);
    const auto it = clashing.find(key);
    if (it != clashing.end()) return it->second;
    const auto overlap = collision::overlapAtRest(world, assembly, p, q);
    return clashing[key] = overlap && overlap->kind == collision::Interference::Kind::Clash;
  };
  // Out until the part's trailing side has passed the assembly's leading side.
  const auto wayLength = [&](const Eigen::AlignedBox3d& box, const Eigen::Vector3d& out) {
    return extentAlong(all, out).second - extentAlong(box, out).first + 2.0 * options.tolerance;
  };
  // Every part's ways, each with the parts whose boxes its way out reaches (until its trailing side has
  // passed the assembly's leading side); those pairs swept ahead on every core, then each way's blockers
  // read in order.
  std::vector<std::vector<std::vector<PartId>>> met;  // per check, per way
  std::vector<PairChecks::Call> calls;
  for (PartId p = 0; p < n; ++p) {
    if (p == base || !inSequence[p]) continue;
    PartCheck check;
    check.part = p;
    check.directions = directionsOf(assembly, p, home);
    const Eigen::AlignedBox3d box = world.worldBounds(ObjectId::part(p));
    auto& onWays = met.emplace_back();
    for (Direction& d : check.directions) {
      d.length = wayLength(box, d.out);
      Eigen::AlignedBox3d swept = box;
      swept.extend(box.min() + d.length * d.out).extend(box.max() + d.length * d.out);
      auto& on = onWays.emplace_back();
      for (const ObjectId& o : world.near(swept, ObjectId::part(p)))
        if (o.kind == ObjectId::Kind::Part && inSequence[o.index]) {
          on.push_back(o.index);
          calls.push_back({p, o.index, d.out, d.alongAxis, d.length});
        }
    }
    plan.checks.push_back(std::move(check));
  }
  const std::string stage = "ways home: " + std::to_string(calls.size()) + " ways past the parts on them";
  checks.runAhead(calls, [&](double f) { return !progress || progress(0.9 * f, stage); });
  for (std::size_t i = 0; i < plan.checks.size(); ++i) {
    PartCheck& check = plan.checks[i];
    if (progress && !progress(0.9 + 0.1 * static_cast<double>(i) / static_cast<double>(plan.checks.size()),
                              "ways home: " + assembly.parts[check.part].name))
      throw LoadCancelled();
    for (std::size_t k = 0; k < check.directions.size(); ++k) {
      Direction& d = check.directions[k];
      for (const PartId o : met[i][k])
        if (const auto b = checks.block(check.part, o, d.out, d.alongAxis, d.length)) d.blockers.push_back(*b);
    }
  }
  // The pairs blocked where they stand along a constraint's way are asked whether they clash, on every core;
  // a way goes through its clashes.
  const auto throughClash = [&](const Direction& d, const Blocker& b) {
    return options.throughClashes && d.constraint && !b.undecided && b.distance <= 0.0;
  };
  {
    std::set<std::pair<PartId, PartId>> asked;
    for (const PartCheck& c : plan.checks)
      for (const Direction& d : c.directions)
        for (const Blocker& b : d.blockers)
          if (throughClash(d, b)) asked.insert(std::minmax(c.part, b.by));
    const std::vector<std::pair<PartId, PartId>> pairs(asked.begin(), asked.end());
    std::vector<char> clashes(pairs.size(), 0);
    vaw::detail::onCores(pairs.size(), [&](std::size_t k, bool) {
      const auto overlap = collision::overlapAtRest(world, assembly, pairs[k].first, pairs[k].second);
      clashes[k] = overlap && overlap->kind == collision::Interference::Kind::Clash;
    });
    for (std::size_t k = 0; k < pairs.size(); ++k) clashing[pairs[k]] = clashes[k] != 0;
  }
  for (PartCheck& c : plan.checks)
    for (Direction& d : c.directions) {
      std::string through;
      std::vector<Blocker> kept;
      for (const Blocker& b : d.blockers) {
        if (throughClash(d, b) && clash(c.part, b.by)) {
          through += (through.empty() ? "" : ", ") + assembly.parts[b.by].name;
          continue;
        }
        kept.push_back(b);
      }
      d.blockers = std::move(kept);
      if (!through.empty()) d.from += " (through its clash with " + through + ")";
      std::sort(d.blockers.begin(), d.blockers.end(),
                [](const Blocker& x, const Blocker& y) { return x.distance != y.distance ? x.distance < y.distance : x.by < y.by; });
    }
  plan.pairChecks = checks.runs;
  plan.reused = checks.reused;
  plan.evaluations = checks.evaluations;
  plan.undecided = checks.undecided;

  // Partners: every part a part is constrained to must be in place before it.
  std::vector<std::set<PartId>> partners(n);
  for (const Constraint& c : assembly.constraints)
    if (c.partner && *c.partner != c.part && inSequence[c.part] && inSequence[*c.partner]) partners[c.part].insert(*c.partner);

  // Assembly by disassembly, round by round.
  std::vector<bool> in = inSequence;
  auto freeWay = [&](const PartCheck& c) {
    for (std::size_t k = 0; k < c.directions.size(); ++k) {
      const auto& bs = c.directions[k].blockers;
      if (std::none_of(bs.begin(), bs.end(), [&](const Blocker& b) { return in[b.by]; })) return static_cast<int>(k);
    }
    return -1;
  };
  auto heldByAnother = [&](PartId p) {
    for (PartId r = 0; r < n; ++r)
      if (r != p && in[r] && partners[r].count(p)) return true;
    return false;
  };
  struct Out {
    PartId part;
    int way;
    int round;
    int group = -1;  // index into plan.subAssemblies
  };
  std::vector<Out> removed;
  std::vector<bool> stuck(n, false);
  // The smallest set of parts still in that comes out along one of a part's ways: the part, what it meets on
  // the way, what those meet, and so on, and every part constrained to one of them; none when the base is
  // among them. Returned in the order the set is put together (its first the part whose way it is, with that
  // way's index; the others -1), found by the same disassembly within the set.
  // A sub-assembly is carried whole: its parts hold together by their constraints (not a part that only
  // lies in another's way).
  const auto connected = [&](const std::vector<PartId>& group) {
    std::vector<PartId> reached{group.front()};
    for (std::size_t i = 0; i < reached.size(); ++i)
      for (const Constraint& c : assembly.constraints) {
        if (!c.partner) continue;
        const PartId x = reached[i], other = c.part == x ? *c.partner : *c.partner == x ? c.part : x;
        if (other != x && std::find(group.begin(), group.end(), other) != group.end() &&
            std::find(reached.begin(), reached.end(), other) == reached.end())
          reached.push_back(other);
      }
    return reached.size() == group.size();
  };
  const auto subAssemblyOut = [&]() -> std::vector<std::pair<PartId, int>> {
    std::vector<PartId> best;
    std::size_t bestWay = 0;
    for (const PartCheck& c : plan.checks) {
      if (!in[c.part]) continue;
      for (std::size_t k = 0; k < c.directions.size(); ++k) {
        const Eigen::Vector3d& out = c.directions[k].out;
        std::vector<PartId> group{c.part};
        std::vector<bool> member(n, false);
        member[c.part] = true;
        bool ok = true;
        for (std::size_t i = 0; i < group.size() && ok; ++i) {
          const PartId m = group[i];
          const Eigen::AlignedBox3d box = world.worldBounds(ObjectId::part(m));
          const double length = wayLength(box, out);
          Eigen::AlignedBox3d swept = box;
          swept.extend(box.min() + length * out).extend(box.max() + length * out);
          const auto join = [&](PartId o) {
            if (member[o]) return;
            member[o] = true;
            group.push_back(o);
          };
          for (const ObjectId& o : world.near(swept, ObjectId::part(m))) {
            if (o.kind != ObjectId::Kind::Part || !in[o.index] || member[o.index]) continue;
            // Along an axis: a bearing carried up its bore slides on it (touching faces across the way are
            // dropped either way).
            const auto b = checks.block(m, o.index, out, true, length);
            if (!b || (options.throughClashes && !b->undecided && b->distance <= 0.0 && clash(m, o.index))) continue;
            if (o.index == base || stuck[o.index]) ok = false;
            else join(o.index);
          }
          // A part still in whose partner leaves with the set would be left waiting for it: it comes too.
          for (PartId r = 0; r < n && ok; ++r)
            if (in[r] && !member[r] && partners[r].count(m)) join(r);
          ok = ok && (best.empty() || group.size() < best.size());
        }
        if (ok && group.size() >= 2 && connected(group)) {
          best = group;
          bestWay = k;
        }
      }
    }
    if (best.empty()) return {};
    // Put together on the bench: the set's own disassembly, reversed, from its first part.
    std::vector<std::pair<PartId, int>> order{{best.front(), static_cast<int>(bestWay)}};
    std::vector<bool> inSet(n, false);
    for (const PartId p : best) inSet[p] = true;
    std::vector<PartId> out;
    for (bool moved = true; moved;) {
      moved = false;
      for (const PartId p : best) {
        if (p == best.front() || !inSet[p]) continue;
        const PartCheck* c = plan.checkOf(p);
        const bool heldInSet = std::any_of(best.begin(), best.end(), [&](PartId r) { return r != p && inSet[r] && partners[r].count(p); });
        const bool free = c && std::any_of(c->directions.begin(), c->directions.end(), [&](const Direction& d) {
          return std::none_of(d.blockers.begin(), d.blockers.end(), [&](const Blocker& b) { return inSet[b.by]; });
        });
        if (!heldInSet && free) {
          inSet[p] = false;
          out.push_back(p);
          moved = true;
        }
      }
    }
    // What the set's own disassembly left in (held among themselves) goes after its first part as found.
    for (const PartId p : best)
      if (p != best.front() && inSet[p]) out.push_back(p);
    // Reversed: the disassembly's last out is the first put on the set's first part.
    for (auto it = out.rbegin(); it != out.rend(); ++it) order.emplace_back(*it, -1);
    return order;
  };
  for (int round = 0;; ++round) {
    std::vector<Out> now;
    for (const PartCheck& c : plan.checks) {
      if (!in[c.part] || heldByAnother(c.part)) continue;
      if (const int k = freeWay(c); k >= 0) now.push_back({c.part, k, round});
    }
    if (!now.empty()) {
      for (const Out& o : now) in[o.part] = false;
      removed.insert(removed.end(), now.begin(), now.end());
      continue;
    }
    // Nothing comes out alone: a sub-assembly may, the parts that only block each other along one way.
    if (auto group = subAssemblyOut(); !group.empty()) {
      const int index = static_cast<int>(plan.subAssemblies.size());
      plan.subAssemblies.push_back({{}, plan.checkOf(group.front().first)->directions[static_cast<std::size_t>(group.front().second)].out});
      for (const auto& [part, way] : group) {
        in[part] = false;
        removed.push_back({part, way, round, index});
      }
      continue;
    }
    // Nothing comes out. First the parts that something always there (the base, or a part already set
    // aside) blocks in every way: no order inserts them. Set aside, they no longer hold the rest in. Only
    // when there are none, the parts that block each other (interlocked) are set aside together.
    auto permanent = [&](PartId b) { return b == base || stuck[b]; };
    std::vector<PartId> blocked;
    for (const PartCheck& c : plan.checks)
      if (in[c.part] && std::all_of(c.directions.begin(), c.directions.end(), [&](const Direction& d) {
            return std::any_of(d.blockers.begin(), d.blockers.end(), [&](const Blocker& b) { return permanent(b.by); });
          }))
        blocked.push_back(c.part);
    if (blocked.empty())
      for (const PartCheck& c : plan.checks)
        if (in[c.part] && freeWay(c) < 0) blocked.push_back(c.part);
    if (blocked.empty()) {
      // Every part left has a way out but is held by another left: a loop of constraints.
      for (const PartCheck& c : plan.checks)
        if (in[c.part]) {
          Stuck s{c.part, {}, {}};
          for (PartId r = 0; r < n; ++r)
            if (r != c.part && in[r] && partners[r].count(c.part)) s.waitsFor.push_back(r);
          plan.stuck.push_back(std::move(s));
          stuck[c.part] = true;
        }
      break;
    }
    for (const PartId p : blocked) {
      Stuck s{p, {}, {}};
      for (const Direction& d : plan.checkOf(p)->directions) {
        std::vector<PartId> by;
        for (const Blocker& b : d.blockers)
          if (in[b.by]) by.push_back(b.by);
        s.blockers.push_back(std::move(by));
      }
      plan.stuck.push_back(std::move(s));
      stuck[p] = true;
    }
    for (const PartId p : blocked) in[p] = false;
    if (std::none_of(plan.checks.begin(), plan.checks.end(), [&](const PartCheck& c) { return in[c.part]; })) break;
  }
  // A part whose partner no order inserts cannot be placed either.
  for (bool changed = true; changed;) {
    changed = false;
    for (const Out& o : removed) {
      if (stuck[o.part]) continue;
      for (const PartId r : partners[o.part])
        if (stuck[r]) {
          plan.stuck.push_back({o.part, {}, {r}});
          stuck[o.part] = changed = true;
          break;
        }
    }
  }

  // Rings held in every way by what passes through them wrap it: fitted by hand after it, last.
  for (auto it = plan.stuck.begin(); it != plan.stuck.end();) {
    const PartId p = it->part;
    std::vector<PartId> wrapped;
    const PartCheck* c = plan.checkOf(p);
    if (it->waitsFor.empty() && c && ring(*assembly.parts[p].mesh))
      for (const Direction& d : c->directions)
        for (const Blocker& b : d.blockers)
          if (b.distance <= kWrapReach && b.by != p && std::find(wrapped.begin(), wrapped.end(), b.by) == wrapped.end()) wrapped.push_back(b.by);
    const bool heldInEveryWay = c && std::all_of(c->directions.begin(), c->directions.end(), [&](const Direction& d) {
      return std::any_of(d.blockers.begin(), d.blockers.end(), [&](const Blocker& b) { return b.distance <= kWrapReach; });
    });
    if (wrapped.empty() || !heldInEveryWay) {
      ++it;
      continue;
    }
    std::sort(wrapped.begin(), wrapped.end());
    plan.wraps.push_back({p, wrapped});
    stuck[p] = false;
    it = plan.stuck.erase(it);
  }

  plan.order.push_back(base);
  plan.way.push_back(-1);
  plan.step.push_back(0);
  plan.subAssembly.push_back(-1);
  const int rounds = removed.empty() ? 0 : removed.back().round + 1;
  for (int r = rounds - 1; r >= 0; --r)
    for (const Out& o : removed)
      if (o.round == r && !stuck[o.part]) {
        plan.order.push_back(o.part);
        plan.way.push_back(o.way);
        plan.step.push_back(rounds - r);
        plan.subAssembly.push_back(o.group);
        if (o.group >= 0) plan.subAssemblies[static_cast<std::size_t>(o.group)].parts.push_back(o.part);
      }

  for (const SequencePlan::Wrap& w : plan.wraps) {
    plan.order.push_back(w.part);
    plan.way.push_back(-1);
    plan.step.push_back(rounds + 1);
    plan.subAssembly.push_back(-1);
  }

  // What the order found rests on.
  auto addPrecedence = [&](PartId before, PartId after, Precedence::Reason why) {
    for (const auto& e : plan.precedence)
      if (e.before == before && e.after == after && e.reason == why) return;
    plan.precedence.push_back({before, after, why});
  };
  for (const SequencePlan::Wrap& w : plan.wraps)
    for (const PartId r : w.wraps)
      if (r != base) addPrecedence(r, w.part, Precedence::Reason::Blocks);
  for (std::size_t i = 1; i < plan.order.size(); ++i) {
    const PartId p = plan.order[i];
    for (const PartId r : partners[p])
      if (r != base) addPrecedence(r, p, Precedence::Reason::Partner);
    if (const Direction* w = plan.wayOf(p))
      for (const Blocker& b : w->blockers)
        if (b.by != base && !stuck[b.by]) addPrecedence(p, b.by, Precedence::Reason::Blocks);
  }
  if (progress && !progress(1.0, "done")) throw LoadCancelled();
  return plan;
}

}  // namespace vaw::eval
