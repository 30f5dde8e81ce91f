// The results file: one synced line per answer, resume, torn last records, malformed files, a file of
// another design, and one session per file.
#include <gtest/gtest.h>

#include <system_error>

#include "trials_test_support.hpp"
#include "vaw/error.hpp"
#include "vaw/trials/runner.hpp"

using namespace vaw;
using namespace vaw::trials;

namespace {

class ResultsFileTest : public trialtest::TrialsFolder {
 protected:
  Design d = trialtest::design(trialtest::staircase(), 21);
  ParticipantModel m{.pse = 0.3, .sigmaLog = 0.2, .seed = 9};

  // Answers `n` trials of the runner (or all that are left).
  void answer(Runner& r, int n) {
    for (int i = 0; i < n && r.next(); ++i) r.answer(simulateAnswer(m, *r.next()));
  }
  static int lines(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }
  // The error's message, failing the test when the file reads.
  static std::string errorOf(const std::filesystem::path& file) {
    try {
      (void)readResults(file);
    } catch (const InputError& e) {
      EXPECT_EQ(e.diagnostic().file, file.string());
      return e.what();
    }
    ADD_FAILURE() << "read without error:\n" << read(file);
    return {};
  }
};

}  // namespace

TEST_F(ResultsFileTest, EveryAnswerIsOneLineOnDiskBeforeTheNextTrial) {
  const auto file = dir / "p01.jsonl";
  Runner r = Runner::open(d, file);
  EXPECT_EQ(lines(read(file)), 1) << "the header is written when the session opens";
  for (int i = 1; i <= 5; ++i) {
    r.answer(simulateAnswer(m, *r.next()));
    EXPECT_EQ(lines(read(file)), 1 + i);
  }
  const ResultsFile f = readResults(file);
  EXPECT_EQ(f.records.size(), 5u);
  EXPECT_FALSE(f.torn);
  EXPECT_EQ(f.design.participant, "P01");
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(f.records[i].trial.scale, r.records()[i].trial.scale);
    EXPECT_EQ(f.records[i].trial.staircase, r.records()[i].trial.staircase);
    EXPECT_EQ(judgedFaster(f.records[i]), judgedFaster(r.records()[i]));
    EXPECT_EQ(f.records[i].answer.measures.caught, r.records()[i].answer.measures.caught);
    EXPECT_EQ(f.records[i].answer.measures.regraspTime_s, r.records()[i].answer.measures.regraspTime_s);
  }
}

TEST_F(ResultsFileTest, ReopeningResumesAtTheFirstUnansweredTrialAndEndsAsAnUninterruptedSession) {
  const auto file = dir / "resumed.jsonl", whole = dir / "whole.jsonl";
  {
    Runner r = Runner::open(d, file);
    answer(r, 13);
  }
  {
    Runner r = Runner::resume(file);  // the design from the file's header
    EXPECT_EQ(r.answered(), 13);
    EXPECT_FALSE(r.recovered());
    answer(r, 7);
  }
  Runner r = Runner::open(d, file);
  EXPECT_EQ(r.answered(), 20);
  answer(r, 1000);
  EXPECT_FALSE(r.next());
  Runner u = Runner::open(d, whole);
  answer(u, 1000);
  EXPECT_EQ(read(file), read(whole)) << "the resumed file is byte for byte the uninterrupted one";
}

TEST_F(ResultsFileTest, TornLastRecordIsReportedAndRecoveredUpToTheLastWholeRecord) {
  const auto file = dir / "torn.jsonl";
  {
    Runner r = Runner::open(d, file);
    answer(r, 6);
  }
  const std::string whole = read(file);
  // A crash inside the 7th record's write: half of it reached the disk.
  Runner probe = Runner::open(d, dir / "probe.jsonl");
  answer(probe, 7);
  const std::string full = read(dir / "probe.jsonl");
  const std::string seventh = full.substr(whole.size());
  ASSERT_EQ(full.substr(0, whole.size()), whole);
  write("torn.jsonl", whole + seventh.substr(0, seventh.size() / 2));

  const ResultsFile f = readResults(file);  // reading reports, and changes nothing
  ASSERT_TRUE(f.torn);
  EXPECT_EQ(f.torn->line, 8);
  EXPECT_EQ(f.torn->offset, whole.size());
  EXPECT_EQ(f.torn->bytes, seventh.size() / 2);
  EXPECT_EQ(f.records.size(), 6u);
  EXPECT_EQ(read(file).size(), whole.size() + seventh.size() / 2);

  Runner r = Runner::open(d, file);  // the runner cuts it off and asks that trial again
  ASSERT_TRUE(r.recovered());
  EXPECT_EQ(r.recovered()->line, 8);
  EXPECT_EQ(r.answered(), 6);
  EXPECT_EQ(read(file), whole);
  answer(r, 1);
  EXPECT_EQ(read(file), full);
}

TEST_F(ResultsFileTest, TornHeaderStartsTheSessionAfresh) {
  const auto file = write("header.jsonl", "{\"format\": \"vaw-trial-res");
  EXPECT_NE(errorOf(file).find("line 1: expected a header line ending in a newline, found a line cut off after 25 bytes"), std::string::npos);
  Runner r = Runner::open(d, file);
  ASSERT_TRUE(r.recovered());
  EXPECT_EQ(r.recovered()->line, 1);
  EXPECT_EQ(r.answered(), 0);
  EXPECT_EQ(lines(read(file)), 1);
}

TEST_F(ResultsFileTest, MalformedRecordsNameTheFileTheLineAndTheField) {
  const auto good = dir / "good.jsonl";
  {
    Runner r = Runner::open(d, good);
    answer(r, 4);
  }
  const std::string text = read(good);
  // Replaces the first occurrence of `from` after the start of line `line` (1-based).
  int files = 0;
  const auto edited = [&](int line, const std::string& from, const std::string& to) {
    std::size_t at = 0;
    for (int i = 1; i < line; ++i) at = text.find('\n', at) + 1;
    std::string s = text;
    const auto p = s.find(from, at);
    EXPECT_NE(p, std::string::npos) << from;
    return write("bad" + std::to_string(++files) + ".jsonl", s.replace(p, from.size(), to));
  };
  const std::pair<std::filesystem::path, std::string> cases[] = {
      {edited(3, "\"answer\":\"", "\"answer\":\"maybe"), "line 3.answer: expected \"too-fast\", \"too-slow\", \"first\" or \"second\""},
      {edited(4, "\"trial\":2", "\"trial\":1"), "line 4.trial: expected trial 2"},
      {edited(2, "\"scale\":", "\"scale\":1"), "line 2.scale: expected 0.08"},
      {edited(5, "\"caught\":", "\"caught\":0,\"x\":"), "line 5.x: expected one of the keys"},
      {edited(3, "\"staircase\":", "\"staircase\":7,\"y\":"), "line 3.y: expected one of the keys"},
      {edited(4, "{", "{{"), "line 4: expected a whole JSON record"},
      {edited(1, "vaw-trial-results", "vaw-trial-result"), "line 1.format: expected \"vaw-trial-results\""},
      {edited(1, "\"seed\":21", "\"seed\":\"x\""), "line 1.design.seed: expected a non-negative integer"},
      {write("empty-line.jsonl", text + "\n" + text.substr(text.find('\n') + 1)), "line 6: expected a whole JSON record"},
  };
  for (const auto& [file, wanted] : cases) {
    const std::string e = errorOf(file);
    EXPECT_NE(e.find(wanted), std::string::npos) << e << "\nwanted: " << wanted;
  }
  // A whole record after the design's last trial.
  Design two = d;
  auto& s = std::get<Staircase>(two.method);
  s.minTrials = s.maxTrials = 1;
  Runner r = Runner::open(two, dir / "short.jsonl");
  answer(r, 2);
  const std::string done = read(dir / "short.jsonl");
  write("long.jsonl", done + done.substr(done.rfind('\n', done.size() - 2) + 1));
  EXPECT_NE(errorOf(dir / "long.jsonl").find("line 4: expected no more records"), std::string::npos);
}

TEST_F(ResultsFileTest, AFileOfAnotherDesignIsRefusedNamingTheField) {
  const auto file = dir / "p.jsonl";
  { Runner r = Runner::open(d, file); }
  Design other = d;
  other.seed = 22;
  try {
    (void)Runner::open(other, file);
    FAIL() << "opened another design's results";
  } catch (const InputError& e) {
    EXPECT_EQ(e.diagnostic().field, "line 1.design.seed");
  }
}

TEST_F(ResultsFileTest, OneSessionPerFile) {
  const auto file = dir / "p.jsonl";
  Runner first = Runner::open(d, file);
  EXPECT_THROW((void)Runner::open(d, file), std::system_error);
  EXPECT_THROW((void)Runner::resume(file), std::system_error);
  Runner moved = std::move(first);
  moved.answer(simulateAnswer(m, *moved.next()));
  EXPECT_EQ(lines(read(file)), 2);
}

TEST_F(ResultsFileTest, ResumingAMissingFileIsAnInputError) {
  EXPECT_THROW((void)Runner::resume(dir / "none.jsonl"), InputError);
  EXPECT_THROW((void)readResults(dir / "none.jsonl"), InputError);
}
