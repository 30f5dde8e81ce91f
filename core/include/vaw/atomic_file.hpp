#pragma once
// Output files that are either the previous complete file or the new complete one, never a mix or a
// truncated one. The data goes to a hidden temporary file in the target's directory; every write is
// checked; commit() syncs the file to disk, renames it over the target (atomic on a POSIX file system)
// and syncs the directory. An interrupted writer (an exception, a full disk, a file-size limit) removes
// its temporary file and leaves the previous target in place; after SIGKILL only a stray
// ".NAME.XXXXXX.tmp" can remain. Every failure throws vaw::OutputError naming the target and the
// system's reason. Concurrent writers of one target each commit a whole file; the last rename wins.
#include <filesystem>
#include <string>
#include <string_view>

namespace vaw {

class AtomicFile {
 public:
  // Creates the temporary file next to `target` (whose directory must exist).
  explicit AtomicFile(std::filesystem::path target);
  ~AtomicFile();  // removes the temporary file unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(std::string_view data);  // buffered; a failed write throws
  AtomicFile& operator<<(std::string_view data) {
    write(data);
    return *this;
  }
  // finish() then publish(). Writers of several files that belong together finish() them all, then
  // publish() them all (vaw-sim run, under a lock on the output directory).
  void commit();
  void finish();   // flushes, syncs to disk and closes; the data is complete under the temporary name
  void publish();  // renames it over the target and syncs the directory
  [[nodiscard]] const std::filesystem::path& target() const { return target_; }

 private:
  void flush();
  [[noreturn]] void failWith(const char* what, int error);

  std::filesystem::path target_, temp_;
  int fd_ = -1;
  std::string buffer_;
  bool committed_ = false;
};

// The whole file at once.
void writeFileAtomically(const std::filesystem::path& target, std::string_view data);

}  // namespace vaw
