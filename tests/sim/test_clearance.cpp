// Clearance along a carried path (docs/clearance.md), against closed forms: a 20 mm cube carried straight
// towards a wall and back at constant speed comes within a gap known exactly, at the turn; its near-miss
// span is the time the gap is below the threshold; pushed into the wall it interferes while it is in.
// Tolerances: distances 1e-6 m (the meshes are exact boxes), times one step.
#include <algorithm>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <memory>

#include "sim_test_support.hpp"
#include "vaw/error.hpp"
#include "vaw/scene_loader.hpp"
#include "vaw/sim/clearance.hpp"
#include "vaw/sim/scene.hpp"

using namespace vaw;
using namespace vaw::sim;
using simtest::at;

namespace {

// A plate (the base, top at z = 40 mm), a wall standing on it (x -50..50, y -10..10, z 40..140 mm) and a
// 20 mm cube at (0, -100, 100) mm, 50 mm above the plate.
std::shared_ptr<const Scene> pegAndWall(std::filesystem::path& file) {
  file = vaw::test::tempDir() / "peg-and-wall.vaw.json";
  std::ofstream(file) << R"({
    "format": "vaw-scene", "version": 1, "name": "Peg past a wall", "units": "mm",
    "materials": {"steel": {"density": 7850, "friction": {"static": 0.3, "kinetic": 0.2, "rotational": 0.0005}}},
    "parts": [
      {"name": "plate", "primitive": {"type": "box", "size": [400, 300, 40]}, "material": "steel", "pose": {"position": [0, 0, 20]}},
      {"name": "wall", "primitive": {"type": "box", "size": [100, 20, 100]}, "material": "steel", "pose": {"position": [0, 0, 90]}},
      {"name": "peg", "primitive": {"type": "box", "size": [20, 20, 20]}, "material": "steel", "pose": {"position": [0, -100, 100]}}
    ],
    "base": "plate",
    "environment": [{"name": "table", "kind": "table", "primitive": {"type": "box", "size": [2400, 1200, 40]}, "pose": {"position": [0, 0, -20]}}]
  })";
  return Scene::build(loadAny(file, vaw::test::importers()));
}

// The cube held at its start, carried along +y to y = `closest` (its centre, m) at constant speed in
// `steps` steps, and back the same way; then let go.
Session carry(const std::filesystem::path& scene, double closest, int steps) {
  Session s;
  s.scene = scene.string();
  const Eigen::Isometry3d start = at(0, -0.100, 0.100);
  const auto hold = [&](double y, bool grab) {
    Input in;
    in.left = simtest::hand(at(0, y, 0.100), grab);
    return in;
  };
  s.inputs.push_back(hold(start.translation().y(), true));
  for (int i = 1; i <= 2 * steps; ++i) {
    const double f = i <= steps ? static_cast<double>(i) / steps : static_cast<double>(2 * steps - i) / steps;
    s.inputs.push_back(hold(-0.100 + f * (closest + 0.100), true));
  }
  s.inputs.push_back(hold(-0.100, false));
  return s;
}

}  // namespace

TEST(Clearance, ACubeCarriedTowardsAWallComesWithinTheGapAtTheTurn) {
  std::filesystem::path file;
  const auto scene = pegAndWall(file);
  const PartId peg = *scene->assembly().findPart("peg");
  const int steps = 90;
  // Its face 5 mm from the wall's at the turn: centre at y = -25 mm.
  const Session s = carry(file, -0.025, steps);
  ClearanceOptions options;
  options.threshold = 0.010;
  options.reach = 0.080;  // beyond the plate's 50 mm, so that it is listed
  const ClearanceReport r = clearanceAlong(scene, s, peg, options);
  const double dt = 1.0 / s.settings.rate;

  ASSERT_FALSE(r.objects.empty());
  const ObjectClearance& wall = r.objects.front();
  EXPECT_EQ(wall.name, "wall");
  EXPECT_NEAR(wall.least, 0.005, 1e-6);
  // The turn is the input of step `steps` + 1 (the first input grabs), seen after that step.
  EXPECT_NEAR(wall.t, (steps + 1) * dt, dt + 1e-9);
  EXPECT_NEAR(wall.onPart.y(), -0.015, 1e-6);
  EXPECT_NEAR(wall.onOther.y(), -0.010, 1e-6);
  // The plate stays 50 mm under the cube throughout.
  const auto plate = std::find_if(r.objects.begin(), r.objects.end(), [](const ObjectClearance& o) { return o.name == "plate"; });
  ASSERT_NE(plate, r.objects.end()) << "the plate lies within reach";
  EXPECT_NEAR(plate->least, 0.050, 1e-6);

  // Every step of the carry, the nearest object and its distance as the closed form has them.
  ASSERT_GE(r.steps.size(), static_cast<std::size_t>(2 * steps));
  for (const auto& step : r.steps) {
    const double gap = -0.010 - step.onPart.y();
    if (step.distance < 0.050 - 1e-6) {
      EXPECT_EQ(scene->collision().info(step.nearest).name, "wall") << step.t;
      EXPECT_NEAR(step.distance, gap, 1e-6) << step.t;
    }
    EXPECT_FALSE(step.interfering);
  }

  // The near miss: the gap under 10 mm, the centre past y = -30 mm, i.e. a sixteenth of each way's 75 mm
  // either side of the turn.
  ASSERT_EQ(r.spans.size(), 1u);
  EXPECT_EQ(r.spans[0].kind, ClearanceSpan::Kind::NearMiss);
  EXPECT_EQ(r.spans[0].name, "wall");
  const double half = 5.0 / 75.0 * steps * dt;
  EXPECT_NEAR(r.spans[0].from, (steps + 1) * dt - half, dt + 1e-9);
  EXPECT_NEAR(r.spans[0].to, (steps + 1) * dt + half, dt + 1e-9);
}

TEST(Clearance, ACubePushedIntoTheWallInterferesWhileItIsIn) {
  std::filesystem::path file;
  const auto scene = pegAndWall(file);
  const PartId peg = *scene->assembly().findPart("peg");
  const int steps = 90;
  // 5 mm into the wall at the turn: centre at y = -15 mm; in from y = -20 mm on.
  const Session s = carry(file, -0.015, steps);
  const ClearanceReport r = clearanceAlong(scene, s, peg);
  const double dt = 1.0 / s.settings.rate;
  ASSERT_FALSE(r.objects.empty());
  EXPECT_EQ(r.objects.front().name, "wall");
  EXPECT_EQ(r.objects.front().least, 0.0);
  const ClearanceSpan* in = nullptr;
  for (const auto& span : r.spans)
    if (span.kind == ClearanceSpan::Kind::Interference) in = &span;
  ASSERT_NE(in, nullptr);
  EXPECT_EQ(in->name, "wall");
  // In while the centre is past y = -20 mm: the last 5 of each way's 85 mm.
  const double half = 5.0 / 85.0 * steps * dt;
  EXPECT_NEAR(in->from, (steps + 1) * dt - half, dt + 1e-9);
  EXPECT_NEAR(in->to, (steps + 1) * dt + half, dt + 1e-9);
  // Before it: a near miss (under 5 mm), then contact or interference; the same after.
  EXPECT_EQ(r.spans.front().kind, ClearanceSpan::Kind::NearMiss);
  EXPECT_EQ(r.spans.back().kind, ClearanceSpan::Kind::NearMiss);
}

TEST(Clearance, AnEmptySpanOrAPartNeverCarriedIsNamed) {
  std::filesystem::path file;
  const auto scene = pegAndWall(file);
  const Session s = carry(file, -0.025, 10);
  try {
    (void)clearanceAlong(scene, s, *scene->assembly().findPart("wall"));
    ADD_FAILURE() << "a part never carried was measured";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("wall is never carried"), std::string::npos) << e.what();
  }
  ClearanceOptions options;
  options.from = 50.0;
  try {
    (void)clearanceAlong(scene, s, *scene->assembly().findPart("peg"), options);
    ADD_FAILURE() << "an empty span was measured";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no step in it"), std::string::npos) << e.what();
  }
}
