#include "vaw/sim/swept_volume.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "vaw/error.hpp"
#include "vaw/sim/carried_path.hpp"
#include "vaw/sim/scene.hpp"
#include "vaw/sim/world.hpp"

namespace vaw::sim {

double tessellationSag(const Part& part) { return part.cad ? std::max(0.0, part.cad->deflection) : 0.0; }

namespace {

// The part's poses over its span, gathered step by step from a replay, then swept.
class PathPoses {
 public:
  PathPoses(const std::shared_ptr<const Scene>& scene, std::string file, PartId part, const SweptVolumeOptions& options)
      : a_(scene->assembly()), file_(std::move(file)), part_(part), options_(options), span_{options.from, options.to} {
    if (part >= a_.parts.size()) fail(file_, "part", "a part of the scene", "part index " + std::to_string(part));
    if (!(options.voxel > 0.0) || !std::isfinite(options.voxel))
      fail(file_, "voxel", "a positive length", std::to_string(1e3 * options.voxel) + " mm");
    if (options.relativeToBase && !a_.base) fail(file_, "relative-to-base", "a scene with a base part", "no base");
    if (options.relativeToBase && *a_.base == part) fail(file_, "relative-to-base", "a part other than the base", a_.parts[part].name);
  }

  void step(const World& w) {
    if (!span_.holds(w, part_)) {
      open_ = false;
      return;
    }
    Eigen::Isometry3d pose = w.part(part_).pose;
    if (options_.relativeToBase) {
      const Eigen::Isometry3d& base = w.part(*a_.base).pose;
      if (!firstBase_) firstBase_ = base;
      pose = base.inverse() * pose;
    }
    if (!open_) runs_.emplace_back();
    if (runs_.size() == 1 && runs_.front().empty()) from_ = w.time();
    open_ = true;
    runs_.back().push_back(pose);
    to_ = w.time();
  }

  SweptVolume finish() const {
    if (runs_.empty()) span_.noStep(file_, a_, part_);
    // The part's collision mesh is what it occupies in the simulation: the same one the clearance measures.
    SweptVolume sv;
    try {
      sv = sweep(*a_.parts[part_].mesh, runs_, options_.voxel, sweepVoxelsInMemory(options_.memoryMB), tessellationSag(a_.parts[part_]));
    } catch (const std::invalid_argument& e) {
      fail(file_, "voxel", "a grid vaw can hold", e.what());
    }
    if (firstBase_) {
      sv.frame = *firstBase_;
      sv.mesh.transform(*firstBase_);
    }
    sv.relativeToBase = options_.relativeToBase;
    sv.from = from_;
    sv.to = to_;
    return sv;
  }

 private:
  const Assembly& a_;
  std::string file_;
  PartId part_;
  SweptVolumeOptions options_;
  PathSpan span_;
  std::vector<std::vector<Eigen::Isometry3d>> runs_;
  std::optional<Eigen::Isometry3d> firstBase_;
  bool open_ = false;
  double from_ = 0.0, to_ = 0.0;
};

}  // namespace

SweptVolume sweptVolume(const std::shared_ptr<const Scene>& scene, const Session& session, PartId part, const SweptVolumeOptions& options) {
  PathPoses path(scene, sessionName(session), part, options);
  (void)replay(scene, session, [&](const World& w) { path.step(w); });
  return path.finish();
}

SweptPathAndClearance sweptVolumeAndClearance(const std::shared_ptr<const Scene>& scene, const Session& session, PartId part,
                                              const SweptVolumeOptions& swept, const ClearanceOptions& clearance) {
  PathPoses path(scene, sessionName(session), part, swept);
  ClearanceMeter meter(scene, sessionName(session), part, clearance);
  (void)replay(scene, session, [&](const World& w) {
    path.step(w);
    meter.step(w);
  });
  return {path.finish(), meter.finish()};
}

}  // namespace vaw::sim

