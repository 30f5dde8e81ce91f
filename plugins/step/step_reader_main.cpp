// vaw-step-import: reads one STEP file with Open CASCADE's XDE and writes what vaw needs (assembly tree,
// one tessellated and measured solid per product, recognised faces) as CBOR. It runs as a child of the
// STEP importer plugin because OCCT crashes or never returns on some files; the plugin turns that into
// an error naming the file (docs/step.md).
//
//   vaw-step-import FILE --out RESULT [--relative-deflection X] [--angular-deflection A] [--parent PID]
//                   [--memory-limit-mb MB] [--max-instances N]
//
// stdout: "progress FRACTION STAGE" lines. Exit 0: RESULT written. Exit 3: the file is bad; one line on
// stderr says why, and RESULT holds {"error": {field, expected, found}}. Exit 2: bad arguments.
#include <Standard_Failure.hxx>
#include <Standard_OutOfMemory.hxx>

#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <memory>
#include <string>
#include <vector>

#include "step_child.hpp"
#include "step_reader.hpp"
#include "step_result.hpp"

using namespace vaw::step::reader;


#ifdef VAW_ADDRESS_SANITIZER
// Under the sanitizers (the asan preset), a SIGSEGV is left to kill the reader as it does in the default
// build, so that the plugin names the crash the same way.
extern "C" const char* __asan_default_options() { return "handle_segv=0"; }
#endif

namespace {

void writeResult(const std::filesystem::path& out, const json& j) {
  const std::vector<std::uint8_t> bytes = json::to_cbor(j);
  const std::filesystem::path tmp = out.string() + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!f) throw std::runtime_error("cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, out);
}

int usage(const char* why) {
  std::fprintf(
      stderr,
      "vaw-step-import: %s\nusage: vaw-step-import FILE --out RESULT [--relative-deflection X] [--angular-deflection A]\n"
      "       [--parent PID] [--memory-limit-mb MB] [--max-instances N]\n", why);
  return 2;
}

#ifdef VAW_FAULT_HOOKS
// A fault on purpose, for the tests of what the plugin makes of each (VAW_STEP_READER_FAULT), only in the
// reader built for the tests (plugins/step/CMakeLists.txt, VAW_FAULT_HOOKS), never in the installed one:
// "crash" dies of SIGSEGV, "hang" never finishes, "memory" allocates until its limit stops it, "truncate"
// writes half a result and reports success.
void injectFault(const std::string& fault, const std::filesystem::path& out) {
  if (fault == "crash") std::raise(SIGSEGV);
  if (fault == "hang")
    for (;;) pause();
  if (fault == "memory") {
    std::vector<std::unique_ptr<char[]>> held;
    for (;;) {
      held.emplace_back(new char[64 << 20]);
      std::memset(held.back().get(), 1, 64 << 20);
    }
  }
  if (fault == "truncate") {
    const std::vector<std::uint8_t> bytes = json::to_cbor(json{{"format", "STEP AP214"}, {"solids", json::array({json::object()})}});
    std::ofstream f(out, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size() / 2));
    std::exit(0);
  }
}
#endif

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path file, out;
  double relative = 0.001, angular = 0.35;
  long parent = 0;
  double memoryMB = 0.0;
  vaw::step::FirstPassLimits limits;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool hasValue = i + 1 < argc;
    try {
      if (a == "--out" && hasValue) out = argv[++i];
      else if (a == "--parent" && hasValue) parent = std::stol(argv[++i]);
      else if (a == "--memory-limit-mb" && hasValue) memoryMB = std::stod(argv[++i]);
      else if (a == "--max-instances" && hasValue) limits.maxInstances = std::stod(argv[++i]);
      else if (a == "--relative-deflection" && hasValue) relative = std::stod(argv[++i]);
      else if (a == "--angular-deflection" && hasValue) angular = std::stod(argv[++i]);
      else if (a.rfind("--", 0) == 0) return usage(("unknown or incomplete option " + a).c_str());
      else if (file.empty()) file = a;
      else return usage("more than one FILE");
    } catch (const std::exception&) {
      return usage(("not a number after " + a).c_str());
    }
  }
  if (file.empty() || out.empty()) return usage("FILE and --out RESULT are required");
  if (!(limits.maxInstances >= 1.0)) return usage("--max-instances must be at least 1");
  if (!(relative > 0.0 && relative < 1.0) || !(angular > 0.0 && angular < 3.2))
    return usage("deflections must be in (0, 1) (relative) and (0, pi] (angular, radians)");

  // A reader spinning on a hostile file must not outlive the window or command that waits for it; the
  // parent may be gone already by now.
  if (!vaw::step::containChild(parent, memoryMB)) return 6;
  const auto outOfMemory = [&] {
    std::fprintf(stderr, "it needed more memory than the reader's limit of %.0f MB\n", memoryMB);
    return 5;
  };
  try {
#ifdef VAW_FAULT_HOOKS
    if (const char* fault = std::getenv("VAW_STEP_READER_FAULT")) injectFault(fault, out);
#endif
    Reader reader(relative, angular, limits);
    json result = reader.read(file, std::filesystem::absolute(out).parent_path());
    progress(0.97, "writing the result");
    writeResult(out, result);
    progress(1.0, "done");
    return 0;
  } catch (const BadFile& bad) {
    std::fprintf(stderr, "%s\n", bad.found.c_str());
    try {
      writeResult(out, json{{"version", vaw::step::kResultVersion}, {"error", {{"field", bad.field}, {"expected", bad.expected}, {"found", bad.found}}}});
    } catch (const std::exception&) {
      // The stderr line alone still tells the plugin what is wrong.
    }
    return 3;
  } catch (const std::bad_alloc&) {
    return outOfMemory();
  } catch (const Standard_OutOfMemory&) {
    return outOfMemory();
  } catch (const Standard_Failure& f) {
    std::fprintf(stderr, "Open CASCADE failed: %s: %s\n", f.DynamicType()->Name(), f.GetMessageString());
    return 4;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 4;
  }
}
