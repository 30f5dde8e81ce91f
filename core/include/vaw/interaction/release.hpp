#pragma once
// The velocity a part has when the hand lets go (docs/physics.md, "Free flight"). The paper differences the two
// most recent poses; tracked hands jitter, so a least-squares fit over a short window is the usual fix.
#include <Eigen/Geometry>
#include <span>

namespace vaw::interact {

struct PoseSample {
  double t = 0.0;                                   // s
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // m, world
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

struct Twist {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();   // m/s, world
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();  // rad/s, world
};

enum class ReleaseEstimator { TwoInstance, WindowedFit };

struct ReleaseSettings {
  ReleaseEstimator estimator = ReleaseEstimator::WindowedFit;
  // The fit uses the samples within this time before the last one; 80 ms is 8 frames at 90 Hz.
  double window = 0.080;
};

// The paper's estimate from the last two samples: (p_k - p_k-1) / dt and log(R_k R_k-1^T) / dt.
Twist twoInstanceVelocity(std::span<const PoseSample> history);

// A quadratic least-squares fit over the window, differentiated at the last sample (so a hand that
// is accelerating as it throws is not lagged by half the window). Rotations are fitted as rotation
// vectors relative to the last orientation. Falls back to the two-instance estimate with fewer than
// four samples in the window.
Twist windowedVelocity(std::span<const PoseSample> history, double window);

Twist releaseVelocity(std::span<const PoseSample> history, const ReleaseSettings& settings);

}  // namespace vaw::interact
