// Record and replay: a scripted session replays bit for bit (every state hash and every transition).
#include <gtest/gtest.h>

#include <fstream>

#include "sim_test_support.hpp"
#include "vaw/sim/session.hpp"

using namespace vaw;
using namespace vaw::sim;

TEST(Session, ScriptedSessionReplaysBitForBit) {
  const auto a = Scene::build(simtest::loadBundled("sleeve-on-shaft.vaw.json"));
  Session s;
  s.scene = "sleeve-on-shaft.vaw.json";
  s.sceneHash = a->contentHash();
  s.inputs = loadInputScript(std::filesystem::path(VAW_SOURCE_DIR) / "tests/sim/scripts/sleeve-turnover.vaw-inputs.json", s.settings);
  ASSERT_FALSE(s.inputs.empty());
  std::vector<std::uint64_t> hashes;
  const World first = replay(a, s, [&](const World& w) { hashes.push_back(w.stateHash()); });
  ASSERT_GE(first.transitions().size(), 5u) << "the script exercises grab, release, slides and flight";
  const auto dir = test::tempDir();
  saveSession(s, dir / "s.vaw-session.json");
  const Session loaded = loadSession(dir / "s.vaw-session.json");
  ASSERT_EQ(loaded.inputs.size(), s.inputs.size());
  std::size_t i = 0;
  bool allEqual = true;
  const World second = replay(a, loaded, [&](const World& w) { allEqual = allEqual && hashes[i++] == w.stateHash(); });
  EXPECT_TRUE(allEqual) << "every step's state hash";
  ASSERT_EQ(second.transitions().size(), first.transitions().size());
  for (std::size_t k = 0; k < first.transitions().size(); ++k) {
    const auto& x = first.transitions()[k];
    const auto& y = second.transitions()[k];
    EXPECT_EQ(x.step, y.step);
    EXPECT_EQ(x.t, y.t);
    EXPECT_EQ(x.part, y.part);
    EXPECT_EQ(x.from, y.from);
    EXPECT_EQ(x.to, y.to);
    EXPECT_EQ(x.event, y.event);
    EXPECT_EQ(x.cause, y.cause);
  }
  // CSV exports.
  std::vector<TrajectoryRow> rows;
  const World third = replay(a, loaded, [&](const World& w) { appendTrajectory(w, rows); });
  writeTrajectoriesCsv(third, rows, dir / "trajectories.csv");
  writeTransitionsCsv(third, dir / "transitions.csv");
  std::ifstream tr(dir / "transitions.csv");
  std::string header;
  std::getline(tr, header);
  EXPECT_EQ(header, "step,t,part,from,to,event,cause");
}

// A tracked hand's measured release velocity is part of the input: saved with 17 digits and replayed exactly.
TEST(Session, MeasuredHandVelocityRoundTrips) {
  const auto scene = Scene::build(simtest::loadBundled("block-on-plate.vaw.json"));
  const PartId block = *scene->assembly().findPart("block");
  const Eigen::Vector3d com = scene->assembly().parts[block].pose * scene->assembly().parts[block].mass.centerOfMass;
  Session s;
  s.scene = "block-on-plate.vaw.json";
  s.sceneHash = scene->contentHash();
  Input in;
  for (int k = 0; k < 30; ++k) {
    in.left = simtest::hand(simtest::at(com.x(), com.y() + 0.003 * k, com.z() + 0.002 * k), k < 20);
    in.left.velocity.reset();
    if (k == 20) in.left.velocity = interact::Twist{Eigen::Vector3d(0.1 / 3.0, 0.27, 0.18), Eigen::Vector3d(0.0, 0.0, 0.7)};
    s.inputs.push_back(in);
  }
  const auto dir = vaw::test::tempDir();
  saveSession(s, dir / "v.vaw-session.json");
  const Session loaded = loadSession(dir / "v.vaw-session.json");
  ASSERT_EQ(loaded.inputs.size(), s.inputs.size());
  ASSERT_TRUE(loaded.inputs[20].left.velocity);
  EXPECT_EQ(loaded.inputs[20].left.velocity->linear, s.inputs[20].left.velocity->linear);
  EXPECT_EQ(loaded.inputs[20].left.velocity->angular, s.inputs[20].left.velocity->angular);
  EXPECT_FALSE(loaded.inputs[21].left.velocity) << "a step without a measurement stays without";
  const World first = replay(scene, s, {});
  const World second = replay(scene, loaded, {});
  EXPECT_EQ(first.stateHash(), second.stateHash());
  EXPECT_EQ(first.part(block).state, interact::PartState::InSpace);
  std::filesystem::remove_all(dir);
}

TEST(Session, BadScriptNamesTheFileAndField) {
  const auto dir = test::tempDir();
  std::ofstream(dir / "bad.json") << R"({"format": "vaw-inputs", "version": 1, "duration": 1,
    "keyframes": [{"t": 0, "left": {"position": [0, 0], "grab": true}}]})";
  Settings s;
  try {
    (void)loadInputScript(dir / "bad.json", s);
    FAIL() << "accepted a 2-vector position";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
    EXPECT_NE(e.diagnostic().field.find("keyframes[0].left.position"), std::string::npos) << e.diagnostic().field;
  }
}

// The bundled hoist demo script: the hand is refused the 40 kg block, the hoist (placed by "hoist_at")
// lifts it, the hand-held base comes under it and it is lowered into its final pose.
TEST(Session, HoistDemoScriptEndsPlaced) {
  const auto scene = Scene::build(simtest::loadBundled("hoist-demo.vaw.json"));
  Session s;
  s.scene = "hoist-demo.vaw.json";
  s.inputs = loadInputScript(std::filesystem::path(VAW_SOURCE_DIR) / "tests/sim/scripts/hoist-demo.vaw-inputs.json", s.settings);
  ASSERT_TRUE(s.settings.hoist.has_value());
  EXPECT_EQ(s.settings.hoist->position, Eigen::Vector2d(0.5, 0.0));
  const World w = replay(scene, s);
  const Assembly& a = scene->assembly();
  const PartId block = *a.findPart("block");
  EXPECT_EQ(simtest::join(simtest::transitionNames(w, block)), "tool-attach:ONTOOL reached-final-location:PLACED");
  ASSERT_EQ(w.refusals().size(), 1u);
  EXPECT_EQ(w.refusals()[0].event, interact::Event::Grab);
}
