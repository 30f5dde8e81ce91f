#include "vaw/sim/clearance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

#include "vaw/error.hpp"
#include "vaw/sim/carried_path.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/sim/world.hpp"

namespace vaw::sim {

namespace {

using collision::ObjectId;
using Kind = ClearanceSpan::Kind;
constexpr double kInf = std::numeric_limits<double>::infinity();

double boxGap(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b) {
  return a.isEmpty() || b.isEmpty() ? kInf : a.exteriorDistance(b);
}

// Does `part` share volume with `other` at their poses: a triangle pair passing through beyond what
// touching allows (docs/collision.md). Faces lying on each other and a bore on its equal shaft touch,
// whatever their tessellations do.
bool interferes(const collision::CollisionWorld& cw, ObjectId part, ObjectId other) {
  // Touching pairs (coplanar ones among them, whose penetration is 0) and coaxial ones dropped in the
  // traversal, so that the first pair kept answers.
  collision::QueryOptions o;
  o.mode = collision::FilterMode::SkipCoaxial;
  o.dropTouching = true;
  o.stopAtFirst = true;
  return !cw.query(part, other, o).contacts.empty();
}

}  // namespace

std::string_view name(ClearanceSpan::Kind k) {
  switch (k) {
    case Kind::NearMiss: return "near miss";
    case Kind::Contact: return "contact";
    case Kind::Interference: return "interference";
  }
  return "?";
}

// The state of one measure: what the lambdas of a single-pass replay would capture, kept between steps.
struct ClearanceMeter::State {
  // Per object: its least clearance so far (its table row) and the span it is in.
  struct Track {
    ObjectClearance row;
    bool seen = false;
    std::optional<Kind> kind;
    double since = 0.0, last = 0.0;
    // The last nearest points in the part's and the object's own frames: carried to this step's poses,
    // two surface points no farther apart than the nearest pair, which bound the search.
    std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> near;
    // The distance when last measured and the two poses then: no point of either has moved farther than
    // its pose change allows since, so the distance now is at least that distance less both moves.
    double measured = -1.0;
    Eigen::Isometry3d partThen = Eigen::Isometry3d::Identity(), otherThen = Eigen::Isometry3d::Identity();
  };

  std::shared_ptr<const Scene> scene;
  std::string file;
  PartId part;
  ClearanceOptions options;
  PathSpan span;
  ClearanceReport out;
  collision::CollisionWorld cw;
  ObjectId self;
  std::vector<ObjectId> others;
  double touching;
  std::vector<Eigen::Isometry3d> placed;
  std::vector<Track> track;
  // How far any point of an object can have moved between two of its poses: the translation plus the
  // turn's angle times the object's largest distance from its own origin (found once, when first needed).
  std::map<std::size_t, double> radii;  // by position in `others`; the part's own under others.size()
  struct Candidate {
    double estimate, gap;
    std::size_t k;
  };
  std::vector<Candidate> order;  // reused by every step

  State(const std::shared_ptr<const Scene>& sc, std::string f, PartId p, const ClearanceOptions& o)
      : scene(sc), file(std::move(f)), part(p), options(o), span{o.from, o.to}, cw(sc->collision().instance()),
        self(ObjectId::part(p)), touching(cw.tolerances().distance) {
    const Assembly& a = scene->assembly();
    out.part = part;
    out.threshold = options.threshold;
    for (const ObjectId& id : cw.objects())
      if (!(id == self)) others.push_back(id);
    track.resize(others.size());
    placed.resize(a.parts.size());
    for (PartId q = 0; q < a.parts.size(); ++q) placed[q] = cw.pose(ObjectId::part(q));
  }

  double moved(std::size_t k, const Eigen::Isometry3d& now, const Eigen::Isometry3d& then) {
    if (now.isApprox(then, 0.0)) return 0.0;
    auto it = radii.find(k);
    if (it == radii.end()) it = radii.emplace(k, cw.maxRadius(k < others.size() ? others[k] : self, Eigen::Vector3d::Zero())).first;
    const double angle = Eigen::AngleAxisd(now.linear() * then.linear().transpose()).angle();
    return (now.translation() - then.translation()).norm() + std::abs(angle) * it->second;
  }

  void close(Track& tr, std::size_t k) {
    if (tr.kind) out.spans.push_back({*tr.kind, others[k], cw.info(others[k]).name, tr.since, tr.last});
    tr.kind.reset();
  }

  void measure(const World& w);
};

void ClearanceMeter::State::measure(const World& w) {
  const double t = w.time();
  if (!span.holds(w, part)) {
    for (std::size_t k = 0; k < others.size(); ++k) close(track[k], k);
    return;
  }
  for (PartId p = 0; p < placed.size(); ++p)
    if (!w.part(p).pose.isApprox(placed[p], 0.0)) {
      placed[p] = w.part(p).pose;
      cw.setPose(ObjectId::part(p), placed[p]);
    }
  // Likely nearest first, so the step's least distance is found early and prunes the rest: by the last
  // nearest points carried to this step (no farther apart than the two objects are), else by the boxes'
  // gap. The boxes alone would put a housing round the part first, far from it though they overlap.
  const Eigen::AlignedBox3d box = cw.worldBounds(self);
  const Eigen::Isometry3d& partPose = cw.pose(self);
  order.clear();
  for (std::size_t k = 0; k < others.size(); ++k) {
    const double gap = boxGap(box, cw.worldBounds(others[k]));
    const auto& near = track[k].near;
    order.push_back({near ? (partPose * near->first - cw.pose(others[k]) * near->second).norm() : gap, gap, k});
  }
  std::sort(order.begin(), order.end(),
            [](const Candidate& x, const Candidate& y) { return std::tie(x.estimate, x.k) < std::tie(y.estimate, y.k); });
  ClearanceStep step;
  step.t = t;
  step.distance = kInf;
  for (const auto& [estimate, gap, k] : order) {
    Track& tr = track[k];
    // From this distance on the object changes nothing: not the step's nearest, not its own row, not a
    // span (a near miss below the threshold, a contact or interference at touching).
    const double needed = std::max({step.distance, tr.seen ? tr.row.least : options.reach, options.threshold,
                                    std::nextafter(touching, kInf)});
    const Eigen::Isometry3d& otherPose = cw.pose(others[k]);
    double atLeast = gap;
    if (tr.measured >= 0.0)
      atLeast = std::max(atLeast, tr.measured - moved(others.size(), partPose, tr.partThen) - moved(k, otherPose, tr.otherThen));
    if (atLeast >= needed) {
      close(tr, k);
      continue;
    }
    collision::CollisionWorld::Nearest hint;
    if (tr.near) {
      hint.onA = partPose * tr.near->first;
      hint.onB = otherPose * tr.near->second;
    }
    const collision::CollisionWorld::Nearest n = cw.nearest(self, others[k], tr.near ? &hint : nullptr, needed);
    if (!std::isfinite(n.distance)) continue;
    tr.measured = n.distance;
    tr.partThen = partPose;
    tr.otherThen = otherPose;
    // Proved no nearer than it matters; the last nearest points still lie on both surfaces.
    if (n.beyond) {
      close(tr, k);
      continue;
    }
    // Points of touching or interfering surfaces are FCL's pick among many: no bound for the next step.
    if (n.distance > 0.0) tr.near.emplace(partPose.inverse() * n.onA, otherPose.inverse() * n.onB);
    else tr.near.reset();
    const bool inside = n.distance <= touching && interferes(cw, self, others[k]);
    if (n.distance < step.distance || (inside && !step.interfering && n.distance <= step.distance)) {
      step.nearest = others[k];
      step.distance = n.distance;
      step.onPart = n.onA;
      step.onOther = n.onB;
      step.interfering = inside;
    }
    if ((!tr.seen && n.distance < options.reach) || (tr.seen && n.distance < tr.row.least)) {
      tr.seen = true;
      tr.row = {others[k], cw.info(others[k]).name, n.distance, t, n.onA, n.onB};
    }
    std::optional<Kind> kind;
    if (inside) kind = Kind::Interference;
    else if (n.distance <= touching) kind = Kind::Contact;
    else if (n.distance < options.threshold) kind = Kind::NearMiss;
    if (kind != tr.kind) {
      close(tr, k);
      if (kind) {
        tr.kind = kind;
        tr.since = t;
      }
    }
    if (tr.kind) tr.last = t;
  }
  if (std::isfinite(step.distance)) out.steps.push_back(step);
}

ClearanceMeter::ClearanceMeter(const std::shared_ptr<const Scene>& scene, std::string file, PartId part,
                               const ClearanceOptions& options) {
  const Assembly& a = scene->assembly();
  if (part >= a.parts.size()) fail(file, "part", "a part of the scene", "part index " + std::to_string(part));
  if (!(options.threshold >= 0.0) || !std::isfinite(options.threshold))
    fail(file, "threshold", "a finite distance of 0 or more", std::to_string(options.threshold));
  s_ = std::make_unique<State>(scene, std::move(file), part, options);
}

ClearanceMeter::~ClearanceMeter() = default;
ClearanceMeter::ClearanceMeter(ClearanceMeter&&) noexcept = default;
ClearanceMeter& ClearanceMeter::operator=(ClearanceMeter&&) noexcept = default;

void ClearanceMeter::step(const World& w) { s_->measure(w); }

ClearanceReport ClearanceMeter::finish() {
  State& s = *s_;
  for (std::size_t k = 0; k < s.others.size(); ++k) s.close(s.track[k], k);
  if (s.out.steps.empty()) s.span.noStep(s.file, s.scene->assembly(), s.part);
  ClearanceReport out = std::move(s.out);
  for (const State::Track& tr : s.track)
    if (tr.seen) out.objects.push_back(tr.row);
  std::sort(out.objects.begin(), out.objects.end(), [](const ObjectClearance& x, const ObjectClearance& y) {
    return std::tie(x.least, x.t, x.name) < std::tie(y.least, y.t, y.name);
  });
  std::sort(out.spans.begin(), out.spans.end(), [](const ClearanceSpan& x, const ClearanceSpan& y) {
    return std::tie(x.from, x.name) < std::tie(y.from, y.name);
  });
  return out;
}

ClearanceReport clearanceAlong(const std::shared_ptr<const Scene>& scene, const Session& session, PartId part,
                               const ClearanceOptions& options) {
  ClearanceMeter meter(scene, sessionName(session), part, options);
  (void)replay(scene, session, [&](const World& w) { meter.step(w); });
  return meter.finish();
}

}  // namespace vaw::sim
