// The trial design file: a complete example loads, round-trips, and every malformed variant is refused
// with an error naming the file, the field and what was expected.
#include <gtest/gtest.h>

#include "trials_test_support.hpp"
#include "vaw/error.hpp"
#include "vaw/trials/design.hpp"

using namespace vaw;
using namespace vaw::trials;

namespace {

const std::string kExample = R"({
  "format": "vaw-trial-design",
  "version": 1,
  "name": "Drop from the hand: natural fall speed",
  "participant": "P07",
  "seed": 20240611,
  "scenario": "drop-from-hand",
  "motion": "free-flight",
  "blind": true,
  "question": {"text": "Did the part fall too fast or too slow to look real?", "answers": "too-fast-too-slow"},
  "method": {"kind": "staircase", "start_low": 0.1, "start_high": 1.5, "step_factors": [2.0, 1.5, 1.25],
             "n_up": 1, "n_down": 1, "min_trials": 20, "min_reversals": 6, "max_trials": 40, "range": [0.05, 2.0]},
  "viewing": {"distance_m": 0.6, "fall_height_m": 0.8, "pitch_limit_deg_s": 300}
})";

class DesignFile : public trialtest::TrialsFolder {
 protected:
  // Loads `text` and returns the error's message, failing the test when it loads.
  std::string errorOf(const std::string& text) {
    const auto file = write("bad.vaw-trial.json", text);
    try {
      (void)loadDesign(file);
    } catch (const InputError& e) {
      EXPECT_EQ(e.diagnostic().file, file.string());
      return e.what();
    }
    ADD_FAILURE() << "accepted:\n" << text;
    return {};
  }
  // The example with one substring replaced.
  static std::string with(const std::string& from, const std::string& to) {
    std::string s = kExample;
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  }
};

}  // namespace

TEST_F(DesignFile, CompleteExampleLoads) {
  const Design d = loadDesign(write("d.json", kExample));
  EXPECT_EQ(d.participant, "P07");
  EXPECT_EQ(d.seed, 20240611u);
  EXPECT_EQ(d.scenario, Scenario::DropFromHand);
  EXPECT_EQ(d.motion, MotionKind::FreeFlight);
  EXPECT_TRUE(d.blind);
  ASSERT_TRUE(std::holds_alternative<Staircase>(d.method));
  const auto& s = std::get<Staircase>(d.method);
  EXPECT_EQ(s.stepFactors.size(), 3u);
  EXPECT_EQ(s.maxTrials, 40);
  ASSERT_TRUE(d.viewing);
  EXPECT_EQ(d.viewing->geometry.distance_m, 0.6);
  EXPECT_EQ(d.viewing->limits.yawRate_deg_s, 600.0) << "an unset limit keeps its default";
}

TEST_F(DesignFile, CanonicalJsonLoadsBackTheSameDesign) {
  for (const Method& m : {Method(trialtest::constantStimuli()), Method(trialtest::staircase()), Method(Adjustment{}), Method(Quest{})}) {
    Design d = trialtest::design(m, 18446744073709551615ull, AnswerKind::TwoInterval);
    d.viewing = Viewing{{0.5, 1.1}, {}};
    d.viewing->limits.acceleration_deg_s2 = 900.0;
    const std::string json = toJson(d);
    EXPECT_EQ(toJson(loadDesign(write("rt.json", json))), json);
  }
}

TEST_F(DesignFile, FormatIsCheckedFirst) {
  const std::string e = errorOf(R"({"format": "vaw-scene", "version": 1, "parts": []})");
  EXPECT_NE(e.find(": format: expected \"vaw-trial-design\", found \"vaw-scene\""), std::string::npos) << e;
  EXPECT_NE(errorOf(R"({"version": 1})").find("format: expected a value for required key \"format\""), std::string::npos);
  EXPECT_NE(errorOf(with("\"version\": 1", "\"version\": 2")).find("version: expected version 1"), std::string::npos);
}

TEST_F(DesignFile, MalformedFieldsNameTheField) {
  const std::pair<std::string, std::string> cases[] = {
      {errorOf(with("\"seed\": 20240611", "\"seed\": -3")), "seed: expected a non-negative integer"},
      {errorOf(with("\"drop-from-hand\"", "\"juggle\"")), "scenario: expected one of \"drop-from-hand\""},
      {errorOf(with("\"motion\": \"free-flight\"", "\"motion\": \"rotation\"")), "motion: expected a motion kind that the scenario \"drop-from-hand\" shows"},
      {errorOf(with("\"kind\": \"staircase\"", "\"kind\": \"bisection\"")), "method.kind: expected one of \"adjustment\""},
      {errorOf(with("[2.0, 1.5, 1.25]", "[2.0, 1.0]")), "method.step_factors[1]: expected a factor > 1"},
      {errorOf(with("\"start_low\": 0.1", "\"start_low\": 3.0")), "method.start_low: expected a scale within the range"},
      {errorOf(with("\"max_trials\": 40", "\"max_trials\": 10")), "method.max_trials: expected an integer >= min_trials"},
      {errorOf(with("\"range\": [0.05, 2.0]", "\"range\": [2.0, 0.05]")), "method.range: expected min < max"},
      {errorOf(with("\"too-fast-too-slow\"", "\"setting\"")), "question.answers: expected \"too-fast-too-slow\" or \"two-interval\""},
      {errorOf(with("\"distance_m\": 0.6", "\"distance_m\": 0")), "viewing.distance_m: expected a positive number"},
      {errorOf(with("\"blind\": true", "\"blind\": \"yes\"")), "blind: expected true or false"},
      {errorOf(with("\"blind\": true", "\"blinded\": true")), "blinded: expected one of the keys"},
      {errorOf(with("\"participant\": \"P07\"", "\"participant\": \"\"")), "participant: expected a non-empty participant id"},
  };
  for (const auto& [message, wanted] : cases) EXPECT_NE(message.find(wanted), std::string::npos) << message << "\nwanted: " << wanted;
}

TEST_F(DesignFile, AdjustmentAsksForASettingAndViewingOnlyForFreeFlight) {
  const std::string adjustment = with(R"("method": {"kind": "staircase", "start_low": 0.1, "start_high": 1.5, "step_factors": [2.0, 1.5, 1.25],
             "n_up": 1, "n_down": 1, "min_trials": 20, "min_reversals": 6, "max_trials": 40, "range": [0.05, 2.0]})",
                                      R"("method": {"kind": "adjustment", "trials": 8, "range": [0.05, 2.0], "start_range": [0.1, 1.5]})");
  EXPECT_NE(errorOf(adjustment).find("question.answers: expected \"setting\""), std::string::npos);
  std::string gear = with("\"drop-from-hand\"", "\"gear-pendulum\"");
  gear = gear.replace(gear.find("\"free-flight\""), 13, "\"rotation\"");
  EXPECT_NE(errorOf(gear).find("viewing: expected no viewing block"), std::string::npos);
}

TEST_F(DesignFile, SyntaxErrorGivesLineAndColumn) {
  const std::string e = errorOf("{\n  \"format\": \"vaw-trial-design\",\n  \"version\": 1,,\n}");
  EXPECT_NE(e.find("line 3, column"), std::string::npos) << e;
}
