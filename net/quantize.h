#pragma once
// The quantisations of a tracking message (docs/protocol.md, "Tracking"), each with its error
// bound, proven by tests/net/quantize_test.cpp:
//   position   int16 millimetres per axis, relative to the sender's root: ±32.767 m, ≤ 0.5 mm
//              per axis (0.87 mm in 3-D)
//   rotation   "smallest three": 2 bits name the largest quaternion component, which is dropped
//              and made positive; the other three, each in [−1/√2, 1/√2], take 15 bits; with one
//              reserved bit, 48 bits: ≤ 0.01° (kRotationErrorBoundDeg)
//   direction  octahedral mapping to two int16: ≤ 0.005° (kDirectionErrorBoundDeg)
// Decoding any bit pattern gives a finite value; a rotation whose three components cannot belong
// to a unit quaternion is reported, not repaired.

#include <array>
#include <cstdint>
#include <optional>

#include "core/math/pose.h"

namespace deixis::net {

inline constexpr float kPositionStep = 0.001f;  // m per unit
inline constexpr float kPositionLimit = 32.767f;
inline constexpr float kRotationErrorBoundDeg = 0.01f;
inline constexpr float kDirectionErrorBoundDeg = 0.005f;

using QuantizedPosition = std::array<std::int16_t, 3>;

// nullopt when the offset is not finite or rounds to more than ±32767 mm on some axis.
std::optional<QuantizedPosition> quantize_position(const Vec3& offset);
// An offset that may be far away but whose direction matters (a target): shortened along its
// direction until it fits, so the angles seen from the root are kept. nullopt when not finite.
std::optional<QuantizedPosition> quantize_direction_preserving(const Vec3& offset);
Vec3 dequantize_position(const QuantizedPosition& q);
// The one int16 value no encoder writes (positions and directions are symmetric); refused.
inline constexpr std::int16_t kUnusedInt16 = -32768;

// 48 bits: c (bits 0–14), b (15–29), a (30–44), the dropped component's index (45–46), bit 47
// reserved (0); a, b, c are the kept components in x, y, z, w order, each sent as
// 16383 + round(16383·√2·v) ∈ [0, 32766]. nullopt when not finite.
std::optional<std::uint64_t> quantize_rotation(const Mat3& rotation);
// nullopt when the reserved or higher bits are set, a component is 32767, or the three
// components have a squared norm above 1 (no unit quaternion has them).
std::optional<Mat3> dequantize_rotation(std::uint64_t packed);

// nullopt when the direction is not finite or has (almost) zero length.
std::optional<std::array<std::int16_t, 2>> quantize_unit_vector(const Vec3& direction);
Vec3 dequantize_unit_vector(const std::array<std::int16_t, 2>& q);  // unit length

}  // namespace deixis::net
