#include "vaw/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "vaw/error.hpp"

namespace vaw {

namespace {
constexpr std::size_t kBufferBytes = 1 << 16;

// The mode a file created with open(0666) would get. umask() cannot be read without setting it, which
// would race with other threads creating files, so read it from /proc (Linux 4.7 and later).
mode_t newFileMode() {
  static const mode_t mode = [] {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
      if (line.rfind("Umask:", 0) == 0) return static_cast<mode_t>(0666 & ~std::stoul(line.substr(6), nullptr, 8));
    return static_cast<mode_t>(0644);
  }();
  return mode;
}

void syncDirectory(const std::filesystem::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // the rename is done; a directory we cannot open cannot be synced either
  (void)::fsync(fd);
  ::close(fd);
}
}  // namespace

AtomicFile::AtomicFile(std::filesystem::path target) : target_(std::move(target)) {
  const std::filesystem::path dir = target_.parent_path();
  const std::string pattern = (dir / ("." + target_.filename().string() + ".XXXXXX.tmp")).string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  fd_ = ::mkstemps(name.data(), 4);
  if (fd_ < 0) failWith("cannot create a temporary file beside", errno);
  temp_ = name.data();
  buffer_.reserve(kBufferBytes);
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_ && !temp_.empty()) ::unlink(temp_.c_str());
}

void AtomicFile::write(std::string_view data) {
  if (buffer_.size() + data.size() > kBufferBytes) flush();
  if (data.size() >= kBufferBytes) {
    buffer_.assign(data);
    flush();
  } else {
    buffer_.append(data);
  }
}

void AtomicFile::flush() {
  std::size_t done = 0;
  while (done < buffer_.size()) {
    const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      failWith("cannot write", errno);
    }
    done += static_cast<std::size_t>(n);
  }
  buffer_.clear();
}

void AtomicFile::commit() {
  finish();
  publish();
}

void AtomicFile::finish() {
  if (fd_ < 0) return;
  flush();
  // mkstemp's 0600 would hide the file from others: give it the target's mode, or a new file's.
  struct stat st {};
  (void)::fchmod(fd_, ::stat(target_.c_str(), &st) == 0 ? (st.st_mode & 07777) : newFileMode());
  if (::fsync(fd_) != 0) failWith("cannot write", errno);
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) failWith("cannot write", errno);
}

void AtomicFile::publish() {
  if (::rename(temp_.c_str(), target_.c_str()) != 0) failWith("cannot replace", errno);
  committed_ = true;
  syncDirectory(target_.parent_path());
}

void AtomicFile::failWith(const char* what, int error) {
  throw OutputError(std::string(what) + " " + target_.string() + ": " + std::strerror(error));
}

void writeFileAtomically(const std::filesystem::path& target, std::string_view data) {
  AtomicFile f(target);
  f.write(data);
  f.commit();
}

}  // namespace vaw
