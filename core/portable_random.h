// Random draws whose values are fixed by this file alone, so a sample regenerated from a seed is
// the same bytes with any standard library: std::mt19937_64 is specified bit for bit, but the
// std:: distributions are not (libstdc++ and libc++ return different numbers for one engine).
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

namespace tpcal {

// Uniform on [0, 1): the top 53 bits of one engine output.
inline double UniformUnit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// Uniform on [lo, hi): one engine output.
inline double UniformIn(std::mt19937_64& rng, double lo, double hi) { return lo + (hi - lo) * UniformUnit(rng); }

// Standard normal deviate (Marsaglia's polar method; the pair's second value is dropped so each
// call is self-contained). Uses two engine outputs per attempt, about 1.27 attempts on average;
// its value depends only on IEEE arithmetic, std::sqrt (correctly rounded) and std::log.
inline double StandardNormal(std::mt19937_64& rng) {
  for (;;) {
    const double u = 2.0 * UniformUnit(rng) - 1.0;
    const double v = 2.0 * UniformUnit(rng) - 1.0;
    const double s = u * u + v * v;
    if (s > 0.0 && s < 1.0) return u * std::sqrt(-2.0 * std::log(s) / s);
  }
}

}  // namespace tpcal
