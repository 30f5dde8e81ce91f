#pragma once
// Peer engines for the work-precision chart (docs/work-precision.md): the slide and pendulum scenarios
// run in general rigid-body engines (Bullet, ODE) from Debian's packages, so the chart shows what a
// general engine gives for the same scene at the same cost. Only the engines found at configure time
// are compiled in; availablePeers() lists them.
#include <functional>
#include <string>
#include <vector>

#include "vaw/dynamics/work_precision.hpp"

namespace vaw::peers {

struct PeerResult {
  vaw::dyn::Samples samples;   // coordinate at t = 0, 0.1, 0.2, ... (kSampleInterval), same count as the reference
  double cpuPerSimSecond = 0;  // median over repeats (vaw::dyn::medianSeconds) / scenario duration
  std::string note;            // solver settings, what the coordinate is
};

struct Peer {
  std::string name;  // "bullet", "ode"
  std::function<PeerResult(const vaw::dyn::SlideScenario&, double stepRate, const vaw::dyn::WorkPrecisionOptions&)>
      slide;
  std::function<PeerResult(const vaw::dyn::PendulumScenario&, double stepRate,
                           const vaw::dyn::WorkPrecisionOptions&)>
      pendulum;
};

// The engines compiled in, in a fixed order (bullet, ode); empty when none was found.
std::vector<Peer> availablePeers();

// Every available engine on the slide and pendulum scenarios that `o` asks for, at its rates, as
// work-precision records against the same references as vaw's methods. `progress` hears "bullet at
// 90 Hz" before each rate; returning false stops.
std::vector<vaw::dyn::Record> runPeers(const vaw::dyn::WorkPrecisionOptions& o,
                                       const std::function<bool(const std::string&)>& progress = {});

// Number of samples for a scenario of this duration: round(duration / kSampleInterval) + 1.
int sampleCount(double duration);
// Steps per sample at this step rate; throws std::invalid_argument unless stepRate * kSampleInterval
// is a positive whole number (true for every rate in kStepRates).
int stepsPerSample(double stepRate);

}  // namespace vaw::peers
