// A session killed with SIGKILL in the middle and resumed: every answered trial is in the file exactly
// once and none is corrupted -- the file ends byte for byte as an uninterrupted session's.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>

#include "trials_test_support.hpp"
#include "vaw/trials/runner.hpp"

using namespace vaw::trials;

namespace {

class KillResume : public vaw::trialtest::TrialsFolder {
 protected:
  // In a child process: opens (or resumes) the session and answers until done, pausing between trials
  // as a person would, so that the kill lands mid-session. Never returns.
  [[noreturn]] void childSession(const Design& d, const ParticipantModel& m, const std::filesystem::path& file) {
    try {
      Runner r = Runner::open(d, file);
      while (r.next()) {
        r.answer(simulateAnswer(m, *r.next()));
        std::this_thread::sleep_for(std::chrono::microseconds(300));
      }
      _exit(0);
    } catch (...) {
      _exit(3);
    }
  }
};

}  // namespace

TEST_F(KillResume, SigkilledSessionsResumeWithEveryAnsweredTrialExactlyOnce) {
  ConstantStimuli cs = vaw::trialtest::constantStimuli(40);  // 280 trials
  const Design d = vaw::trialtest::design(cs, 99);
  const ParticipantModel m{.pse = 0.3, .sigmaLog = 0.2, .lapse = 0.02, .seed = 5};
  const auto file = dir / "killed.jsonl", reference = dir / "reference.jsonl";
  {
    Runner r = Runner::open(d, reference);
    while (r.next()) r.answer(simulateAnswer(m, *r.next()));
  }
  // Each round starts the session in a child, waits until it has answered at least one more trial
  // (so the kill lands in the middle of a session in any build, sanitizers included), lets it run a
  // little longer, different each time, and kills it.
  int kills = 0;
  std::size_t before = 0;
  for (int attempt = 0; attempt < 30; ++attempt) {
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) childSession(d, m, file);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    const auto answered = [&] {
      const std::string text = std::filesystem::exists(file) ? read(file) : std::string();
      return std::max<std::ptrdiff_t>(std::count(text.begin(), text.end(), '\n') - 1, 0);
    };
    while (answered() <= static_cast<std::ptrdiff_t>(before) && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    std::this_thread::sleep_for(std::chrono::microseconds(700 * (attempt % 5)));
    ::kill(child, SIGKILL);
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    if (WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) ++kills;
    else ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the child failed: status " << status;
    // Between kills: the file reads, it gained answers and lost none, and its records match the reference's.
    const ResultsFile f = readResults(file);
    EXPECT_GT(f.records.size(), before) << "attempt " << attempt << ": no progress, or answered trials lost";
    before = f.records.size();
    const std::string text = read(file), ref = read(reference);
    const std::size_t whole = f.torn ? f.torn->offset : text.size();
    EXPECT_EQ(text.substr(0, whole), ref.substr(0, whole)) << "attempt " << attempt;
    if (f.records.size() == 280) break;
  }
  EXPECT_GE(kills, 20) << "the session must be killed in the middle, many times";
  // Resume to the end in this process.
  Runner r = Runner::open(d, file);
  while (r.next()) r.answer(simulateAnswer(m, *r.next()));
  EXPECT_EQ(read(file), read(reference));
  const ResultsFile f = readResults(file);
  ASSERT_EQ(f.records.size(), 280u);
  for (std::size_t i = 0; i < f.records.size(); ++i) EXPECT_EQ(f.records[i].trial.index, static_cast<int>(i));
  std::printf("[ info ] %d kills; %zu of 280 trials answered when the kills stopped\n", kills, before);
}
