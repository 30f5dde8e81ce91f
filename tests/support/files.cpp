#include "files.hpp"

#include <unistd.h>

#include <fstream>
#include <random>
#include <stdexcept>

namespace vaw::test {

namespace {
struct TempRoot {
  std::filesystem::path path;
  TempRoot() {
    std::random_device rd;
    path = std::filesystem::temp_directory_path() / ("vaw-test-" + std::to_string(::getpid()) + "-" + std::to_string(rd()));
    std::filesystem::create_directories(path);
  }
  ~TempRoot() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};
}  // namespace

std::filesystem::path tempDir() {
  static TempRoot root;
  static int counter = 0;
  auto dir = root.path / std::to_string(++counter);
  std::filesystem::create_directories(dir);
  return dir;
}

std::filesystem::path writeFile(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out.flush()) throw std::runtime_error("cannot write " + path.string());
  return path;
}

}  // namespace vaw::test
