#include "vaw/sim/rate_meter.hpp"

namespace vaw::sim {

void RateMeter::sample(double wall, double simTime, double stepping) {
  steppingTotal_ += stepping;
  if (!samples_.empty() && (wall < samples_.back().wall || simTime < samples_.back().simTime)) samples_.clear();
  samples_.push_back({wall, simTime, steppingTotal_});
  while (samples_.size() > 2 && wall - samples_[1].wall >= window_) samples_.pop_front();
}

std::optional<RateMeter::Reading> RateMeter::reading() const {
  if (samples_.size() < 2) return std::nullopt;
  const Sample& a = samples_.front();
  const Sample& b = samples_.back();
  const double span = b.wall - a.wall;
  if (!(span >= 0.5 * window_)) return std::nullopt;
  return Reading{(b.simTime - a.simTime) / span, (b.steppingTotal - a.steppingTotal) / span};
}

bool fallingBehind(const RateMeter::Reading& r, double speed, bool wasBehind) {
  return r.rate < (wasBehind ? 0.98 : 0.95) * speed;
}

}  // namespace vaw::sim
