// Assemblies as CAD systems exported them, read from the real files kept beside the project (the folder
// VAW_CAD_EXPORTS_DIR names; tests/step/CMakeLists.txt sets it, and each test is skipped, naming it, where it
// is absent). What each file is: that folder's README. Every file opens, its parts named as its products,
// the base the part it stands on, its fits found, its warnings readable.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>

#include "bundled.hpp"
#include "vaw/collision/interference.hpp"
#include "vaw/evaluation/sequence.hpp"
#include "vaw/scene_loader.hpp"

namespace {

namespace fs = std::filesystem;
using vaw::Assembly;
using vaw::Constraint;

fs::path exportFile(const std::string& name) { return fs::path(VAW_CAD_EXPORTS_DIR) / name; }

// The file loaded once per test process; a skip when the folder is not there.
const Assembly* loaded(const std::string& name) {
  static std::map<std::string, Assembly> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    const fs::path file = exportFile(name);
    if (!fs::exists(file)) return nullptr;
    vaw::LoadOptions options;
    options.import.resultCache.clear();
    it = cache.emplace(name, vaw::loadAny(file, vaw::test::importers(), options)).first;
  }
  return &it->second;
}

#define LOAD_OR_SKIP(var, name) \
  const Assembly* var = loaded(name); \
  if (!var) GTEST_SKIP() << "no " << exportFile(name) << " (set VAW_CAD_EXPORTS_DIR to the real exports)"

// Every warning reads as a sentence: never an empty expectation ("expected , found").
void expectReadableWarnings(const Assembly& a) {
  for (const auto& w : a.warnings) EXPECT_EQ(w.message().find("expected , found"), std::string::npos) << w.message();
}

bool anyWarning(const Assembly& a, const std::string& text) {
  return std::any_of(a.warnings.begin(), a.warnings.end(), [&](const vaw::Diagnostic& w) { return w.message().find(text) != std::string::npos; });
}

int count(const Assembly& a, Constraint::Found::Fit fit) {
  return static_cast<int>(std::count_if(a.constraints.begin(), a.constraints.end(),
                                        [&](const Constraint& c) { return c.found && c.found->fit == fit; }));
}

const vaw::Part* byProduct(const Assembly& a, const std::string& prefix) {
  for (const auto& p : a.parts)
    if (p.product.rfind(prefix, 0) == 0) return &p;
  return nullptr;
}

TEST(CadExports, SolidWorksRotaryTableOpensNamedWithItsUnitsAndThreads) {
  LOAD_OR_SKIP(a, "Drehtisch.STEP");
  expectReadableWarnings(*a);
  // Every screw's tessellation closed: none left open (the cap screws' cone apex was cut open before).
  EXPECT_FALSE(anyWarning(*a, "a closed tessellation"));
  for (const auto& p : a->parts) EXPECT_EQ(p.name.rfind("NAUO", 0), std::string::npos) << "SolidWorks' usage ids are no names: " << p.name;
  EXPECT_NE(a->findPart("Tischneu"), std::nullopt);
  EXPECT_EQ(a->parts[*a->base].product.rfind("Bodenplatte", 0), 0u) << a->parts[*a->base].name << ": " << a->baseReason;
  // The stepper motor and the two servos are bought-in units, each one part.
  const vaw::Part* motor = byProduct(*a, "NEMA 17");
  ASSERT_NE(motor, nullptr);
  EXPECT_EQ(motor->unitMembers.size(), 10u);
  EXPECT_EQ(std::count_if(a->parts.begin(), a->parts.end(), [](const vaw::Part& p) { return p.product == "Standard Servo Assembly"; }), 2);
  EXPECT_GE(count(*a, Constraint::Found::Fit::Threaded), 4) << "the ISO 4762 M4 screws into their ISO 4032 nuts";
}

TEST(CadExports, Fusion360ArmOpensNamedWithItsServosAsUnits) {
  LOAD_OR_SKIP(a, "arm.step");
  expectReadableWarnings(*a);
  EXPECT_FALSE(anyWarning(*a, "a closed tessellation")) << "the countersink cone whose seam was tilted by 3e-16";
  EXPECT_TRUE(anyWarning(*a, "378 names are not quoted strings")) << "one line for the check list's 378";
  for (const auto& p : a->parts) EXPECT_EQ(p.name.rfind("SOLID", 0), std::string::npos) << p.name;
  EXPECT_EQ(a->parts[*a->base].name, "Base:1") << a->baseReason;
  EXPECT_TRUE(a->findPart("moving side:1").has_value());
  const auto units = std::count_if(a->parts.begin(), a->parts.end(), [](const vaw::Part& p) { return !p.unitMembers.empty(); });
  EXPECT_EQ(units, 6) << "the Dynamixel servos";
}

// Every part placed by some order: the rotary table's table with what it carries lowered onto its shaft as
// one sub-assembly, its pinion through the internal gear it is drawn into (a clash, noted).
TEST(CadExports, SolidWorksRotaryTableGoesTogether) {
  LOAD_OR_SKIP(a, "Drehtisch.STEP");
  const vaw::eval::SequencePlan plan = vaw::eval::planSequence(*a);
  EXPECT_TRUE(plan.complete()) << plan.stuck.size() << " stuck";
  EXPECT_FALSE(plan.subAssemblies.empty());
  const auto table = *a->findPart("Tischneu");
  const auto* sub = plan.subAssemblyOf(table);
  ASSERT_NE(sub, nullptr) << "the table comes home carrying what is fastened to it";
  EXPECT_GE(sub->parts.size(), 3u);
}

TEST(CadExports, Fusion360ArmGoesTogether) {
  LOAD_OR_SKIP(a, "arm.step");
  const vaw::eval::SequencePlan plan = vaw::eval::planSequence(*a);
  EXPECT_TRUE(plan.complete()) << plan.stuck.size() << " stuck";
}

// The belt round both pulleys can be placed by no rigid motion: it is fitted by hand, last, and is no failure.
TEST(CadExports, CatiaBeltDriveWrapsItsBeltLast) {
  LOAD_OR_SKIP(a, "Product1.stp");
  const vaw::eval::SequencePlan plan = vaw::eval::planSequence(*a);
  EXPECT_TRUE(plan.complete());
  const auto belt = *a->findPart("Belt.1");
  EXPECT_EQ(plan.order.back(), belt);
  const auto* wrap = plan.wrapOf(belt);
  ASSERT_NE(wrap, nullptr);
  std::vector<std::string> names;
  for (const auto p : wrap->wraps) names.push_back(a->parts[p].name);
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"Driven Pulley.1", "Driving Pulley.1"}));
}

TEST(CadExports, ProEngineerAs1NamedAsItsProducts) {
  LOAD_OR_SKIP(a, "as1_pe_203.stp");
  expectReadableWarnings(*a);
  EXPECT_EQ(a->parts.size(), 18u);
  for (const char* name : {"PLATE", "L-BRACKET", "L-BRACKET #2", "BOLT", "NUT", "ROD"}) EXPECT_TRUE(a->findPart(name)) << name;
  EXPECT_EQ(a->parts[*a->base].name, "PLATE");
}

TEST(CadExports, CatiaFanOpens) {
  LOAD_OR_SKIP(a, "Ventilator.stp");
  expectReadableWarnings(*a);
  EXPECT_EQ(a->parts.size(), 1u);
  EXPECT_GT(a->parts[0].mass.volume, 0.0);
}

TEST(CadExports, GeneratedRigShowsItsMisplacedPlateAsClashes) {
  // The rig's plate lies 200 mm off its tiles in the file itself (Open CASCADE's own reading of the file
  // agrees): its bolts stand in solid plate, which the check at rest shows rather than leaving the holes
  // silently without constraints.
  LOAD_OR_SKIP(a, "generated/rig199.stp");
  const auto all = vaw::collision::interferences(*a, vaw::collision::assembledPoses(*a));
  const auto clashes = std::count_if(all.begin(), all.end(), [&](const vaw::collision::Interference& i) {
    return i.kind == vaw::collision::Interference::Kind::Clash && (a->parts[i.a].name == "plate" || a->parts[i.b].name == "plate");
  });
  EXPECT_GE(clashes, 40);
}

}  // namespace
