#pragma once
// The capture's random numbers: xoshiro256** seeded through splitmix64, with its own uniform and
// normal draws. The standard library's distributions are implementation-defined, so they would
// make a dataset depend on the library version; these do not, and the same seed gives the same
// bytes (tests/capture/determinism_test.cpp).

#include <cmath>
#include <cstdint>
#include <numbers>
#include <string_view>

namespace deixis::capture {

// splitmix64's finaliser: a bijective mix of 64 bits.
inline std::uint64_t mix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// Combines seeds (e.g. global seed, set, subject, category, index) into one.
inline std::uint64_t combine_seed(std::uint64_t a, std::uint64_t b) {
  return mix64(a ^ mix64(b + 0x632BE59BD9B4E019ull));
}

// FNV-1a: a stable hash of a name (subject, set) for seeding.
inline std::uint64_t hash_name(std::string_view name) {
  std::uint64_t h = 0xCBF29CE484222325ull;
  for (const char c : name) {
    h = (h ^ static_cast<unsigned char>(c)) * 0x100000001B3ull;
  }
  return h;
}

class Random {
 public:
  explicit Random(std::uint64_t seed) {
    for (std::uint64_t& word : state_) {
      seed = mix64(seed);
      word = seed;
    }
  }

  std::uint64_t next() {
    const std::uint64_t result = rotl(state_[1] * 5, 7) * 9;
    const std::uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = rotl(state_[3], 45);
    return result;
  }

  // Uniform in [0, 1) with 53 bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  float uniform(float lo, float hi) { return lo + static_cast<float>(uniform()) * (hi - lo); }
  double uniform(double lo, double hi) { return lo + uniform() * (hi - lo); }
  // Uniform integer in [lo, hi].
  int integer(int lo, int hi) {
    const auto span = static_cast<std::uint64_t>(hi - lo + 1);
    return lo + static_cast<int>(next() % span);
  }
  bool chance(double p) { return uniform() < p; }
  float sign() { return chance(0.5) ? 1.0f : -1.0f; }

  // Standard normal (Box–Muller, one value per call; the pair's second value is discarded so a
  // draw never depends on how many draws came before in another stream).
  float normal() {
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    return static_cast<float>(std::sqrt(-2.0 * std::log(u1)) *
                              std::cos(2.0 * std::numbers::pi * u2));
  }
  float normal(float mean, float sigma) { return mean + sigma * normal(); }

  // An independent stream derived from this one's seed material and a stream number.
  Random fork(std::uint64_t stream) const {
    return Random(combine_seed(state_[0] ^ state_[2], stream));
  }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t state_[4];
};

}  // namespace deixis::capture
