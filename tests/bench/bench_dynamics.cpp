// One step of each reduced model with each method; closed-form free-flight pose evaluation.
//   build/bin/vaw_bench_dynamics --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include "vaw/dynamics/free_flight.hpp"
#include "vaw/dynamics/gravity.hpp"
#include "vaw/dynamics/hinge.hpp"
#include "vaw/dynamics/slide.hpp"
#include "vaw/dynamics/stability.hpp"

namespace {

using namespace vaw::dyn;
constexpr double kH = 1.0 / 90.0;

void BM_AxisSlideStep(benchmark::State& state) {
  const auto m = static_cast<Method>(state.range(0));
  AxisSlideInput in;
  in.u = Eigen::Vector3d(std::cos(0.5), 0, -std::sin(0.5));
  in.g = worldGravity();
  AxisSlideState s{0.0, 0.0, true};
  for (auto _ : state) {
    stepAxisSlide(s, in, {0.3, 0.2}, kH, m);
    if (s.s > 1e6) s = {0.0, 0.0, true};  // keep the numbers in range over billions of steps
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(std::string(name(m)));
}
BENCHMARK(BM_AxisSlideStep)->DenseRange(0, 4);

void BM_PlaneSlideStep(benchmark::State& state) {
  const auto m = static_cast<Method>(state.range(0));
  PlaneSlideInput in;
  in.n = Eigen::Vector3d(std::sin(0.5), 0, std::cos(0.5));
  in.e1 = Eigen::Vector3d(std::cos(0.5), 0, -std::sin(0.5));
  in.e2 = in.n.cross(in.e1);
  in.g = worldGravity();
  PlaneSlideState s{Eigen::Vector2d::Zero(), Eigen::Vector2d(0.0, 1.0), true};
  for (auto _ : state) {
    stepPlaneSlide(s, in, {0.6, 0.5}, kH, m);
    if (!s.moving) s = {Eigen::Vector2d::Zero(), Eigen::Vector2d(0.0, 1.0), true};
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(std::string(name(m)) + " (velocity across the slope)");
}
BENCHMARK(BM_PlaneSlideStep)->DenseRange(0, 3);

Hinge gear() {
  const Eigen::Matrix3d I = Eigen::Vector3d(3.75e-4, 1.875e-4, 1.875e-4).asDiagonal();
  return *Hinge::make(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(), Eigen::Isometry3d::Identity(), 0.3,
                      Eigen::Vector3d(0, 0.02, 0), I, 0.0005);
}

void BM_HingeStep(benchmark::State& state) {
  const auto m = static_cast<Method>(state.range(0));
  const Hinge h = gear();
  const HingeTorque t = h.torque(Eigen::Matrix3d::Identity(), worldGravity());
  HingeState s;
  for (auto _ : state) {
    h.step(s, t, kH, m);
    benchmark::DoNotOptimize(s);
  }
  state.SetLabel(std::string(name(m)));
}
BENCHMARK(BM_HingeStep)->DenseRange(0, 3);

// The per-step work when the base moves: torque coefficients from the base's orientation, then a step.
void BM_HingeStepMovingBase(benchmark::State& state) {
  const Hinge h = gear();
  HingeState s;
  double a = 0.0;
  for (auto _ : state) {
    a += 1e-3;
    const Eigen::Matrix3d base = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix();
    h.step(s, h.torque(base, worldGravity()), kH, Method::RK4);
    benchmark::DoNotOptimize(s);
  }
}
BENCHMARK(BM_HingeStepMovingBase);

// The tennis-racket flip of the work-precision chart: the steel block spun near its intermediate axis.
Release tennisRacket() {
  Release r;
  r.omega = {0.02, 6.0, -0.02};
  return r;
}
const Eigen::Matrix3d kBlockInertia = Eigen::Vector3d(0.0082, 0.0278, 0.0327).asDiagonal();

// One closed-form step at a constant step (the world's case): two additions of the elliptic functions,
// Simpson's rule on psi, the orientation.
void BM_TorqueFreeStep(benchmark::State& state) {
  TorqueFree tf(tennisRacket(), kBlockInertia);
  for (auto _ : state) {
    tf.step(kH);
    benchmark::DoNotOptimize(tf.orientation());
  }
}
BENCHMARK(BM_TorqueFreeStep);

// A whole 3 s flight at 90 Hz from the release (set-up included), as the goal counts it: CPU per
// simulated second = this / 3.
void BM_TorqueFreeFlight3s(benchmark::State& state) {
  for (auto _ : state) {
    TorqueFree tf(tennisRacket(), kBlockInertia);
    for (int i = 0; i < 270; ++i) tf.step(kH);
    benchmark::DoNotOptimize(tf.orientation());
  }
  state.SetLabel("270 steps of 1/90 s");
}
BENCHMARK(BM_TorqueFreeFlight3s);

// The choice made on every release: 0.3 s (27 steps, each sampled) and 1 s (every third of 90 steps)
// flights of the tumbling block, below the tolerance so that no sample stops it early; 2 s stops early.
void BM_ChooseRotationModel(benchmark::State& state) {
  Release r = tennisRacket();
  const double flight = static_cast<double>(state.range(0)) / 10.0;
  for (auto _ : state) {
    r.omega.x() += 1e-12;  // a new release each time
    benchmark::DoNotOptimize(chooseRotationModel(r, kBlockInertia, flight, kH));
  }
  state.SetLabel("flight " + std::to_string(flight).substr(0, 3) + " s, " +
                 std::string(name(chooseRotationModel(r, kBlockInertia, flight, kH).model)));
}
BENCHMARK(BM_ChooseRotationModel)->Arg(3)->Arg(10)->Arg(20);

void BM_FreeFlightPose(benchmark::State& state) {
  Release r;
  r.position = {0.1, 0.2, 1.0};
  r.velocity = {0.5, 0.0, 1.0};
  r.omega = {3, 1, 5};
  const Eigen::Vector3d g = 0.25 * worldGravity();
  double t = 0.0;
  for (auto _ : state) {
    t += kH;
    benchmark::DoNotOptimize(ballisticPosition(r, g, t));
    benchmark::DoNotOptimize(constantOmegaOrientation(r, t));
  }
  state.SetLabel("closed-form position + constant-omega orientation");
}
BENCHMARK(BM_FreeFlightPose);

void BM_StabilityCheck(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(checkStability(Method::VelocityVerlet, 10.9, 1.0, kH));
  state.SetLabel("run once per part and setting change, not per step");
}
BENCHMARK(BM_StabilityCheck);

}  // namespace

BENCHMARK_MAIN();
