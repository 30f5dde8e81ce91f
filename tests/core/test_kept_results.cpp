// Results kept between sessions (vaw/kept_results.hpp): what is found is what was stored, whole, whoever
// else writes the same entry at once; a damaged entry, a full disk or a folder that cannot be made keep
// nothing half-written and never pass a wrong result off as kept.
#include <gtest/gtest.h>

#include <dlfcn.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "files.hpp"
#include "vaw/error.hpp"
#include "vaw/kept_results.hpp"

using namespace vaw;

namespace {

std::vector<std::uint8_t> filled(std::size_t n, std::uint8_t byte) { return std::vector<std::uint8_t>(n, byte); }

std::size_t filesIn(const std::filesystem::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++n;
  return n;
}

}  // namespace

TEST(KeptResults, WhatIsStoredIsFoundAndADamagedEntryIsNot) {
  const KeptResults kept(test::tempDir() / "kept", 1 << 20);
  EXPECT_FALSE(kept.find("a").has_value());
  const auto payload = filled(5000, 7);
  kept.store("a", payload);
  EXPECT_EQ(kept.find("a"), payload);
  // One byte changed on disk: not found, and removed.
  {
    std::fstream f(kept.entry("a"), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-10, std::ios::end);
    f.put('x');
  }
  EXPECT_FALSE(kept.find("a").has_value());
  EXPECT_FALSE(std::filesystem::exists(kept.entry("a")));
  // An entry stored under another key (a file copied or renamed) is not this key's.
  kept.store("b", payload);
  std::filesystem::copy_file(kept.entry("b"), kept.entry("c"));
  EXPECT_FALSE(kept.find("c").has_value());
  EXPECT_EQ(kept.find("b"), payload);
}

TEST(KeptResults, TheFolderKeepsToItsLimitLeastRecentlyUsedFirst) {
  const KeptResults kept(test::tempDir() / "kept", 25000);
  kept.store("old", filled(10000, 1));
  kept.store("used", filled(10000, 2));
  // "old" is older than "used" by its time stamp; "used" is asked for, then a third entry goes over.
  std::filesystem::last_write_time(kept.entry("old"), std::filesystem::file_time_type::clock::now() - std::chrono::hours(2));
  ASSERT_TRUE(kept.find("used").has_value());
  kept.store("new", filled(10000, 3));
  EXPECT_FALSE(kept.find("old").has_value());
  EXPECT_TRUE(kept.find("used").has_value());
  EXPECT_TRUE(kept.find("new").has_value());
}

// Two processes store and read the same key at once, each its own payload: every read is one of the two
// whole payloads, never a mix, a torn one or nothing once both have stored.
TEST(KeptResults, TwoProcessesWritingOneEntryAtOnceNeverMixIt) {
  const std::filesystem::path dir = test::tempDir() / "kept";
  const KeptResults kept(dir, 64 << 20);
  kept.store("same", filled(300000, 'a'));
  const auto writer = [&](std::uint8_t mine) {
    return [&kept, mine] {
      const auto payload = filled(300000, mine);
      for (int i = 0; i < 100; ++i) {
        kept.store("same", payload);
        const auto found = kept.find("same");
        if (!found) ::_exit(3);
        if (found->size() != 300000) ::_exit(4);
        const std::uint8_t first = found->front();
        if (first != 'a' && first != 'b') ::_exit(5);
        if (std::any_of(found->begin(), found->end(), [first](std::uint8_t c) { return c != first; })) ::_exit(6);
      }
    };
  };
  const pid_t a = test::startChild(writer('a')), b = test::startChild(writer('b'));
  EXPECT_EQ(test::finishChild(a), 0) << "3: not found, 4: torn, 5: foreign, 6: mixed";
  EXPECT_EQ(test::finishChild(b), 0) << "3: not found, 4: torn, 5: foreign, 6: mixed";
  EXPECT_EQ(filesIn(dir), 1u) << "no temporary file left";
}

// A disk that fills (a file-size limit here): the store fails with a named error, nothing half-written is
// left, and what was kept before is still found whole.
TEST(KeptResults, AFullDiskKeepsNothingHalfWritten) {
  const std::filesystem::path dir = test::tempDir() / "kept";
  const KeptResults kept(dir, 64 << 20);
  kept.store("before", filled(1000, 9));
  const int status = test::inChild([&] {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{65536, 65536};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    try {
      kept.store("big", filled(1 << 20, 4));
    } catch (const OutputError& e) {
      ::_exit(std::string(e.what()).find("File too large") != std::string::npos ? 42 : 1);
    }
    ::_exit(2);
  });
  EXPECT_EQ(status, 42);
  EXPECT_FALSE(kept.find("big").has_value());
  EXPECT_EQ(kept.find("before"), filled(1000, 9));
  EXPECT_EQ(filesIn(dir), 1u) << "no temporary file left";
}

// A folder that cannot be made (here: a file stands where it would be; root may write anywhere else):
// the store says so, finding is simply nothing.
TEST(KeptResults, AFolderThatCannotBeMadeIsANamedErrorAndNothingFound) {
  const std::filesystem::path file = test::writeFile(test::tempDir() / "not-a-folder", "x");
  const KeptResults kept(file / "kept", 1 << 20);
  EXPECT_FALSE(kept.find("a").has_value());
  try {
    kept.store("a", filled(10, 1));
    FAIL() << "stored under a file";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("not-a-folder/kept"), std::string::npos) << e.what();
  }
}

// A build stands in a key by its build-id: the same read from the loaded library and from its file, another
// for another program, so that a rebuilt one computes anew.
TEST(KeptResults, ABuildIsKnownByItsBuildId) {
  const auto inCore = static_cast<std::uint64_t (*)(const void*)>(&buildIdentity);
  const std::uint64_t core = buildIdentity(reinterpret_cast<const void*>(inCore));
  EXPECT_NE(core, 0u);
  Dl_info info{};
  ASSERT_NE(dladdr(reinterpret_cast<const void*>(inCore), &info), 0);
  EXPECT_EQ(buildIdentity(std::filesystem::path(info.dli_fname)), core) << info.dli_fname;
  // This test program is another build; a copy of the library with its time stamp changed is the same.
  const std::uint64_t here = buildIdentity(reinterpret_cast<const void*>(&filled));
  EXPECT_NE(here, 0u);
  EXPECT_NE(here, core);
  const std::filesystem::path copy = test::tempDir() / "copy.so";
  std::filesystem::copy_file(info.dli_fname, copy);
  std::filesystem::last_write_time(copy, std::filesystem::file_time_type::clock::now() + std::chrono::hours(1));
  EXPECT_EQ(buildIdentity(copy), core);
  // A file with no build-id (not a program) stands by its size and time stamp.
  const std::filesystem::path text = test::writeFile(test::tempDir() / "not-a-program", "x");
  EXPECT_NE(buildIdentity(text), 0u);
  EXPECT_NE(buildIdentity(text), core);
}
