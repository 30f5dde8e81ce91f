#include "vaw/peers/peers.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "engines.hpp"

namespace vaw::peers {

std::vector<Peer> availablePeers() {
  std::vector<Peer> peers;
#ifdef VAW_HAVE_BULLET
  peers.push_back(detail::bulletPeer());
#endif
#ifdef VAW_HAVE_ODE
  peers.push_back(detail::odePeer());
#endif
  return peers;
}

int sampleCount(double duration) {
  if (!(duration >= 0.0) || !std::isfinite(duration))
    throw std::invalid_argument("peers: scenario duration must be finite and >= 0");
  return static_cast<int>(std::lround(duration / vaw::dyn::kSampleInterval)) + 1;
}

int stepsPerSample(double stepRate) {
  const double exact = stepRate * vaw::dyn::kSampleInterval;
  const long n = std::isfinite(exact) ? std::lround(exact) : 0;
  if (n < 1 || std::abs(exact - static_cast<double>(n)) > 1e-9 * exact)
    throw std::invalid_argument("peers: step rate " + std::to_string(stepRate) +
                                " Hz is not a whole number of steps per sample interval");
  return static_cast<int>(n);
}

std::vector<vaw::dyn::Record> runPeers(const vaw::dyn::WorkPrecisionOptions& o,
                                       const std::function<bool(const std::string&)>& progress) {
  std::vector<vaw::dyn::Record> records;
  const vaw::dyn::SlideScenario slide;
  vaw::dyn::PendulumScenario undamped, damped;
  damped.fr = 0.0005;
  const bool wantSlide = o.wants("slide-with-stop");
  const auto pendulumName = [](const vaw::dyn::PendulumScenario& p) { return p.fr > 0 ? "gear-pendulum-damped" : "gear-pendulum"; };
  const vaw::dyn::Samples slideRef = wantSlide ? vaw::dyn::slideReference(slide) : vaw::dyn::Samples{};
  const vaw::dyn::Samples undampedRef = o.wants(pendulumName(undamped)) ? vaw::dyn::pendulumReference(undamped) : vaw::dyn::Samples{};
  const vaw::dyn::Samples dampedRef = o.wants(pendulumName(damped)) ? vaw::dyn::pendulumReference(damped) : vaw::dyn::Samples{};
  for (const auto& peer : availablePeers()) {
    for (int rate : o.stepRates()) {
      if (progress && !progress(peer.name + " at " + std::to_string(rate) + " Hz")) return records;
      if (wantSlide) {
        const auto s = peer.slide(slide, rate, o);
        records.push_back({"slide-with-stop", peer.name, static_cast<double>(rate), s.cpuPerSimSecond,
                           vaw::dyn::maxAbsDifference(s.samples, slideRef), "m", true, s.note});
      }
      for (const auto* p : {&undamped, &damped}) {
        if (!o.wants(pendulumName(*p))) continue;
        const auto r = peer.pendulum(*p, rate, o);
        records.push_back({pendulumName(*p), peer.name, static_cast<double>(rate), r.cpuPerSimSecond,
                           vaw::dyn::maxAbsDifference(r.samples, p->fr > 0 ? dampedRef : undampedRef), "rad", true, r.note});
      }
    }
  }
  return records;
}

}  // namespace vaw::peers
