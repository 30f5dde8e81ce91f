#pragma once
// Work-precision measurements (docs/work-precision.md): for each scenario, each method and each step
// size, the CPU time per simulated second and the error against a reference solution. vaw-sim's
// `work-precision` command writes them as CSV and charts them.
#include <algorithm>
#include <array>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "vaw/dynamics/integrators.hpp"

namespace vaw::dyn {

// Values of one coordinate at the sample times 0, 0.1, 0.2, ... s (0.1 s is a whole number of steps
// for every step size in kStepRates, so every method is compared at the same instants).
using Samples = std::vector<double>;
inline constexpr double kSampleInterval = 0.1;
inline constexpr std::array<int, 7> kStepRates{30, 60, 90, 120, 250, 500, 1000};  // Hz

// The scenarios' physical parameters, shared with the peer engines (Bullet, ODE) so that all solve the
// same problem.
struct SlideScenario {
  double tiltDeg = 8.0;             // incline below the static and kinetic angles: the part stops
  double fs = 0.3, fd = 0.2;
  double v0 = 1.5;                  // m/s down the slope at t = 0
  double mass = 0.1944;             // kg, the aluminium block of block-on-plate
  double size[3] = {0.06, 0.04, 0.03};
  double duration = 4.0;            // s
};

struct PendulumScenario {
  // The paper-like gear (docs/physics.md): solid disk r = 0.05 m, m = 0.3 kg, CM 0.02 m off the axis.
  double radius = 0.05, mass = 0.3, arm = 0.02;
  double fr = 0.0;                  // N m s
  double theta0Deg = 60.0;          // released from rest, measured from the bottom
  double duration = 10.0;           // s
  [[nodiscard]] double inertia() const { return 0.5 * mass * radius * radius + mass * arm * arm; }
};

struct TumbleScenario {
  std::string name = "tumbling-block";
  double size[3] = {0.2, 0.1, 0.05};  // steel block: principal moments along x < y < z
  double density = 7850;
  double omega[3] = {3.0, 1.0, 5.0};  // rad/s, body = world at release
  double duration = 2.0;
};
// The tennis-racket flip: the same block spun about its intermediate axis (y) with a small part along
// the unstable direction; it turns over after 1.7 s.
inline TumbleScenario tennisRacketScenario() { return {"tennis-racket", {0.2, 0.1, 0.05}, 7850, {0.02, 6.0, -0.02}, 3.0}; }

// Analytic / reference solutions at the sample times.
Samples slideReference(const SlideScenario& s);          // closed form with the exact stop, m along the slope
Samples pendulumReference(const PendulumScenario& p);    // Dormand-Prince 1e-12, angle from the bottom (rad)

struct Record {
  std::string scenario;
  std::string method;   // a vaw method, or a peer engine's name
  double stepRate = 0;  // Hz
  double cpuPerSimSecond = 0;  // s of CPU per simulated s (median of repeats)
  double error = 0;     // max |value - reference| over the samples
  std::string errorUnit;
  bool stable = true;   // the method's linear stability at this step (pendulums)
  std::string note;
};

// The scenarios' names, as Record::scenario gives them.
inline constexpr std::array<const char*, 5> kScenarios{"slide-with-stop", "gear-pendulum", "gear-pendulum-damped",
                                                       "tumbling-block", "tennis-racket"};

struct WorkPrecisionOptions {
  int repeats = 5;               // timings are the median of this many runs
  double minTimedSeconds = 2e-3; // each timed run repeats the scenario until it takes at least this long
  // Only these scenarios (kScenarios' names); empty: all. The workbench's chart runs the selected part's.
  std::vector<std::string> scenarios;
  // The step rates, Hz; empty: kStepRates. Each must be a whole number of steps per kSampleInterval.
  std::vector<int> rates;
  [[nodiscard]] bool wants(std::string_view scenario) const {
    return scenarios.empty() || std::find(scenarios.begin(), scenarios.end(), scenario) != scenarios.end();
  }
  [[nodiscard]] std::vector<int> stepRates() const {
    return rates.empty() ? std::vector<int>(kStepRates.begin(), kStepRates.end()) : rates;
  }
};

// Progress: (done, total) runs; return false to stop.
using WorkProgress = std::function<bool(int done, int total)>;

std::vector<Record> runWorkPrecision(const WorkPrecisionOptions& o = {}, const WorkProgress& progress = {});

double maxAbsDifference(const Samples& a, const Samples& b);

// Times `body` (one full scenario run) and returns the median CPU seconds per run.
double medianSeconds(const std::function<void()>& body, const WorkPrecisionOptions& o);

}  // namespace vaw::dyn
