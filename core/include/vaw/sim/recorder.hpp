#pragma once
// A timeline: the session being recorded (or played back) together with a World at some step of it.
// Stepping at the end records; seek() moves the world to any recorded step by restoring the nearest
// periodic snapshot at or before it and replaying the recorded inputs and edits from there; recording
// from a step in the past first discards the recorded future. The workbench's SimulationController owns
// one; the timeline view scrubs it; `vaw SESSION --at` seeks it.
//
// Hours at the workbench (docs/simulation.md, "The recorder"): snapshots share each part's state while it
// does not change; one is kept every second of the last ten minutes and every tenth second before, so a
// seek replays at most ten seconds; and the inputs are
// stored as runs of identical ones (InputLog). When memory runs short, giveUpOldest() drops the oldest
// snapshots (never the first): the recording stays whole and replayable, only seeking into that past
// replays from further back.
#include <cstdint>
#include <memory>
#include <vector>

#include "vaw/sim/session.hpp"
#include "vaw/sim/world.hpp"

namespace vaw::sim {

class Recorder {
 public:
  // A new, empty recording. `scenePath` is what the session will name.
  Recorder(std::shared_ptr<const Scene> scene, Settings settings, std::string scenePath);
  // A recorded session, played through once (to know its whole timeline) and put back at step 0. An
  // InputError when the session does not fit the scene (checkScene, edits it refuses).
  Recorder(std::shared_ptr<const Scene> scene, Session session);

  [[nodiscard]] const World& world() const { return world_; }
  [[nodiscard]] const Scene& scene() const { return *scene_; }
  [[nodiscard]] const std::shared_ptr<const Scene>& scenePtr() const { return scene_; }
  // Everything recorded: inputs and edits of every step, whatever step the world is at.
  [[nodiscard]] const Session& session() const { return session_; }
  [[nodiscard]] std::uint64_t step() const { return world_.stepCount(); }
  [[nodiscard]] std::uint64_t length() const { return session_.inputs.size(); }
  [[nodiscard]] bool atEnd() const { return step() == length(); }
  // Simulated time at the end of the recording (s).
  [[nodiscard]] double endTime() const { return endTime_; }

  // The logs of the whole recording (the world's own stop at its step while it is in the past).
  [[nodiscard]] const std::vector<TransitionRecord>& transitions() const;
  [[nodiscard]] const std::vector<Refusal>& refusals() const;
  [[nodiscard]] const std::vector<EditRecord>& edits() const;

  // Steps the world with `input` and records it; in the past, the recorded future is discarded first.
  void record(const Input& input);
  // Steps the world with the recorded input of its current step (and that step's edits); false at the end.
  bool playNext();
  // Applies an edit now and records it; in the past, the recorded future is discarded first. Returns the
  // world's refusal (empty on success); a refused edit discards nothing and records nothing.
  [[nodiscard]] std::string apply(const Edit& edit);
  // Puts the world at step `n` (clamped to the recording).
  void seek(std::uint64_t n);
  // The step at the end of which the time is closest to `seconds` (for seeking by time), and the time
  // after `n` steps of the recording.
  [[nodiscard]] std::uint64_t stepAt(double seconds) const;
  [[nodiscard]] double timeAt(std::uint64_t n) const;
  // Drops everything recorded after the world's current step.
  void discardFuture();

  // Steps between snapshots (one second of simulated time at the initial rate). Every snapshot of the last
  // kRecent intervals is kept, every kSparseEvery-th before them, and the first.
  static constexpr std::uint64_t kRecent = 600, kSparseEvery = 10;
  // Whether the snapshot at interval `k` is kept when the newest is at interval `now`.
  [[nodiscard]] static bool keeps(std::uint64_t k, std::uint64_t now) {
    return k == 0 || now - k < kRecent || k % kSparseEvery == 0;
  }
  [[nodiscard]] std::uint64_t snapshotInterval() const { return interval_; }
  [[nodiscard]] std::size_t snapshotCount() const { return snapshots_.size(); }
  // The steps of the snapshots held, ascending (the first is step 0).
  [[nodiscard]] std::vector<std::uint64_t> snapshotSteps() const;

  // Heap bytes the recording holds: its inputs, edits and snapshots (the world's live state not counted).
  [[nodiscard]] std::size_t memoryBytes() const;
  // Drops the oldest snapshots but the first until memoryBytes() is at most `targetBytes` (or only the first
  // and the newest remain). Returns the step before which seeking now replays from further back (0 when
  // nothing was dropped).
  std::uint64_t giveUpOldest(std::size_t targetBytes);

 private:
  void advance(const Input& input);  // one step of the world, with the session's edits for it
  void keepTimeline();               // the whole-recording logs while the world leaves the end
  std::shared_ptr<const Scene> scene_;
  Session session_;
  World world_;
  std::uint64_t interval_ = 90;
  void keepSnapshot();               // at a multiple of interval_: take one, thin the older ones
  std::vector<Snapshot> snapshots_;  // ascending steps, each a multiple of interval_, the first at step 0
  std::size_t nextEdit_ = 0;         // first session edit not yet applied to the world
  double endTime_ = 0.0;
  // The whole recording's logs, valid while the world is before the end.
  bool pastLogs_ = false;
  std::vector<TransitionRecord> transitions_;
  std::vector<Refusal> refusals_;
  std::vector<EditRecord> edits_;
};

}  // namespace vaw::sim
