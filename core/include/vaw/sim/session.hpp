#pragma once
// Record and replay: a session holds the scene reference (its path and content hash), the settings, every
// step's input and every live edit with the step it took effect at, so a fresh World fed the same inputs
// and edits reproduces every state and transition bit for bit (docs/inputs-format.md). Also the input
// script (keyframes sampled at the step rate) and the CSV exports. Every file is written through
// vaw::AtomicFile: a failed or interrupted write leaves the previous file.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vaw/atomic_file.hpp"
#include "vaw/sim/input_log.hpp"
#include "vaw/sim/world.hpp"

namespace vaw::sim {

// Version 2 adds the scene's content hash, edits, grab targets and inputs written as changes; version 1
// sessions still load and replay.
inline constexpr int kSessionFormatVersion = 2;
inline constexpr int kInputsFormatVersion = 1;

struct Session {
  std::string scene;                     // path of the scene file, as given
  std::optional<std::uint64_t> sceneHash;  // Scene::contentHash when recorded (absent in version 1)
  Settings settings;
  InputLog inputs;                       // one per step
  std::vector<EditRecord> edits;         // in step order; an edit at step k is applied before step k runs
  std::filesystem::path file;            // where it was loaded from (for messages); empty in memory
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

// An InputError (naming the session file and its scene_hash) when the session was recorded on a scene
// whose content differs from `scene`'s: a replay would not reproduce it.
void checkScene(const Session& s, const Scene& scene);

// Applies the session's edits recorded for the world's current step (those with step == w.stepCount()),
// starting at `next`; returns the index of the first edit not applied. An edit the world refuses is an
// InputError naming the session's file and the edit.
std::size_t applyEdits(World& w, const Session& s, std::size_t next);

// Runs a fresh World over the session's inputs and edits; `afterStep` (optional) sees each step.
World replay(std::shared_ptr<const Scene> scene, const Session& s, const std::function<void(const World&)>& afterStep = {});

void appendTrajectory(const World& w, std::vector<TrajectoryRow>& rows);
// The trajectories CSV: its header, and one row as text (for writers that stream a long run).
inline constexpr std::string_view kTrajectoriesCsvHeader = "step,t,part,state,x,y,z,qw,qx,qy,qz\n";
void appendTrajectoryCsv(const World& w, const TrajectoryRow& row, std::string& out);
void writeTrajectoriesCsv(const World& w, const std::vector<TrajectoryRow>& rows, const std::filesystem::path& file);
void writeTransitionsCsv(const World& w, const std::filesystem::path& file);
// The same columns from logs kept elsewhere (a recording's whole timeline).
void writeTransitionsCsv(const Assembly& assembly, const std::vector<TransitionRecord>& transitions,
                         const std::vector<Refusal>& refusals, const std::filesystem::path& file);
// Into a file the caller commits.
void writeTransitionsCsv(const World& w, AtomicFile& out);
void writeTransitionsCsv(const Assembly& assembly, const std::vector<TransitionRecord>& transitions,
                         const std::vector<Refusal>& refusals, AtomicFile& out);

}  // namespace vaw::sim
