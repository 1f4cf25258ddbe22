#pragma once
// The tracking message (docs/protocol.md, "Tracking"): one TrackingFrame in kTrackingBytes = 82
// bytes, positions relative to the sender's root O (from its hello). Encoding and decoding work on
// caller-owned spans and allocate nothing.

#include <cstddef>
#include <cstdint>
#include <span>

#include "core/tracking.h"
#include "net/protocol.h"

namespace deixis::net {

struct TrackingMessage {
  std::uint32_t sequence = 0;  // +1 per frame sent on this connection, from 0
  TrackingFrame frame;         // frame.time: the sender's clock, carried in whole milliseconds
};

struct TrackingEncoding {
  std::size_t bytes = 0;           // kTrackingBytes, or 0 when `out` is too small
  std::uint8_t dropped_parts = 0;  // tracked::* flags cleared: not finite, or beyond ±32.767 m
};

// `root` is the sender's root position (its hello's T_world_root). Parts flagged valid that
// cannot be represented are sent as not valid and reported in dropped_parts; a target that is
// not finite is sent as kNoTarget; a target farther than 32.767 m is brought closer along its
// direction (its angles from the root are what the receiver uses).
TrackingEncoding encode_tracking(const TrackingMessage& message, const Vec3& root,
                                 std::span<std::byte> out);

// `root` is the sender's root position, from the sender's hello. Parts not flagged valid decode
// to the identity pose / zero; targets that are kNoTarget decode with a zero position.
WireResult decode_tracking(std::span<const std::byte> packet, const Vec3& root,
                           TrackingMessage& out);

}  // namespace deixis::net
