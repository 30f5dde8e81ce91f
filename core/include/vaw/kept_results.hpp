#pragma once
// Results vaw can compute again but would rather not: kept in a folder between sessions, each under a key
// that names everything it depends on (docs/step.md, "Reopening a file"). An entry holds a header (the
// key again, the payload's length and hash) and the payload; one whose header does not match its payload
// (a damaged disk, a foreign file) is removed and reported as absent. Entries are written through
// vaw::AtomicFile, so a writer that dies leaves no half-written entry under an entry's name, only a hidden
// temporary file, which a later store removes once it is an hour old. After each store the folder is
// trimmed to its size limit, least recently used first.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "vaw/hash.hpp"

namespace vaw {

class KeptResults {
 public:
  // `limitBytes`: the folder's entries together stay at or under this (0: nothing is kept).
  KeptResults(std::filesystem::path dir, std::uint64_t limitBytes);
  // The folder `name` under `root` with a limit of `limitMB`, or nothing when `root` is empty or the limit
  // is not positive (ImportOptions::resultCache and resultCacheMB: nothing kept).
  static std::optional<KeptResults> under(const std::filesystem::path& root, double limitMB, const std::string& name);

  // The kept payload, or nothing (no entry, or a damaged one, which is removed). Marks the entry used.
  [[nodiscard]] std::optional<std::vector<std::uint8_t>> find(const std::string& key) const;
  // Keeps `payload` under `key`, then trims the folder. Throws vaw::OutputError when it cannot be written.
  void store(const std::string& key, std::span<const std::uint8_t> payload) const;
  void remove(const std::string& key) const;

  [[nodiscard]] std::filesystem::path entry(const std::string& key) const;
  [[nodiscard]] const std::filesystem::path& dir() const { return dir_; }

 private:
  void trim() const;

  std::filesystem::path dir_;
  std::uint64_t limit_;
};

// The key a result is kept under, the one way every kept result makes it: the build that computes the
// result first (buildIdentity), then each thing the result depends on, in order. FNV-1a over them, as text.
class ResultKey {
 public:
  explicit ResultKey(std::uint64_t build) { add(build); }
  ResultKey& add(const void* data, std::size_t size) {
    h_ = fnv1a(data, size, h_);
    return *this;
  }
  ResultKey& add(std::string_view text) { return add(text.data(), text.size()); }
  template <typename T>
  requires std::is_trivially_copyable_v<T> &&(!std::is_pointer_v<T>)ResultKey& add(const T& value) {
    return add(&value, sizeof value);
  }
  [[nodiscard]] std::string text() const { return hashText(h_); }

 private:
  std::uint64_t h_ = kFnvOffset;
};

// What stands for a build in a key, so that a rebuilt library or program computes anew: the GNU build-id
// (the linker's --build-id, a hash of what it linked) of the loaded object that holds `code` (a function
// of a library or program), or of the program file `program`; the file's size and time stamp where there
// is no build-id. 0 when neither can be found.
std::uint64_t buildIdentity(const void* code);
std::uint64_t buildIdentity(const std::filesystem::path& program);

}  // namespace vaw
