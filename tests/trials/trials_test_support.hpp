#pragma once
// Designs, folders and simulated sessions shared by the trial tests.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "vaw/trials/analysis.hpp"
#include "vaw/trials/procedure.hpp"
#include "vaw/trials/simulated_participant.hpp"

namespace vaw::trialtest {

inline trials::Design design(trials::Method method, std::uint64_t seed = 7,
                             trials::AnswerKind answers = trials::AnswerKind::TooFastTooSlow) {
  trials::Design d;
  d.name = "test";
  d.participant = "P01";
  d.seed = seed;
  d.question.text = "Did the part fall too fast or too slow to look real?";
  d.question.answers = std::holds_alternative<trials::Adjustment>(method) ? trials::AnswerKind::Setting : answers;
  if (d.question.answers == trials::AnswerKind::TwoInterval) d.question.referenceScale = 0.5;
  d.method = std::move(method);
  return d;
}

inline trials::ConstantStimuli constantStimuli(int repetitions = 10) {
  trials::ConstantStimuli c;
  c.scales = {0.1, 0.15, 0.2, 0.3, 0.45, 0.7, 1.0};
  c.repetitions = repetitions;
  return c;
}

inline trials::Staircase staircase() {
  trials::Staircase s;
  s.startLow = 0.08;
  s.startHigh = 1.2;
  s.stepFactors = {2.0, 1.5, 1.25, 1.12};
  s.minTrials = 30;
  s.minReversals = 8;
  s.maxTrials = 40;
  s.range = {0.02, 3.0};
  return s;
}

// Runs a whole session in memory against a simulated participant.
inline trials::ResultsFile simulate(const trials::Design& d, const trials::ParticipantModel& m) {
  trials::Procedure p(d);
  while (p.next()) p.answer(trials::simulateAnswer(m, *p.next()));
  return {"simulated", d, p.records(), std::nullopt};
}

// A fresh folder per test, removed afterwards.
class TrialsFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = std::filesystem::path(::testing::TempDir()) /
          ("vaw-trials-" + std::to_string(::getpid()) + "-" + info->test_suite_name() + "-" + info->name());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
  }
  void TearDown() override {
    if (!HasFailure()) std::filesystem::remove_all(dir);
  }
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name, std::ios::binary) << text;
    return dir / name;
  }
  static std::string read(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  std::filesystem::path dir;
};

}  // namespace vaw::trialtest
