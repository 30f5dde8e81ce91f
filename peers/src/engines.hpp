#pragma once
// Private to vaw_peers: one factory per engine, compiled only when the engine was found.
#include <sstream>
#include <string>
#include <utility>

#include "vaw/peers/peers.hpp"

namespace vaw::peers::detail {

// Runs `run` (one full scenario run into `samples`) once for the samples, then times it with
// vaw::dyn::medianSeconds; notes when a repeat run differs from the first (it must not: every run
// resets the world's moving body, and the timed runs are meant to repeat the recorded one).
template <class Run>
PeerResult measure(Run&& run, int count, double duration, const vaw::dyn::WorkPrecisionOptions& o, std::string note) {
  PeerResult r;
  r.samples.assign(static_cast<std::size_t>(count), 0.0);
  run(r.samples);
  vaw::dyn::Samples scratch(r.samples.size(), 0.0);
  const double seconds = vaw::dyn::medianSeconds([&] { run(scratch); }, o);
  r.cpuPerSimSecond = duration > 0.0 ? seconds / duration : 0.0;
  if (scratch != r.samples) note += "; WARNING: repeat runs are not bitwise identical";
  r.note = std::move(note);
  return r;
}

// A number for a note (ostream default: 6 significant digits).
inline std::string fmt(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

#ifdef VAW_HAVE_BULLET
Peer bulletPeer();
#endif
#ifdef VAW_HAVE_ODE
Peer odePeer();
#endif
}  // namespace vaw::peers::detail
