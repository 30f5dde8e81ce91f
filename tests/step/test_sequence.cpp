// Which order puts an assembly together, from its geometry: on STEP assemblies the fixtures write with
// Open CASCADE, the precedence and order found are the ones the geometry forces, and a part that no order
// can insert is named with what blocks it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <string>

#include "bundled.hpp"
#include "files.hpp"
#include "step_fixtures.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/evaluation/way_clearance.hpp"
#include "vaw/collision/collision_world.hpp"
#include "vaw/error.hpp"
#include "vaw/mesh.hpp"
#include "vaw/scene_loader.hpp"

namespace {

namespace fs = std::filesystem;
using vaw::Assembly;
using vaw::PartId;
using vaw::eval::Precedence;
using vaw::eval::SequencePlan;
using vaw::Constraint;

Assembly load(const std::string& name, void (*write)(const fs::path&)) {
  const fs::path file = vaw::test::tempDir() / name;
  write(file);
  return vaw::loadAny(file, vaw::test::importers());
}

PartId id(const Assembly& a, const std::string& name) {
  for (const auto& p : a.parts)
    if (p.name == name) return p.id;
  ADD_FAILURE() << "no part " << name;
  return 0;
}

std::size_t position(const SequencePlan& plan, PartId p) {
  return static_cast<std::size_t>(std::find(plan.order.begin(), plan.order.end(), p) - plan.order.begin());
}

// "before -> after (partner|blocks)" for every precedence, by name.
std::set<std::string> precedence(const Assembly& a, const SequencePlan& plan) {
  std::set<std::string> out;
  for (const auto& e : plan.precedence)
    out.insert(a.parts[e.before].name + " -> " + a.parts[e.after].name +
               (e.reason == Precedence::Reason::Partner ? " (partner)" : " (blocks)"));
  return out;
}

std::string names(const Assembly& a, const std::vector<PartId>& ids) {
  std::string s;
  for (const PartId p : ids) s += (s.empty() ? "" : " ") + a.parts[p].name;
  return s;
}

}  // namespace

TEST(Sequence, BoltedBracketGoesTogetherStudsBracketNuts) {
  const Assembly a = load("bolted-bracket.stp", [](const fs::path& f) { vaw::steptest::writeBoltedBracket(f); });
  const SequencePlan plan = vaw::eval::planSequence(a);
  ASSERT_TRUE(plan.complete());
  EXPECT_EQ(plan.order.size(), a.parts.size());
  EXPECT_EQ(plan.order.front(), *a.base);
  std::printf("[ info ] order: %s; %d pair checks, %d distance and blocked checks\n", names(a, plan.order).c_str(), plan.pairChecks, plan.evaluations);

  // The bracket goes over both studs and under both nuts, which stand in its way out: the nuts block it.
  const std::set<std::string> expected = {
      "stud-1 -> bracket (partner)", "stud-2 -> bracket (partner)", "stud-1 -> nut-1 (partner)", "stud-2 -> nut-2 (partner)",
      "bracket -> nut-1 (partner)",  "bracket -> nut-2 (partner)",  "bracket -> nut-1 (blocks)", "bracket -> nut-2 (blocks)",
      "pin -> sleeve (partner)"};
  EXPECT_EQ(precedence(a, plan), expected);
  for (const auto& e : plan.precedence) EXPECT_LT(position(plan, e.before), position(plan, e.after)) << names(a, {e.before, e.after});

  // The nut's way home is down its stud's axis, and nothing is in it; the bracket's way out meets each nut
  // after it has slid 8 mm up the studs, the nut's height resting on it... no: the nuts sit on the flange,
  // so the bracket meets them at once, at 0 mm of travel.
  const auto* nutWay = plan.wayOf(id(a, "nut-1"));
  ASSERT_TRUE(nutWay);
  EXPECT_GT(nutWay->out.z(), 0.999);
  EXPECT_TRUE(nutWay->blockers.empty());
  const auto* bracket = plan.checkOf(id(a, "bracket"));
  ASSERT_TRUE(bracket);
  const auto& up = bracket->directions.front();
  EXPECT_GT(up.out.z(), 0.999) << up.from;
  std::set<std::string> upBlockers;
  for (const auto& b : up.blockers) {
    upBlockers.insert(a.parts[b.by].name);
    EXPECT_LT(b.distance, 1e-4) << a.parts[b.by].name << ": the nuts rest on the flange";
  }
  EXPECT_EQ(upBlockers, (std::set<std::string>{"nut-1", "nut-2"}));
  // The stud comes out through the bracket's clearance hole and its nut's bore: free.
  EXPECT_TRUE(plan.wayOf(id(a, "stud-1"))->blockers.empty());
}

TEST(Sequence, ThePegGoesInBeforeItsCover) {
  const Assembly a = load("peg-under-cover.stp", vaw::steptest::writePegUnderCover);
  ASSERT_EQ(a.parts[*a.base].name, "plate");
  const SequencePlan plan = vaw::eval::planSequence(a);
  ASSERT_TRUE(plan.complete());
  EXPECT_EQ(names(a, plan.order), "plate peg cover");
  EXPECT_EQ(precedence(a, plan), (std::set<std::string>{"peg -> cover (blocks)"}));
  // Up out of its hole, the peg meets the cover's pocket ceiling after 3 mm.
  const auto* peg = plan.checkOf(id(a, "peg"));
  ASSERT_TRUE(peg);
  const auto& up = peg->directions.front();
  ASSERT_EQ(up.blockers.size(), 1u);
  EXPECT_EQ(a.parts[up.blockers[0].by].name, "cover");
  EXPECT_NEAR(up.blockers[0].distance, 0.003, 2e-5);
  // Down, the blind hole's bottom stops it at once.
  ASSERT_GE(peg->directions.size(), 2u);
  EXPECT_LT(peg->directions[1].out.z(), -0.999);
  ASSERT_EQ(peg->directions[1].blockers.size(), 1u);
  EXPECT_EQ(peg->directions[1].blockers[0].by, *a.base);
  EXPECT_NEAR(peg->directions[1].blockers[0].distance, 0.0, 2e-5);
}

// How close each way home comes to the parts already in, on the bracket whose fits are known: the sleeve
// slides on its pin (0.2 mm radial play) and the nuts on their studs, which are guides, not near misses;
// the bracket's upright stands 1 mm beside each nut (nut outer radius 10 about y = 40, upright from
// y = 51), which a nut passes all the way down onto the flange it rests on.
TEST(Sequence, WaysHomeNameWhatTheyPassAndHowClose) {
  const Assembly a = load("bolted-bracket.stp", [](const fs::path& f) { vaw::steptest::writeBoltedBracket(f); });
  const SequencePlan plan = vaw::eval::planSequence(a);
  ASSERT_TRUE(plan.complete());
  vaw::eval::WayClearanceOptions o;
  o.threshold = 0.005;
  const auto ways = vaw::eval::wayClearances(a, plan, o);
  ASSERT_EQ(ways.size(), plan.order.size() - 1);
  std::map<std::string, const vaw::eval::WayClearance*> by;
  for (const auto& w : ways) by[a.parts[w.part].name] = &w;
  ASSERT_EQ(by.size(), 7u);
  const std::vector<Eigen::Isometry3d> home = vaw::eval::homePoses(a);
  Assembly together = a;
  for (PartId p = 0; p < a.parts.size(); ++p) together.parts[p].pose = home[p];
  vaw::collision::CollisionWorld cw(together);

  // The studs go into the plate's blind holes (their guides) with nothing else in yet.
  EXPECT_EQ(names(a, by["stud-1"]->guides), "base-plate");
  EXPECT_TRUE(by["stud-1"]->objects.empty());
  // The bracket slides down both studs onto the plate: no near miss.
  EXPECT_EQ(names(a, by["bracket"]->guides), "stud-1 stud-2");
  EXPECT_EQ(names(a, by["bracket"]->seatedOn), "base-plate");
  EXPECT_FALSE(by["bracket"]->nearMiss(o.threshold));
  // The sleeve slides down the pin with 0.2 mm of play onto the plate: no near miss; the bracket is the
  // nearest it passes, more than 5 mm off.
  EXPECT_EQ(names(a, by["sleeve"]->guides), "pin");
  EXPECT_EQ(names(a, by["sleeve"]->seatedOn), "base-plate");
  EXPECT_FALSE(by["sleeve"]->nearMiss(o.threshold));
  ASSERT_NE(by["sleeve"]->nearest(), nullptr);
  EXPECT_EQ(a.parts[by["sleeve"]->nearest()->part].name, "bracket");
  // Each nut passes the upright 1 mm off (its polygon's outermost point at most the facets' sag inside the
  // circle), from the top of its way down to the flange: a near miss, although the bracket is its seat.
  for (const char* nut : {"nut-1", "nut-2"}) {
    const auto& w = *by[nut];
    EXPECT_EQ(names(a, w.guides), nut == std::string("nut-1") ? "stud-1" : "stud-2");
    EXPECT_EQ(names(a, w.seatedOn), "bracket");
    ASSERT_TRUE(w.nearMiss(o.threshold)) << nut;
    const auto& near = *w.nearest();
    EXPECT_EQ(a.parts[near.part].name, "bracket");
    EXPECT_GE(near.least, 0.001 - o.tolerance) << nut;
    EXPECT_LE(near.least, 0.00102) << nut;
    // The upright's face stands 11 mm from the nut's axis.
    const Eigen::Vector3d axis = cw.worldBounds(vaw::collision::ObjectId::part(w.part)).center();
    EXPECT_NEAR(near.onOther.y() - axis.y(), 0.011, 1e-6) << "on the upright's face";
    EXPECT_GE(near.at, o.threshold) << "the last approach onto the seat is not counted";
  }
  // Each way's nearest agrees with a dense walk down the way (every 0.1 mm, so the walk's least is within
  // 0.05 mm above the true one): the search is never more than its accuracy above it (the tolerance, or 5 %
  // of the least's excess over the threshold), and never below the true least.
  const double walk = 1e-4;
  for (const auto& w : ways) {
    if (w.objects.empty()) continue;
    const auto& ob = w.objects.front();
    double dense = std::numeric_limits<double>::infinity();
    const double from = std::find(w.seatedOn.begin(), w.seatedOn.end(), ob.part) != w.seatedOn.end() ? o.threshold + o.tolerance : 0.0;
    for (double s = from; s <= w.length + 1e-12; s += walk) {
      Eigen::Isometry3d pose = home[w.part];
      pose.pretranslate(s * w.out);
      dense = std::min(dense, cw.distance(vaw::collision::ObjectId::part(w.part), pose, vaw::collision::ObjectId::part(ob.part)));
    }
    EXPECT_LE(ob.least, dense + std::max(o.tolerance, 0.05 * (ob.least - o.threshold))) << a.parts[w.part].name << " / " << a.parts[ob.part].name;
    EXPECT_GE(ob.least, dense - 0.5 * walk) << a.parts[w.part].name << " / " << a.parts[ob.part].name;
  }

  // The nut's way as a swept volume: a tube sliding along its own axis sweeps a longer tube, its bore open.
  o.voxel = 0.001;
  const auto swept = vaw::eval::wayClearances(a, plan, o);
  const auto nut = std::find_if(swept.begin(), swept.end(), [&](const auto& w) { return a.parts[w.part].name == "nut-1"; });
  ASSERT_TRUE(nut != swept.end() && nut->swept);
  const double h = 0.008 + nut->length, pi = 3.14159265358979, slack = 1.25 * std::sqrt(3.0) * o.voxel;
  EXPECT_GE(nut->swept->volume, pi * (0.0099 * 0.0099 - 0.006 * 0.006) * h);
  EXPECT_LE(nut->swept->volume, pi * (std::pow(0.010 + slack, 2) - std::pow(0.006 - slack, 2)) * (h + 2 * slack));
  // A point of the nut's wall and of its bore, from its axis half way up.
  const Eigen::Vector3d centre = cw.worldBounds(vaw::collision::ObjectId::part(nut->part), home[nut->part]).center();
  const Eigen::Vector3d wall = centre + Eigen::Vector3d(0.008, 0.0, 0.0);
  EXPECT_TRUE(nut->swept->contains(wall)) << "the nut at home";
  EXPECT_TRUE(nut->swept->contains(wall + nut->length * nut->out)) << "the nut where it starts";
  EXPECT_FALSE(nut->swept->contains(centre + 0.5 * nut->length * nut->out)) << "its bore";
  // Kept without its mesh (a thousand ways' meshes are hundreds of MB); made again, it encloses the voxels.
  EXPECT_TRUE(nut->swept->mesh.triangles.empty());
  const vaw::TriMesh space = nut->swept->surface();
  EXPECT_TRUE(vaw::checkMesh(space).valid()) << vaw::checkMesh(space).summary();
  double enclosed = 0.0;
  for (const auto& t : space.triangles)
    enclosed += space.vertices[t[0]].dot(space.vertices[t[1]].cross(space.vertices[t[2]])) / 6.0;
  EXPECT_NEAR(enclosed, nut->swept->volume, 1e-6 * nut->swept->volume);
  // Options that are no lengths are refused, naming the field.
  o.tolerance = 0.0;
  EXPECT_THROW((void)vaw::eval::wayClearances(a, plan, o), vaw::InputError);
}

TEST(Sequence, ACaptiveRingIsNamedWithItsBlocker) {
  const Assembly a = load("captive-ring.stp", vaw::steptest::writeCaptiveRing);
  ASSERT_EQ(a.parts[*a.base].name, "base");
  const SequencePlan plan = vaw::eval::planSequence(a);
  EXPECT_FALSE(plan.complete());
  ASSERT_EQ(plan.stuck.size(), 1u);
  const auto& stuck = plan.stuck[0];
  EXPECT_EQ(a.parts[stuck.part].name, "ring");
  const auto* ring = plan.checkOf(stuck.part);
  ASSERT_TRUE(ring);
  ASSERT_EQ(ring->directions.size(), 2u) << "up and down its axis";
  ASSERT_EQ(stuck.blockers.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(names(a, stuck.blockers[k]), "base") << ring->directions[k].from;
  }
  // Up its axis it slides 30 mm before the flange stops it; down, the plate stops it at once.
  const auto& up = ring->directions[0].out.z() > 0 ? ring->directions[0] : ring->directions[1];
  const auto& down = ring->directions[0].out.z() > 0 ? ring->directions[1] : ring->directions[0];
  EXPECT_NEAR(up.blockers.at(0).distance, 0.030, 2e-5);
  EXPECT_NEAR(down.blockers.at(0).distance, 0.0, 2e-5);
  // The cap on the flange is unaffected.
  EXPECT_EQ(names(a, plan.order), "base cap");
}

// ---- after the assembler tried: a scripted session on the bolted bracket ----

#include "assembler.hpp"
#include "vaw/evaluation/dfa.hpp"
#include "vaw/evaluation/session_stats.hpp"

namespace {

struct Scripted {
  vaw::eval::SessionStats stats;
  std::map<std::string, double> grabbedAfter;  // world time just before each part's first carry
  std::map<std::string, double> releasedAt;    // world time after each part's last release step
  std::map<std::string, int> carries;
  double nut2Distance = 0.0;                   // how far the script moved nut-2's centre in its one carry
  double rate = 0.0;
};

Scripted scriptSession(const Assembly& a) {
  Scripted s;
  vaw::test::Assembler as(a);
  std::optional<vaw::eval::SessionObserver> observer;
  as.afterStep = [&](const vaw::sim::World& w) {
    if (!observer) observer.emplace(w);
    observer->observe(w);
  };
  s.rate = as.world().settings().rate;
  auto carry = [&](const std::string& part, const Eigen::Isometry3d& target) {
    if (!s.grabbedAfter.count(part)) s.grabbedAfter[part] = as.world().time();
    ++s.carries[part];
    as.carry(part, target);
    s.releasedAt[part] = as.world().time();
    as.settle();
  };
  // The nut onto its stud before the stud is there: refused; then back to the table.
  carry("nut-1", as.above("nut-1", 0.0));
  Eigen::Isometry3d aside = a.parts[*a.findPart("nut-1")].pose;
  aside.translation().z() += 0.001;
  carry("nut-1", aside);
  // The stud pushed through its hole's bottom (let go there, not recognised: a drop), then 5 mm above home.
  carry("stud-1", as.above("stud-1", -5.0));
  carry("stud-1", as.above("stud-1", 5.0));
  carry("stud-2", as.above("stud-2", 5.0));
  carry("bracket", as.above("bracket", 4.0));
  const PartId nut2 = *a.findPart("nut-2");
  const Eigen::Isometry3d target = as.above("nut-2", 6.0);
  s.nut2Distance = (target * a.parts[nut2].mass.centerOfMass - as.world().part(nut2).pose * a.parts[nut2].mass.centerOfMass).norm();
  carry("nut-2", target);
  s.stats = observer->finish(as.world(), "scripted");
  return s;
}

}  // namespace

TEST(Session, AScriptedSessionsFiguresAreWhatTheScriptDid) {
  const Assembly a = load("bolted-bracket.stp", [](const fs::path& f) { vaw::steptest::writeBoltedBracket(f); });
  const Scripted s = scriptSession(a);
  const auto& st = s.stats;
  auto part = [&](const std::string& name) { return *st.find(id(a, name)); };

  EXPECT_EQ(names(a, st.placedOrder), "stud-1 stud-2 bracket nut-2");
  for (const auto& [name, n] : s.carries) {
    const auto p = part(name);
    EXPECT_EQ(p.grabs, n) << name << ": one grab per carry";
    // Grabbed within the five steps the hand closes in; PLACED after the last release, while it settled.
    ASSERT_TRUE(p.firstHandled_s) << name;
    EXPECT_GT(*p.firstHandled_s, s.grabbedAfter.at(name)) << name;
    EXPECT_LE(*p.firstHandled_s, s.grabbedAfter.at(name) + 5.0 / s.rate + 1e-9) << name;
    if (name == "nut-1") {
      EXPECT_FALSE(p.placed_s) << "nut-1 was never placed";
      continue;
    }
    ASSERT_TRUE(p.placed_s) << name;
    EXPECT_GE(*p.placed_s, s.releasedAt.at(name) - 1.0 / s.rate) << name;
    EXPECT_LE(*p.placed_s, s.releasedAt.at(name) + 300.0 / s.rate) << name;
    EXPECT_NEAR(*p.timeToPlace(), *p.placed_s - *p.firstHandled_s, 1e-12);
    EXPECT_EQ(p.holders(), "right hand") << name;
  }
  // The refusal, with its reason; the nut's first release was near its mate, its second away from it.
  const auto nut1 = part("nut-1");
  ASSERT_FALSE(nut1.refusals.empty());
  for (const auto& r : nut1.refusals) EXPECT_NE(r.find("its partner stud-1 is not placed yet"), std::string::npos) << r;
  EXPECT_GE(nut1.drops, 1);
  EXPECT_EQ(part("stud-1").drops, 1) << "let go through the hole's bottom, away from its home";
  EXPECT_EQ(part("stud-2").drops, 0);
  for (const char* name : {"stud-2", "bracket", "nut-2", "pin", "sleeve"}) EXPECT_TRUE(part(name).refusals.empty()) << name;
  // The nut stopped on the bracket on its way down its stud.
  const auto nut2 = part("nut-2");
  ASSERT_FALSE(nut2.blocked.empty());
  EXPECT_NE(nut2.blocked.back().find("bracket"), std::string::npos) << nut2.blocked.back();
  // Carried: the hand took it in one move from where it lay to 6 mm above home.
  EXPECT_NEAR(nut2.carried_m, s.nut2Distance, 1e-9);
  EXPECT_EQ(part("pin").grabs, 0);
  EXPECT_FALSE(part("pin").firstHandled_s);
  // Totals are the parts' sums.
  int grabs = 0, drops = 0, refusals = 0;
  double carried = 0.0;
  for (const auto& p : st.parts) {
    grabs += p.grabs;
    drops += p.drops;
    refusals += static_cast<int>(p.refusals.size());
    carried += p.carried_m;
  }
  EXPECT_EQ(st.grabs, grabs);
  EXPECT_EQ(st.grabs, 7);
  EXPECT_EQ(st.drops, drops);
  EXPECT_EQ(st.refusals, refusals);
  EXPECT_NEAR(st.carried_m, carried, 1e-12);
}

TEST(Session, SessionsSideBySideGiveMeansAndSpread) {
  const vaw::eval::Spread s = vaw::eval::spread({1.0, 2.0, 3.0, 6.0});
  EXPECT_EQ(s.n, 4);
  EXPECT_DOUBLE_EQ(s.mean, 3.0);
  EXPECT_NEAR(s.sd, std::sqrt((4.0 + 1.0 + 0.0 + 9.0) / 3.0), 1e-12);
  EXPECT_EQ(s.min, 1.0);
  EXPECT_EQ(s.max, 6.0);
  // Two participants: the second one's nut-2 took twice as long.
  vaw::eval::SessionStats p1, p2;
  vaw::eval::PartSession nut;
  nut.name = "nut-2";
  nut.firstHandled_s = 1.0;
  nut.placed_s = 3.0;
  nut.grabs = 1;
  p1.parts = {nut};
  nut.placed_s = 5.0;
  nut.grabs = 3;
  nut.drops = 2;
  p2.parts = {nut};
  const auto c = vaw::eval::compare({p1, p2});
  ASSERT_EQ(c.parts.size(), 1u);
  EXPECT_EQ(c.parts[0].placedIn, 2);
  EXPECT_DOUBLE_EQ(c.parts[0].timeToPlace.mean, 3.0);
  EXPECT_NEAR(c.parts[0].timeToPlace.sd, std::sqrt(2.0), 1e-12);
  EXPECT_DOUBLE_EQ(c.parts[0].grabs.mean, 2.0);
  EXPECT_DOUBLE_EQ(c.parts[0].drops.max, 2.0);
}

TEST(Dfa, TheBracketsPartsGetTheChartsCodes) {
  const Assembly a = load("bolted-bracket.stp", [](const fs::path& f) { vaw::steptest::writeBoltedBracket(f); });
  const SequencePlan plan = vaw::eval::planSequence(a);
  auto estimate = [&](const std::string& name) {
    const PartId p = id(a, name);
    const Constraint* how = nullptr;
    for (const auto& c : a.constraints)
      if (c.part == p && c.type == vaw::Constraint::Type::Insert && !how) how = &c;
    const vaw::eval::DfaEstimate e = vaw::eval::estimateDfa(a, p, plan.wayOf(p)->out, how);
    std::printf("[ info ] %s: %s\n", name.c_str(), e.why.c_str());
    return e;
  };
  // The stud: round about its axis, either end first (alpha + beta = 180: row 0), 34 mm by 12 mm (column
  // 0): 1.13 s; into its hole with no clearance: not easy to align and it resists (03): 3.5 s.
  const auto stud = estimate("stud-1");
  EXPECT_EQ(stud.alpha_deg, 0.0);
  EXPECT_EQ(stud.beta_deg, 180.0);
  EXPECT_NEAR(stud.size_m, 0.034, 1e-6);
  EXPECT_NEAR(stud.thickness_m, 0.012, 1e-4);
  EXPECT_EQ(stud.handlingCode, "00");
  EXPECT_EQ(stud.insertionCode, "03");
  EXPECT_DOUBLE_EQ(stud.total_s(), 1.13 + 3.5);
  // The nut: the same symmetry, 20 mm across, 8 mm thick; onto its stud with no clearance.
  const auto nut = estimate("nut-1");
  EXPECT_EQ(nut.alpha_deg + nut.beta_deg, 180.0);
  EXPECT_EQ(nut.handlingCode, "00");
  EXPECT_EQ(nut.insertionCode, "03");
  // The sleeve onto its pin with 0.2 mm of clearance: easy (00), 1.5 s.
  const auto sleeve = estimate("sleeve");
  EXPECT_EQ(sleeve.insertionCode, "00");
  EXPECT_DOUBLE_EQ(sleeve.insertion_s, 1.5);
  // The bracket, an L with its upright to one side: no symmetry either way (alpha + beta = 720: row 3),
  // 70 mm long: 1.95 s; over the studs with 0.5 mm of clearance: easy, 1.5 s.
  const auto bracket = estimate("bracket");
  EXPECT_EQ(bracket.alpha_deg, 360.0);
  EXPECT_EQ(bracket.beta_deg, 360.0);
  EXPECT_EQ(bracket.handlingCode, "30");
  EXPECT_DOUBLE_EQ(bracket.handling_s, 1.95);
  EXPECT_EQ(bracket.insertionCode, "00");
}

// ---- the report, opened in a real browser ----

#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "vaw/report/gltf.hpp"
#include "vaw/report/report.hpp"

namespace {

std::string run(const std::string& command) {
  std::string out;
  FILE* p = popen(command.c_str(), "r");
  if (!p) return out;
  char buf[65536];
  for (std::size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
  pclose(p);
  return out;
}

std::vector<std::vector<std::string>> csvRows(const fs::path& file) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::string cell;
    bool quoted = false;
    for (const char c : line) {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) {
        cells.push_back(cell);
        cell.clear();
      } else cell += c;
    }
    cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

}  // namespace

TEST(Report, TheHtmlShowsTheCsvsNumbersInChromium) {
  const Assembly a = load("bolted-bracket.stp", [](const fs::path& f) { vaw::steptest::writeBoltedBracket(f); });
  const SequencePlan plan = vaw::eval::planSequence(a);
  Scripted first = scriptSession(a), second = scriptSession(a);
  first.stats.label = "P01";
  second.stats.label = "P02";
  // In the build tree, so that the screenshot stays to be looked at.
  const fs::path dir = fs::absolute("report-bolted-bracket");
  const auto files = vaw::report::writeReport(a, plan, {first.stats, second.stats}, dir);
  ASSERT_TRUE(fs::exists(files.html));

  const std::string chromium = "/usr/bin/chromium";
  ASSERT_TRUE(fs::exists(chromium)) << "Debian's chromium (packaging/install-deps.sh installs it) renders the report";
  const std::string flags = " --headless --no-sandbox --disable-gpu --hide-scrollbars --virtual-time-budget=5000 ";
  const std::string dom = run(chromium + flags + "--dump-dom 'file://" + files.html.string() + "' 2>/dev/null");
  ASSERT_FALSE(dom.empty()) << "chromium printed no page";
  // Every picture decoded in the browser: the assembly, and one per step of the order.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(dom, m, std::regex("data-pictures-shown=\"(\\d+)\""))) << "the page's load handler did not run";
  EXPECT_EQ(std::stoul(m[1]), plan.order.size() + 1);
  (void)run(chromium + flags + "--window-size=1200,3000 --screenshot='" + (dir / "report.png").string() + "' 'file://" + files.html.string() +
            "' 2>/dev/null");
  EXPECT_GT(fs::file_size(dir / "report.png"), 20000u) << "a screenshot of the page, to look at";

  // The parts table as the browser has it, cell by cell against parts.csv.
  const auto table = dom.substr(dom.find("id=\"parts\""), dom.find("</table>", dom.find("id=\"parts\"")) - dom.find("id=\"parts\""));
  std::vector<std::vector<std::string>> htmlRows;
  const std::regex row("<tr[^>]*>(.*?)</tr>"), cell("<td[^>]*>(.*?)</td>");
  for (auto r = std::sregex_iterator(table.begin(), table.end(), row); r != std::sregex_iterator(); ++r) {
    const std::string body = (*r)[1];
    std::vector<std::string> cells;
    for (auto c = std::sregex_iterator(body.begin(), body.end(), cell); c != std::sregex_iterator(); ++c) cells.push_back((*c)[1]);
    if (!cells.empty()) htmlRows.push_back(cells);
  }
  const auto csv = csvRows(files.partsCsv);
  ASSERT_EQ(htmlRows.size() + 1, csv.size()) << "one row per part in both";
  for (std::size_t i = 0; i < htmlRows.size(); ++i) {
    const auto& h = htmlRows[i];
    const auto& c = csv[i + 1];
    EXPECT_EQ(h[0], c[0]);                          // part
    EXPECT_EQ(h[1], c[1]);                          // step
    EXPECT_EQ(h[4], c[4]) << c[0];                  // handling code
    EXPECT_EQ(h[5], c[5]) << c[0];                  // insertion code
    EXPECT_EQ(h[6].substr(0, c[8].size()), c[8]) << c[0];  // estimate s
    EXPECT_EQ(h[8], c[12]) << c[0];                 // time to place, mean
    EXPECT_EQ(h[9], c[13]) << c[0];                 // sd
    EXPECT_EQ(h[10], c[14]) << c[0];                // grabs
    EXPECT_EQ(h[11], c[15]) << c[0];                // drops
    EXPECT_EQ(h[12], c[16]) << c[0];                // refusals
    EXPECT_EQ(h[13], c[17]) << c[0];                // carried
  }
  // And the CSV holds what the sessions measured: nut-2's time to place, both participants alike.
  for (const auto& c : csv)
    if (c[0] == "nut-2") {
      EXPECT_EQ(c[12], vaw::report::formatNumber(*first.stats.find(id(a, "nut-2"))->timeToPlace()));
      EXPECT_EQ(c[13], vaw::report::formatNumber(0.0));
      EXPECT_EQ(c[11], "2");
    }
}

// The ways home in the report: a row each, the near misses marked, a picture of each way, ways.csv and
// evaluation.json with the same numbers.
// The order in 3D, in Debian's Chromium drawing with WebGL in software: the order's glTF is inlined whole;
// the slider's step (through the address, "#step=K", as the slider sets it) shows the base and the parts
// up to that step, a part picked ("select=NAME", as a click picks it) marks its rows in the tables, and
// the canvas is drawn. The screenshots stay in the build tree to be looked at.
TEST(Report, TheOrderPlaysIn3DInChromium) {
  const Assembly a = load("bolted-bracket.stp", [](const fs::path& f) { vaw::steptest::writeBoltedBracket(f); });
  const SequencePlan plan = vaw::eval::planSequence(a);
  ASSERT_EQ(plan.order.size(), 8u);
  const fs::path dir = fs::absolute("report-3d");
  const auto files = vaw::report::writeReport(a, plan, {}, dir);
  EXPECT_LT(fs::file_size(files.html), 2u << 20) << "the bundled sample's page under 2 MB";
  std::ifstream in(files.html);
  const std::string page((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // The glTF inlined is the order's, byte for byte.
  const std::string open = "<script type='application/octet-stream' id='view3d-glb'>";
  const auto from = page.find(open);
  ASSERT_NE(from, std::string::npos);
  const std::string text = page.substr(from + open.size(), page.find("</script>", from) - from - open.size());
  std::vector<std::uint8_t> bytes;
  std::uint32_t acc = 0;
  int bits = 0;
  for (const char c : text) {
    const auto at = std::string_view("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/").find(c);
    if (at == std::string_view::npos) continue;
    acc = (acc << 6) | static_cast<std::uint32_t>(at);
    if ((bits += 6) >= 8) bytes.push_back(static_cast<std::uint8_t>(acc >> (bits -= 8)));
  }
  EXPECT_EQ(bytes, vaw::report::glb(a, vaw::report::orderMotion(a, plan, 1.0, 20.0)));

  const std::string chromium = "/usr/bin/chromium";
  ASSERT_TRUE(fs::exists(chromium)) << "Debian's chromium (packaging/install-deps.sh installs it) draws the view";
  const std::string flags = " --headless --no-sandbox --hide-scrollbars --virtual-time-budget=8000 --window-size=1150,900 ";
  const auto view = [&](const std::string& hash) {
    const std::string dom = run(chromium + flags + "--dump-dom 'file://" + files.html.string() + "#" + hash + "' 2>/dev/null");
    std::smatch m;
    if (!std::regex_search(dom, m, std::regex("data-view=\"([^\"]*)\""))) return std::pair{nlohmann::json(), dom};
    std::string j = m[1];
    for (std::size_t at; (at = j.find("&quot;")) != std::string::npos;) j.replace(at, 6, "\"");
    return std::pair{nlohmann::json::parse(j), dom};
  };
  const auto name = [&](std::size_t i) { return a.parts[plan.order[i]].name; };
  for (const std::size_t step : {std::size_t{0}, std::size_t{2}, plan.order.size() - 1}) {
    const auto [v, dom] = view("step=" + std::to_string(step) + "&select=" + name(1));
    ASSERT_TRUE(v.is_object()) << "the view's script did not finish";
    ASSERT_FALSE(v.contains("error")) << v.dump();
    EXPECT_EQ(v["step"], step);
    EXPECT_EQ(v["parts"], a.parts.size());
    EXPECT_EQ(v["shown"], step + 1) << "the base and the parts up to the step";
    EXPECT_EQ(v["selected"], name(1));
    EXPECT_GT(v["drawn"].get<double>(), 0.05) << "the canvas shows the parts";
    // The picked part's row in the parts table is marked, no other.
    const auto table = dom.substr(dom.find("id=\"parts\""), dom.find("</table>", dom.find("id=\"parts\"")) - dom.find("id=\"parts\""));
    const std::regex marked("<tr class=\"sel\"><td>([^<]*)</td>");
    std::vector<std::string> rows;
    for (auto r = std::sregex_iterator(table.begin(), table.end(), marked); r != std::sregex_iterator(); ++r) rows.push_back((*r)[1]);
    EXPECT_EQ(rows, std::vector<std::string>{name(1)});
  }
  // Drawn less at the first step (the base alone) than at the last; the exploded view drawn otherwise.
  const double assembled = view("step=7").first["drawn"].get<double>();
  EXPECT_LT(view("step=0").first["drawn"].get<double>(), assembled);
  const auto apart = view("step=7&exploded").first;
  EXPECT_EQ(apart["exploded"], true);
  EXPECT_EQ(apart["shown"], plan.order.size());
  EXPECT_NE(apart["drawn"].get<double>(), assembled);
  for (const auto& [shot, hash] : {std::pair{"view-step-3.png", "step=2"}, std::pair{"view-assembled.png", "step=7&select=bracket"},
                                   std::pair{"view-exploded.png", "step=7&exploded"}})
    (void)run(chromium + flags + "--screenshot='" + (dir / shot).string() + "' 'file://" + files.html.string() + "#" + hash + "' 2>/dev/null");
  EXPECT_GT(fs::file_size(dir / "view-step-3.png"), 20000u) << "a screenshot of the view, to look at";
}

TEST(Report, WaysHomeAreTabledAndPicturedWithTheirNearMisses) {
  const Assembly a = load("bolted-bracket.stp", [](const fs::path& f) { vaw::steptest::writeBoltedBracket(f); });
  const SequencePlan plan = vaw::eval::planSequence(a);
  vaw::report::WaysHome ways;
  ways.options.voxel = 0.002;
  ways.ways = vaw::eval::wayClearances(a, plan, ways.options);
  const fs::path dir = fs::absolute("report-ways");
  const auto files = vaw::report::writeReport(a, plan, {}, dir, {}, &ways);
  ASSERT_EQ(files.waysCsv, dir / "ways.csv");

  std::ifstream csvIn(files.waysCsv);
  std::string line;
  std::vector<std::string> lines;
  while (std::getline(csvIn, line)) lines.push_back(line);
  ASSERT_EQ(lines.size(), 8u) << "a header and the seven ways";
  int misses = 0;
  for (const auto& l : lines) misses += l.find(",yes,") != std::string::npos ? 1 : 0;
  EXPECT_EQ(misses, 2);
  const auto nut = std::find_if(lines.begin(), lines.end(), [](const std::string& l) { return l.rfind("nut-1,", 0) == 0; });
  ASSERT_NE(nut, lines.end());
  EXPECT_NE(nut->find(",stud-1,bracket,bracket,1.015,"), std::string::npos) << *nut;

  const nlohmann::json j = nlohmann::json::parse(std::ifstream(files.json));
  ASSERT_EQ(j.at("ways").at("parts").size(), 7u);
  EXPECT_DOUBLE_EQ(j["ways"]["threshold_m"].get<double>(), 0.005);
  for (const auto& w : j["ways"]["parts"])
    if (w["part"] == "nut-1") {
      EXPECT_TRUE(w["near_miss"].get<bool>());
      EXPECT_NEAR(w["objects"][0]["least_m"].get<double>(), 0.001015, 1e-5);
      EXPECT_GT(w["swept"]["volume_m3"].get<double>(), 0.0);
    }

  std::stringstream page;
  page << std::ifstream(files.html).rdbuf();
  const std::string h = page.str();
  EXPECT_NE(h.find("<table id='ways'>"), std::string::npos);
  std::size_t rows = 0;
  for (auto at = h.find("<tr class='miss'>"); at != std::string::npos; at = h.find("<tr class='miss'>", at + 1)) ++rows;
  EXPECT_EQ(rows, 2u);
  std::size_t pictures = 0;
  for (auto at = h.find("alt='way home of "); at != std::string::npos; at = h.find("alt='way home of ", at + 1)) ++pictures;
  EXPECT_EQ(pictures, 7u);
  EXPECT_NE(h.find("<b>nut-1</b> down: 1.015 mm from bracket (near miss)"), std::string::npos);
  // The first picture is a near miss's (the nearest pass first).
  EXPECT_LT(h.find("alt='way home of nut-"), h.find("alt='way home of sleeve'"));
}

TEST(Report, ALongOrderIsSummedUpByStepAndPicturedPerStep) {
  // 96 parts in five tiles: past a few dozen parts the page shows a picture per step, not per part, and a
  // summary table of the steps before everything else; the chart has a bar per kind of part.
  const Assembly a = load("tiled-5x1.stp", [](const fs::path& f) { vaw::steptest::writeTiledProduct(f, 5, 1); });
  const SequencePlan plan = vaw::eval::planSequence(a);
  ASSERT_TRUE(plan.complete());
  ASSERT_EQ(plan.order.size(), 96u);
  std::vector<std::size_t> perStep;  // parts per step, in the order
  for (std::size_t i = 0; i < plan.order.size(); ++i)
    if (i == 0 || plan.step[i] != plan.step[i - 1]) perStep.push_back(1);
    else ++perStep.back();
  ASSERT_GT(perStep.size(), 2u);
  const fs::path dir = fs::absolute("report-tiled-5x1");
  const auto files = vaw::report::writeReport(a, plan, {}, dir);
  // three.js (about 0.96 MB) is inlined for the 3D view; the rest is the order's glTF, the pictures and tables.
  EXPECT_LT(fs::file_size(files.html), 2u << 20) << "a page to open, not an archive";

  const std::string chromium = "/usr/bin/chromium";
  ASSERT_TRUE(fs::exists(chromium));
  const std::string flags = " --headless --no-sandbox --disable-gpu --hide-scrollbars --virtual-time-budget=5000 ";
  const std::string dom = run(chromium + flags + "--dump-dom 'file://" + files.html.string() + "' 2>/dev/null");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(dom, m, std::regex("data-pictures-shown=\"(\\d+)\"")));
  EXPECT_EQ(std::stoul(m[1]), perStep.size() + 1) << "the assembly, and one picture per step";
  (void)run(chromium + flags + "--window-size=1200,2400 --screenshot='" + (dir / "report.png").string() + "' 'file://" + files.html.string() +
            "' 2>/dev/null");
  EXPECT_GT(fs::file_size(dir / "report.png"), 20000u) << "a screenshot of the page, to look at";

  // The summary comes first, a row per step with its number of parts, then the total.
  const auto at = dom.find("id=\"summary\"");
  ASSERT_NE(at, std::string::npos);
  EXPECT_LT(at, dom.find("<img")) << "the summary before the pictures";
  const std::string table = dom.substr(at, dom.find("</table>", at) - at);
  const std::regex row("<tr[^>]*>(.*?)</tr>"), cell("<t[dh][^>]*>(.*?)</t[dh]>");
  std::vector<std::vector<std::string>> rows;
  for (auto r = std::sregex_iterator(table.begin(), table.end(), row); r != std::sregex_iterator(); ++r) {
    const std::string body = (*r)[1];
    std::vector<std::string> cells;
    for (auto c = std::sregex_iterator(body.begin(), body.end(), cell); c != std::sregex_iterator(); ++c) cells.push_back((*c)[1]);
    rows.push_back(cells);
  }
  ASSERT_EQ(rows.size(), perStep.size() + 2) << "header, one row per step, total";
  for (std::size_t k = 0; k < perStep.size(); ++k) EXPECT_EQ(rows[k + 1].at(1), std::to_string(perStep[k])) << "step row " << k;
  EXPECT_EQ(rows.back().at(1), "96");
  EXPECT_EQ(rows[1].at(2), "base-plate");
  EXPECT_NE(rows[perStep.size()].at(2).find("nut-1 \u00d75"), std::string::npos) << "the nuts of all five tiles go in last, counted by kind";
  // The chart: one bar per kind (the base left out), named with its count.
  const auto chart = dom.substr(dom.find("aria-label=\"time per part\""));
  std::set<std::string> kinds;
  for (const auto& p : a.parts)
    if (p.id != *a.base) kinds.insert(p.name.substr(0, p.name.rfind(" #") == std::string::npos ? p.name.size() : p.name.rfind(" #")));
  std::size_t bars = 0;
  for (auto at2 = chart.find("<title>estimate"); at2 != std::string::npos; at2 = chart.find("<title>estimate", at2 + 1)) ++bars;
  EXPECT_EQ(bars, kinds.size());
  EXPECT_NE(chart.find("nut-1 (\u00d75)"), std::string::npos);
}

#include <clocale>

#include "vaw/cad_assembly.hpp"

namespace {

// The window runs in the user's locale, which Qt applies to the C library: under a decimal comma
// ("1,5"), what vaw writes for files and reads back keeps its point. The reader's progress reaches the
// window with its stages, a slanted up written by "Put This Face Down" is read back, the report's CSV
// numbers have a point.
TEST(DecimalComma, NumbersKeepTheirPoint) {
  const char* before = std::setlocale(LC_ALL, nullptr);
  const std::string saved = before != nullptr ? before : "C";
  if (std::setlocale(LC_ALL, "de_DE.UTF-8") == nullptr) GTEST_SKIP() << "no de_DE.UTF-8 locale (packaging/install-deps.sh makes it)";
  struct Restore {
    std::string locale;
    ~Restore() { std::setlocale(LC_ALL, locale.c_str()); }
  } restore{saved};
  char comma[16];
  std::snprintf(comma, sizeof comma, "%.1f", 1.5);
  ASSERT_STREQ(comma, "1,5") << "the locale writes a comma";

  EXPECT_EQ(vaw::report::formatNumber(1.5), "1.500");
  EXPECT_EQ(vaw::report::formatNumber(-1234.56789), "-1234.568");

  const fs::path file = vaw::test::tempDir() / "decimal-comma.stp";
  vaw::steptest::writeBoltedRod(file, {4, true, true, false, false, "AP214"});
  double reader = 0.0;
  std::set<std::string> stages;
  const Assembly a = vaw::loadAny(file, vaw::test::importers(), {}, [&](double f, const std::string& stage) {
    if (stage.find("tessellating") != std::string::npos) {
      reader = std::max(reader, f);
      stages.insert(stage);
    }
    return true;
  });
  EXPECT_FALSE(stages.empty()) << "the reader's stages reach the caller";
  EXPECT_GT(reader, 0.0) << "with their fraction";

  const Eigen::Vector3d slanted = Eigen::Vector3d(1, 2, 2).normalized();
  const auto up = vaw::upForFaceDown(a, slanted);
  ASSERT_TRUE(up.has_value());
  EXPECT_EQ(up->find(','), std::string::npos) << *up;
  ASSERT_TRUE(vaw::upDirection(*up).has_value()) << *up;
  EXPECT_TRUE(vaw::validUpChoice(*up)) << *up;
}

}  // namespace
