// A scene saved with its tuning: the "settings" block (rate, gravity scales, rotation method, material and
// per-part friction) written from a running world reopens with the same tuning; relative paths still find
// their files from another folder; bad values in the block are named.
#include <gtest/gtest.h>

#include <fstream>

#include "sim_test_support.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/scene_file.hpp"

using namespace vaw;
using namespace vaw::sim;

TEST(SceneFile, TuningSavedWithTheSceneReopensTheSame) {
  const auto scene = Scene::build(simtest::loadBundled("sleeve-on-shaft.vaw.json"));
  const PartId sleeve = *scene->assembly().findPart("sleeve");
  World w(scene, settingsFor(scene->assembly()));
  ASSERT_EQ(w.apply(RateEdit{120.0}), "");
  ASSERT_EQ(w.apply(GravityEdit{{0.3, 0.9, 0.8}}), "");
  ASSERT_EQ(w.apply(MethodEdit{dyn::Method::SemiImplicitEuler}), "");
  ASSERT_EQ(w.apply(MaterialFrictionEdit{"steel", {0.4, 0.35, 0.001}}), "");
  ASSERT_EQ(w.apply(PartFrictionEdit{sleeve, FrictionValues{0.12, 0.1, 0.002}}), "");
  const auto dir = vaw::test::tempDir() / "elsewhere";  // not the scene's folder: paths must be rewritten
  std::filesystem::create_directories(dir);
  saveScene(scene->assembly(), w, dir / "tuned.vaw.json");

  const Assembly again = loadScene(dir / "tuned.vaw.json", simtest::importers());
  EXPECT_EQ(again.parts.size(), scene->assembly().parts.size());
  EXPECT_EQ(again.parts[sleeve].mesh->triangleCount(), scene->assembly().parts[sleeve].mesh->triangleCount());
  const Settings s = settingsFor(again);
  EXPECT_EQ(s.rate, 120.0);
  EXPECT_EQ(s.gravity.freeFlight, 0.3);
  EXPECT_EQ(s.gravity.slide, 0.9);
  EXPECT_EQ(s.gravity.rotation, 0.8);
  EXPECT_EQ(s.rotationMethod, dyn::Method::SemiImplicitEuler);
  const World reopened(Scene::build(again), s);
  EXPECT_EQ(reopened.materialFriction("steel"), (FrictionValues{0.4, 0.35, 0.001}));
  EXPECT_EQ(reopened.materialFriction("brass"), w.materialFriction("brass"));
  EXPECT_EQ(reopened.friction(sleeve), (FrictionValues{0.12, 0.1, 0.002}));
  EXPECT_EQ(reopened.friction(*again.base), (FrictionValues{0.4, 0.35, 0.001}));
  // Everything else in the file is as it was: its name, description, constraints, and the key order.
  std::ifstream in(dir / "tuned.vaw.json");
  std::string first, second;
  std::getline(in, first);
  std::getline(in, second);
  EXPECT_NE(second.find("\"format\": \"vaw-scene\""), std::string::npos) << second;
  EXPECT_EQ(again.name, scene->assembly().name);
  EXPECT_EQ(again.constraints.size(), scene->assembly().constraints.size());
  EXPECT_FALSE(std::filesystem::exists(dir / "tuned.vaw.json.saving"));
  std::filesystem::remove_all(dir.parent_path());
}

TEST(SceneFile, SettingsBlockValuesAreChecked) {
  const auto dir = vaw::test::tempDir();
  const auto write = [&](const std::string& settings) {
    std::ofstream(dir / "s.vaw.json") << R"({"format": "vaw-scene", "version": 2, "name": "s", "units": "mm",
      "materials": {"steel": {"density": 7850, "friction": {"static": 0.3, "kinetic": 0.2, "rotational": 0.0}}},
      "parts": [{"name": "block", "material": "steel", "primitive": {"type": "box", "size": [10, 10, 10]}}],
      "settings": )" + settings + "}";
    return dir / "s.vaw.json";
  };
  const auto fieldOf = [&](const std::string& settings) -> std::string {
    try {
      (void)loadScene(write(settings), simtest::importers());
      return "accepted";
    } catch (const InputError& e) {
      return e.diagnostic().field;
    }
  };
  EXPECT_EQ(fieldOf(R"({"rotation_method": "exact"})"), "settings.rotation_method");
  EXPECT_EQ(fieldOf(R"({"rate": 0.5})"), "settings.rate");
  EXPECT_EQ(fieldOf(R"({"gravity_scale": {"slide": -1}})"), "settings.gravity_scale.slide");
  EXPECT_EQ(fieldOf(R"({"friction": {"materials": {"steel": {"static": 0.2, "kinetic": 0.3}}}})"),
            "settings.friction.materials.steel.kinetic");
  EXPECT_EQ(fieldOf(R"({"friction": {"materials": {"wood": {"static": 0.2, "kinetic": 0.1}}}})"),
            "settings.friction.materials.wood");
  EXPECT_EQ(fieldOf(R"({"friction": {"parts": {"nothing": {"static": 0.2, "kinetic": 0.1}}}})"),
            "settings.friction.parts.nothing");
  EXPECT_EQ(fieldOf(R"({"rate": 240, "friction": {"parts": {"block": {"static": 0.2, "kinetic": 0.1}}}})"), "accepted");
  std::filesystem::remove_all(dir);
}
