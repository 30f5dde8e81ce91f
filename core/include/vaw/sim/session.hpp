#pragma once
// Record and replay: a session holds the scene reference, the settings and every step's input, so a
// fresh World fed the same inputs reproduces every state and transition bit for bit. Also the input
// script (docs/inputs-format.md: keyframes sampled at the step rate) and the CSV exports. Every file is
// written through vaw::AtomicFile: a failed or interrupted write leaves the previous file.
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "vaw/atomic_file.hpp"
#include "vaw/sim/world.hpp"

namespace vaw::sim {

inline constexpr int kSessionFormatVersion = 1;
inline constexpr int kInputsFormatVersion = 1;

struct Session {
  std::string scene;       // path of the scene file, as given
  Settings settings;
  std::vector<Input> inputs;  // one per step
};

// Reads an input script (docs/inputs-format.md) and samples it at `settings.rate` (the script's "rate",
// when given, replaces it). Errors are vaw::InputError naming the file and field.
std::vector<Input> loadInputScript(const std::filesystem::path& file, Settings& settings);

// JSON with doubles written for an exact round trip.
void saveSession(const Session& s, const std::filesystem::path& file);
void saveSession(const Session& s, AtomicFile& out);  // into a file the caller commits
Session loadSession(const std::filesystem::path& file);

// One row per part per step, written after each step.
struct TrajectoryRow {
  std::uint64_t step;
  double t;
  PartId part;
  interact::PartState state;
  Eigen::Vector3d position;
  Eigen::Quaterniond orientation;
};

// Runs a fresh World over the session's inputs on `assembly`; `afterStep` (optional) sees each step.
World replay(const Assembly& assembly, const Session& s, const std::function<void(const World&)>& afterStep = {});

void appendTrajectory(const World& w, std::vector<TrajectoryRow>& rows);
// The trajectories CSV: its header, and one row as text (for writers that stream a long run).
inline constexpr std::string_view kTrajectoriesCsvHeader = "step,t,part,state,x,y,z,qw,qx,qy,qz\n";
void appendTrajectoryCsv(const World& w, const TrajectoryRow& row, std::string& out);
void writeTrajectoriesCsv(const World& w, const std::vector<TrajectoryRow>& rows, const std::filesystem::path& file);
void writeTransitionsCsv(const World& w, const std::filesystem::path& file);
void writeTransitionsCsv(const World& w, AtomicFile& out);  // into a file the caller commits

}  // namespace vaw::sim
