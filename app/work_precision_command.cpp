#include "work_precision_command.hpp"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

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
  std::ofstream out(file);
  out << "scenario,method,step_rate_hz,cpu_s_per_sim_s,error,error_unit,stable,note\n";
  out.precision(9);
  for (const auto& r : records) {
    std::string note = r.note;
    for (auto& c : note)
      if (c == '"') c = '\'';
    out << r.scenario << ',' << r.method << ',' << r.stepRate << ',' << r.cpuPerSimSecond << ',' << r.error << ','
        << r.errorUnit << ',' << (r.stable ? "yes" : "no") << ",\"" << note << "\"\n";
  }
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
    else if (args[i] == "--repeats" && i + 1 < args.size()) options.repeats = std::max(1, std::atoi(args[++i].c_str()));
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
  for (const auto& file : ui::writeWorkPrecisionCharts(records, outDir, argc, argv)) std::printf("wrote %s\n", file.c_str());
#else
  (void)argc;
  (void)argv;
  std::fprintf(stderr, "vaw-sim: built without Qt Charts; no chart written\n");
#endif
  return 0;
}

}  // namespace vaw::app
