#pragma once
// libFuzzer harnesses for the file parsers and the mesh checks. The parsers read files, so each input
// is written to one scratch file per process first. A harness may only end in success or vaw::InputError;
// anything else (another exception, a crash, a sanitizer report, a hang) is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace vaw::fuzz {

// The scratch file for this process: <tmp>/vaw-fuzz-<pid>/<name>, rewritten with each input.
inline std::filesystem::path writeInput(const std::uint8_t* data, std::size_t size, const char* name) {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("vaw-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  const auto file = dir / name;
  std::ofstream(file, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return file;
}

}  // namespace vaw::fuzz
