#include "vaw/sim/recorder.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace vaw::sim {

Recorder::Recorder(std::shared_ptr<const Scene> scene, Settings settings, std::string scenePath)
    : scene_(std::move(scene)), world_(scene_, settings) {
  session_.scene = std::move(scenePath);
  session_.sceneHash = scene_->contentHash();
  session_.settings = settings;
  interval_ = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(settings.rate)));
  snapshots_.push_back(world_.snapshot());
}

Recorder::Recorder(std::shared_ptr<const Scene> scene, Session session)
    : scene_(std::move(scene)), session_(std::move(session)), world_(scene_, session_.settings) {
  checkScene(session_, *scene_);
  if (!session_.sceneHash) session_.sceneHash = scene_->contentHash();
  interval_ = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(session_.settings.rate)));
  snapshots_.push_back(world_.snapshot());
  while (playNext()) {
  }
  endTime_ = world_.time();
  seek(0);
}

const std::vector<TransitionRecord>& Recorder::transitions() const {
  return pastLogs_ ? transitions_ : world_.transitions();
}
const std::vector<Refusal>& Recorder::refusals() const { return pastLogs_ ? refusals_ : world_.refusals(); }
const std::vector<EditRecord>& Recorder::edits() const { return pastLogs_ ? edits_ : world_.edits(); }

void Recorder::advance(const Input& input) {
  nextEdit_ = applyEdits(world_, session_, nextEdit_);
  world_.step(input);
  if (world_.stepCount() % interval_ == 0 && snapshots_.back().step() < world_.stepCount()) keepSnapshot();
  if (atEnd()) {
    // The edits recorded after the last step (applied, but no step ran with them yet).
    nextEdit_ = applyEdits(world_, session_, nextEdit_);
    endTime_ = world_.time();
    pastLogs_ = false;
  }
}

void Recorder::keepSnapshot() {
  snapshots_.push_back(world_.snapshot());
  // The one that has just grown ten minutes old goes unless it is on a tenth-second mark.
  const std::uint64_t now = world_.stepCount() / interval_;
  if (now < kRecent || keeps(now - kRecent, now)) return;
  const std::uint64_t step = (now - kRecent) * interval_;
  const auto it = std::lower_bound(snapshots_.begin(), snapshots_.end(), step,
                                   [](const Snapshot& s, std::uint64_t at) { return s.step() < at; });
  if (it != snapshots_.end() && it->step() == step) snapshots_.erase(it);
}

std::vector<std::uint64_t> Recorder::snapshotSteps() const {
  std::vector<std::uint64_t> steps;
  steps.reserve(snapshots_.size());
  for (const Snapshot& s : snapshots_) steps.push_back(s.step());
  return steps;
}

std::size_t Recorder::memoryBytes() const {
  std::size_t bytes = session_.inputs.bytes() + session_.edits.capacity() * sizeof(EditRecord) + snapshots_.capacity() * sizeof(Snapshot);
  std::unordered_set<const void*> counted;
  for (const Snapshot& s : snapshots_) bytes += s.bytes(counted);
  return bytes;
}

std::uint64_t Recorder::giveUpOldest(std::size_t targetBytes) {
  // Snapshots share what did not change, so what dropping one frees is only known afterwards: drop by the
  // average and measure again.
  std::size_t dropped = 0;
  for (int round = 0; round < 8; ++round) {
    const std::size_t bytes = memoryBytes();
    const std::size_t droppable = snapshots_.size() > 2 ? snapshots_.size() - 2 : 0;  // never the first or the newest
    if (bytes <= targetBytes || droppable == 0) break;
    const std::size_t average = std::max<std::size_t>(1, bytes / snapshots_.size());
    const std::size_t n = std::clamp<std::size_t>((bytes - targetBytes + average - 1) / average, 1, droppable);
    snapshots_.erase(snapshots_.begin() + 1, snapshots_.begin() + 1 + static_cast<std::ptrdiff_t>(n));
    dropped += n;
  }
  if (dropped == 0) return 0;
  snapshots_.shrink_to_fit();
  return snapshots_[1].step();
}

void Recorder::record(const Input& input) {
  if (!atEnd()) discardFuture();
  session_.inputs.push_back(input);
  advance(input);
}

bool Recorder::playNext() {
  if (atEnd()) return false;
  advance(session_.inputs[step()]);
  return true;
}

std::string Recorder::apply(const Edit& edit) {
  if (std::string problem = validate(edit, scene_->assembly()); !problem.empty()) return problem;
  if (!atEnd()) discardFuture();
  std::string problem = world_.apply(edit);
  if (problem.empty()) {
    session_.edits.push_back(world_.edits().back());
    nextEdit_ = session_.edits.size();
  }
  return problem;
}

void Recorder::keepTimeline() {
  if (pastLogs_ || !atEnd()) return;
  transitions_ = world_.transitions();
  refusals_ = world_.refusals();
  edits_ = world_.edits();
  pastLogs_ = true;
}

void Recorder::seek(std::uint64_t n) {
  n = std::min(n, length());
  if (n == step()) return;
  keepTimeline();
  // From the nearest snapshot at or before n, unless the world is already between it and n.
  const auto after = std::upper_bound(snapshots_.begin(), snapshots_.end(), n,
                                      [](std::uint64_t step, const Snapshot& s) { return step < s.step(); });
  const Snapshot& s = *std::prev(after);
  if (!(step() >= s.step() && step() < n)) {
    world_.restore(s);
    // The session's edits are the world's, in order: those the snapshot holds are done.
    nextEdit_ = std::min(world_.edits().size(), session_.edits.size());
  }
  while (step() < n) advance(session_.inputs[step()]);
  if (atEnd()) pastLogs_ = false;
}

double Recorder::timeAt(std::uint64_t n) const {
  // The world's rule: the step count over the rate, counted on from each rate edit.
  double rateTime = 0.0, rate = session_.settings.rate;
  std::uint64_t rateStep = 0;
  for (const EditRecord& e : session_.edits) {
    if (e.step >= n) break;
    if (const auto* r = std::get_if<RateEdit>(&e.edit)) {
      rateTime += static_cast<double>(e.step - rateStep) / rate;
      rateStep = e.step;
      rate = r->rate;
    }
  }
  return rateTime + static_cast<double>(n - rateStep) / rate;
}

std::uint64_t Recorder::stepAt(double seconds) const {
  // Time grows with the step: the first step whose end is at or after `seconds`, or the nearer neighbour.
  std::uint64_t lo = 0, hi = length();
  while (lo < hi) {
    const std::uint64_t mid = lo + (hi - lo) / 2;
    if (timeAt(mid) < seconds) lo = mid + 1;
    else hi = mid;
  }
  if (lo > 0 && seconds - timeAt(lo - 1) < timeAt(lo) - seconds) --lo;
  return lo;
}

void Recorder::discardFuture() {
  const std::uint64_t n = step();
  session_.inputs.resize(n);
  // Edits at step n that the world has applied stay (they are the present); later ones go.
  session_.edits.resize(std::min(session_.edits.size(), world_.edits().size()));
  while (snapshots_.size() > 1 && snapshots_.back().step() > n) snapshots_.pop_back();
  nextEdit_ = session_.edits.size();
  endTime_ = world_.time();
  pastLogs_ = false;
}

}  // namespace vaw::sim
