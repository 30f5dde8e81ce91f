// STEP import: starts vaw-step-import (Open CASCADE, next to this plugin) on the file, relays its progress,
// and turns its result into vaw's CAD assembly. Open CASCADE crashes or never returns on some files
// (docs/step.md), so it never runs in the workbench's own process: a crash, a hang past the time limit
// or a cancel ends only the child.
#include <dlfcn.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "vaw/error.hpp"
#include "vaw/atomic_file.hpp"
#include "vaw/cad_assembly.hpp"
#include "vaw/importer.hpp"
#include "vaw/mesh_export.hpp"
#include "vaw/kept_results.hpp"
#include "vaw/limits.hpp"

#include "step_result_cache.hpp"
#include "step_result_parser.hpp"

extern char** environ;

namespace {

using Clock = std::chrono::steady_clock;

// Where this plugin's file is: the reader is installed beside it.
std::filesystem::path pluginDir() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&pluginDir), &info) == 0 || info.dli_fname == nullptr) return {};
  return std::filesystem::path(info.dli_fname).parent_path();
}

// A fresh private folder for the child's result, removed however the read ends.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "vaw-step-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr)
      throw vaw::OutputError("cannot create a temporary folder: " + std::string(std::strerror(errno)));
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Ends the child if the read stops early (cancel, timeout, an exception from the progress callback).
class Child {
 public:
  explicit Child(pid_t pid) : pid_(pid) {}
  ~Child() { kill(); }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  void kill() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {}
    pid_ = -1;
  }
  // The wait status once it has exited, without blocking.
  bool exited(int& status) {
    if (pid_ <= 0) return false;
    const pid_t r = waitpid(pid_, &status, WNOHANG);
    if (r == pid_) {
      pid_ = -1;
      return true;
    }
    return false;
  }

 private:
  pid_t pid_;
};

class Fd {
 public:
  explicit Fd(int fd = -1) : fd_(fd) {}
  ~Fd() { close(); }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  [[nodiscard]] int get() const { return fd_; }

 private:
  int fd_;
};

std::string seconds(double s) {
  std::ostringstream o;
  o << s;
  return o.str();
}

std::string lastLine(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  return last;
}

std::string signalName(int sig) {
  const char* abbrev = sigabbrev_np(sig);
  return "signal " + std::to_string(sig) + (abbrev ? std::string(", SIG") + abbrev : std::string());
}

// A child's memory limit: the one set, else vaw's default.
double memoryLimitMB(double set) { return set > 0.0 ? set : vaw::limits::defaultMemoryMB(); }

// Why a child was stopped before it ended by itself; the caller's `stopped` says it (and throws).
enum class Stop { CannotStart, Cancelled, TimedOut };

// Runs one of the plugin's children (the reader, the writer) contained: its stdin /dev/null, its stderr into
// `errors`, its progress lines on stdout ("progress 0.350 tessellating bracket"; anything else there is Open
// CASCADE's) passed to `progress`, which stops it by returning false; it is killed past `timeoutSeconds`, or
// when this call ends early by an exception. The child itself dies with this process and keeps to its memory
// limit (its --parent and --memory-limit-mb, in `args`). `stage` follows the last stage it named. Returns its
// wait status; `stopped` is called after the child is gone and must throw.
int runChild(std::vector<std::string> args, const std::filesystem::path& errors, double timeoutSeconds,
             const vaw::ProgressFn& progress, std::string& stage, const std::function<void(Stop, const std::string&)>& stopped) {
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  int pipeFds[2];
  if (pipe2(pipeFds, O_CLOEXEC) != 0) throw vaw::OutputError(std::string("cannot create a pipe: ") + std::strerror(errno));
  Fd readEnd(pipeFds[0]), writeEnd(pipeFds[1]);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, writeEnd.get(), STDOUT_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, errors.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    stopped(Stop::CannotStart, std::strerror(spawned));
    throw std::logic_error("runChild: `stopped` returned");
  }
  Child child(pid);
  writeEnd.close();

  const auto start = Clock::now();
  double fraction = 0.0;
  auto lastReport = Clock::now();
  const auto stop = [&](Stop why) {
    child.kill();
    stopped(why, stage);
    throw std::logic_error("runChild: `stopped` returned");
  };
  const auto report = [&] {
    lastReport = Clock::now();
    if (progress && !progress(fraction, stage)) stop(Stop::Cancelled);
  };
  report();

  std::string pending;
  bool open = true;
  int status = 0;
  bool done = false;
  while (!done) {
    if (open) {
      pollfd p{readEnd.get(), POLLIN, 0};
      const int r = poll(&p, 1, 20);
      if (r > 0) {
        char buf[4096];
        const ssize_t n = ::read(readEnd.get(), buf, sizeof buf);
        if (n > 0) {
          pending.append(buf, static_cast<std::size_t>(n));
          for (std::size_t nl; (nl = pending.find('\n')) != std::string::npos;) {
            const std::string line = pending.substr(0, nl);
            pending.erase(0, nl + 1);
            if (line.rfind("progress ", 0) != 0) continue;
            // from_chars: the child writes a point; strtod would read the window's locale's comma.
            double f = 0.0;
            const char* const last = line.data() + line.size();
            const auto [end, err] = std::from_chars(line.data() + 9, last, f);
            if (err != std::errc()) continue;
            fraction = std::clamp(f, 0.0, 1.0);
            stage = end != last && *end == ' ' ? std::string(end + 1, last) : std::string();
            report();
          }
        } else if (n == 0 || (errno != EINTR && errno != EAGAIN)) {
          open = false;
        }
      }
    } else {
      done = child.exited(status);
      if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (std::chrono::duration<double>(Clock::now() - start).count() > timeoutSeconds) stop(Stop::TimedOut);
    // Open CASCADE reports nothing during a long parse, transfer or write: ask the caller anyway, so a
    // stop is honoured within a fifth of a second.
    if (Clock::now() - lastReport > std::chrono::milliseconds(200)) report();
  }
  return status;
}

class StepImporter final : public vaw::MeshImporter {
 public:
  [[nodiscard]] std::string name() const override { return "Open CASCADE STEP"; }
  [[nodiscard]] std::vector<std::string> extensions() const override { return {"stp", "step", "p21"}; }
  [[nodiscard]] bool canRead(const std::filesystem::path& file) const override {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext == ".stp" || ext == ".step" || ext == ".p21";
  }

  [[nodiscard]] vaw::ImportedMesh read(const std::filesystem::path& file, const vaw::ImportOptions& options,
                                       const vaw::ProgressFn& progress) const override {
    const std::string name = file.string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) vaw::fail(name, "", "an existing, readable file", "no such file");
    const std::filesystem::path reader = pluginDir() / "vaw-step-import";
    if (access(reader.c_str(), X_OK) != 0)
      vaw::fail(name, "", "a STEP reader installed with the STEP plugin", "no executable " + reader.string());

    // An unchanged file read before with the same settings is not read again.
    const std::optional<vaw::KeptResults> cache = vaw::KeptResults::under(options.resultCache, options.resultCacheMB, "step-results");
    std::string key, content;  // content: the file's hash, handed on so that it is hashed once per open
    if (cache) {
      if (progress && !progress(0.0, "checking whether " + file.filename().string() + " was read before")) throw vaw::LoadCancelled();
      content = vaw::fileContentHash(file);
      key = vaw::step::resultKey(content, options, reader);
      if (auto kept = cache->find(key)) {
        if (progress && !progress(0.5, "opening " + file.filename().string() + " as read before (unchanged)")) throw vaw::LoadCancelled();
        try {
          auto r = vaw::step::parseResult(*kept);
          if (auto* assembly = std::get_if<vaw::ImportedMesh>(&r)) {
            assembly->contentHash = content;
            return std::move(*assembly);
          }
        } catch (const vaw::step::MalformedResult&) {
          // Intact on disk yet unreadable (a result of another format under a colliding key): read afresh.
        }
        cache->remove(key);
      }
    }

    TempDir tmp;
    const std::filesystem::path result = tmp.path() / "result.cbor";
    const std::filesystem::path errors = tmp.path() / "stderr.txt";
    const std::string rel = seconds(options.relativeDeflection), ang = seconds(options.angularDeflection);
    const std::string memory = std::to_string(static_cast<long long>(memoryLimitMB(options.readerMemoryMB)));
    const std::vector<std::string> args = {reader.string(),        name, "--out", result.string(), "--relative-deflection", rel,
                                           "--angular-deflection", ang, "--parent", std::to_string(getpid()), "--memory-limit-mb", memory,
                                           "--max-instances", std::to_string(static_cast<long long>(options.maxInstances))};
    std::string stage = "starting the STEP reader";
    const int status = runChild(args, errors, options.timeoutSeconds, progress, stage, [&](Stop why, const std::string& detail) {
      if (why == Stop::Cancelled) throw vaw::LoadCancelled();
      if (why == Stop::CannotStart) vaw::fail(name, "", "a STEP reader that starts", "cannot start " + reader.string() + ": " + detail);
      vaw::fail(name, "", "a STEP file Open CASCADE reads within the time limit of " + seconds(options.timeoutSeconds) + " s",
                "still reading after " + seconds(options.timeoutSeconds) + " s, at \"" + detail +
                    "\" (a large file may need longer: raise the limit with File > STEP Settings or vaw-sim --timeout S)");
    });

    if (WIFSIGNALED(status))
      vaw::fail(name, "", "a STEP file Open CASCADE can read",
                "the reader crashed (" + signalName(WTERMSIG(status)) + ") while " + stage);
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    // The reader's result: the assembly, or its named error about the file.
    std::vector<std::uint8_t> bytes;
    const auto readResult = [&] {
      std::ifstream in(result, std::ios::binary);
      if (!in) throw vaw::step::MalformedResult("the reader wrote no result");
      bytes.assign(std::istreambuf_iterator<char>(in), {});
      return vaw::step::parseResult(bytes);
    };
    if (code == 3) {
      try {
        const auto r = readResult();
        if (const auto* bad = std::get_if<vaw::step::ReaderError>(&r)) vaw::fail(name, bad->field, bad->expected, bad->found);
      } catch (const vaw::step::MalformedResult&) {
        // The reader's stderr line below still says what is wrong.
      }
      vaw::fail(name, "", "a STEP file Open CASCADE can read", lastLine(errors));
    }
    if (code == 5)
      vaw::fail(name, "", "a STEP file Open CASCADE reads within the reader's memory limit of " + memory + " MB",
                lastLine(errors) + " while " + stage + " (the limit is half the machine's memory unless set; vaw-sim: --reader-memory MB)");
    if (code != 0) {
      const std::string why = lastLine(errors);
      vaw::fail(name, "", "a STEP file Open CASCADE can read",
                "the reader failed (exit code " + std::to_string(code) + ")" + (why.empty() ? "" : ": " + why));
    }

    try {
      auto r = readResult();
      if (auto* assembly = std::get_if<vaw::ImportedMesh>(&r)) {
        assembly->contentHash = content;
        if (cache) {
          try {
            cache->store(key, bytes);
          } catch (const vaw::OutputError& e) {
            assembly->warnings.push_back(std::string("not kept for reopening without reading again: ") + e.what());
          }
        }
        return std::move(*assembly);
      }
      throw vaw::step::MalformedResult("an error about the file, yet the reader exited 0");
    } catch (const vaw::step::MalformedResult& e) {
      vaw::fail(name, "", "a STEP file Open CASCADE can read", std::string("an unreadable result from the reader: ") + e.what());
    }
  }
};

// Writes a solid through vaw-step-write, a child like the reader: the mesh goes to it as a binary STL in
// the file's unit, the file comes back under a temporary name beside the target and is renamed over it, so a
// failed write leaves what was there.
class StepExporter final : public vaw::SolidExporter {
 public:
  [[nodiscard]] std::string name() const override { return "STEP (AP214 B-rep)"; }
  [[nodiscard]] std::vector<std::string> extensions() const override { return {"step", "stp"}; }
  void write(const vaw::TriMesh& mesh, const std::string& solidName, vaw::LengthUnit unit, const std::filesystem::path& file,
             const vaw::ExportOptions& options, const vaw::ProgressFn& progress) const override {
    const std::filesystem::path writer = pluginDir() / "vaw-step-write";
    if (access(writer.c_str(), X_OK) != 0) throw vaw::OutputError(file.string() + ": no STEP writer installed with the STEP plugin (" + writer.string() + ")");
    TempDir tmp;
    const std::filesystem::path stl = tmp.path() / "mesh.stl", errors = tmp.path() / "stderr.txt";
    vaw::writeFileAtomically(stl, vaw::binaryStl(mesh, 1.0 / vaw::toMetres(unit), "vaw solid, " + std::string(vaw::name(unit))));
    const std::filesystem::path part = file.parent_path() / ("." + file.filename().string() + ".writing");
    const std::string memory = std::to_string(static_cast<long long>(memoryLimitMB(options.memoryMB)));
    std::vector<std::string> args = {writer.string(), stl.string(),  "--out",    part.string(), "--unit", std::string(vaw::name(unit)),
                                     "--name",        solidName,     "--parent", std::to_string(getpid()), "--memory-limit-mb", memory};
    if (options.faceted) args.emplace_back("--faceted");
    std::error_code ec;
    const auto notWritten = [&](const std::string& why) {
      std::filesystem::remove(part, ec);
      throw vaw::OutputError(file.string() + ": not written: " + why);
    };
    std::string stage = "starting the STEP writer";
    const int status = runChild(args, errors, options.timeoutSeconds, progress, stage, [&](Stop why, const std::string& detail) {
      if (why == Stop::Cancelled) notWritten("stopped while " + detail);
      if (why == Stop::CannotStart) notWritten("cannot start " + writer.string() + ": " + detail);
      notWritten("still writing after " + seconds(options.timeoutSeconds) + " s, while " + detail +
                 " (a larger voxel makes fewer faces; or raise the limit: File > STEP Settings, vaw-sim sweep --step-timeout S)");
    });
    if (WIFSIGNALED(status)) notWritten("the STEP writer died of " + signalName(WTERMSIG(status)) + " while " + stage);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 5)
      notWritten(lastLine(errors) + " while " + stage + " (a larger voxel makes fewer faces; or raise the limit: File > STEP Settings, vaw-sim sweep --step-memory MB)");
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      const std::string why = lastLine(errors);
      notWritten(why.empty() ? "the STEP writer failed" : why);
    }
    std::filesystem::rename(part, file, ec);
    if (ec) {
      std::filesystem::remove(part, ec);
      throw vaw::OutputError(file.string() + ": cannot put the written file in place: " + ec.message());
    }
  }
};

}  // namespace

extern "C" __attribute__((visibility("default"))) vaw::SolidExporter* vaw_create_solid_exporter() { return new StepExporter(); }
extern "C" __attribute__((visibility("default"))) int vaw_plugin_abi_version() { return vaw::kImporterAbiVersion; }
extern "C" __attribute__((visibility("default"))) vaw::MeshImporter* vaw_create_mesh_importer() { return new StepImporter(); }
