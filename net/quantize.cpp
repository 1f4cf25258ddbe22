#include "net/quantize.h"

#include <algorithm>
#include <cmath>

namespace deixis::net {

namespace {

constexpr float kInvSqrt2 = 0.70710678118f;
constexpr int kComponentBits = 15;
constexpr std::uint64_t kComponentMask = (std::uint64_t{1} << kComponentBits) - 1;
// A component v ∈ [−1/√2, 1/√2] is sent as 16383 + round(16383·√2·v) ∈ [0, 32766]: zero and
// ±1/√2 are exact, and 32767 is never sent (refused on receipt).
constexpr float kComponentHalf = 16383.0f;

constexpr long kMaxMillimetres = 32767;  // −32768 is never sent (and refused on receipt)

std::uint64_t quantize_component(float v) {
  const float scaled = std::clamp(v / kInvSqrt2, -1.0f, 1.0f) * kComponentHalf;
  return static_cast<std::uint64_t>(std::lround(scaled + kComponentHalf));
}

float dequantize_component(std::uint64_t u) {
  return (static_cast<float>(u) - kComponentHalf) / kComponentHalf * kInvSqrt2;
}

float sign_not_zero(float v) {
  return v < 0.0f ? -1.0f : 1.0f;
}

}  // namespace

std::optional<QuantizedPosition> quantize_position(const Vec3& offset) {
  // The range is checked on the rounded millimetres, so that whatever decodes re-encodes.
  if (!offset.allFinite() || offset.cwiseAbs().maxCoeff() > 2.0f * kPositionLimit) {
    return std::nullopt;
  }
  QuantizedPosition q{};
  for (int k = 0; k < 3; ++k) {
    const long mm = std::lround(offset[k] / kPositionStep);
    if (mm < -kMaxMillimetres || mm > kMaxMillimetres) {
      return std::nullopt;
    }
    q[static_cast<std::size_t>(k)] = static_cast<std::int16_t>(mm);
  }
  return q;
}

std::optional<QuantizedPosition> quantize_direction_preserving(const Vec3& offset) {
  if (!offset.allFinite()) {
    return std::nullopt;
  }
  const float largest = offset.cwiseAbs().maxCoeff();
  return quantize_position(largest > kPositionLimit ? Vec3(offset * (kPositionLimit / largest))
                                                    : offset);
}

Vec3 dequantize_position(const QuantizedPosition& q) {
  return Vec3(static_cast<float>(q[0]), static_cast<float>(q[1]), static_cast<float>(q[2])) *
         kPositionStep;
}

std::optional<std::uint64_t> quantize_rotation(const Mat3& rotation) {
  if (!rotation.allFinite()) {
    return std::nullopt;
  }
  Quat q(rotation);
  q.normalize();
  const std::array<float, 4> c = {q.x(), q.y(), q.z(), q.w()};
  std::size_t largest = 0;
  for (std::size_t i = 1; i < 4; ++i) {
    if (std::abs(c[i]) > std::abs(c[largest])) {
      largest = i;
    }
  }
  // q and −q are the same rotation: make the dropped component positive so it is sqrt(1 − Σ).
  const float sign = sign_not_zero(c[largest]);
  std::uint64_t packed = std::uint64_t{largest} << (3 * kComponentBits);
  int shift = 2 * kComponentBits;
  for (std::size_t i = 0; i < 4; ++i) {
    if (i != largest) {
      packed |= quantize_component(sign * c[i]) << shift;
      shift -= kComponentBits;
    }
  }
  return packed;
}

std::optional<Mat3> dequantize_rotation(std::uint64_t packed) {
  if ((packed >> (3 * kComponentBits + 2)) != 0) {
    return std::nullopt;  // the reserved bit (or bits beyond 48)
  }
  const auto largest = static_cast<std::size_t>((packed >> (3 * kComponentBits)) & 3u);
  std::array<float, 4> c{};
  float sum = 0.0f;
  int shift = 2 * kComponentBits;
  for (std::size_t i = 0; i < 4; ++i) {
    if (i != largest) {
      const std::uint64_t u = (packed >> shift) & kComponentMask;
      if (u > 2 * static_cast<std::uint64_t>(kComponentHalf)) {
        return std::nullopt;  // 32767: never sent
      }
      c[i] = dequantize_component(u);
      sum += c[i] * c[i];
      shift -= kComponentBits;
    }
  }
  // Legitimate encodings stay below 3/4 (the dropped component is the largest); allow rounding.
  if (sum > 1.0f) {
    return std::nullopt;
  }
  c[largest] = std::sqrt(1.0f - sum);
  Quat q(c[3], c[0], c[1], c[2]);  // Eigen's constructor takes w first
  q.normalize();
  return q.toRotationMatrix();
}

std::optional<std::array<std::int16_t, 2>> quantize_unit_vector(const Vec3& direction) {
  if (!direction.allFinite() || direction.norm() < 1e-6f) {
    return std::nullopt;
  }
  const Vec3 n = direction / direction.cwiseAbs().sum();  // onto the octahedron |x|+|y|+|z| = 1
  float u = n.x();
  float v = n.y();
  if (n.z() < 0.0f) {  // fold the lower half over the diagonals
    u = (1.0f - std::abs(n.y())) * sign_not_zero(n.x());
    v = (1.0f - std::abs(n.x())) * sign_not_zero(n.y());
  }
  const auto to_int16 = [](float x) {
    return static_cast<std::int16_t>(std::lround(std::clamp(x, -1.0f, 1.0f) * 32767.0f));
  };
  return std::array<std::int16_t, 2>{to_int16(u), to_int16(v)};
}

Vec3 dequantize_unit_vector(const std::array<std::int16_t, 2>& q) {
  const float u = std::clamp(static_cast<float>(q[0]) / 32767.0f, -1.0f, 1.0f);
  const float v = std::clamp(static_cast<float>(q[1]) / 32767.0f, -1.0f, 1.0f);
  Vec3 n(u, v, 1.0f - std::abs(u) - std::abs(v));
  if (n.z() < 0.0f) {
    const float x = n.x();
    n.x() = (1.0f - std::abs(n.y())) * sign_not_zero(x);
    n.y() = (1.0f - std::abs(x)) * sign_not_zero(n.y());
  }
  return n.normalized();  // never zero: |x|+|y|+|z| = 1 on the octahedron
}

}  // namespace deixis::net
