#include "peers/peers.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "peers/engines.hpp"

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

}  // namespace vaw::peers
