#include "net/tracking_codec.h"

#include <cmath>

#include "core/target_map.h"
#include "net/quantize.h"
#include "net/wire.h"

namespace deixis::net {

namespace {

// The sender's clock in whole milliseconds, modulo 2^32 (it wraps after 49.7 days; receivers
// only use differences, docs/protocol.md).
std::uint32_t to_wire_time(double seconds) {
  if (!std::isfinite(seconds)) {
    return 0;
  }
  const double ms = std::round(std::fmod(seconds * 1000.0, 4294967296.0));
  const double wrapped = ms < 0.0 ? ms + 4294967296.0 : ms;
  return static_cast<std::uint32_t>(static_cast<std::uint64_t>(wrapped) & 0xFFFFFFFFu);
}

void write_position(WireWriter& w, const QuantizedPosition& q) {
  w.i16(q[0]);
  w.i16(q[1]);
  w.i16(q[2]);
}

struct PartEncoder {
  WireWriter& w;
  const Vec3& root;
  std::uint8_t valid;
  std::uint8_t dropped = 0;

  // A pose part (head or wrist): position then rotation; identity and zero when not valid.
  void pose(std::uint8_t flag, const Pose& T) {
    std::optional<QuantizedPosition> p;
    std::optional<std::uint64_t> r;
    if (valid & flag) {
      p = quantize_position(T.translation - root);
      r = quantize_rotation(T.rotation);
      if (!p || !r) {
        drop(flag);
      }
    }
    const bool ok = (valid & flag) != 0;
    write_position(w, ok ? *p : QuantizedPosition{});
    w.u48(ok ? *r : *quantize_rotation(Mat3::Identity()));
  }

  void gaze(const Vec3& direction) {
    std::optional<std::array<std::int16_t, 2>> g;
    if (valid & tracked::kGaze) {
      g = quantize_unit_vector(direction);
      if (!g) {
        drop(tracked::kGaze);
      }
    }
    const std::array<std::int16_t, 2> bits =
        (valid & tracked::kGaze) ? *g : std::array<std::int16_t, 2>{0, 0};
    w.i16(bits[0]);
    w.i16(bits[1]);
  }

  // A fingertip belongs to its hand: it is sent when the hand is, and drops the hand with it.
  void point(std::uint8_t flag, const Vec3& p) {
    std::optional<QuantizedPosition> q;
    if (valid & flag) {
      q = quantize_position(p - root);
      if (!q) {
        drop(flag);
      }
    }
    write_position(w, (valid & flag) ? *q : QuantizedPosition{});
  }

  void drop(std::uint8_t flag) {
    valid = static_cast<std::uint8_t>(valid & ~flag);
    dropped = static_cast<std::uint8_t>(dropped | flag);
  }
};

// −1 none, 0 the other person, 1–1,000,000 an object, 1,000,001–1,000,254 a person of a room
// (docs/protocol.md §4.8, core/target_map.h).
bool is_target_on_wire(std::int32_t id) {
  return (id >= kNoTarget && id <= kMaxTargetIdOnWire) || is_person_target(id);
}

struct TargetOnWire {
  std::int32_t id = kNoTarget;
  QuantizedPosition position{};
};

TargetOnWire target_on_wire(TargetId id, const Vec3& position, const Vec3& root) {
  if (!is_target_on_wire(id)) {
    return {};
  }
  if (id == kNoTarget) {
    return {};
  }
  const std::optional<QuantizedPosition> q = quantize_direction_preserving(position - root);
  return q ? TargetOnWire{id, *q} : TargetOnWire{};
}

}  // namespace

TrackingEncoding encode_tracking(const TrackingMessage& message, const Vec3& root,
                                 std::span<std::byte> out) {
  if (out.size() < kTrackingBytes) {
    return {};
  }
  const TrackingFrame& f = message.frame;
  // A part's validity is only known after quantising it, and the flags byte comes first: write
  // the parts after a placeholder and patch the flags in at the end.
  WireWriter w(out.first(kTrackingBytes));
  w.u8(static_cast<std::uint8_t>(MessageType::kTracking));
  w.u32(message.sequence);
  w.u32(to_wire_time(f.time));
  w.u8(0);  // flags, patched below
  PartEncoder parts{w, root, static_cast<std::uint8_t>(f.valid & tracked::kAll)};
  // A hand with a fingertip that cannot be sent is dropped as a whole, so check those first.
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    if ((parts.valid & tracked::hand(h)) && !quantize_position(f.index_tip[index(h)] - root)) {
      parts.drop(tracked::hand(h));
    }
  }
  parts.pose(tracked::kHead, f.T_world_head);
  parts.gaze(f.gaze);
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    parts.pose(tracked::hand(h), f.T_world_wrist[index(h)]);
  }
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    parts.point(tracked::hand(h), f.index_tip[index(h)]);
  }
  const TargetOnWire head = target_on_wire(f.head_target, f.head_target_position, root);
  const TargetOnWire hand = target_on_wire(f.hand_target, f.hand_target_position, root);
  w.i32(head.id);
  w.i32(hand.id);
  write_position(w, head.position);
  write_position(w, hand.position);
  out[9] = static_cast<std::byte>(parts.valid);
  return {w.failed() ? 0 : w.size(), parts.dropped};
}

namespace {

bool read_position(WireReader& r, QuantizedPosition& q) {
  return r.i16(q[0]) && r.i16(q[1]) && r.i16(q[2]);
}

bool symmetric(const QuantizedPosition& q) {
  return q[0] != kUnusedInt16 && q[1] != kUnusedInt16 && q[2] != kUnusedInt16;
}

WireResult read_pose(WireReader& r, bool valid, const Vec3& root, Pose& T, const char* field) {
  QuantizedPosition p{};
  std::uint64_t packed = 0;
  if (!read_position(r, p) || !r.u48(packed)) {
    return wire_error(DropReason::kTruncated, field);
  }
  if (!valid) {
    T = Pose{};
    return wire_ok();
  }
  const std::optional<Mat3> rotation = dequantize_rotation(packed);
  if (!rotation || !symmetric(p)) {
    return wire_error(DropReason::kOutOfRange, field);
  }
  T = Pose{*rotation, root + dequantize_position(p)};
  return wire_ok();
}

WireResult read_target(WireReader& r, TargetId& id, const char* field) {
  std::int32_t v = 0;
  if (!r.i32(v)) {
    return wire_error(DropReason::kTruncated, field);
  }
  if (!is_target_on_wire(v)) {
    return wire_error(DropReason::kOutOfRange, field);
  }
  id = v;
  return wire_ok();
}

}  // namespace

WireResult decode_tracking(std::span<const std::byte> packet, const Vec3& root,
                           TrackingMessage& out) {
  if (packet.empty()) {
    return wire_error(DropReason::kEmpty, "tracking");
  }
  if (packet[0] != static_cast<std::byte>(MessageType::kTracking)) {
    return wire_error(DropReason::kUnknownType, "tracking.type");
  }
  if (packet.size() < kTrackingBytes) {
    return wire_error(DropReason::kTruncated, "tracking");
  }
  if (packet.size() > kTrackingBytes) {
    return wire_error(DropReason::kTrailingBytes, "tracking");
  }
  WireReader r(packet.subspan(1));
  TrackingMessage m;
  std::uint32_t time_ms = 0;
  std::uint8_t valid = 0;
  r.u32(m.sequence);
  r.u32(time_ms);
  r.u8(valid);
  if ((valid & ~tracked::kAll) != 0) {
    return wire_error(DropReason::kOutOfRange, "tracking.valid");
  }
  TrackingFrame& f = m.frame;
  f.time = static_cast<double>(time_ms) / 1000.0;
  f.valid = valid;
  if (WireResult e = read_pose(r, valid & tracked::kHead, root, f.T_world_head, "tracking.head");
      !e.ok()) {
    return e;
  }
  std::array<std::int16_t, 2> gaze{};
  r.i16(gaze[0]);
  r.i16(gaze[1]);
  if ((valid & tracked::kGaze) && (gaze[0] == kUnusedInt16 || gaze[1] == kUnusedInt16)) {
    return wire_error(DropReason::kOutOfRange, "tracking.gaze");
  }
  f.gaze = (valid & tracked::kGaze) ? dequantize_unit_vector(gaze) : Vec3(0, 0, -1);
  constexpr const char* kWristField[2] = {"tracking.left_wrist", "tracking.right_wrist"};
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    if (WireResult e = read_pose(r, valid & tracked::hand(h), root, f.T_world_wrist[index(h)],
                                 kWristField[index(h)]);
        !e.ok()) {
      return e;
    }
  }
  constexpr const char* kTipField[2] = {"tracking.left_index_tip", "tracking.right_index_tip"};
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    QuantizedPosition q{};
    read_position(r, q);
    if ((valid & tracked::hand(h)) && !symmetric(q)) {
      return wire_error(DropReason::kOutOfRange, kTipField[index(h)]);
    }
    f.index_tip[index(h)] =
        (valid & tracked::hand(h)) ? Vec3(root + dequantize_position(q)) : Vec3(Vec3::Zero());
  }
  if (WireResult e = read_target(r, f.head_target, "tracking.head_target"); !e.ok()) {
    return e;
  }
  if (WireResult e = read_target(r, f.hand_target, "tracking.hand_target"); !e.ok()) {
    return e;
  }
  QuantizedPosition head_target{};
  QuantizedPosition hand_target{};
  read_position(r, head_target);
  read_position(r, hand_target);
  if (r.failed() || r.remaining() != 0) {  // cannot happen with the size checked above
    return wire_error(DropReason::kTruncated, "tracking");
  }
  if ((f.head_target != kNoTarget && !symmetric(head_target)) ||
      (f.hand_target != kNoTarget && !symmetric(hand_target))) {
    return wire_error(DropReason::kOutOfRange, "tracking.target_position");
  }
  f.head_target_position = f.head_target == kNoTarget
                               ? Vec3(Vec3::Zero())
                               : Vec3(root + dequantize_position(head_target));
  f.hand_target_position = f.hand_target == kNoTarget
                               ? Vec3(Vec3::Zero())
                               : Vec3(root + dequantize_position(hand_target));
  out = m;
  return wire_ok();
}

}  // namespace deixis::net
