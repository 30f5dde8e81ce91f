#include "vaw/fits.hpp"

#include <array>
#include <cmath>

namespace vaw {

namespace {

constexpr double kInch = 0.0254;

// ISO 261 metric (coarse, then the common fine pitches) and ASME B1.1 unified threads: the nominal
// diameter and the pitch. A size appears once per pitch; the coarse one first.
constexpr std::array kThreads = {
    ThreadSize{"M1.6", 1.6e-3, 0.35e-3}, ThreadSize{"M2", 2.0e-3, 0.4e-3},    ThreadSize{"M2.5", 2.5e-3, 0.45e-3},
    ThreadSize{"M3", 3.0e-3, 0.5e-3},    ThreadSize{"M4", 4.0e-3, 0.7e-3},    ThreadSize{"M5", 5.0e-3, 0.8e-3},
    ThreadSize{"M6", 6.0e-3, 1.0e-3},    ThreadSize{"M8", 8.0e-3, 1.25e-3},   ThreadSize{"M10", 10.0e-3, 1.5e-3},
    ThreadSize{"M12", 12.0e-3, 1.75e-3}, ThreadSize{"M14", 14.0e-3, 2.0e-3},  ThreadSize{"M16", 16.0e-3, 2.0e-3},
    ThreadSize{"M20", 20.0e-3, 2.5e-3},  ThreadSize{"M24", 24.0e-3, 3.0e-3},  ThreadSize{"M30", 30.0e-3, 3.5e-3},
    ThreadSize{"M36", 36.0e-3, 4.0e-3},  ThreadSize{"M8x1", 8.0e-3, 1.0e-3},  ThreadSize{"M10x1.25", 10.0e-3, 1.25e-3},
    ThreadSize{"M12x1.5", 12.0e-3, 1.5e-3},
    ThreadSize{"#2-56 UNC", 0.086 * kInch, kInch / 56},    ThreadSize{"#4-40 UNC", 0.112 * kInch, kInch / 40},
    ThreadSize{"#6-32 UNC", 0.138 * kInch, kInch / 32},    ThreadSize{"#8-32 UNC", 0.164 * kInch, kInch / 32},
    ThreadSize{"#10-24 UNC", 0.190 * kInch, kInch / 24},   ThreadSize{"1/4-20 UNC", 0.25 * kInch, kInch / 20},
    ThreadSize{"5/16-18 UNC", 0.3125 * kInch, kInch / 18}, ThreadSize{"3/8-16 UNC", 0.375 * kInch, kInch / 16},
    ThreadSize{"7/16-14 UNC", 0.4375 * kInch, kInch / 14}, ThreadSize{"1/2-13 UNC", 0.5 * kInch, kInch / 13},
    ThreadSize{"5/8-11 UNC", 0.625 * kInch, kInch / 11},   ThreadSize{"3/4-10 UNC", 0.75 * kInch, kInch / 10},
    ThreadSize{"#10-32 UNF", 0.190 * kInch, kInch / 32},   ThreadSize{"1/4-28 UNF", 0.25 * kInch, kInch / 28},
    ThreadSize{"5/16-24 UNF", 0.3125 * kInch, kInch / 24}, ThreadSize{"3/8-24 UNF", 0.375 * kInch, kInch / 24},
    ThreadSize{"1/2-20 UNF", 0.5 * kInch, kInch / 20},
};

// A screw modelled at its nominal diameter: within 2 % (some libraries draw the major diameter a little
// under nominal) or 20 um.
bool nominal(double diameter, const ThreadSize& t) { return std::abs(diameter - t.major) <= std::max(0.02 * t.major, 20e-6); }

}  // namespace

std::optional<ThreadSize> threadOfDiameter(double diameter) {
  for (const ThreadSize& t : kThreads)
    if (nominal(diameter, t)) return t;
  return std::nullopt;
}

std::optional<DesignedInterference> designedInterference(double shaftRadius, double boreRadius) {
  const double interference = shaftRadius - boreRadius;
  if (!(interference > 0.0) || !(boreRadius > 0.0)) return std::nullopt;
  if (interference <= 0.01 * shaftRadius) return DesignedInterference{Constraint::Found::Fit::Press, {}};
  const double D = 2.0 * shaftRadius, d = 2.0 * boreRadius;
  for (const ThreadSize& t : kThreads) {
    if (!nominal(D, t)) continue;
    // The internal thread's minor diameter is D - 1.0825 P; tap drills are about D - P; a modeller's
    // allowance either side.
    if (d >= t.major - 1.25 * t.pitch && d <= t.major - 0.4 * t.pitch) return DesignedInterference{Constraint::Found::Fit::Threaded, t.name};
  }
  return std::nullopt;
}

}  // namespace vaw
