// The live world: edits applied between steps (with the rule for parts already in a state), snapshots that
// restore the whole runtime state, the recorder's seek and discard, and sessions (version 2 with edits and
// the scene hash, version 1 still replaying bit for bit). Tolerances: slides and flights are closed forms
// (1e-12 m); replays and restores are compared bit for bit (state hashes, transitions).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "sim_test_support.hpp"
#include "vaw/hash.hpp"
#include "vaw/sim/recorder.hpp"
#include "vaw/sim/session.hpp"
#include "vaw/units.hpp"

using namespace vaw;
using namespace vaw::sim;
using interact::Event;
using interact::PartState;
using simtest::at;

namespace {

using vaw::kDeg;

std::shared_ptr<const Scene> bundled(const std::string& name) { return Scene::build(simtest::loadBundled(name)); }

// The plate tilted about the world x axis through its own origin.
Eigen::Isometry3d tilted(double deg) { return simtest::rotAbout(Eigen::Vector3d::UnitX(), deg * kDeg, Eigen::Vector3d::Zero()); }

// Block-on-plate with the block put on the plate's face (ONBASESTATIC) by the left hand.
World blockOnPlate(const std::shared_ptr<const Scene>& scene, PartId& block) {
  World w(scene);
  block = *scene->assembly().findPart("block");
  Input in;
  in.left = simtest::hand(w.part(block).pose, true);
  w.step(in);
  in.left = simtest::hand(at(0.0, 0.0, 0.0552), true);  // 0.2 mm above its mate, turned as it was grabbed
  w.step(in);
  in.left.grab = false;
  w.step(in);
  return w;
}

std::vector<std::uint64_t> hashesOver(World& w, const std::vector<Input>& inputs, std::size_t from, std::size_t to) {
  std::vector<std::uint64_t> h;
  for (std::size_t i = from; i < to; ++i) {
    w.step(inputs[i]);
    h.push_back(w.stateHash());
  }
  return h;
}

void expectSameLogs(const World& a, const World& b) {
  ASSERT_EQ(a.transitions().size(), b.transitions().size());
  for (std::size_t k = 0; k < a.transitions().size(); ++k) {
    EXPECT_EQ(a.transitions()[k].step, b.transitions()[k].step);
    EXPECT_EQ(a.transitions()[k].t, b.transitions()[k].t);
    EXPECT_EQ(a.transitions()[k].to, b.transitions()[k].to);
    EXPECT_EQ(a.transitions()[k].cause, b.transitions()[k].cause);
  }
  EXPECT_EQ(a.refusals().size(), b.refusals().size());
  EXPECT_EQ(a.edits().size(), b.edits().size());
}

std::vector<Input> sleeveScript(Settings& settings) {
  return loadInputScript(std::filesystem::path(VAW_SOURCE_DIR) / "tests/sim/scripts/sleeve-turnover.vaw-inputs.json", settings);
}

}  // namespace

// Raising the static friction above the tilt's tangent holds the block; lowering it again starts the slide
// at the edit's step, and the slide from rest follows the closed form a = g (sin b - f_d cos b).
TEST(LiveEdits, FrictionEditDecidesWhetherTheTiltedBlockSlides) {
  const auto scene = bundled("block-on-plate.vaw.json");
  PartId block = 0;
  World w = blockOnPlate(scene, block);
  ASSERT_EQ(w.part(block).state, PartState::OnBaseStatic) << simtest::join(simtest::transitionNames(w, block));
  const std::string material = scene->assembly().parts[block].material;
  ASSERT_EQ(w.apply(MaterialFrictionEdit{material, {0.40, 0.30, 0.0005}}), "");
  Input in;
  in.base = tilted(18.0);  // below atan(0.40) = 21.8 deg, above atan(0.30) = 16.7 deg
  const Eigen::Vector3d before = w.part(block).pose.translation();
  for (int i = 0; i < 45; ++i) w.step(in);
  EXPECT_EQ(w.part(block).state, PartState::OnBaseStatic);
  const Eigen::Vector3d riding = tilted(18.0) * scene->assembly().parts[*scene->assembly().base].pose.inverse() * before;
  EXPECT_LT((w.part(block).pose.translation() - riding).norm(), 1e-12) << "rides with the plate, not sliding";

  const std::uint64_t editStep = w.stepCount();
  ASSERT_EQ(w.apply(MaterialFrictionEdit{material, {0.30, 0.20, 0.0005}}), "");
  ASSERT_EQ(w.edits().size(), 2u);
  EXPECT_EQ(w.edits().back().step, editStep);
  EXPECT_EQ(w.friction(block).staticFriction, 0.30);
  const Eigen::Vector3d start = w.part(block).pose.translation();
  const int steps = 30;
  for (int i = 0; i < steps; ++i) w.step(in);
  const auto& moved = w.transitions().back();
  EXPECT_EQ(moved.event, Event::StaticFrictionOvercome);
  EXPECT_EQ(moved.step, editStep) << "the first step after the edit starts the slide";
  ASSERT_EQ(w.part(block).state, PartState::OnBaseSlide);
  const double b = 18.0 * kDeg;
  const double a = kStandardGravity * (std::sin(b) - 0.20 * std::cos(b));
  const double t = steps / w.settings().rate;
  const double travelled = (w.part(block).pose.translation() - start).norm();
  RecordProperty("slide_after_edit_error_m", simtest::num(std::abs(travelled - 0.5 * a * t * t)));
  EXPECT_NEAR(travelled, 0.5 * a * t * t, 1e-12);
}

// A part in free flight when the free-flight gravity changes is re-based: its path continues from where it
// is, with its velocity, under the new gravity (z(t) piecewise parabolic, continuous in z and dz/dt).
TEST(LiveEdits, GravityEditRebasesAFlight) {
  const auto scene = bundled("sleeve-on-shaft.vaw.json");
  const PartId sleeve = *scene->assembly().findPart("sleeve");
  World w(scene);
  Input in;
  in.right = simtest::hand(w.part(sleeve).pose, true);
  w.step(in);
  in.right.grab = false;
  w.step(in);  // released at rest: drops
  ASSERT_EQ(w.part(sleeve).state, PartState::InSpace);
  // Released at rest from its load pose in the second step (which starts at t0).
  const double z0 = scene->assembly().parts[sleeve].pose.translation().z();
  const double t0 = w.transitions().back().t - w.settings().step();
  const double g1 = 0.25 * kStandardGravity, g2 = 1.0 * kStandardGravity;
  for (int i = 0; i < 9; ++i) w.step(in);
  const double te = w.time();
  dyn::GravityScales scales;
  scales.freeFlight = 1.0;
  ASSERT_EQ(w.apply(GravityEdit{scales}), "");
  double worst = 0.0;
  for (int i = 0; i < 9 && w.part(sleeve).state == PartState::InSpace; ++i) {
    w.step(in);
    const double a = te - t0, b = w.time() - te;
    const double expected = z0 - 0.5 * g1 * a * a - g1 * a * b - 0.5 * g2 * b * b;
    worst = std::max(worst, std::abs(w.part(sleeve).pose.translation().z() - expected));
  }
  RecordProperty("rebased_flight_error_m", simtest::num(worst));
  EXPECT_LT(worst, 1e-12);
}

TEST(LiveEdits, RefusedEditsChangeNothingAndSayWhichRule) {
  const auto scene = bundled("block-on-plate.vaw.json");
  World w(scene);
  const std::string bad1 = w.apply(MaterialFrictionEdit{"steel", {0.2, 0.3, 0.0}});
  EXPECT_NE(bad1.find("kinetic friction must not exceed static friction"), std::string::npos) << bad1;
  const std::string bad2 = w.apply(MaterialFrictionEdit{"steel", {std::nan(""), 0.1, 0.0}});
  EXPECT_NE(bad2.find("must be numbers"), std::string::npos) << bad2;
  const std::string bad3 = w.apply(MaterialFrictionEdit{"steel", {0.3, 0.2, -1.0}});
  EXPECT_NE(bad3.find("rotational friction must not be negative"), std::string::npos) << bad3;
  const std::string bad4 = w.apply(MethodEdit{dyn::Method::Exact});
  EXPECT_NE(bad4.find("cannot use exact"), std::string::npos) << bad4;
  const std::string bad5 = w.apply(MaterialFrictionEdit{"unobtainium", {0.3, 0.2, 0.0}});
  EXPECT_NE(bad5.find("no material"), std::string::npos) << bad5;
  dyn::GravityScales g;
  g.slide = -1.0;
  EXPECT_NE(w.apply(GravityEdit{g}).find("slide gravity scale"), std::string::npos);
  EXPECT_NE(w.apply(RateEdit{0.0}).find("step rate"), std::string::npos);
  EXPECT_TRUE(w.edits().empty());
  EXPECT_EQ(w.materialFriction("steel").staticFriction, 0.3);
}

// Time counts on from the rate edit: n steps later it is t_edit + n / new rate.
TEST(LiveEdits, RateEditChangesTheStepFromThere) {
  World w(bundled("block-on-plate.vaw.json"));
  Input in;
  for (int i = 0; i < 90; ++i) w.step(in);
  EXPECT_EQ(w.time(), 1.0);
  ASSERT_EQ(w.apply(RateEdit{240.0}), "");
  for (int i = 0; i < 120; ++i) w.step(in);
  EXPECT_EQ(w.settings().step(), 1.0 / 240.0);
  EXPECT_DOUBLE_EQ(w.time(), 1.5);
}

// A snapshot restores everything: stepping on from it reproduces the original future bit for bit (every
// state hash, every transition), backwards and forwards, and the logs return to what they were.
TEST(Snapshots, RestoreReproducesTheFutureBitForBit) {
  const auto scene = bundled("sleeve-on-shaft.vaw.json");
  Settings settings;
  const auto inputs = sleeveScript(settings);
  World w(scene, settings);
  for (std::size_t i = 0; i < 100; ++i) w.step(inputs[i]);
  const Snapshot at100 = w.snapshot();
  for (std::size_t i = 100; i < 200; ++i) w.step(inputs[i]);
  ASSERT_EQ(w.apply(MaterialFrictionEdit{"brass", {0.2, 0.1, 0.001}}), "");
  const Snapshot at200 = w.snapshot();
  const auto future = hashesOver(w, inputs, 200, inputs.size());
  const std::size_t transitions = w.transitions().size();
  ASSERT_GT(transitions, 4u);

  World fresh(scene, settings);
  for (std::size_t i = 0; i < 200; ++i) fresh.step(inputs[i]);
  ASSERT_EQ(fresh.apply(MaterialFrictionEdit{"brass", {0.2, 0.1, 0.001}}), "");
  (void)hashesOver(fresh, inputs, 200, inputs.size());

  w.restore(at100);
  EXPECT_EQ(w.stepCount(), 100u);
  EXPECT_TRUE(w.edits().empty());
  EXPECT_EQ(w.materialFriction("brass").staticFriction, 0.25) << "the edit came later";
  w.restore(at200);  // forwards again: logs, edits and materials come back
  EXPECT_EQ(w.stepCount(), 200u);
  EXPECT_EQ(w.edits().size(), 1u);
  EXPECT_EQ(w.materialFriction("brass").staticFriction, 0.2);
  EXPECT_EQ(hashesOver(w, inputs, 200, inputs.size()), future);
  expectSameLogs(w, fresh);
}

// The recorder: recording, seeking to any step (the world there equals a fresh replay to that step), and
// recording from the past discarding the recorded future.
TEST(Recorder, SeekMatchesAFreshReplayAndRecordingFromThePastDiscardsTheFuture) {
  const auto scene = bundled("sleeve-on-shaft.vaw.json");
  Settings settings;
  const auto inputs = sleeveScript(settings);
  Recorder rec(scene, settings, "sleeve-on-shaft.vaw.json");
  std::vector<std::uint64_t> hashes;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    if (i == 150) {
      ASSERT_EQ(rec.apply(GravityEdit{{0.5, 1.0, 1.0}}), "");
    }
    rec.record(inputs[i]);
    hashes.push_back(rec.world().stateHash());
  }
  ASSERT_EQ(rec.length(), inputs.size());
  EXPECT_EQ(rec.snapshotCount(), inputs.size() / rec.snapshotInterval() + 1);
  const std::size_t allTransitions = rec.transitions().size();
  for (const std::uint64_t n : {37ull, 400ull, 149ull, 150ull, 151ull, 1ull, static_cast<unsigned long long>(inputs.size())}) {
    rec.seek(n);
    EXPECT_EQ(rec.step(), n);
    EXPECT_EQ(rec.world().stateHash(), hashes[n - 1]) << "step " << n;
    EXPECT_EQ(rec.transitions().size(), allTransitions) << "the timeline keeps the whole recording";
    for (const auto& t : rec.world().transitions()) EXPECT_LE(t.step, n);
  }
  EXPECT_EQ(rec.stepAt(rec.timeAt(321)), 321u);
  rec.seek(120);
  rec.record(Input{});
  EXPECT_EQ(rec.length(), 121u);
  EXPECT_TRUE(rec.session().edits.empty()) << "the edit at step 150 was in the discarded future";
  EXPECT_LE(rec.transitions().size(), allTransitions);
  for (const auto& t : rec.transitions()) EXPECT_LE(t.step, 120u);
}

// Version 2: inputs as changes, grab targets, edits and the scene hash survive a save and load, and the
// loaded session replays bit for bit; a changed scene is detected.
TEST(Sessions, Version2RoundTripsEditsAndReplaysBitForBit) {
  const auto scene = bundled("sleeve-on-shaft.vaw.json");
  Settings settings;
  auto inputs = sleeveScript(settings);
  inputs[5].right.target = *scene->assembly().findPart("sleeve");
  Recorder rec(scene, settings, "sleeve-on-shaft.vaw.json");
  std::vector<std::uint64_t> hashes;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    if (i == 200) {
      ASSERT_EQ(rec.apply(MaterialFrictionEdit{"brass", {0.1, 0.05, 0.002}}), "");
    }
    if (i == 300) {
      ASSERT_EQ(rec.apply(MethodEdit{dyn::Method::SemiImplicitEuler}), "");
    }
    rec.record(inputs[i]);
    hashes.push_back(rec.world().stateHash());
  }
  const auto dir = vaw::test::tempDir();
  saveSession(rec.session(), dir / "s.vaw-session.json");
  const Session loaded = loadSession(dir / "s.vaw-session.json");
  ASSERT_EQ(loaded.sceneHash, scene->contentHash());
  ASSERT_EQ(loaded.edits.size(), 2u);
  EXPECT_EQ(loaded.edits[0].step, 200u);
  EXPECT_EQ(loaded.inputs[5].right.target, inputs[5].right.target);
  ASSERT_EQ(loaded.inputs.size(), inputs.size());
  std::size_t i = 0;
  bool same = true;
  const World w = replay(scene, loaded, [&](const World& x) { same = same && x.stateHash() == hashes[i++]; });
  EXPECT_TRUE(same) << "every step's state hash";
  expectSameLogs(w, rec.world());

  // A scene whose content changed is refused with the session's file and field named.
  Assembly changed = scene->assembly();
  changed.materials["brass"].staticFriction = 0.26;
  try {
    (void)replay(Scene::build(changed), loaded);
    FAIL() << "replayed a session on a changed scene";
  } catch (const InputError& e) {
    EXPECT_EQ(e.diagnostic().field, "scene_hash");
    EXPECT_NE(e.diagnostic().file.find("s.vaw-session.json"), std::string::npos);
  }
  std::filesystem::remove_all(dir);
}

// Inputs are written as changes: a long idle stretch costs a few bytes a step.
TEST(Sessions, IdleStepsCostAFewBytes) {
  const auto scene = bundled("block-on-plate.vaw.json");
  Recorder rec(scene, Settings{}, "block-on-plate.vaw.json");
  for (int i = 0; i < 9000; ++i) rec.record(Input{});
  const auto dir = vaw::test::tempDir();
  saveSession(rec.session(), dir / "idle.vaw-session.json");
  EXPECT_LT(std::filesystem::file_size(dir / "idle.vaw-session.json"), 9000u * 4 + 2000);
  EXPECT_EQ(loadSession(dir / "idle.vaw-session.json").inputs.size(), 9000u);
  std::filesystem::remove_all(dir);
}

// A session written by vaw before version 2 (tests/sim/data/sleeve-turnover-v1.vaw-session.json, recorded
// with the sleeve-turnover script) still loads and replays: the same transitions at the same steps as the
// version that wrote it (the sleeve slides down onto its shoulder, and off the shaft once the base is
// turned over, onto the table), and the final state hash of this engine (tests/sim/data/sleeve-turnover-v1.hash).
// The hash is the engine's, not the file's: the free motion on the base leaves a blocked part a few
// micrometres from where the engine that wrote the file did, so the bits moved while the events did not.
TEST(Sessions, Version1SessionStillReplaysBitForBit) {
  const auto scene = bundled("sleeve-on-shaft.vaw.json");
  const Session s = loadSession(std::filesystem::path(VAW_SOURCE_DIR) / "tests/sim/data/sleeve-turnover-v1.vaw-session.json");
  EXPECT_FALSE(s.sceneHash.has_value());
  ASSERT_TRUE(s.settings.hoist.has_value()) << "version 1 always wrote the hoist";
  const World w = replay(scene, s);
  std::ifstream expected(std::filesystem::path(VAW_SOURCE_DIR) / "tests/sim/data/sleeve-turnover-v1.hash");
  std::string hash;
  expected >> hash;
  ASSERT_EQ(hash.size(), 16u);
  EXPECT_EQ(hashText(w.stateHash()), hash);
  const std::vector<std::string> events = simtest::transitionNames(w, *w.assembly().findPart("sleeve"));
  ASSERT_EQ(events.size(), 7u) << simtest::join(events);
  EXPECT_EQ(events[5], "lost-contact:INSPACE") << simtest::join(events);
  EXPECT_EQ(events[6], "hit-environment:STATIC") << simtest::join(events);
  EXPECT_EQ(w.transitions()[5].step, 312u);  // t = 3.4778 s, as version 1 printed
  EXPECT_EQ(w.transitions()[6].step, 341u);  // t = 3.8 s
}

// Inputs are kept as runs of bit-identical ones: read back step by step, by index and in order, exactly as
// they were recorded, and truncated like the vector they replace.
TEST(InputLog, KeepsRunsOfIdenticalInputsAndReadsBackEveryStep) {
  std::vector<Input> steps(10);
  for (std::size_t k = 4; k < 7; ++k) steps[k].right.pose.translation().x() = 0.01 * static_cast<double>(k);
  steps[8].hoist.height = -0.0;  // not the same bits as 0.0
  steps[9].hoist.height = -0.0;
  steps[7] = steps[6];
  const InputLog log(steps);
  EXPECT_EQ(log.size(), 10u);
  EXPECT_EQ(log.runs(), 5u) << "steps 0-3, 4, 5, 6-7, 8-9";
  std::size_t k = 0;
  for (const Input& in : log) EXPECT_TRUE(identical(in, steps[k++])) << k;
  EXPECT_EQ(k, 10u);
  for (std::size_t i = 0; i < steps.size(); ++i) EXPECT_TRUE(identical(log[i], steps[i])) << i;
  EXPECT_FALSE(identical(steps[7], steps[8]));
  InputLog cut = log;
  cut.resize(6);
  EXPECT_EQ(cut.size(), 6u);
  EXPECT_EQ(cut.runs(), 3u);
  cut.push_back(steps[5]);
  EXPECT_EQ(cut.runs(), 3u) << "the same as the last step: the run grows";
  EXPECT_TRUE(identical(cut.back(), steps[5]));
  EXPECT_THROW((void)log[10], std::out_of_range);
}

// Eleven minutes recorded: a snapshot every second of the last ten minutes and every tenth second before;
// a seek anywhere still equals a fresh replay, and so it does after the oldest snapshots are given up (a seek
// then replays from the start).
TEST(Recorder, ThinsOldSnapshotsAndGivesUpTheOldestWhenAsked) {
  const auto scene = bundled("sleeve-on-shaft.vaw.json");
  Settings settings;
  const auto script = sleeveScript(settings);
  Recorder rec(scene, settings, "sleeve-on-shaft.vaw.json");
  const std::uint64_t interval = rec.snapshotInterval();
  const std::uint64_t total = 660 * interval;  // eleven minutes
  std::vector<std::uint64_t> hashes;
  for (std::uint64_t i = 0; i < total; ++i) {
    rec.record(script[i % script.size()]);
    hashes.push_back(rec.world().stateHash());
  }
  std::vector<std::uint64_t> expected;
  for (std::uint64_t k = 0; k <= 660; ++k)
    if (Recorder::keeps(k, 660)) expected.push_back(k * interval);
  EXPECT_EQ(rec.snapshotSteps(), expected);
  // The last ten minutes' 600 (61 s to 660 s) and 0, 10, ..., 60 s before them.
  EXPECT_EQ(expected.size(), 600u + 7u);
  const auto seekAll = [&](const char* when) {
    for (const std::uint64_t n : {total - 1, std::uint64_t{1}, 29 * interval + 89, 59 * interval + 89, 95 * interval + 7, 299 * interval + 89, 620 * interval, total / 2}) {
      rec.seek(n);
      EXPECT_EQ(rec.world().stateHash(), hashes[n - 1]) << "step " << n << ", " << when;
      // And on from there as recorded: the models restored (histories, hinges, flights), not only the poses.
      for (std::uint64_t k = n; k < std::min(n + 300, total); ++k) {
        ASSERT_TRUE(rec.playNext());
        ASSERT_EQ(rec.world().stateHash(), hashes[k]) << "step " << k + 1 << " after a seek to " << n << ", " << when;
      }
    }
  };
  seekAll("thinned");
  const std::size_t before = rec.memoryBytes();
  const std::uint64_t slowBefore = rec.giveUpOldest(0);  // as little as it can hold
  EXPECT_EQ(rec.snapshotSteps(), (std::vector<std::uint64_t>{0, total})) << "the first stays (the recording stays whole), and the newest";
  EXPECT_EQ(slowBefore, total);
  EXPECT_LT(rec.memoryBytes(), before);
  seekAll("after giving up the oldest");
  rec.seek(total);
  EXPECT_TRUE(rec.atEnd());
}

// Snapshots share each part's state while it does not change: restoring any of them and playing on gives
// the recorded steps bit for bit in every model (a gear swinging on its shaft, a tray on the hoist), not
// only in the sleeve's slide.
TEST(Recorder, SharedSnapshotsRestoreEveryModel) {
  const auto check = [](const std::shared_ptr<const Scene>& scene, const std::vector<Input>& inputs, const char* what) {
    Recorder rec(scene, Settings{}, "scene");
    std::vector<std::uint64_t> hashes;
    for (const Input& in : inputs) {
      rec.record(in);
      hashes.push_back(rec.world().stateHash());
    }
    const std::uint64_t interval = rec.snapshotInterval();
    for (std::uint64_t n = interval / 2; n < inputs.size(); n += interval) {
      rec.seek(n);
      ASSERT_EQ(rec.world().stateHash(), hashes[n - 1]) << what << ", step " << n;
      for (std::uint64_t k = n; k < std::min<std::uint64_t>(n + interval, inputs.size()); ++k) {
        ASSERT_TRUE(rec.playNext());
        ASSERT_EQ(rec.world().stateHash(), hashes[k]) << what << ", step " << k + 1 << " after a seek to " << n;
      }
    }
  };
  {
    const auto scene = bundled("gear-on-shaft.vaw.json");
    const Part& g = scene->assembly().parts[*scene->assembly().findPart("gear")];
    // Let go 20 degrees off hanging on its shaft: it swings for the rest of the recording.
    const Eigen::Isometry3d release = simtest::rotAbout(Eigen::Vector3d::UnitX(), 20.0 * std::numbers::pi / 180.0,
                                                        Eigen::Vector3d(0, 0, 0.15)) * *g.finalPose;
    std::vector<Input> inputs(900);
    inputs[0].left = simtest::hand(g.pose, true);
    inputs[1].left = simtest::hand(release, true);
    for (std::size_t k = 2; k < inputs.size(); ++k) inputs[k].left = simtest::hand(release, false);
    check(scene, inputs, "gear");
  }
  {
    Settings settings;
    const auto inputs = loadInputScript(std::filesystem::path(VAW_SOURCE_DIR) / "tests/sim/scripts/hoist-demo.vaw-inputs.json", settings);
    check(bundled("hoist-demo.vaw.json"), inputs, "hoist");
  }
}
