#include <gtest/gtest.h>

#include <functional>
#include <nlohmann/json.hpp>

#include "test_support.hpp"
#include "vaw/scene_loader.hpp"

using namespace vaw;
using nlohmann::json;

namespace {

std::vector<std::filesystem::path> bundledScenes() {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(test::resources() / "scenes"))
    if (e.path().string().ends_with(".vaw.json")) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

const Assembly& load(const std::string& name) {
  static std::map<std::string, Assembly> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, loadScene(test::resources() / "scenes" / name, test::importers())).first;
  return it->second;
}

const Part& part(const Assembly& a, const std::string& name) {
  const auto id = a.findPart(name);
  EXPECT_TRUE(id.has_value()) << name;
  return a.parts.at(id.value_or(0));
}

}  // namespace

TEST(BundledScenes, EveryOneLoads) {
  const auto scenes = bundledScenes();
  ASSERT_GE(scenes.size(), 4u);
  for (const auto& s : scenes) {
    SCOPED_TRACE(s.string());
    const Assembly a = loadScene(s, test::importers());
    EXPECT_FALSE(a.parts.empty());
    EXPECT_TRUE(a.base.has_value()) << "every bundled scene has a base";
    bool table = false;
    for (const auto& e : a.environment) table = table || e.kind == "table";
    EXPECT_TRUE(table) << "every bundled scene has a table";
    for (const auto& p : a.parts) EXPECT_EQ(inertiaProblem(p.mass.inertiaCm), "") << p.name;
    for (const auto& w : a.warnings) ADD_FAILURE() << "unexpected warning: " << w.message();
  }
}

TEST(BundledScenes, SleeveOnShaft) {
  const Assembly& a = load("sleeve-on-shaft.vaw.json");
  ASSERT_TRUE(a.base);
  EXPECT_EQ(a.parts[*a.base].name, "base");
  const Part& sleeve = part(a, "sleeve");
  EXPECT_EQ(sleeve.category.category, Category::OneHand);
  ASSERT_EQ(a.constraints.size(), 1u);
  EXPECT_EQ(a.constraints[0].type, Constraint::Type::Insert);
  EXPECT_EQ(a.constraints[0].part, sleeve.id);
  // The property file gives the true cylinder; the tessellated mesh is slightly smaller.
  ASSERT_TRUE(sleeve.fileMass && sleeve.meshMass && sleeve.disagreement);
  EXPECT_EQ(sleeve.massSource, MassSource::PropertyFile);
  EXPECT_GT(sleeve.disagreement->massRel, 0.0);
  EXPECT_LT(sleeve.disagreement->massRel, 0.01);
  EXPECT_LT(sleeve.fileMass->mass, 1.0);
  EXPECT_GT(sleeve.fileMass->mass, 0.05);
}

TEST(BundledScenes, GearCentreOfMassIsOffItsBore) {
  const Assembly& a = load("gear-on-shaft.vaw.json");
  const Part* gear = nullptr;
  for (const auto& c : a.constraints)
    if (c.type == Constraint::Type::Insert) gear = &a.parts[c.part];
  ASSERT_NE(gear, nullptr);
  // The paper-like gear (docs/physics.md, "Stability limits"): about 0.3 kg with the CM about 0.02 m off the axis.
  EXPECT_NEAR(gear->mass.mass, 0.3, 0.1);
  const auto& c = a.constraints[0];
  const Eigen::Vector3d r = gear->mass.centerOfMass - c.partAxis.point;
  const double d = (r - c.partAxis.direction * c.partAxis.direction.dot(r)).norm();
  EXPECT_NEAR(d, 0.02, 0.005);
}

TEST(BundledScenes, BlockOnPlateIsAPlaneMate) {
  const Assembly& a = load("block-on-plate.vaw.json");
  ASSERT_EQ(a.constraints.size(), 1u);
  EXPECT_EQ(a.constraints[0].type, Constraint::Type::Mate);
  const Material& m = a.materials.at(a.parts[a.constraints[0].part].material);
  EXPECT_GT(m.staticFriction, 0.0);
  EXPECT_LE(m.kineticFriction, m.staticFriction);
}

TEST(BundledScenes, LargeAssemblyIsLarge) {
  const Assembly& a = load("large-gearbox.vaw.json");
  EXPECT_GE(a.parts.size(), 50u);
  EXPECT_GE(a.totalTriangles(), 250000u);
}

TEST(SceneLoader, UnitsConvertToSI) {
  const auto dir = test::tempDir();
  json s = {{"format", "vaw-scene"}, {"version", 1}, {"name", "inch"}, {"units", {{"length", "inch"}, {"mass", "lb"}}},
            {"materials", {{"al", {{"density", "0.0975 lb/in^3"}}}}},
            {"parts", {{{"name", "cube"}, {"primitive", {{"type", "box"}, {"size", {1, 1, 1}}}}, {"material", "al"},
                        {"pose", {{"position", {10, 0, 0}}}}}}}};
  const Assembly a = loadScene(test::writeFile(dir / "inch.vaw.json", s.dump()), test::importers());
  const Part& p = a.parts[0];
  EXPECT_EQ(a.units, LengthUnit::Inch);
  EXPECT_NEAR(p.mass.volume, 0.0254 * 0.0254 * 0.0254, 1e-18);
  EXPECT_NEAR(p.mass.mass, 0.0975 * 0.45359237, 1e-12);  // 1 in^3 of 0.0975 lb/in^3
  EXPECT_NEAR(p.pose.translation().x(), 0.254, 1e-15);
}

TEST(SceneLoader, GroupsComposePosesAndShowInTheTree) {
  const auto dir = test::tempDir();
  const json s = json::parse(R"({"format": "vaw-scene", "version": 1, "name": "groups", "units": "m",
    "materials": {"steel": {"density": 7850}},
    "parts": [{"name": "fasteners", "pose": {"position": [1, 0, 0], "rotation": {"axis": [0, 0, 1], "angle": 90}},
               "children": [{"name": "bolt", "primitive": {"type": "cylinder", "radius": 0.005, "height": 0.04},
                             "material": "steel", "pose": {"position": [0.1, 0, 0]}}]}]})");
  const Assembly a = loadScene(test::writeFile(dir / "g.vaw.json", s.dump()), test::importers());
  ASSERT_EQ(a.tree.children.size(), 1u);
  EXPECT_EQ(a.tree.children[0].kind, TreeNode::Kind::Group);
  EXPECT_EQ(a.tree.children[0].name, "fasteners");
  ASSERT_EQ(a.tree.children[0].children.size(), 1u);
  EXPECT_EQ(a.tree.children[0].children[0].name, "bolt");
  EXPECT_LE((a.parts[0].pose.translation() - Eigen::Vector3d(1, 0.1, 0)).norm(), 1e-15);
}

TEST(SceneLoader, ProgressIsMonotoneAndCancellable) {
  const auto scene = test::resources() / "scenes" / "sleeve-on-shaft.vaw.json";
  double last = -1;
  bool monotone = true;
  (void)loadScene(scene, test::importers(), {}, [&](double f, const std::string&) {
    monotone = monotone && f >= last;
    last = f;
    return true;
  });
  EXPECT_TRUE(monotone);
  EXPECT_DOUBLE_EQ(last, 1.0);
  int calls = 0;
  EXPECT_THROW((void)loadScene(scene, test::importers(), {}, [&](double, const std::string&) { return ++calls < 3; }),
               LoadCancelled);
}

TEST(SceneLoader, StricterCategoriesChangeTheVerdict) {
  LoadOptions strict;
  strict.categories = CategorySettings::stricter();
  const Assembly big = loadScene(test::resources() / "scenes" / "large-gearbox.vaw.json", test::importers(), strict);
  EXPECT_EQ(big.categorySettings.preset, "stricter");
  for (const auto& p : big.parts) {
    if (p.mass.mass > 16.0) {
      EXPECT_EQ(p.category.category, Category::Tool) << p.name;
    } else if (p.mass.mass > 3.0) {
      EXPECT_EQ(p.category.category, Category::TwoHand) << p.name;
    }
  }
}
