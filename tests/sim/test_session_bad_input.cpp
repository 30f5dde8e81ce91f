// Hostile input scripts and sessions: every value outside its physical or stated range is refused with
// the file, the field and the range named, before anything is allocated or stepped. Each case crashed
// (bad_alloc, an FCL assertion), ran for no step, or was accepted silently before.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sim_test_support.hpp"
#include "vaw/sim/session.hpp"

using namespace vaw;
using namespace vaw::sim;
using nlohmann::json;

namespace {

json validScript() {
  return json::parse(R"({
    "format": "vaw-inputs", "version": 1, "units": "mm", "rate": 90, "duration": 1.0, "description": "probe",
    "hoist_at": [500, 0],
    "keyframes": [
      {"t": 0.0, "left": {"position": [250, 0, 150], "grab": false}, "hoist": {"height": 150}},
      {"t": 0.5, "left": {"position": [250, 0, 300], "grab": true}, "base": {"position": [0, 0, 0]}},
      {"t": 1.0, "left": {"position": [0, 0, 300]}, "hoist": {"height": 300}}
    ]
  })");
}

json validSession() {
  Session s;
  s.scene = "sleeve-on-shaft.vaw.json";
  s.inputs = std::vector<Input>(3);
  const auto dir = test::tempDir();
  saveSession(s, dir / "s.vaw-session.json");
  std::ifstream in(dir / "s.vaw-session.json");
  json j = json::parse(in);
  // A session lists only what changed since the previous step; every step in full is valid too, and gives
  // the cases below whole inputs to spoil.
  j["inputs"][1] = j["inputs"][0];
  j["inputs"][2] = j["inputs"][0];
  return j;
}

struct Case {
  std::string name;
  bool session;                       // a session file, else an input script
  std::function<void(json&)> change;  // one edit of the valid file
  std::string field, expected;        // substrings of the diagnostic
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

std::vector<Case> cases() {
  const auto script = [](std::string name, std::function<void(json&)> f, std::string field, std::string expected) {
    return Case{std::move(name), false, std::move(f), std::move(field), std::move(expected)};
  };
  const auto session = [](std::string name, std::function<void(json&)> f, std::string field, std::string expected) {
    return Case{std::move(name), true, std::move(f), std::move(field), std::move(expected)};
  };
  return {
      script("HugeDuration", [](json& j) { j["duration"] = 1e12; }, "duration", "a number from 0 to 3600 s"),
      script("TooManySteps", [](json& j) { j["duration"] = 3600; j["rate"] = 1000; }, "duration", "a duration of 1 to 1000000 steps"),
      script("HugeRate", [](json& j) { j["rate"] = 1e9; }, "rate", "a number from 1 to 10000 Hz"),
      script("TinyRate", [](json& j) { j["rate"] = 1e-9; }, "rate", "a number from 1 to 10000 Hz"),
      script("NoStepAtAll", [](json& j) { j["duration"] = 0.001; }, "duration", "a duration of 1 to"),
      script("FarAwayHand", [](json& j) { j["keyframes"][1]["left"]["position"][0] = 1e300; }, "keyframes[1].left.position",
             "world bound"),
      script("FarAwayBase", [](json& j) { j["keyframes"][1]["base"]["position"][2] = 1e300; }, "keyframes[1].base.position",
             "world bound"),
      script("FarAwayHoist", [](json& j) { j["keyframes"][2]["hoist"]["height"] = 1e300; }, "keyframes[2].hoist.height",
             "world bound"),
      script("FarAwayHoistLine", [](json& j) { j["hoist_at"] = {1e300, 0}; }, "hoist_at", "world bound"),
      script("HandTooFast", [](json& j) { j["keyframes"][1]["left"]["position"] = {250, 0, 150000}; },
             "keyframes[1].left.position", "at up to 100 m/s"),
      script("HandJumpsAtOneInstant", [](json& j) { j["keyframes"][1]["t"] = 0.0; }, "keyframes[1].left.position", "at up to 100 m/s"),
      script("HoistTooFast", [](json& j) { j["keyframes"][2]["hoist"]["height"] = 300000; }, "keyframes[2].hoist.height",
             "at up to 100 m/s"),
      script("LateKeyframe", [](json& j) { j["keyframes"][2]["t"] = 1e300; }, "keyframes[2].t", "a number from 0 to 3600 s"),
      script("DescriptionNotAString", [](json& j) { j["description"] = {1, 2}; }, "description", "a string"),
      script("VersionWrapsAround", [](json& j) { j["version"] = 4294967297ULL; }, "version", "an integer from"),
      script("SessionGivenAsScript", [](json& j) { j["format"] = "vaw-session"; }, "format", "\"vaw-inputs\" (an input script)"),
      session("HugeGravityScale", [](json& j) { j["settings"]["gravity_scale"]["free_flight"] = 1e300; },
              "settings.gravity_scale.free_flight", "a number from 0 to 10"),
      session("TinyRate", [](json& j) { j["settings"]["rate"] = 1e-300; }, "settings.rate", "a number from 1 to 10000 Hz"),
      session("HugeGrabReach", [](json& j) { j["settings"]["grab_reach"] = 1e300; }, "settings.grab_reach", "a number from 0 to 1 m"),
      session("HugeHoistLine", [](json& j) { j["settings"]["hoist"]["x"] = 1e300; }, "settings.hoist.x", "a number from -1000 to 1000 m"),
      session("ExactRotation", [](json& j) { j["settings"]["rotation_method"] = "exact"; }, "settings.rotation_method",
              "a method a rotation about an axis supports: paper-explicit, semi-implicit-euler, velocity-verlet or rk4"),
      session("LongSceneName", [](json& j) { j["scene"] = std::string(5000, 's'); }, "scene", "1 to 4096 characters"),
      session("PoseNotARotation", [](json& j) { j["inputs"][1]["left"]["pose"][0] = 2.0; }, "inputs[1].left.pose", "is a rotation"),
      session("FarAwayPose", [](json& j) { j["inputs"][1]["right"]["pose"][3] = 1e300; }, "inputs[1].right.pose", "world bound"),
      session("HandTooFast", [](json& j) { j["inputs"][2]["left"]["pose"][11] = 5.0; }, "inputs[2].left", "at up to 100 m/s"),
      session("HugeHoistHeight", [](json& j) { j["inputs"][0]["hoist"]["height"] = 1e300; }, "inputs[0].hoist.height",
              "a number from -1000 to 1000 m"),
      session("ScriptGivenAsSession", [](json& j) { j["format"] = "vaw-inputs"; }, "format",
              "\"vaw-session\" (a session)"),
  };
}

class BadSessionInput : public ::testing::TestWithParam<Case> {};

TEST_P(BadSessionInput, NamedErrorNoCrash) {
  const Case& c = GetParam();
  json j = c.session ? validSession() : validScript();
  c.change(j);
  const auto file = test::writeFile(test::tempDir() / "probe.json", j.dump());
  try {
    Settings settings;
    if (c.session) (void)loadSession(file);
    else (void)loadInputScript(file, settings);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(e.diagnostic().field.find(c.field), std::string::npos) << e.what();
    EXPECT_NE(e.diagnostic().expected.find(c.expected), std::string::npos) << e.what();
    EXPECT_TRUE(e.diagnostic().file.ends_with("probe.json")) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Files, BadSessionInput, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& p) { return (p.param.session ? "Session" : "Script") + p.param.name; });

TEST(BadSessionInputSuite, TheValidProbesLoad) {
  // Each case above is one edit of these files, so each error is caused by its edit alone.
  Settings settings;
  const auto dir = test::tempDir();
  EXPECT_EQ(loadInputScript(test::writeFile(dir / "script.json", validScript().dump()), settings).size(), 90u);
  EXPECT_EQ(loadSession(test::writeFile(dir / "session.json", validSession().dump())).inputs.size(), 3u);
}

}  // namespace
