#include "work_precision_command.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "vaw/atomic_file.hpp"
#include "vaw/error.hpp"

#include "vaw/dynamics/work_precision.hpp"
#ifdef VAW_HAVE_PEERS
#include "peers/peers.hpp"
#endif
#ifdef VAW_HAVE_CHARTS
#include "vaw/ui/work_precision_chart.hpp"
#endif

namespace vaw::app {

namespace {

void writeCsv(const std::filesystem::path& file, const std::vector<dyn::Record>& records) {
  std::ostringstream out;
  out << "scenario,method,step_rate_hz,cpu_s_per_sim_s,error,error_unit,stable,note\n";
  out.precision(9);
  for (const auto& r : records) {
    std::string note = r.note;
    for (auto& c : note)
      if (c == '"') c = '\'';
    out << r.scenario << ',' << r.method << ',' << r.stepRate << ',' << r.cpuPerSimSecond << ',' << r.error << ','
        << r.errorUnit << ',' << (r.stable ? "yes" : "no") << ",\"" << note << "\"\n";
  }
  writeFileAtomically(file, out.str());
}

// A positive count, strictly: "abc", "-5" and "3x" are refused, not read as 0 or 1.
bool parseCount(const std::string& text, int& out) {
  if (text.empty() || text.size() > 6 || text.find_first_not_of("0123456789") != std::string::npos) return false;
  out = std::stoi(text);
  return out >= 1 && out <= 1000;
}

#ifdef VAW_HAVE_PEERS
void addPeers(std::vector<dyn::Record>& records, const dyn::WorkPrecisionOptions& o, bool tty) {
  const dyn::SlideScenario slide;
  dyn::PendulumScenario undamped, damped;
  damped.fr = 0.0005;
  const dyn::Samples slideRef = dyn::slideReference(slide);
  const dyn::Samples undampedRef = dyn::pendulumReference(undamped), dampedRef = dyn::pendulumReference(damped);
  for (const auto& peer : peers::availablePeers()) {
    for (int rate : dyn::kStepRates) {
      if (tty) std::fprintf(stderr, "\rpeer %s at %d Hz        ", peer.name.c_str(), rate);
      const auto s = peer.slide(slide, rate, o);
      records.push_back({"slide-with-stop", peer.name, static_cast<double>(rate), s.cpuPerSimSecond,
                         dyn::maxAbsDifference(s.samples, slideRef), "m", true, s.note});
      for (const auto* p : {&undamped, &damped}) {
        const auto r = peer.pendulum(*p, rate, o);
        records.push_back({p->fr > 0 ? "gear-pendulum-damped" : "gear-pendulum", peer.name, static_cast<double>(rate),
                           r.cpuPerSimSecond, dyn::maxAbsDifference(r.samples, p->fr > 0 ? dampedRef : undampedRef), "rad",
                           true, r.note});
      }
    }
  }
  if (tty) std::fprintf(stderr, "\n");
}
#endif

}  // namespace

int workPrecision(const std::vector<std::string>& args, int argc, char** argv) {
  std::filesystem::path outDir;
  dyn::WorkPrecisionOptions options;
  bool peers = true;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--out" && i + 1 < args.size()) outDir = args[++i];
    else if (args[i] == "--repeats" && i + 1 < args.size()) {
      if (!parseCount(args[++i], options.repeats)) {
        std::fprintf(stderr, "vaw-sim work-precision: --repeats: expected a whole number from 1 to 1000, found \"%s\"\n", args[i].c_str());
        return 2;
      }
    }
    else if (args[i] == "--no-peers") peers = false;
    else {
      std::fprintf(stderr, "vaw-sim work-precision: unknown argument %s\n", args[i].c_str());
      return 2;
    }
  }
  if (outDir.empty()) {
    std::fprintf(stderr, "vaw-sim work-precision: --out DIR is required\n");
    return 2;
  }
  std::error_code ec;
  std::filesystem::create_directories(outDir, ec);
  if (!ec && !std::filesystem::is_directory(outDir, ec)) ec = std::make_error_code(std::errc::not_a_directory);
  if (ec) {
    std::fprintf(stderr, "vaw-sim work-precision: cannot create %s: %s\n", outDir.c_str(), ec.message().c_str());
    return 1;
  }
  const bool tty = isatty(STDERR_FILENO) != 0;
  auto records = dyn::runWorkPrecision(options, [tty](int done, int total) {
    if (tty || done == total) std::fprintf(stderr, "\rwork-precision: %d / %d runs", done, total);
    return true;
  });
  std::fprintf(stderr, "\n");
#ifdef VAW_HAVE_PEERS
  if (peers) addPeers(records, options, tty);
#else
  if (peers) std::fprintf(stderr, "vaw-sim: built without the Bullet/ODE peers\n");
#endif
  const auto csv = outDir / "work-precision.csv";
  writeCsv(csv, records);
  std::printf("wrote %s (%zu records)\n", csv.c_str(), records.size());
#ifdef VAW_HAVE_CHARTS
  // Drawn into a private directory, checked, then renamed over the old charts one by one, so that an
  // interrupted run never leaves a truncated chart where a good one was.
  const std::string staging = (outDir / ".charts.XXXXXX").string();
  std::vector<char> name(staging.begin(), staging.end());
  name.push_back('\0');
  if (::mkdtemp(name.data()) == nullptr) throw OutputError("cannot create a directory in " + outDir.string() + ": " + std::strerror(errno));
  const std::filesystem::path tmp(name.data());
  struct Cleanup {
    std::filesystem::path dir;
    ~Cleanup() {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    }
  } cleanup{tmp};
  for (const auto& drawn : ui::writeWorkPrecisionCharts(records, tmp, argc, argv)) {
    if (std::filesystem::file_size(drawn, ec) == 0 || ec) throw OutputError("cannot write the chart " + drawn.filename().string());
    const std::filesystem::path file = outDir / drawn.filename();
    std::filesystem::rename(drawn, file);
    std::printf("wrote %s\n", file.c_str());
  }
#else
  (void)argc;
  (void)argv;
  std::fprintf(stderr, "vaw-sim: built without Qt Charts; no chart written\n");
#endif
  return 0;
}

}  // namespace vaw::app
