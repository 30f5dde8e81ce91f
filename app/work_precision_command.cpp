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
#include "vaw/peers/peers.hpp"
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

}  // namespace

int workPrecision(const WorkPrecisionArgs& args, int argc, char** argv) {
  const std::filesystem::path& outDir = args.out;
  dyn::WorkPrecisionOptions options;
  options.repeats = args.repeats;
  const bool withPeers = args.peers;
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
  if (withPeers) {
    const auto peerRecords = peers::runPeers(options, [tty](const std::string& what) {
      if (tty) std::fprintf(stderr, "\r%-40s", what.c_str());
      return true;
    });
    if (tty) std::fprintf(stderr, "\n");
    records.insert(records.end(), peerRecords.begin(), peerRecords.end());
  }
#else
  if (withPeers) std::fprintf(stderr, "vaw-sim: built without the Bullet/ODE peers\n");
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
