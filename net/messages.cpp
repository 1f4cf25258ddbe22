#include "net/messages.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "net/wire.h"

namespace deixis::net {

namespace {

constexpr float kMaxWorldCoordinate = 1e6f;  // m; the target-map file's limit too
constexpr float kMinHeight = 0.5f, kMaxHeight = 2.5f;
constexpr float kMinArm = 0.2f, kMaxArm = 1.5f;
constexpr float kMaxRestWrist = 2.0f;  // m from the root, per axis
constexpr float kUnitTolerance = 1e-3f;

std::byte type_byte(MessageType t) {
  return static_cast<std::byte>(t);
}

// ---- shared rules ----

WireResult check_float(float v, float lo, float hi, const char* field) {
  if (!std::isfinite(v)) {
    return wire_error(DropReason::kNonFinite, field);
  }
  if (v < lo || v > hi) {
    return wire_error(DropReason::kOutOfRange, field);
  }
  return wire_ok();
}

WireResult check_vec3(const Vec3& v, float lo, float hi, const char* field) {
  for (int k = 0; k < 3; ++k) {
    if (WireResult e = check_float(v[k], lo, hi, field); !e.ok()) {
      return e;
    }
  }
  return wire_ok();
}

WireResult check_text(std::string_view s, std::size_t min_bytes, const char* field) {
  if (s.size() < min_bytes || s.size() > kMaxTextBytes) {
    return wire_error(DropReason::kOutOfRange, field);
  }
  if (!is_wire_text(s)) {
    return wire_error(DropReason::kBadText, field);
  }
  return wire_ok();
}

WireResult check_rotation(const Mat3& R, const char* field) {
  if (!R.allFinite()) {
    return wire_error(DropReason::kNonFinite, field);
  }
  const float off = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (off > kUnitTolerance || R.determinant() <= 0.0f) {
    return wire_error(DropReason::kOutOfRange, field);
  }
  return wire_ok();
}

// ---- reading helpers: each names its field ----

struct Fields {
  WireReader& r;

  WireResult u8(std::uint8_t& v, const char* field) {
    return r.u8(v) ? wire_ok() : wire_error(DropReason::kTruncated, field);
  }
  WireResult f32(float& v, const char* field) {
    return r.f32(v) ? wire_ok() : wire_error(DropReason::kTruncated, field);
  }
  WireResult vec3(Vec3& v, const char* field) {
    float x = 0, y = 0, z = 0;
    if (!r.f32(x) || !r.f32(y) || !r.f32(z)) {
      return wire_error(DropReason::kTruncated, field);
    }
    v = Vec3(x, y, z);
    return wire_ok();
  }
  // A u8 length, then that many bytes of text. The length is checked against the packet before
  // anything is read or allocated.
  WireResult text(std::string& s, const char* field) {
    std::uint8_t length = 0;
    if (!r.u8(length)) {
      return wire_error(DropReason::kTruncated, field);
    }
    if (length > r.remaining()) {
      return wire_error(DropReason::kLengthBeyondPacket, field);
    }
    const std::span<const std::byte> bytes = r.take(length);
    s.assign(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    return wire_ok();
  }
  template <std::size_t N>
  WireResult raw(std::array<std::byte, N>& a, const char* field) {
    return r.bytes(a) ? wire_ok() : wire_error(DropReason::kTruncated, field);
  }
};

WireResult check_header(std::span<const std::byte> packet, MessageType type, const char* field) {
  if (packet.empty()) {
    return wire_error(DropReason::kEmpty, field);
  }
  if (packet[0] != type_byte(type)) {
    return wire_error(DropReason::kUnknownType, field);
  }
  return wire_ok();
}

WireResult check_end(const WireReader& r, const char* field) {
  return r.remaining() == 0 ? wire_ok() : wire_error(DropReason::kTrailingBytes, field);
}

WireResult read_magic_and_version(WireReader& r, std::uint16_t& version, const char* magic_field,
                                  const char* version_field) {
  std::array<std::byte, 4> magic{};
  if (!r.bytes(magic)) {
    return wire_error(DropReason::kTruncated, magic_field);
  }
  if (magic != kMagic) {
    return wire_error(DropReason::kBadMagic, magic_field);
  }
  if (!r.u16(version)) {
    return wire_error(DropReason::kTruncated, version_field);
  }
  if (version != kProtocolVersion) {
    return wire_error(DropReason::kWrongVersion, version_field);
  }
  return wire_ok();
}

WireResult read_auth(WireReader& r, AuthMode& auth, const char* field) {
  std::uint8_t v = 0;
  if (!r.u8(v)) {
    return wire_error(DropReason::kTruncated, field);
  }
  if (v > static_cast<std::uint8_t>(AuthMode::kPassphrase)) {
    return wire_error(DropReason::kOutOfRange, field);
  }
  auth = static_cast<AuthMode>(v);
  return wire_ok();
}

void start(std::vector<std::byte>& out, MessageType type, std::size_t size) {
  out.assign(size, std::byte{0});
  out[0] = type_byte(type);
}

// Runs the steps in order and returns the first error.
template <typename... Steps>
WireResult first_error(Steps&&... steps) {
  WireResult result = wire_ok();
  ((result.ok() ? (result = steps(), 0) : 0), ...);
  return result;
}

}  // namespace

// ---------------------------------------------------------------- welcome, join, accept

void encode(const Welcome& m, std::vector<std::byte>& out) {
  start(out, MessageType::kWelcome, kWelcomeBytes);
  WireWriter w{std::span<std::byte>(out).subspan(1)};
  w.bytes(kMagic);
  w.u16(m.protocol_version);
  w.u8(static_cast<std::uint8_t>(m.auth));
  w.bytes(m.salt);
  w.u32(m.kdf.opslimit);
  w.u32(m.kdf.memlimit_kib);
  w.bytes(m.host_challenge);
  w.bytes(m.host_key);
}

WireResult decode(std::span<const std::byte> packet, Welcome& out) {
  if (WireResult e = check_header(packet, MessageType::kWelcome, "welcome.type"); !e.ok()) {
    return e;
  }
  WireReader r(packet.subspan(1));
  Welcome m;
  if (WireResult e = read_magic_and_version(r, m.protocol_version, "welcome.magic",
                                            "welcome.protocol_version");
      !e.ok()) {
    return e;
  }
  if (WireResult e = read_auth(r, m.auth, "welcome.auth"); !e.ok()) {
    return e;
  }
  if (!r.bytes(m.salt) || !r.u32(m.kdf.opslimit) || !r.u32(m.kdf.memlimit_kib) ||
      !r.bytes(m.host_challenge) || !r.bytes(m.host_key)) {
    return wire_error(DropReason::kTruncated, "welcome");
  }
  if (m.auth == AuthMode::kPassphrase &&
      (m.kdf.opslimit < kMinKdfOps || m.kdf.opslimit > kMaxKdfOps ||
       m.kdf.memlimit_kib < kMinKdfMemKib || m.kdf.memlimit_kib > kMaxKdfMemKib)) {
    return wire_error(DropReason::kOutOfRange, "welcome.kdf");
  }
  if (WireResult e = check_end(r, "welcome"); !e.ok()) {
    return e;
  }
  out = m;
  return wire_ok();
}

void encode(const Join& m, std::vector<std::byte>& out) {
  start(out, MessageType::kJoin, kJoinBytes);
  WireWriter w{std::span<std::byte>(out).subspan(1)};
  w.bytes(kMagic);
  w.u16(m.protocol_version);
  w.u8(static_cast<std::uint8_t>(m.auth));
  w.bytes(m.joiner_challenge);
  w.bytes(m.joiner_key);
  w.bytes(m.proof);
}

WireResult decode(std::span<const std::byte> packet, Join& out) {
  if (WireResult e = check_header(packet, MessageType::kJoin, "join.type"); !e.ok()) {
    return e;
  }
  WireReader r(packet.subspan(1));
  Join m;
  if (WireResult e =
          read_magic_and_version(r, m.protocol_version, "join.magic", "join.protocol_version");
      !e.ok()) {
    return e;
  }
  if (WireResult e = read_auth(r, m.auth, "join.auth"); !e.ok()) {
    return e;
  }
  if (!r.bytes(m.joiner_challenge) || !r.bytes(m.joiner_key) || !r.bytes(m.proof)) {
    return wire_error(DropReason::kTruncated, "join");
  }
  if (WireResult e = check_end(r, "join"); !e.ok()) {
    return e;
  }
  out = m;
  return wire_ok();
}

void encode(const Accept& m, std::vector<std::byte>& out) {
  start(out, MessageType::kAccept, kAcceptBytes);
  WireWriter w{std::span<std::byte>(out).subspan(1)};
  w.bytes(m.proof);
}

WireResult decode(std::span<const std::byte> packet, Accept& out) {
  if (WireResult e = check_header(packet, MessageType::kAccept, "accept.type"); !e.ok()) {
    return e;
  }
  WireReader r(packet.subspan(1));
  Accept m;
  if (!r.bytes(m.proof)) {
    return wire_error(DropReason::kTruncated, "accept.proof");
  }
  if (WireResult e = check_end(r, "accept"); !e.ok()) {
    return e;
  }
  out = m;
  return wire_ok();
}

// ---------------------------------------------------------------- hello

WireResult validate(const Hello& m) {
  const BodyCalibration& b = m.avatar.body;
  if (m.protocol_version != kProtocolVersion) {
    return wire_error(DropReason::kWrongVersion, "hello.protocol_version");
  }
  return first_error(
      [&] { return check_text(m.site, 1, "hello.site"); },
      [&] { return check_text(m.avatar.model, 0, "hello.avatar_model"); },
      [&] { return check_float(b.height, kMinHeight, kMaxHeight, "hello.height"); },
      [&] { return check_float(b.arm_length, kMinArm, kMaxArm, "hello.arm_length"); },
      [&] {
        return b.deictic_hand == Hand::kLeft || b.deictic_hand == Hand::kRight
                   ? wire_ok()
                   : wire_error(DropReason::kOutOfRange, "hello.deictic_hand");
      },
      [&] {
        return check_vec3(b.T_world_root.translation, -kMaxWorldCoordinate, kMaxWorldCoordinate,
                          "hello.root_position");
      },
      [&] { return check_rotation(b.T_world_root.rotation, "hello.root_rotation"); },
      [&] {
        return check_vec3(b.rest_wrist_in_root[0], -kMaxRestWrist, kMaxRestWrist,
                          "hello.rest_wrist_left");
      },
      [&] {
        return check_vec3(b.rest_wrist_in_root[1], -kMaxRestWrist, kMaxRestWrist,
                          "hello.rest_wrist_right");
      });
}

WireResult encode(const Hello& m, std::vector<std::byte>& out) {
  out.clear();
  if (WireResult e = validate(m); !e.ok()) {
    return e;
  }
  const BodyCalibration& b = m.avatar.body;
  out.assign(1 + 2 + 1 + m.site.size() + 1 + m.avatar.model.size() + 4 + 4 + 1 + 12 + 16 + 24,
             std::byte{0});
  WireWriter w(out);
  w.u8(static_cast<std::uint8_t>(MessageType::kHello));
  w.u16(m.protocol_version);
  w.u8(static_cast<std::uint8_t>(m.site.size()));
  w.text(m.site);
  w.u8(static_cast<std::uint8_t>(m.avatar.model.size()));
  w.text(m.avatar.model);
  w.f32(b.height);
  w.f32(b.arm_length);
  w.u8(static_cast<std::uint8_t>(b.deictic_hand));
  for (int k = 0; k < 3; ++k) {
    w.f32(b.T_world_root.translation[k]);
  }
  const Quat q = Quat(b.T_world_root.rotation).normalized();
  for (const float c : {q.x(), q.y(), q.z(), q.w()}) {
    w.f32(c);
  }
  for (const Vec3& v : b.rest_wrist_in_root) {
    for (int k = 0; k < 3; ++k) {
      w.f32(v[k]);
    }
  }
  return wire_ok();
}

WireResult decode(std::span<const std::byte> packet, Hello& out) {
  if (WireResult e = check_header(packet, MessageType::kHello, "hello.type"); !e.ok()) {
    return e;
  }
  WireReader r(packet.subspan(1));
  Fields f{r};
  Hello m;
  BodyCalibration& b = m.avatar.body;
  if (!r.u16(m.protocol_version)) {
    return wire_error(DropReason::kTruncated, "hello.protocol_version");
  }
  if (m.protocol_version != kProtocolVersion) {
    return wire_error(DropReason::kWrongVersion, "hello.protocol_version");
  }
  std::uint8_t hand = 0;
  std::array<float, 4> q{};
  if (WireResult e =
          first_error([&] { return f.text(m.site, "hello.site"); },
                      [&] { return f.text(m.avatar.model, "hello.avatar_model"); },
                      [&] { return f.f32(b.height, "hello.height"); },
                      [&] { return f.f32(b.arm_length, "hello.arm_length"); },
                      [&] { return f.u8(hand, "hello.deictic_hand"); },
                      [&] { return f.vec3(b.T_world_root.translation, "hello.root_position"); },
                      [&] {
                        return r.f32(q[0]) && r.f32(q[1]) && r.f32(q[2]) && r.f32(q[3])
                                   ? wire_ok()
                                   : wire_error(DropReason::kTruncated, "hello.root_rotation");
                      },
                      [&] { return f.vec3(b.rest_wrist_in_root[0], "hello.rest_wrist_left"); },
                      [&] { return f.vec3(b.rest_wrist_in_root[1], "hello.rest_wrist_right"); },
                      [&] { return check_end(r, "hello"); });
      !e.ok()) {
    return e;
  }
  if (hand > static_cast<std::uint8_t>(Hand::kRight)) {
    return wire_error(DropReason::kOutOfRange, "hello.deictic_hand");
  }
  b.deictic_hand = static_cast<Hand>(hand);
  for (const float c : q) {
    if (!std::isfinite(c)) {
      return wire_error(DropReason::kNonFinite, "hello.root_rotation");
    }
  }
  const Quat quat(q[3], q[0], q[1], q[2]);
  if (std::abs(quat.norm() - 1.0f) > kUnitTolerance) {
    return wire_error(DropReason::kOutOfRange, "hello.root_rotation");
  }
  b.T_world_root.rotation = quat.normalized().toRotationMatrix();
  if (WireResult e = validate(m); !e.ok()) {
    return e;
  }
  out = std::move(m);
  return wire_ok();
}

// ---------------------------------------------------------------- target map

WireResult validate(const TargetMap& m) {
  if (WireResult e = check_text(m.site, 0, "target_map.site"); !e.ok()) {
    return e;
  }
  if (m.objects.size() > kMaxTargetObjects) {
    return wire_error(DropReason::kOutOfRange, "target_map.object_count");
  }
  std::vector<TargetId> ids;
  ids.reserve(m.objects.size());
  for (const TargetObject& o : m.objects) {
    if (o.id < 1 || o.id > kMaxTargetIdOnWire) {
      return wire_error(DropReason::kOutOfRange, "target_map.object.id");
    }
    if (o.kind != TargetKind::kSphere && o.kind != TargetKind::kBox &&
        o.kind != TargetKind::kScreen) {
      return wire_error(DropReason::kOutOfRange, "target_map.object.kind");
    }
    if (WireResult e =
            first_error([&] { return check_text(o.name, 1, "target_map.object.name"); },
                        [&] {
                          return check_vec3(o.position, -kMaxWorldCoordinate, kMaxWorldCoordinate,
                                            "target_map.object.position");
                        },
                        [&] { return check_vec3(o.size, 0.0f, 100.0f, "target_map.object.size"); });
        !e.ok()) {
      return e;
    }
    if (!(o.size.minCoeff() > 0.0f)) {
      return wire_error(DropReason::kOutOfRange, "target_map.object.size");
    }
    ids.push_back(o.id);
  }
  std::sort(ids.begin(), ids.end());
  if (std::adjacent_find(ids.begin(), ids.end()) != ids.end()) {
    return wire_error(DropReason::kDuplicateId, "target_map.object.id");
  }
  return wire_ok();
}

WireResult encode(const TargetMap& m, std::vector<std::byte>& out) {
  out.clear();
  if (WireResult e = validate(m); !e.ok()) {
    return e;
  }
  std::size_t size = 1 + 1 + m.site.size() + 2;
  for (const TargetObject& o : m.objects) {
    size += 4 + 1 + 1 + o.name.size() + 24;
  }
  out.assign(size, std::byte{0});
  WireWriter w(out);
  w.u8(static_cast<std::uint8_t>(MessageType::kTargetMap));
  w.u8(static_cast<std::uint8_t>(m.site.size()));
  w.text(m.site);
  w.u16(static_cast<std::uint16_t>(m.objects.size()));
  for (const TargetObject& o : m.objects) {
    w.i32(o.id);
    w.u8(static_cast<std::uint8_t>(o.kind));
    w.u8(static_cast<std::uint8_t>(o.name.size()));
    w.text(o.name);
    for (const Vec3* v : {&o.position, &o.size}) {
      for (int k = 0; k < 3; ++k) {
        w.f32((*v)[k]);
      }
    }
  }
  return wire_ok();
}

WireResult decode(std::span<const std::byte> packet, TargetMap& out) {
  if (WireResult e = check_header(packet, MessageType::kTargetMap, "target_map.type"); !e.ok()) {
    return e;
  }
  WireReader r(packet.subspan(1));
  Fields f{r};
  TargetMap m;
  if (WireResult e = f.text(m.site, "target_map.site"); !e.ok()) {
    return e;
  }
  std::uint16_t count = 0;
  if (!r.u16(count)) {
    return wire_error(DropReason::kTruncated, "target_map.object_count");
  }
  if (count > kMaxTargetObjects) {
    return wire_error(DropReason::kOutOfRange, "target_map.object_count");
  }
  // Every object takes at least 31 bytes: a count the packet cannot hold is refused before
  // anything is reserved for it.
  constexpr std::size_t kMinObjectBytes = 4 + 1 + 1 + 1 + 24;
  if (static_cast<std::size_t>(count) * kMinObjectBytes > r.remaining()) {
    return wire_error(DropReason::kLengthBeyondPacket, "target_map.object_count");
  }
  m.objects.resize(count);
  for (TargetObject& o : m.objects) {
    std::uint8_t kind = 0;
    if (!r.i32(o.id)) {
      return wire_error(DropReason::kTruncated, "target_map.object.id");
    }
    if (WireResult e = first_error([&] { return f.u8(kind, "target_map.object.kind"); },
                                   [&] { return f.text(o.name, "target_map.object.name"); },
                                   [&] { return f.vec3(o.position, "target_map.object.position"); },
                                   [&] { return f.vec3(o.size, "target_map.object.size"); });
        !e.ok()) {
      return e;
    }
    if (kind > static_cast<std::uint8_t>(TargetKind::kScreen)) {
      return wire_error(DropReason::kOutOfRange, "target_map.object.kind");
    }
    o.kind = static_cast<TargetKind>(kind);
  }
  if (WireResult e = check_end(r, "target_map"); !e.ok()) {
    return e;
  }
  if (WireResult e = validate(m); !e.ok()) {
    return e;
  }
  out = std::move(m);
  return wire_ok();
}

// ---------------------------------------------------------------- heartbeat, bye

std::size_t encode(const Heartbeat& m, std::span<std::byte> out) {
  WireWriter w(out);
  w.u8(static_cast<std::uint8_t>(MessageType::kHeartbeat));
  w.u32(m.count);
  return w.failed() ? 0 : w.size();
}

WireResult decode(std::span<const std::byte> packet, Heartbeat& out) {
  if (WireResult e = check_header(packet, MessageType::kHeartbeat, "heartbeat.type"); !e.ok()) {
    return e;
  }
  WireReader r(packet.subspan(1));
  Heartbeat m;
  if (!r.u32(m.count)) {
    return wire_error(DropReason::kTruncated, "heartbeat.count");
  }
  if (WireResult e = check_end(r, "heartbeat"); !e.ok()) {
    return e;
  }
  out = m;
  return wire_ok();
}

std::size_t encode(const Bye& m, std::span<std::byte> out) {
  WireWriter w(out);
  w.u8(static_cast<std::uint8_t>(MessageType::kBye));
  w.u8(static_cast<std::uint8_t>(m.reason));
  return w.failed() ? 0 : w.size();
}

WireResult decode(std::span<const std::byte> packet, Bye& out) {
  if (WireResult e = check_header(packet, MessageType::kBye, "bye.type"); !e.ok()) {
    return e;
  }
  WireReader r(packet.subspan(1));
  std::uint8_t reason = 0;
  if (!r.u8(reason)) {
    return wire_error(DropReason::kTruncated, "bye.reason");
  }
  if (reason > kMaxByeReason) {
    return wire_error(DropReason::kOutOfRange, "bye.reason");
  }
  if (WireResult e = check_end(r, "bye"); !e.ok()) {
    return e;
  }
  out.reason = static_cast<ByeReason>(reason);
  return wire_ok();
}

std::string wire_message(std::string_view what, WireResult why) {
  return std::string(what) + ": " + why.field + ": " + std::string(drop_reason_name(why.reason));
}

std::vector<std::byte> encode_replacement_hello(const Hello& current, Hello& next,
                                                std::string_view avatar_model,
                                                std::string_view who) {
  if (next.site != current.site) {
    throw Error(std::string(who) + ": our hello cannot change the site's name ('" + current.site +
                "' to '" + next.site + "')");
  }
  if (!avatar_model.empty()) {
    next.avatar.model = std::string(avatar_model);
  }
  std::vector<std::byte> bytes;
  if (WireResult e = encode(next, bytes); !e.ok()) {
    throw Error(wire_message(std::string(who) + ": our hello", e));
  }
  return bytes;
}

}  // namespace deixis::net
