#pragma once
// Scratch files for tests: the one temporary-directory helper every test program uses.
#include <filesystem>
#include <string>

namespace vaw::test {

// A fresh, empty folder under the system's temporary directory. All of them live under one root per
// test program, which is removed when the program exits, however its tests end.
std::filesystem::path tempDir();
// Writes `text` to `path` (creating its folder) and returns the path.
std::filesystem::path writeFile(const std::filesystem::path& path, const std::string& text);

}  // namespace vaw::test
