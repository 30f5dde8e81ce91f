// Record and replay: a scripted session replays bit for bit (every state hash and every transition).
#include <gtest/gtest.h>

#include <fstream>

#include "sim_test_support.hpp"
#include "vaw/sim/session.hpp"

using namespace vaw;
using namespace vaw::sim;

TEST(Session, ScriptedSessionReplaysBitForBit) {
  const Assembly a = simtest::loadBundled("sleeve-on-shaft.vaw.json");
  Settings settings;
  const auto inputs = loadInputScript(std::filesystem::path(VAW_SOURCE_DIR) / "tests/sim/scripts/sleeve-turnover.vaw-inputs.json", settings);
  ASSERT_FALSE(inputs.empty());
  Session s{"sleeve-on-shaft.vaw.json", settings, inputs};
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
  const Assembly a = simtest::loadBundled("hoist-demo.vaw.json");
  Settings settings;
  const auto inputs = loadInputScript(std::filesystem::path(VAW_SOURCE_DIR) / "tests/sim/scripts/hoist-demo.vaw-inputs.json", settings);
  EXPECT_EQ(settings.hoistXY, Eigen::Vector2d(0.5, 0.0));
  const World w = replay(a, Session{"hoist-demo.vaw.json", settings, inputs});
  const PartId block = *a.findPart("block");
  EXPECT_EQ(simtest::join(simtest::transitionNames(w, block)), "tool-attach:ONTOOL reached-final-location:PLACED");
  ASSERT_EQ(w.refusals().size(), 1u);
  EXPECT_EQ(w.refusals()[0].event, interact::Event::Grab);
}
