// Output files are the previous complete file or the new complete one: never truncated, never mixed,
// whatever stops the writer (an exception, a file-size limit, SIGKILL).
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <fstream>
#include <sstream>
#include <string>

#include "child_process.hpp"
#include "files.hpp"
#include "vaw/atomic_file.hpp"
#include "vaw/error.hpp"

using namespace vaw;

namespace {

std::string read(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::size_t entries(const std::filesystem::path& dir) {
  return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()));
}

}  // namespace

TEST(AtomicFile, CommitReplacesTheWholeFile) {
  const auto dir = test::tempDir();
  const auto file = test::writeFile(dir / "out.csv", "old\n");
  ::chmod(file.c_str(), 0640);
  AtomicFile f(file);
  const std::string big(200000, 'x');  // several buffers
  f << "new\n" << big;
  EXPECT_EQ(read(file), "old\n") << "nothing visible before the commit";
  f.commit();
  EXPECT_EQ(read(file), "new\n" + big);
  EXPECT_EQ(entries(dir), 1u) << "no temporary file left";
  struct stat st {};
  ASSERT_EQ(::stat(file.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640u) << "the replaced file keeps its mode";
}

TEST(AtomicFile, AbandonedWriteLeavesThePreviousFile) {
  const auto dir = test::tempDir();
  const auto file = test::writeFile(dir / "out.csv", "good\n");
  {
    AtomicFile f(file);
    f << std::string(100000, 'p');  // an exception would end here, before commit()
  }
  EXPECT_EQ(read(file), "good\n");
  EXPECT_EQ(entries(dir), 1u);
}

TEST(AtomicFile, KilledWriterLeavesThePreviousFile) {
  const auto dir = test::tempDir();
  const auto file = test::writeFile(dir / "trajectories.csv", "good\n");
  const int status = test::inChild([&] {
    AtomicFile f(file);
    f << std::string(300000, 'p');
    ::kill(::getpid(), SIGKILL);
  });
  EXPECT_EQ(status, 128 + SIGKILL);
  EXPECT_EQ(read(file), "good\n") << "the good file is not replaced by a partial one";
}

TEST(AtomicFile, FileSizeLimitIsANamedErrorAndLeavesThePreviousFile) {
  const auto dir = test::tempDir();
  const auto file = test::writeFile(dir / "trajectories.csv", "good\n");
  const int status = test::inChild([&] {
    std::signal(SIGXFSZ, SIG_IGN);  // as vaw-sim does: the write fails instead of killing the process
    const rlimit limit{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    try {
      AtomicFile f(file);
      f << std::string(100000, 'p');
      f.commit();
    } catch (const OutputError& e) {
      const std::string what = e.what();
      ::_exit(what.find("trajectories.csv") != std::string::npos && what.find("File too large") != std::string::npos ? 42 : 1);
    }
    ::_exit(2);
  });
  EXPECT_EQ(status, 42);
  EXPECT_EQ(read(file), "good\n");
  EXPECT_EQ(entries(dir), 1u);
}

TEST(AtomicFile, MissingDirectoryIsANamedError) {
  const auto file = test::tempDir() / "absent" / "out.csv";
  try {
    AtomicFile f(file);
    FAIL();
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
}
