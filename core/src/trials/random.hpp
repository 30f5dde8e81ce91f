#pragma once
// Random draws for trials. Each draw stream is keyed by (seed, purpose, index), so a trial's random
// choices depend on nothing but the design and its position: a resumed session draws exactly what an
// uninterrupted one would have. std::mt19937_64's output is fixed by the standard; the standard's
// distributions are not, so the few needed here are written out to give the same numbers everywhere.
#include <cmath>
#include <cstdint>
#include <cstddef>
#include <limits>
#include <random>
#include <utility>

namespace vaw::trials::detail {

// Purposes, so that two uses of one seed never share a stream.
enum class Stream : std::uint64_t { Order = 1, Start = 2, Interleave = 3, TwoInterval = 4, Participant = 5, QuestOffset = 6 };

inline std::uint64_t splitmix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

class Random {
 public:
  Random(std::uint64_t seed, Stream stream, std::uint64_t index)
      : engine_(splitmix(splitmix(seed) ^ splitmix(static_cast<std::uint64_t>(stream) << 40 ^ index))) {}

  // [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

  // Uniform on {0, ..., n - 1} by rejection, without modulo bias.
  std::uint64_t below(std::uint64_t n) {
    const std::uint64_t limit = std::numeric_limits<std::uint64_t>::max() - std::numeric_limits<std::uint64_t>::max() % n;
    std::uint64_t x;
    do x = engine_(); while (x >= limit);
    return x % n;
  }

  // Standard normal by Box-Muller (one of the pair; simplicity over speed).
  double normal() {
    const double u1 = 1.0 - uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }

  template <typename It>
  void shuffle(It first, It last) {
    for (auto n = last - first; n > 1; --n) std::swap(first[n - 1], first[static_cast<std::ptrdiff_t>(below(static_cast<std::uint64_t>(n)))]);
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace vaw::trials::detail
