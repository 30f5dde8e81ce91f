// Which order puts an assembly together, from its geometry: on STEP assemblies the fixtures write with
// Open CASCADE, the precedence and order found are the ones the geometry forces, and a part that no order
// can insert is named with what blocks it.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>

#include "bundled.hpp"
#include "files.hpp"
#include "step_fixtures.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/scene_loader.hpp"

namespace {

namespace fs = std::filesystem;
using vaw::Assembly;
using vaw::PartId;
using vaw::eval::Precedence;
using vaw::eval::SequencePlan;

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
  std::printf("[ info ] order: %s; %d pair sweeps, %d checks\n", names(a, plan.order).c_str(), plan.sweeps, plan.evaluations);

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
