#pragma once
// Output commands (run, clearance) publish their files together under an exclusive lock on
// DIR/.vaw-run.lock, so concurrent commands into one DIR leave the files of one of them.
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "vaw/error.hpp"

namespace vaw::app {

// Holds an exclusive lock on DIR/.vaw-run.lock for its lifetime.
class DirectoryLock {
 public:
  explicit DirectoryLock(const std::filesystem::path& dir) {
    const std::filesystem::path file = dir / ".vaw-run.lock";
    fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd_ < 0 || ::flock(fd_, LOCK_EX) != 0) throw OutputError("cannot lock " + file.string() + ": " + std::strerror(errno));
  }
  ~DirectoryLock() {
    if (fd_ >= 0) ::close(fd_);  // closing releases the lock
  }
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace vaw::app
