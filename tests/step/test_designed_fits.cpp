// Assemblies modelled the way designers model fasteners and fits (docs/step.md, "Fits as designers model
// them"; tests/step/step_fixtures.hpp has the geometry): tapped holes at the tap drill with screws at
// nominal, counterbores, countersinks, press-fitted dowels, chamfers and fillets; a bearing as a
// sub-assembly with its balls; a solid written unsewn and one with a void. Each checks what is recognised,
// what overlaps at rest against Open CASCADE's exact boolean common, and the order a fitter would take.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "bundled.hpp"
#include "files.hpp"
#include "step_fixtures.hpp"
#include "vaw/collision/interference.hpp"
#include "vaw/constraint_recognition.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/fits.hpp"
#include "vaw/report/report.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/scene_file.hpp"
#include "vaw/sim/world.hpp"

namespace {

namespace fs = std::filesystem;
using vaw::Assembly;
using vaw::Constraint;
using vaw::PartId;
using vaw::collision::Interference;
using vaw::steptest::DesignerStyle;
using Fit = Constraint::Found::Fit;

Assembly load(const fs::path& file) { return vaw::loadAny(file, vaw::test::importers()); }

PartId id(const Assembly& a, const std::string& name) {
  const auto p = a.findPart(name);
  if (!p) ADD_FAILURE() << "no part " << name;
  return p.value_or(0);
}

// The insert between two parts (either way round), or null.
const Constraint* insertBetween(const Assembly& a, const std::string& x, const std::string& y) {
  const PartId p = id(a, x), q = id(a, y);
  for (const Constraint& c : a.constraints) {
    const PartId partner = c.partner.value_or(*a.base);
    if (c.type == Constraint::Type::Insert && ((c.part == p && partner == q) || (c.part == q && partner == p))) return &c;
  }
  return nullptr;
}

const Interference* overlapOf(const std::vector<Interference>& all, const Assembly& a, const std::string& x, const std::string& y) {
  const PartId p = std::min(id(a, x), id(a, y)), q = std::max(id(a, x), id(a, y));
  for (const Interference& i : all)
    if (i.a == p && i.b == q) return &i;
  return nullptr;
}

struct Variant {
  const char* label;
  DesignerStyle style;
  double mm;  // metres per file unit as the file declares it
};

class FastenedBlock : public ::testing::TestWithParam<Variant> {
 protected:
  static std::map<std::string, Assembly>& cache() {
    static std::map<std::string, Assembly> loaded;
    return loaded;
  }
  const Assembly& assembly() {
    auto it = cache().find(GetParam().label);
    if (it == cache().end()) {
      const fs::path file = vaw::test::tempDir() / (std::string("fastened-") + GetParam().label + ".stp");
      vaw::steptest::writeFastenedBlock(file, GetParam().style);
      it = cache().emplace(GetParam().label, load(file)).first;
    }
    return it->second;
  }
};

std::string label(const ::testing::TestParamInfo<Variant>& info) { return info.param.label; }
void PrintTo(const Variant& v, std::ostream* os) { *os << v.label; }

const Variant kVariants[] = {
    {"Millimetres", {}, 1e-3},
    {"Inches", {true, false, false}, 1e-3},
    {"BSplineFaces", {false, true, false}, 1e-3},
};

TEST_P(FastenedBlock, EveryFitRecognisedWithItsKind) {
  const Assembly& a = assembly();
  ASSERT_EQ(a.parts.size(), 9u);
  EXPECT_EQ(a.parts[*a.base].name, "base");
  int inserts = 0, mates = 0, threaded = 0, press = 0;
  for (const Constraint& c : a.constraints) {
    (c.type == Constraint::Type::Insert ? inserts : mates) += 1;
    if (c.found && c.found->fit == Fit::Threaded) ++threaded;
    if (c.found && c.found->fit == Fit::Press) ++press;
  }
  // The fillets, chamfers and drill points give none.
  EXPECT_EQ(inserts, 12);
  EXPECT_EQ(mates, 6);
  EXPECT_EQ(threaded, 4);
  EXPECT_EQ(press, 2);
  for (const char* screw : {"cap-screw-1", "cap-screw-2"}) {
    const Constraint* thread = insertBetween(a, screw, "base");
    ASSERT_NE(thread, nullptr) << screw;
    ASSERT_TRUE(thread->found);
    EXPECT_EQ(thread->found->fit, Fit::Threaded);
    EXPECT_EQ(thread->found->thread, "M6");
    EXPECT_NEAR(thread->found->interference, 0.5e-3, 1e-7);
    const Constraint* counterbore = insertBetween(a, screw, "bracket");
    ASSERT_NE(counterbore, nullptr) << screw;
    EXPECT_EQ(counterbore->found->fit, Fit::Clearance);
    EXPECT_NEAR(counterbore->found->clearance, 0.2e-3, 1e-7) << "the shank's clearance, the tighter of the counterbore's two";
    EXPECT_EQ(counterbore->found->seat, Constraint::Found::Seat::Counterbore) << screw;
    EXPECT_NEAR(counterbore->found->seatRadius, 5.5e-3, 1e-7);
    EXPECT_EQ(thread->found->seat, Constraint::Found::Seat::None) << "a thread is no counterbore";
  }
  int counterbores = 0;
  for (const Constraint& c : a.constraints) counterbores += c.found && c.found->seat == Constraint::Found::Seat::Counterbore ? 1 : 0;
  EXPECT_EQ(counterbores, 2) << "the dowels' and the countersunk screws' fits are no counterbores";
  for (const char* screw : {"csk-screw-1", "csk-screw-2"}) {
    const Constraint* thread = insertBetween(a, screw, "bracket");
    ASSERT_NE(thread, nullptr) << screw;
    EXPECT_EQ(thread->found->fit, Fit::Threaded);
    EXPECT_EQ(thread->found->thread, "M5");
    // The head's 90 degree cone in the cover's countersink (r 2.75 at the hole to r 5 at the cover's top):
    // the seat of the shank's insert in the cover, whose fit stays the shank's (r 2.5 in r 2.75).
    const Constraint* countersink = insertBetween(a, screw, "cover");
    ASSERT_NE(countersink, nullptr) << screw;
    EXPECT_EQ(countersink->found->seat, Constraint::Found::Seat::Countersink) << screw;
    EXPECT_NEAR(countersink->found->seatRadius, 5.0e-3, 1e-6);
    EXPECT_NEAR(countersink->found->seatAngle, 0.25 * M_PI, 1e-4);
    EXPECT_EQ(countersink->found->fit, Fit::Clearance);
    EXPECT_NEAR(countersink->found->clearance, 0.25e-3, 1e-7);
    EXPECT_EQ(thread->found->seat, Constraint::Found::Seat::None) << "the drill point under the thread is no seat";
  }
  int countersinks = 0;
  for (const Constraint& c : a.constraints)
    countersinks += c.found && c.found->seat == Constraint::Found::Seat::Countersink ? 1 : 0;
  EXPECT_EQ(countersinks, 2) << "the chamfers and the drill points are no countersinks";
  for (const char* dowel : {"dowel-1", "dowel-2"}) {
    const Constraint* pressed = insertBetween(a, dowel, "base");
    ASSERT_NE(pressed, nullptr) << dowel;
    EXPECT_EQ(pressed->found->fit, Fit::Press);
    EXPECT_NEAR(pressed->found->interference, 3e-6, 1e-7);
    EXPECT_EQ(insertBetween(a, dowel, "bracket")->found->fit, Fit::Clearance);
  }
}

TEST_P(FastenedBlock, OverlapsAtRestMeasuredAgainstTheExactCommonVolume) {
  const Assembly& a = assembly();
  const auto all = vaw::collision::interferences(a, vaw::collision::assembledPoses(a));
  std::map<Interference::Kind, int> count;
  for (const Interference& i : all) ++count[i.kind];
  EXPECT_EQ(count[Interference::Kind::Clash], 0);
  EXPECT_EQ(count[Interference::Kind::Threaded], 4);
  EXPECT_EQ(count[Interference::Kind::Press], 2);
  // The designed band is the modelled cylinders' (pi (R^2 - r^2) times their axial overlap): the exact
  // common volume adds the screw tip's chamfer, about 2 % of an M6's.
  const struct {
    const char *a, *b;
    Interference::Kind kind;
    double depth;  // m
  } expected[] = {{"base", "cap-screw-1", Interference::Kind::Threaded, 0.5e-3}, {"bracket", "csk-screw-2", Interference::Kind::Threaded, 0.4e-3},
                  {"base", "dowel-1", Interference::Kind::Press, 3e-6}};
  for (const auto& e : expected) {
    const Interference* i = overlapOf(all, a, e.a, e.b);
    ASSERT_NE(i, nullptr) << e.a << " and " << e.b;
    EXPECT_EQ(i->kind, e.kind) << e.a << " and " << e.b;
    const double exact = vaw::steptest::fastenedBlockOverlap(e.a, e.b) * 1e-9;
    EXPECT_NEAR(i->volume, exact, 0.05 * exact) << e.a << " and " << e.b;
    EXPECT_NEAR(i->depth, e.depth, 1e-7);
  }
  EXPECT_EQ(overlapOf(all, a, "cap-screw-1", "base")->thread, "M6");
}

TEST_P(FastenedBlock, OrderAsAFitterPutsItTogether) {
  const Assembly& a = assembly();
  const vaw::eval::SequencePlan plan = vaw::eval::planSequence(a);
  ASSERT_TRUE(plan.complete());
  const auto at = [&](const char* name) {
    return std::find(plan.order.begin(), plan.order.end(), id(a, name)) - plan.order.begin();
  };
  // Dowels before what they locate, the bracket before its cap screws, the cover over the cap screws, the
  // countersunk screws through the cover.
  for (const char* dowel : {"dowel-1", "dowel-2"}) EXPECT_LT(at(dowel), at("bracket"));
  for (const char* screw : {"cap-screw-1", "cap-screw-2"}) {
    EXPECT_LT(at("bracket"), at(screw));
    EXPECT_LT(at(screw), at("cover"));
  }
  for (const char* screw : {"csk-screw-1", "csk-screw-2"}) EXPECT_LT(at("cover"), at(screw));
  // Each screw goes home along its axis through its thread, never "blocked at once" by it.
  for (const char* screw : {"cap-screw-1", "csk-screw-1"}) {
    const vaw::eval::Direction* way = plan.wayOf(id(a, screw));
    ASSERT_NE(way, nullptr);
    EXPECT_TRUE(way->alongAxis) << screw;
  }
}

INSTANTIATE_TEST_SUITE_P(Styles, FastenedBlock, ::testing::ValuesIn(kVariants), label);

class KeyedHub : public ::testing::TestWithParam<Variant> {
 protected:
  const Assembly& assembly() {
    static std::map<std::string, Assembly> loaded;
    auto it = loaded.find(GetParam().label);
    if (it == loaded.end()) {
      const fs::path file = vaw::test::tempDir() / (std::string("keyed-hub-") + GetParam().label + ".stp");
      vaw::steptest::writeKeyedHub(file, GetParam().style);
      it = loaded.emplace(GetParam().label, load(file)).first;
    }
    return it->second;
  }
};

// The key fits (two parallel faces between two of the partner's) between two parts, either way round.
std::vector<const Constraint*> keyFits(const Assembly& a, const std::string& x, const std::string& y) {
  std::vector<const Constraint*> out;
  const PartId p = id(a, x), q = id(a, y);
  for (const Constraint& c : a.constraints) {
    const PartId partner = c.partner.value_or(*a.base);
    if (c.found && c.found->keyWidth > 0.0 && ((c.part == p && partner == q) || (c.part == q && partner == p))) out.push_back(&c);
  }
  return out;
}

TEST_P(KeyedHub, TheKeyIsOneFitInItsKeywayAndOneInTheHubsSlot) {
  const Assembly& a = assembly();
  ASSERT_EQ(a.parts.size(), 4u);
  EXPECT_EQ(a.parts[*a.base].name, "base");
  int keys = 0;
  for (const Constraint& c : a.constraints) keys += c.found && c.found->keyWidth > 0.0 ? 1 : 0;
  EXPECT_EQ(keys, 2) << "the chamfers, the key's round ends and its floor are no key fits";
  for (const char* holder : {"shaft", "hub"}) {
    const std::vector<const Constraint*> fits = keyFits(a, "key", holder);
    ASSERT_EQ(fits.size(), 1u) << holder;
    EXPECT_EQ(fits[0]->type, Constraint::Type::Mate);
    EXPECT_NEAR(fits[0]->found->keyWidth, 6e-3, 1e-6) << holder;
    // Its sides are perpendicular to the key's width (world y: the key stands on the shaft's +x side).
    const vaw::Part& partner = a.parts[fits[0]->partner.value_or(*a.base)];
    const Eigen::Vector3d n = (partner.finalPose->linear() * fits[0]->basePlane.normal).normalized();
    EXPECT_NEAR(std::abs(n.y()), 1.0, 1e-6) << holder;
  }
  // The hub's bore on the shaft, 10 um of play; the key's floor on the keyway's and its round ends in the
  // keyway's are the key's other constraints.
  const Constraint* bore = insertBetween(a, "hub", "shaft");
  ASSERT_NE(bore, nullptr);
  EXPECT_NEAR(bore->found->clearance, 0.01e-3, 1e-7);
}

TEST_P(KeyedHub, TheKeyGoesInBeforeTheHub) {
  const Assembly& a = assembly();
  const vaw::eval::SequencePlan plan = vaw::eval::planSequence(a);
  ASSERT_TRUE(plan.complete());
  const auto at = [&](const char* name) {
    return std::find(plan.order.begin(), plan.order.end(), id(a, name)) - plan.order.begin();
  };
  EXPECT_LT(at("shaft"), at("key"));
  EXPECT_LT(at("key"), at("hub"));
}

INSTANTIATE_TEST_SUITE_P(Styles, KeyedHub, ::testing::ValuesIn(kVariants), label);

TEST(KeyedHubScene, KeyFitsAreSavedWithTheScene) {
  const fs::path file = vaw::test::tempDir() / "keyed-hub-saved.stp";
  vaw::steptest::writeKeyedHub(file);
  const Assembly a = load(file);
  const fs::path scene = file.parent_path() / "keyed-hub-saved.vaw.json";
  vaw::sim::saveScene(a, vaw::sim::World(a, vaw::sim::settingsFor(a)), scene);
  const Assembly b = load(scene);
  ASSERT_EQ(b.constraints.size(), a.constraints.size());
  int keys = 0;
  for (std::size_t i = 0; i < a.constraints.size(); ++i) {
    ASSERT_TRUE(b.constraints[i].found.has_value());
    EXPECT_NEAR(b.constraints[i].found->keyWidth, a.constraints[i].found->keyWidth, 1e-12) << a.constraints[i].name;
    keys += b.constraints[i].found->keyWidth > 0.0 ? 1 : 0;
  }
  EXPECT_EQ(keys, 2);
}

TEST(FastenedBlockScene, FitsAndSeatsAreSavedWithTheScene) {
  const fs::path file = vaw::test::tempDir() / "fastened-saved.stp";
  vaw::steptest::writeFastenedBlock(file);
  const Assembly a = load(file);
  const fs::path scene = file.parent_path() / "fastened-saved.vaw.json";
  vaw::sim::saveScene(a, vaw::sim::World(a, vaw::sim::settingsFor(a)), scene);
  const Assembly b = load(scene);
  ASSERT_EQ(b.constraints.size(), a.constraints.size());
  for (std::size_t i = 0; i < a.constraints.size(); ++i) {
    ASSERT_TRUE(b.constraints[i].found.has_value());
    EXPECT_EQ(b.constraints[i].found->fit, a.constraints[i].found->fit) << a.constraints[i].name;
    EXPECT_EQ(b.constraints[i].found->seat, a.constraints[i].found->seat) << a.constraints[i].name;
    EXPECT_NEAR(b.constraints[i].found->seatRadius, a.constraints[i].found->seatRadius, 1e-12);
    EXPECT_NEAR(b.constraints[i].found->seatAngle, a.constraints[i].found->seatAngle, 1e-12);
  }
}

TEST(FastenedBlockClash, AClashIsMeasuredShownAndPassedThroughWithANote) {
  const fs::path file = vaw::test::tempDir() / "fastened-clash.stp";
  vaw::steptest::writeFastenedBlock(file, {false, false, true});
  const Assembly a = load(file);
  // The dowel drawn 0.3 mm too large in radius is no press fit, so no insert; but a near miss in both its
  // holes, with the test that refused it and its measure.
  EXPECT_EQ(insertBetween(a, "dowel-1", "base"), nullptr);
  const std::vector<vaw::NearMiss> misses = vaw::nearMisses(a);
  ASSERT_EQ(misses.size(), 2u);
  for (const vaw::NearMiss& m : misses) {
    EXPECT_EQ(a.parts[m.b].name, "dowel-1");
    EXPECT_TRUE(a.parts[m.a].name == "base" || a.parts[m.a].name == "bracket") << a.parts[m.a].name;
    EXPECT_EQ(m.type, vaw::Constraint::Type::Insert);
    // r 3.3 in the base's r 3 hole and the bracket's r 3.01.
    EXPECT_NEAR(m.value, a.parts[m.a].name == "base" ? 0.3e-3 : 0.29e-3, 1e-7) << m.why;
    EXPECT_NE(m.why.find("0.3 mm larger in radius than the bore"), std::string::npos) << m.why;
  }
  const auto all = vaw::collision::interferences(a, vaw::collision::assembledPoses(a));
  const Interference* clash = overlapOf(all, a, "base", "dowel-1");
  ASSERT_NE(clash, nullptr);
  EXPECT_EQ(clash->kind, Interference::Kind::Clash);
  const double exact = vaw::steptest::fastenedBlockOverlap("base", "dowel-1", {false, false, true}) * 1e-9;
  EXPECT_NEAR(clash->volume, exact, 0.05 * exact);
  // The overlap's thickness is 0.3 mm; measured along the file's axes it reads up to half as much again.
  EXPECT_GT(clash->depth, 0.25e-3);
  EXPECT_LT(clash->depth, 0.5e-3);
  EXPECT_NEAR(clash->where.y(), a.parts[id(a, "dowel-1")].finalPose->translation().y(), 0.5e-3);
  // Clashes come first.
  EXPECT_EQ(all.front().kind, Interference::Kind::Clash);

  const vaw::eval::SequencePlan plan = vaw::eval::planSequence(a);
  EXPECT_TRUE(plan.complete()) << "a clash is passed through, not blocked at once";
  const vaw::eval::Direction* way = plan.wayOf(id(a, "dowel-1"));
  ASSERT_NE(way, nullptr);
  EXPECT_NE(way->from.find("through its clash with base"), std::string::npos) << way->from;
}

TEST(FastenedBlockClash, TheReportListsWhatOverlapsClashesFirst) {
  const fs::path file = vaw::test::tempDir() / "fastened-clash-report.stp";
  vaw::steptest::writeFastenedBlock(file, {false, false, true});
  const Assembly a = load(file);
  const auto all = vaw::collision::interferences(a, vaw::collision::assembledPoses(a));
  const fs::path dir = vaw::test::tempDir() / "fastened-clash-report";
  const auto files = vaw::report::writeReport(a, vaw::eval::planSequence(a), {}, dir, {}, nullptr, &all);
  ASSERT_FALSE(files.interferencesCsv.empty());
  std::ifstream in(files.interferencesCsv);
  std::string header, first;
  std::getline(in, header);
  std::getline(in, first);
  EXPECT_EQ(header, "kind,thread,part,with,volume_mm3,depth_mm,x_mm,y_mm,z_mm");
  EXPECT_EQ(first.rfind("clash,,base,dowel-1,", 0), 0u) << first;
  std::ifstream page(files.html);
  const std::string html((std::istreambuf_iterator<char>(page)), std::istreambuf_iterator<char>());
  EXPECT_NE(html.find("<h2>Interferences at rest</h2>"), std::string::npos);
  EXPECT_NE(html.find("2 clash(es)"), std::string::npos);
}

TEST(BearingUnit, ABearingWithItsBallsIsOnePartAndGoesInWhole) {
  const fs::path file = vaw::test::tempDir() / "bearing.stp";
  vaw::steptest::writeBearingInHousing(file);
  const Assembly a = load(file);
  ASSERT_EQ(a.parts.size(), 3u);
  const vaw::Part& bearing = a.parts[id(a, "bearing")];
  EXPECT_EQ(bearing.unitMembers.size(), 10u);
  EXPECT_NE(std::find(bearing.unitMembers.begin(), bearing.unitMembers.end(), "ball-3"), bearing.unitMembers.end());
  EXPECT_NE(bearing.unitReason.find("ball-"), std::string::npos) << bearing.unitReason;
  // Its mass is its parts' together: the rings' and eight balls' volumes.
  const double ball = 4.0 / 3.0 * M_PI * std::pow(1.75e-3, 3);
  EXPECT_GT(bearing.mass.volume, 8 * ball);
  // The tree shows it as a part holding its parts by name.
  bool shown = false;
  for (const vaw::TreeNode& n : a.tree.children)
    if (n.name == "bearing") shown = n.kind == vaw::TreeNode::Kind::Part && n.children.size() == 10;
  EXPECT_TRUE(shown);
  const vaw::eval::SequencePlan plan = vaw::eval::planSequence(a);
  ASSERT_TRUE(plan.complete());
  EXPECT_LT(std::find(plan.order.begin(), plan.order.end(), id(a, "bearing")), std::find(plan.order.begin(), plan.order.end(), id(a, "shaft")));

  // Taken apart on request: its ten parts, the balls among them.
  vaw::LoadOptions apart;
  apart.cadSplit = {"bearing"};
  const Assembly parts = vaw::loadAny(file, vaw::test::importers(), apart);
  EXPECT_EQ(parts.parts.size(), 12u);
  EXPECT_TRUE(parts.findPart("ball-1").has_value());
  EXPECT_TRUE(parts.parts[*parts.findPart("ring-inner")].unitMembers.empty());
}

TEST(Units, TheUsersChoicesAreSavedWithTheSceneAndWhatNamesNoSubAssemblyIsSaid) {
  const fs::path file = vaw::test::tempDir() / "bearing-saved-apart.stp";
  vaw::steptest::writeBearingInHousing(file);
  vaw::LoadOptions apart;
  apart.cadSplit = {"bearing"};
  const Assembly a = vaw::loadAny(file, vaw::test::importers(), apart);
  ASSERT_EQ(a.parts.size(), 12u);
  const fs::path scene = file.parent_path() / "bearing-saved-apart.vaw.json";
  vaw::sim::saveScene(a, vaw::sim::World(a, vaw::sim::settingsFor(a)), scene);
  std::ifstream in(scene);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\"units_apart\": [\n      \"bearing\"\n    ]"), std::string::npos) << text;
  // Opened again, the bearing stays apart; asked now to be one unit, it is one, and saved so.
  const Assembly b = load(scene);
  EXPECT_EQ(b.parts.size(), 12u);
  EXPECT_EQ(b.cadSplit, (std::set<std::string>{"bearing"}));
  vaw::LoadOptions whole;
  whole.cadJoin = {"bearing"};
  const Assembly c = vaw::loadAny(scene, vaw::test::importers(), whole);
  EXPECT_EQ(c.parts.size(), 3u);
  EXPECT_TRUE(c.cadSplit.empty());
  // Its saved constraints named the rings: with the unit they are found anew, and that is said.
  EXPECT_TRUE(std::any_of(c.warnings.begin(), c.warnings.end(), [](const vaw::Diagnostic& w) { return w.field == "cad.units_apart"; }));
  EXPECT_TRUE(std::any_of(c.constraints.begin(), c.constraints.end(), [&](const Constraint& k) { return c.parts[k.part].name == "bearing"; }));

  // A scene naming a sub-assembly the file no longer has opens with a warning naming it.
  const fs::path stale = file.parent_path() / "bearing-renamed.vaw.json";
  std::ofstream(stale) << R"({"format": "vaw-scene", "version": 3, "name": "renamed", "units": "m",
    "cad": {"file": "bearing-saved-apart.stp", "units_apart": ["bearing-608"]}})";
  const Assembly d = load(stale);
  EXPECT_EQ(d.parts.size(), 3u);
  const auto said = std::find_if(d.warnings.begin(), d.warnings.end(), [](const vaw::Diagnostic& w) { return w.field == "units_apart"; });
  ASSERT_NE(said, d.warnings.end());
  EXPECT_NE(said->found.find("\"bearing-608\", which names none"), std::string::npos) << said->found;

  // A name that is no string is refused, naming the field.
  std::string bad = text;
  bad.replace(bad.find("\"bearing\"\n    ]"), 9, "3");
  const fs::path broken = file.parent_path() / "bearing-broken.vaw.json";
  std::ofstream(broken) << bad;
  try {
    (void)load(broken);
    ADD_FAILURE() << "a number as a sub-assembly's name was accepted";
  } catch (const vaw::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cad.units_apart[0]"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("the instance name of a sub-assembly"), std::string::npos) << e.what();
  }
}

TEST(Units, ASubAssemblyThatComesApartIsPartsUnlessJoined) {
  // The bolted bracket's pin and sleeve come apart: two parts, or one when asked.
  const fs::path file = vaw::test::tempDir() / "bolted-bracket-units.stp";
  vaw::steptest::writeBoltedBracket(file);
  const Assembly parts = load(file);
  EXPECT_TRUE(parts.findPart("pin") && parts.findPart("sleeve"));
  vaw::LoadOptions joined;
  joined.cadJoin = {"pin-assembly"};
  const Assembly unit = vaw::loadAny(file, vaw::test::importers(), joined);
  ASSERT_EQ(unit.parts.size(), parts.parts.size() - 1);
  const vaw::Part& p = unit.parts[id(unit, "pin-assembly")];
  EXPECT_EQ(p.unitMembers, (std::vector<std::string>{"pin", "sleeve"}));
  EXPECT_EQ(p.unitReason, "joined as one unit");
  EXPECT_NEAR(p.mass.mass, parts.parts[id(parts, "pin")].mass.mass + parts.parts[id(parts, "sleeve")].mass.mass, 1e-9);
}

TEST(UnsewnAndHollow, AnUnsewnSolidIsSewnAndAVoidKeepsItsVolumeAndInertia) {
  const fs::path file = vaw::test::tempDir() / "unsewn-hollow.stp";
  vaw::steptest::writeUnsewnAndHollow(file);
  const Assembly a = load(file);
  ASSERT_EQ(a.parts.size(), 2u);
  const vaw::Part& unsewn = a.parts[id(a, "unsewn-box")];
  EXPECT_NEAR(unsewn.mass.volume, 40e-3 * 30e-3 * 20e-3, 1e-12);
  bool said = false;
  for (const auto& w : a.warnings) said = said || w.message().find("sewn into 1 closed solid") != std::string::npos;
  EXPECT_TRUE(said);
  const vaw::Part& hollow = a.parts[id(a, "hollow-box")];
  const double outer = 0.04, inner = 0.02;
  EXPECT_NEAR(hollow.mass.volume, outer * outer * outer - inner * inner * inner, 1e-12);
  // About its centre, a cube of side s and density rho has I = rho s^5 / 6 about each axis.
  const double rho = hollow.mass.density;
  const double I = rho * (std::pow(outer, 5) - std::pow(inner, 5)) / 6.0;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(hollow.mass.inertiaCm(k, k), I, 1e-6 * I);
  EXPECT_TRUE(vaw::checkMesh(*hollow.mesh).valid());
}

TEST(Fits, ThreadsAndPressFitsAsTabled) {
  const auto threaded = vaw::designedInterference(3.0e-3, 2.5e-3);
  ASSERT_TRUE(threaded);
  EXPECT_EQ(threaded->thread, "M6");
  EXPECT_EQ(vaw::designedInterference(2.5e-3, 2.1e-3)->thread, "M5");
  // 1/4-20 UNC: nominal 6.35 mm, tap drill #7 (5.11 mm).
  EXPECT_EQ(vaw::designedInterference(0.125 * 0.0254, 5.11e-3 / 2)->thread, "1/4-20 UNC");
  EXPECT_EQ(vaw::designedInterference(3.003e-3, 3.0e-3)->fit, Fit::Press);
  // An M6 shank in a 4 mm hole is neither: the hole is smaller than any M6 tap drill.
  EXPECT_FALSE(vaw::designedInterference(3.0e-3, 2.0e-3));
  // Nor is a 6.6 mm pin in a 6 mm hole (5 % interference).
  EXPECT_FALSE(vaw::designedInterference(3.3e-3, 3.0e-3));
}

}  // namespace
