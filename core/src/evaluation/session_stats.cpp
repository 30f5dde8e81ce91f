#include "vaw/evaluation/session_stats.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace vaw::eval {

using interact::Event;
using interact::PartState;

std::optional<double> PartSession::timeToPlace() const {
  if (!firstHandled_s || !placed_s) return std::nullopt;
  return *placed_s - *firstHandled_s;
}

std::string PartSession::holders() const {
  std::vector<std::string> hands;
  if (left) hands.emplace_back("left");
  if (right) hands.emplace_back("right");
  std::string s;
  if (!hands.empty()) s = hands.size() == 1 ? hands[0] + " hand" : "left and right hands";
  if (both) s += std::string(s.empty() ? "" : ", ") + "both together";
  if (hoist) s += std::string(s.empty() ? "" : ", ") + "hoist";
  return s;
}

const PartSession* SessionStats::find(PartId p) const {
  for (const auto& s : parts)
    if (s.part == p) return &s;
  return nullptr;
}

namespace {

Eigen::Vector3d centreOf(const sim::World& w, PartId p) { return w.part(p).pose * w.assembly().parts[p].mass.centerOfMass; }

}  // namespace

SessionObserver::SessionObserver(const sim::World& world) {
  const Assembly& a = world.assembly();
  for (PartId p = 0; p < a.parts.size(); ++p) {
    lastCentre_.push_back(centreOf(world, p));
    wasHeld_.push_back(world.part(p).holder != sim::Holder::None);
    PartSession s;
    s.part = p;
    s.name = a.parts[p].name;
    parts_.push_back(std::move(s));
  }
}

void SessionObserver::observe(const sim::World& world) {
  for (PartId p = 0; p < parts_.size(); ++p) {
    const sim::Holder h = world.part(p).holder;
    const bool held = h != sim::Holder::None;
    const Eigen::Vector3d c = centreOf(world, p);
    // Carried: the way the centre went while a hand or the hoist had it on both sides of the step.
    if (held && wasHeld_[p]) parts_[p].carried_m += (c - lastCentre_[p]).norm();
    PartSession& s = parts_[p];
    s.left = s.left || h == sim::Holder::Left;
    s.right = s.right || h == sim::Holder::Right;
    s.both = s.both || h == sim::Holder::Both;
    s.hoist = s.hoist || h == sim::Holder::Hoist;
    lastCentre_[p] = c;
    wasHeld_[p] = held;
  }
}

SessionStats SessionObserver::finish(const sim::World& world, std::string label) const {
  SessionStats out;
  out.label = std::move(label);
  out.duration_s = world.time();
  std::vector<PartSession> parts = parts_;
  for (const auto& t : world.transitions()) {
    PartSession& s = parts[t.part];
    if (t.event == Event::Grab || t.event == Event::ToolAttach) {
      (t.event == Event::Grab ? s.grabs : s.toolLifts) += 1;
      if (!s.firstHandled_s) s.firstHandled_s = t.t;
    }
    if (t.event == Event::Release || t.event == Event::ToolDetach) ++s.drops;
    if (t.event == Event::Blocked) s.blocked.push_back(t.cause);
    if (t.to == PartState::Placed) s.placed_s = t.t;
    else if (t.from == PartState::Placed) s.placed_s.reset();
  }
  for (const auto& r : world.refusals())
    parts[r.part].refusals.push_back(std::string(interact::name(r.event)) + ": " + r.reason);
  // Each part starts in the state its first transition leaves (or stays in the one it ends in).
  for (PartId p = 0; p < parts.size(); ++p) {
    double from = 0.0;
    std::optional<PartState> state;
    for (const auto& t : world.transitions()) {
      if (t.part != p) continue;
      if (!state) state = t.from;
      if (t.t > from) out.spans.push_back({p, from, t.t, *state});
      from = t.t;
      state = t.to;
    }
    if (!state) state = world.part(p).state;
    if (out.duration_s > from) out.spans.push_back({p, from, out.duration_s, *state});
  }
  const auto base = world.assembly().base;
  for (auto& s : parts) {
    if (base && s.part == *base) continue;
    if (world.part(s.part).state != PartState::Placed) s.placed_s.reset();
    out.grabs += s.grabs;
    out.toolLifts += s.toolLifts;
    out.drops += s.drops;
    out.refusals += static_cast<int>(s.refusals.size());
    out.blocked += static_cast<int>(s.blocked.size());
    out.carried_m += s.carried_m;
    if (s.placed_s) out.placedOrder.push_back(s.part);
    out.parts.push_back(std::move(s));
  }
  std::stable_sort(out.placedOrder.begin(), out.placedOrder.end(),
                   [&](PartId a, PartId b) { return *out.find(a)->placed_s < *out.find(b)->placed_s; });
  return out;
}

SessionStats sessionStats(std::shared_ptr<const sim::Scene> scene, const sim::Session& session, std::string label,
                          const ProgressFn& progress) {
  std::optional<SessionObserver> observer;
  const std::size_t steps = session.inputs.size();
  const std::size_t every = std::max<std::size_t>(steps / 100, 1);
  std::size_t step = 0;
  const sim::World w = sim::replay(std::move(scene), session, [&](const sim::World& world) {
    if (!observer) observer.emplace(world);
    observer->observe(world);
    if (progress && ++step % every == 0 &&
        !progress(static_cast<double>(step) / static_cast<double>(std::max<std::size_t>(steps, 1)), "replaying " + label))
      throw LoadCancelled();
  });
  if (!observer) observer.emplace(w);
  return observer->finish(w, std::move(label));
}

Spread spread(const std::vector<double>& values) {
  Spread s;
  s.n = static_cast<int>(values.size());
  if (values.empty()) return s;
  double sum = 0.0;
  for (double v : values) sum += v;
  s.mean = sum / s.n;
  s.min = *std::min_element(values.begin(), values.end());
  s.max = *std::max_element(values.begin(), values.end());
  if (s.n > 1) {
    double ss = 0.0;
    for (double v : values) ss += (v - s.mean) * (v - s.mean);
    s.sd = std::sqrt(ss / (s.n - 1));
  }
  return s;
}

Comparison compare(std::vector<SessionStats> sessions) {
  Comparison c;
  std::vector<std::string> names;
  for (const auto& s : sessions)
    for (const auto& p : s.parts)
      if (std::find(names.begin(), names.end(), p.name) == names.end()) names.push_back(p.name);
  for (const auto& name : names) {
    PartAcross pa;
    pa.name = name;
    std::vector<double> time, grabs, drops, refusals, carried;
    for (const auto& s : sessions)
      for (const auto& p : s.parts) {
        if (p.name != name) continue;
        if (const auto t = p.timeToPlace()) {
          time.push_back(*t);
          ++pa.placedIn;
        }
        grabs.push_back(p.grabs + p.toolLifts);
        drops.push_back(p.drops);
        refusals.push_back(static_cast<double>(p.refusals.size()));
        carried.push_back(p.carried_m);
      }
    pa.timeToPlace = spread(time);
    pa.grabs = spread(grabs);
    pa.drops = spread(drops);
    pa.refusals = spread(refusals);
    pa.carried = spread(carried);
    c.parts.push_back(std::move(pa));
  }
  std::vector<double> duration, placed;
  for (const auto& s : sessions) {
    duration.push_back(s.duration_s);
    placed.push_back(static_cast<double>(s.placedOrder.size()));
  }
  c.duration = spread(duration);
  c.placed = spread(placed);
  c.sessions = std::move(sessions);
  return c;
}

}  // namespace vaw::eval
