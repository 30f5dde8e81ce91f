// A STEP assembly made ready to assemble, and assembled: the constraints found in the bolted bracket's
// geometry (in millimetres, in inches, with every face a B-spline), the layout on the table, saving and
// reopening, and parts mated to parts in the world (a stud into the plate, the bracket over the studs, a
// nut onto a stud, refused before its stud). The files are written by the fixtures with Open CASCADE.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <numbers>
#include <set>
#include <sstream>

#include "assembler.hpp"
#include "bundled.hpp"
#include "files.hpp"
#include "step_fixtures.hpp"
#include "vaw/constraint_recognition.hpp"
#include "vaw/cad_assembly.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/scene_file.hpp"
#include "vaw/sim/world.hpp"

namespace {

namespace fs = std::filesystem;
using vaw::Assembly;
using vaw::Constraint;
using vaw::PartId;
using vaw::interact::PartState;

fs::path bracketFile(const vaw::steptest::FixtureOptions& options = {}) {
  const fs::path file = vaw::test::tempDir() / "bolted-bracket.stp";
  vaw::steptest::writeBoltedBracket(file, options);
  return file;
}

Assembly loadStep(const fs::path& file) { return vaw::loadAny(file, vaw::test::importers()); }

std::string partnerOf(const Assembly& a, const Constraint& c) { return a.parts[c.partner.value_or(*a.base)].name; }

// "kind part partner clearance-in-um" for every constraint, sorted.
std::multiset<std::string> described(const Assembly& a) {
  std::multiset<std::string> out;
  for (const Constraint& c : a.constraints) {
    std::ostringstream s;
    s << name(c.type) << ' ' << a.parts[c.part].name << ' ' << partnerOf(a, c);
    if (c.type == Constraint::Type::Insert) {
      s << ' ' << std::lround(c.found->clearance * 1e6);
      // The part's own radius first: the bracket's bore on a stud, the nut's bore on a stud, a stud in a hole.
      EXPECT_NEAR(c.found->partnerRadius - c.found->partRadius, (c.found->partRadius > c.found->partnerRadius ? -1 : 1) * c.found->clearance, 1e-12);
      const std::string part = a.parts[c.part].name;
      const double own = part == "bracket" ? 0.0065 : part == "sleeve" ? 0.0052 : part == "pin" ? 0.005 : 0.006;
      EXPECT_NEAR(c.found->partRadius, own, 1e-9) << c.name;
    }
    out.insert(s.str());
  }
  return out;
}

const std::multiset<std::string> kExpected = {
    "insert stud-1 base-plate 0",   "mate stud-1 base-plate",    "insert stud-2 base-plate 0", "mate stud-2 base-plate",
    "insert pin base-plate 0",      "mate pin base-plate",       "mate bracket base-plate",    "insert bracket stud-1 500",
    "insert bracket stud-2 500",    "insert nut-1 stud-1 0",     "mate nut-1 bracket",         "insert nut-2 stud-2 0",
    "mate nut-2 bracket",           "insert sleeve pin 200",     "mate sleeve base-plate"};

// Where a constraint's partner geometry lies in the world at the assembled pose.
Eigen::Isometry3d partnerPose(const Assembly& a, const Constraint& c) {
  return c.partner ? *a.parts[*c.partner].finalPose : a.parts[*a.base].pose;
}

void expectBracketConstraints(const Assembly& a) {
  ASSERT_TRUE(a.base.has_value());
  EXPECT_EQ(a.parts[*a.base].name, "base-plate") << "the heaviest part is the base";
  EXPECT_EQ(described(a), kExpected);
  // Every insert's axis is vertical and passes through its hole: (40, 40), (80, 40) or (105, 15) mm from the
  // plate's corner; every mate's plane is horizontal. Geometry in each one's frame must agree at the
  // assembled pose (the part's plane or axis onto the partner's).
  Eigen::AlignedBox3d plate;
  for (const auto& v : a.parts[*a.base].mesh->vertices) plate.extend(a.parts[*a.base].pose * v);
  for (const Constraint& c : a.constraints) {
    const Eigen::Isometry3d P = *a.parts[c.part].finalPose, B = partnerPose(a, c);
    if (c.type == Constraint::Type::Insert) {
      const Eigen::Vector3d u = B.linear() * c.baseAxis.direction, o = B * c.baseAxis.point;
      EXPECT_NEAR(std::abs(u.z()), 1.0, 1e-9) << c.name;
      const Eigen::Vector2d hole = (o - plate.min()).head<2>() * 1e3;
      const bool known = (hole - Eigen::Vector2d(40, 40)).norm() < 1e-6 || (hole - Eigen::Vector2d(80, 40)).norm() < 1e-6 ||
                         (hole - Eigen::Vector2d(105, 15)).norm() < 1e-6;
      EXPECT_TRUE(known) << c.name << " at " << hole.transpose() << " mm";
      const Eigen::Vector3d up = P.linear() * c.partAxis.direction, op = P * c.partAxis.point;
      EXPECT_NEAR(std::abs(up.dot(u)), 1.0, 1e-9) << c.name;
      EXPECT_LT(((op - o) - u * u.dot(op - o)).norm(), 1e-9) << c.name;
      EXPECT_TRUE((B.linear() * c.homeDirection).isApprox(Eigen::Vector3d::UnitZ(), 1e-9)) << c.name << ": comes from above";
    } else {
      const Eigen::Vector3d n = B.linear() * c.basePlane.normal;
      EXPECT_NEAR(n.z(), 1.0, 1e-9) << c.name << ": the partner's face looks up at the part";
      EXPECT_NEAR((P.linear() * c.partPlane.normal).dot(n), -1.0, 1e-9) << c.name;
      EXPECT_NEAR(n.dot(P * c.partPlane.point - B * c.basePlane.point), 0.0, 1e-9) << c.name;
      EXPECT_GT(c.found->overlap, 0.0) << c.name;
    }
  }
}

TEST(StepAssembly, BoltedBracketGivesExactlyTheExpectedConstraints) {
  const Assembly a = loadStep(bracketFile());
  ASSERT_EQ(a.parts.size(), 8u);
  expectBracketConstraints(a);
  for (const Constraint& c : a.constraints) EXPECT_FALSE(c.found->fromSpline) << c.name;
  // The bracket's flange on the plate: 70 x 34 mm less its two 6.5 mm holes, within the tessellation's error.
  for (const Constraint& c : a.constraints)
    if (c.name == "mate bracket on base-plate") {
      EXPECT_NEAR(c.found->overlap * 1e6, 70.0 * 34.0 - 2.0 * std::numbers::pi * 6.5 * 6.5, 3.0);
    }
}

TEST(StepAssembly, TheSameAssemblyInInchesGivesTheSameConstraintsAndPoses) {
  const Assembly mm = loadStep(bracketFile());
  const fs::path inchFile = vaw::test::tempDir() / "bolted-bracket-inch.stp";
  vaw::steptest::writeBoltedBracket(inchFile, {.inches = true});
  const Assembly inch = loadStep(inchFile);
  expectBracketConstraints(inch);
  ASSERT_EQ(inch.parts.size(), mm.parts.size());
  for (PartId id = 0; id < mm.parts.size(); ++id) {
    EXPECT_EQ(inch.parts[id].name, mm.parts[id].name);
    EXPECT_NEAR(inch.parts[id].mass.volume / mm.parts[id].mass.volume, 1.0, 1e-9) << mm.parts[id].name;
    EXPECT_LT((inch.parts[id].pose.matrix() - mm.parts[id].pose.matrix()).norm(), 1e-9) << mm.parts[id].name;
  }
}

TEST(StepAssembly, BsplineFacesAreRecognisedAsTheirPlanesAndCylinders) {
  const Assembly a = loadStep(bracketFile({.bsplineFaces = true}));
  expectBracketConstraints(a);
  for (const Constraint& c : a.constraints) EXPECT_TRUE(c.found->fromSpline) << c.name;
}

TEST(StepAssembly, PartsTouchingAtAnEdgeAreNoConstraint) {
  const fs::path file = vaw::test::tempDir() / "edge.stp";
  vaw::steptest::writeEdgeTouchingBoxes(file);
  const Assembly a = loadStep(file);
  ASSERT_EQ(a.parts.size(), 2u);
  EXPECT_TRUE(a.constraints.empty()) << a.constraints.front().name;
}

TEST(StepAssembly, PartsAreLaidOutOnTheTableWithoutOverlapInTheirAssembledOrientation) {
  const Assembly a = loadStep(bracketFile());
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const auto& p : a.parts) {
    Eigen::AlignedBox3d b;
    for (const auto& v : p.mesh->vertices) b.extend(p.pose * v);
    EXPECT_NEAR(b.min().z(), 0.0, 1e-9) << p.name << " rests on the table top";
    if (p.finalPose) {
      EXPECT_TRUE(p.pose.linear().isApprox(p.finalPose->linear(), 1e-12)) << p.name << " stands as assembled";
    }
    boxes.push_back(b);
  }
  for (std::size_t i = 0; i < boxes.size(); ++i)
    for (std::size_t j = i + 1; j < boxes.size(); ++j) {
      const Eigen::AlignedBox3d common = boxes[i].intersection(boxes[j]);
      EXPECT_TRUE(common.isEmpty() || (common.sizes().array() <= 1e-9).any()) << a.parts[i].name << " and " << a.parts[j].name;
    }
  ASSERT_EQ(a.environment.size(), 1u);
  Eigen::AlignedBox3d table;
  for (const auto& v : a.environment[0].mesh->vertices) table.extend(a.environment[0].pose * v);
  EXPECT_NEAR(table.max().z(), 0.0, 1e-12);
  for (const auto& b : boxes) EXPECT_TRUE(table.contains(Eigen::Vector3d(b.center().x(), b.center().y(), -0.01)));
}

TEST(StepAssembly, ASavedSceneReopensIdenticallyAndNoticesAChangedFile) {
  const fs::path file = bracketFile();
  const Assembly a = loadStep(file);
  const vaw::sim::World world(a, vaw::sim::settingsFor(a));
  const fs::path scene = file.parent_path() / "bolted-bracket.vaw.json";
  vaw::sim::saveScene(a, world, scene);
  const Assembly b = vaw::loadAny(scene, vaw::test::importers());
  EXPECT_EQ(b.source, scene);
  EXPECT_EQ(b.cadFile, file);
  ASSERT_EQ(b.parts.size(), a.parts.size());
  EXPECT_EQ(b.base, a.base);
  ASSERT_EQ(b.constraints.size(), a.constraints.size());
  for (std::size_t i = 0; i < a.constraints.size(); ++i) {
    EXPECT_EQ(b.constraints[i].name, a.constraints[i].name);
    EXPECT_EQ(b.constraints[i].partner, a.constraints[i].partner);
    EXPECT_LT((b.constraints[i].homeDirection - a.constraints[i].homeDirection).norm(), 1e-12);
    ASSERT_TRUE(b.constraints[i].found.has_value());
    EXPECT_EQ(b.constraints[i].found->clearance, a.constraints[i].found->clearance);
    EXPECT_EQ(b.constraints[i].found->overlap, a.constraints[i].found->overlap);
    if (a.constraints[i].type == Constraint::Type::Insert) {
      EXPECT_LT((b.constraints[i].baseAxis.point - a.constraints[i].baseAxis.point).norm(), 1e-12);
      EXPECT_LT((b.constraints[i].partAxis.direction - a.constraints[i].partAxis.direction).norm(), 1e-12);
    } else {
      EXPECT_LT((b.constraints[i].basePlane.normal - a.constraints[i].basePlane.normal).norm(), 1e-12);
      EXPECT_LT((b.constraints[i].partPlane.point - a.constraints[i].partPlane.point).norm(), 1e-12);
    }
  }
  for (PartId id = 0; id < a.parts.size(); ++id) EXPECT_TRUE(b.parts[id].pose.isApprox(a.parts[id].pose, 1e-12));
  EXPECT_EQ(vaw::sim::Scene::build(b)->contentHash(), vaw::sim::Scene::build(Assembly(a))->contentHash());

  // The file is known by the XXH3 hash of its bytes; a scene saved when it was FNV-1a's still matches.
  EXPECT_EQ(a.cadHash, vaw::fileContentHash(file));
  EXPECT_TRUE(a.cadHash.starts_with("xxh3:")) << a.cadHash;
  const auto hashWarned = [](const Assembly& x) {
    return std::any_of(x.warnings.begin(), x.warnings.end(), [](const auto& w) { return w.field == "cad.hash"; });
  };
  EXPECT_FALSE(hashWarned(b));
  std::string text;
  {
    std::ifstream in(scene);
    text.assign(std::istreambuf_iterator<char>(in), {});
  }
  const auto withHash = [&](const std::string& hash) {
    std::string t = text;
    t.replace(t.find(a.cadHash), a.cadHash.size(), hash);
    const fs::path older = file.parent_path() / "bolted-bracket-older.vaw.json";
    std::ofstream(older) << t;
    return vaw::loadAny(older, vaw::test::importers());
  };
  EXPECT_FALSE(hashWarned(withHash(vaw::fileContentHashFnv(file))));
  EXPECT_TRUE(hashWarned(withHash("fnv1a64:0123456789abcdef")));

  // The file changes on disk: the scene still opens, with a warning that names the hash.
  { std::ofstream(file, std::ios::app) << "\n"; }
  const Assembly c = vaw::loadAny(scene, vaw::test::importers());
  bool warned = false;
  for (const auto& w : c.warnings) warned = warned || (w.field == "cad.hash" && w.found.find("changed since") != std::string::npos);
  EXPECT_TRUE(warned);
  EXPECT_EQ(c.constraints.size(), a.constraints.size());
}

TEST(StepAssembly, PartsGoOntoPlacedPartsInOrderAndANutBeforeItsStudIsRefused) {
  const Assembly a = loadStep(bracketFile());
  vaw::test::Assembler as(a);
  // The nut at its final pose before its stud is there: not placed, not captured, and the refusal says why.
  as.carry("nut-1", as.above("nut-1", 0.0));
  EXPECT_NE(as.state("nut-1"), PartState::Placed);
  ASSERT_FALSE(as.world().refusals().empty());
  EXPECT_NE(as.world().refusals().front().reason.find("its partner stud-1 is not placed yet"), std::string::npos)
      << as.world().refusals().front().reason;
  as.settle();
  // Back to the table where it was, out of the bracket's way.
  Eigen::Isometry3d aside = a.parts[*a.findPart("nut-1")].pose;
  aside.translation().z() += 0.001;
  as.carry("nut-1", aside);
  as.settle();

  // Pushed 5 mm through the bottom of its blind hole, the stud is past its home: not put on the hole there.
  as.carry("stud-1", as.above("stud-1", -5.0));
  EXPECT_EQ(as.events("stud-1").find("constraint-recognized"), std::string::npos) << as.events("stud-1", true);
  as.settle();

  // The stud's tip 3 mm into its hole, 5 mm above home: it slides down the hole and is PLACED at its bottom.
  as.carry("stud-1", as.above("stud-1", 5.0));
  as.settle();
  EXPECT_EQ(as.state("stud-1"), PartState::Placed) << as.events("stud-1", true);
  const std::string events = as.events("stud-1");
  EXPECT_EQ(events.substr(events.rfind("grab")), "grab constraint-recognized static-friction-overcome blocked reached-final-location");
  as.carry("stud-2", as.above("stud-2", 5.0));
  as.settle();
  EXPECT_EQ(as.state("stud-2"), PartState::Placed) << as.events("stud-2", true);

  // The bracket over both studs, 4 mm above the plate: down its first stud onto the plate.
  as.carry("bracket", as.above("bracket", 4.0));
  as.settle();
  EXPECT_EQ(as.state("bracket"), PartState::Placed) << as.events("bracket", true);

  // The second nut onto its stud, 6 mm up: down the stud until the bracket stops it, at home.
  as.carry("nut-2", as.above("nut-2", 6.0));
  as.settle();
  EXPECT_EQ(as.state("nut-2"), PartState::Placed) << as.events("nut-2", true);
  bool byBracket = false;
  for (const auto& t : as.world().transitions())
    if (a.parts[t.part].name == "nut-2" && t.event == vaw::interact::Event::Blocked) byBracket = t.cause.find("bracket") != std::string::npos;
  EXPECT_TRUE(byBracket) << "the nut stops on the bracket it clamps";

  // Placed parts ride with the base: tilted 20 degrees, the nut keeps its place on the plate.
  const PartId nut = *a.findPart("nut-2"), plate = *a.base;
  const Eigen::Isometry3d rel = as.world().part(plate).pose.inverse() * as.world().part(nut).pose;
  vaw::sim::Input in;
  Eigen::Isometry3d tilted = a.parts[plate].pose;
  tilted.linear() = Eigen::AngleAxisd(20.0 * std::numbers::pi / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  tilted.translation().z() += 0.1;
  in.base = tilted;
  for (int i = 0; i < 200; ++i) as.world().step(in);
  EXPECT_TRUE((as.world().part(plate).pose.inverse() * as.world().part(nut).pose).isApprox(rel, 1e-9));
  EXPECT_EQ(as.state("nut-2"), PartState::Placed);
}

}  // namespace
