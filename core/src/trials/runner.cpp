#include "vaw/trials/runner.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <string>
#include <system_error>
#include <utility>

#include "../base/json_node.hpp"
#include "design_json.hpp"
#include "results_lines.hpp"

namespace vaw::trials {

namespace {

[[noreturn]] void systemFail(const std::filesystem::path& file, const std::string& what) {
  throw std::system_error(errno, std::generic_category(), file.string() + ": " + what);
}

// Plain POSIX I/O: one write() of a whole line, then fsync. A short write is continued; a failed one
// is undone by truncating back, so the file never keeps half a record that was not reported.
void appendDurably(int fd, const std::filesystem::path& file, const std::string& line) {
  struct stat st {};
  if (::fstat(fd, &st) != 0) systemFail(file, "cannot stat");
  std::size_t done = 0;
  while (done < line.size()) {
    const ssize_t n = ::write(fd, line.data() + done, line.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int saved = errno;
      if (::ftruncate(fd, st.st_size) == 0) (void)::fsync(fd);
      errno = saved;
      systemFail(file, "cannot write a record");
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) systemFail(file, "cannot sync a record to disk");
}

std::string readAll(int fd, const std::filesystem::path& file) {
  std::string text;
  char buffer[1 << 16];
  for (off_t at = 0;;) {
    const ssize_t n = ::pread(fd, buffer, sizeof buffer, at);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) systemFail(file, "cannot read");
    if (n == 0) return text;
    text.append(buffer, static_cast<std::size_t>(n));
    at += n;
  }
}

// A new file's name must survive a crash too: sync the directory that holds it.
void syncDirectory(const std::filesystem::path& file) {
  const std::filesystem::path dir = file.parent_path().empty() ? std::filesystem::path(".") : file.parent_path();
  const int d = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (d < 0) systemFail(dir, "cannot open the folder to sync it");
  const int rc = ::fsync(d);
  ::close(d);
  if (rc != 0) systemFail(dir, "cannot sync the folder");
}

// The first top-level field in which two designs differ, to name it in the error.
std::string firstDifference(const vaw::detail::Json& a, const vaw::detail::Json& b) {
  for (const auto& [key, value] : a.items())
    if (!b.contains(key) || b.at(key) != value) return key;
  for (const auto& [key, value] : b.items())
    if (!a.contains(key)) return key;
  return {};
}

}  // namespace

Runner::Runner(Procedure procedure, std::filesystem::path path, int fd, std::optional<TornTail> recovered)
    : procedure_(std::move(procedure)), path_(std::move(path)), fd_(fd), recovered_(recovered) {}

Runner::Runner(Runner&& other) noexcept
    : procedure_(std::move(other.procedure_)),
      path_(std::move(other.path_)),
      fd_(std::exchange(other.fd_, -1)),
      recovered_(other.recovered_) {}

Runner& Runner::operator=(Runner&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    procedure_ = std::move(other.procedure_);
    path_ = std::move(other.path_);
    fd_ = std::exchange(other.fd_, -1);
    recovered_ = other.recovered_;
  }
  return *this;
}

Runner::~Runner() {
  if (fd_ >= 0) ::close(fd_);  // also releases the lock
}

Runner Runner::open(const Design& design, const std::filesystem::path& results) { return openExisting(design, results); }

Runner Runner::resume(const std::filesystem::path& results) { return openExisting(std::nullopt, results); }

Runner Runner::openExisting(const std::optional<Design>& design, const std::filesystem::path& results) {
  const int flags = O_RDWR | O_APPEND | O_CLOEXEC | (design ? O_CREAT : 0);
  const int fd = ::open(results.c_str(), flags, 0644);
  if (fd < 0) {
    if (errno == ENOENT && !design) vaw::fail(results.string(), "", "an existing results file to resume", "no such file");
    systemFail(results, "cannot open the results file");
  }
  // From here on the descriptor must be closed on every throw.
  struct Guard {
    int fd;
    ~Guard() {
      if (fd >= 0) ::close(fd);
    }
  } guard{fd};
  // One session per file: two writers would interleave their records.
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) systemFail(results, "the results file is in use by another session");

  const std::string text = readAll(fd, results);
  std::optional<TornTail> recovered;
  if (text.find('\n') == std::string::npos) {
    // Empty, or the header itself was cut off: nothing was answered yet.
    if (!design) (void)detail::parseResults(text, results);  // throws, naming the missing header
    if (!text.empty()) recovered = TornTail{1, 0, text.size()};
    if (::ftruncate(fd, 0) != 0) systemFail(results, "cannot truncate");
    appendDurably(fd, results, detail::headerLine(*design));
    syncDirectory(results);
    Runner r(Procedure(*design), results, fd, recovered);
    guard.fd = -1;
    return r;
  }
  detail::Parsed parsed = detail::parseResults(text, results);
  if (design) {
    const auto given = detail_json::designToJson(*design), stored = detail_json::designToJson(parsed.file.design);
    if (given != stored)
      vaw::fail(results.string(), "line 1.design." + firstDifference(stored, given),
                "the design this session was started with (" + design->name + ")", "a different value: the file belongs to another design");
  }
  if (parsed.file.torn) {
    if (::ftruncate(fd, static_cast<off_t>(parsed.file.torn->offset)) != 0 || ::fsync(fd) != 0)
      systemFail(results, "cannot cut off the torn last record");
    recovered = parsed.file.torn;
  }
  Runner r(std::move(parsed.procedure), results, fd, recovered);
  guard.fd = -1;
  return r;
}

void Runner::answer(const Answer& a) {
  procedure_.check(a);
  appendDurably(fd_, path_, detail::recordLine(Record{*procedure_.next(), a}));
  procedure_.answer(a);
}

}  // namespace vaw::trials
