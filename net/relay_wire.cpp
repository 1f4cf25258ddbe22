#include "net/relay_wire.h"

#include "net/wire.h"

namespace deixis::net {

namespace {

bool write_header(WireWriter& w, RelayType type, std::uint16_t version) {
  return w.u8(static_cast<std::uint8_t>(type)) && w.bytes(kRelayMagic) && w.u16(version);
}

// Type, magic and version; kWrongVersion only after the magic matched.
WireResult read_header(WireReader& r, RelayType type, std::uint16_t& version) {
  std::uint8_t t = 0;
  if (!r.u8(t)) {
    return wire_error(DropReason::kEmpty, "type");
  }
  if (t != static_cast<std::uint8_t>(type)) {
    return wire_error(DropReason::kUnknownType, "type");
  }
  std::array<std::byte, 4> magic{};
  if (!r.bytes(magic)) {
    return wire_error(DropReason::kTruncated, "relay.magic");
  }
  if (magic != kRelayMagic) {
    return wire_error(DropReason::kBadMagic, "relay.magic");
  }
  if (!r.u16(version)) {
    return wire_error(DropReason::kTruncated, "relay.version");
  }
  if (version != kRelayVersion) {
    return wire_error(DropReason::kWrongVersion, "relay.version");
  }
  return wire_ok();
}

WireResult read_type(WireReader& r, RelayType type) {
  std::uint8_t t = 0;
  if (!r.u8(t)) {
    return wire_error(DropReason::kEmpty, "type");
  }
  return t == static_cast<std::uint8_t>(type) ? wire_ok()
                                              : wire_error(DropReason::kUnknownType, "type");
}

// A u8 length, then that many bytes (at most `max`).
WireResult read_blob(WireReader& r, std::size_t max, std::span<const std::uint8_t>& out,
                     const char* length_field, const char* field) {
  std::uint8_t n = 0;
  if (!r.u8(n)) {
    return wire_error(DropReason::kTruncated, length_field);
  }
  if (n > max) {
    return wire_error(DropReason::kOutOfRange, length_field);
  }
  if (n > r.remaining()) {
    return wire_error(DropReason::kLengthBeyondPacket, field);
  }
  out = as_u8(r.take(n));
  return wire_ok();
}

bool write_blob(WireWriter& w, std::span<const std::uint8_t> blob, std::size_t max) {
  if (blob.size() > max) {
    return false;
  }
  return w.u8(static_cast<std::uint8_t>(blob.size())) && w.bytes(as_wire(blob));
}

WireResult finish(const WireReader& r) {
  return r.remaining() == 0 ? wire_ok() : wire_error(DropReason::kTrailingBytes, "end");
}

bool is_member(MemberId id) {
  return id >= kFirstMember && id <= kLastMember;
}

std::size_t written(const WireWriter& w) {
  return w.failed() ? 0 : w.size();
}

WireResult decode_payload_message(std::span<const std::byte> packet, RelayType type, bool to_all_ok,
                                  MemberId& id, std::span<const std::byte>& payload) {
  WireReader r(packet);
  if (WireResult e = read_type(r, type); !e.ok()) {
    return e;
  }
  if (!r.u8(id)) {
    return wire_error(DropReason::kTruncated, "forward.member");
  }
  if (!is_member(id) && !(to_all_ok && id == kAllMembers)) {
    return wire_error(DropReason::kOutOfRange, "forward.member");
  }
  if (r.remaining() == 0) {
    return wire_error(DropReason::kTruncated, "forward.payload");
  }
  if (r.remaining() > kRelayPayloadMax) {
    return wire_error(DropReason::kOutOfRange, "forward.payload");
  }
  payload = r.take(r.remaining());
  return wire_ok();
}

std::size_t encode_payload_message(RelayType type, MemberId id, std::span<const std::byte> payload,
                                   std::span<std::byte> out) {
  if (payload.empty() || payload.size() > kRelayPayloadMax) {
    return 0;
  }
  WireWriter w(out);
  w.u8(static_cast<std::uint8_t>(type));
  w.u8(id);
  w.bytes(payload);
  return written(w);
}

}  // namespace

std::string_view relay_message_name(std::uint8_t type) {
  switch (static_cast<RelayType>(type)) {
    case RelayType::kWelcome:
      return "relay welcome";
    case RelayType::kEnter:
      return "enter";
    case RelayType::kEntered:
      return "entered";
    case RelayType::kJoined:
      return "member joined";
    case RelayType::kLeft:
      return "member left";
    case RelayType::kRefused:
      return "refused";
    case RelayType::kForward:
      return "forward";
    case RelayType::kForwarded:
      return "forwarded";
    case RelayType::kKeepalive:
      return "keepalive";
  }
  return "unknown";
}

bool is_relay_type(std::uint8_t type) {
  return relay_message_name(type) != "unknown";
}

bool relay_channel_allowed(std::uint8_t type, Channel channel) {
  const auto t = static_cast<RelayType>(type);
  if (t == RelayType::kForward || t == RelayType::kForwarded) {
    return true;
  }
  return channel == Channel::kReliable;
}

// ---------------------------------------------------------------- encoders

std::size_t encode(const RelayWelcome& m, std::span<std::byte> out) {
  WireWriter w(out);
  write_header(w, RelayType::kWelcome, m.version);
  w.u8(m.max_people);
  return written(w);
}

std::size_t encode(const RelayEnter& m, std::span<std::byte> out) {
  WireWriter w(out);
  write_header(w, RelayType::kEnter, m.version);
  w.bytes(as_wire(std::span<const std::uint8_t>(m.room)));
  if (!write_blob(w, m.params, kRoomParamsMax) || !write_blob(w, m.announce, kAnnounceMax)) {
    return 0;
  }
  return written(w);
}

std::size_t encode(const RelayEntered& m, std::span<std::byte> out) {
  if (!is_member(m.self) || m.count > m.members.size()) {
    return 0;
  }
  WireWriter w(out);
  w.u8(static_cast<std::uint8_t>(RelayType::kEntered));
  w.u8(m.self);
  if (!write_blob(w, m.params, kRoomParamsMax)) {
    return 0;
  }
  w.u8(m.count);
  for (std::size_t i = 0; i < m.count; ++i) {
    if (!is_member(m.members[i].id)) {
      return 0;
    }
    w.u8(m.members[i].id);
    if (!write_blob(w, m.members[i].announce, kAnnounceMax)) {
      return 0;
    }
  }
  return written(w);
}

std::size_t encode(const RelayJoined& m, std::span<std::byte> out) {
  if (!is_member(m.member.id)) {
    return 0;
  }
  WireWriter w(out);
  w.u8(static_cast<std::uint8_t>(RelayType::kJoined));
  w.u8(m.member.id);
  if (!write_blob(w, m.member.announce, kAnnounceMax)) {
    return 0;
  }
  return written(w);
}

std::size_t encode(const RelayLeft& m, std::span<std::byte> out) {
  if (!is_member(m.id)) {
    return 0;
  }
  WireWriter w(out);
  w.u8(static_cast<std::uint8_t>(RelayType::kLeft));
  w.u8(m.id);
  return written(w);
}

std::size_t encode(const RelayRefused& m, std::span<std::byte> out) {
  WireWriter w(out);
  write_header(w, RelayType::kRefused, m.version);
  w.u8(static_cast<std::uint8_t>(m.reason));
  return written(w);
}

std::size_t encode_keepalive(std::span<std::byte> out) {
  WireWriter w(out);
  w.u8(static_cast<std::uint8_t>(RelayType::kKeepalive));
  return written(w);
}

std::size_t encode_forward(MemberId to, std::span<const std::byte> payload,
                           std::span<std::byte> out) {
  if (!is_member(to) && to != kAllMembers) {
    return 0;
  }
  return encode_payload_message(RelayType::kForward, to, payload, out);
}

std::size_t encode_forwarded(MemberId from, std::span<const std::byte> payload,
                             std::span<std::byte> out) {
  if (!is_member(from)) {
    return 0;
  }
  return encode_payload_message(RelayType::kForwarded, from, payload, out);
}

// ---------------------------------------------------------------- decoders

WireResult decode(std::span<const std::byte> packet, RelayWelcome& out) {
  WireReader r(packet);
  if (WireResult e = read_header(r, RelayType::kWelcome, out.version); !e.ok()) {
    return e;
  }
  if (!r.u8(out.max_people)) {
    return wire_error(DropReason::kTruncated, "welcome.max_people");
  }
  if (out.max_people < 2 || out.max_people > kMaxRoomPeople) {
    return wire_error(DropReason::kOutOfRange, "welcome.max_people");
  }
  return finish(r);
}

WireResult decode(std::span<const std::byte> packet, RelayEnter& out) {
  WireReader r(packet);
  if (WireResult e = read_header(r, RelayType::kEnter, out.version); !e.ok()) {
    return e;
  }
  if (!r.bytes(std::as_writable_bytes(std::span(out.room)))) {
    return wire_error(DropReason::kTruncated, "enter.room");
  }
  if (WireResult e =
          read_blob(r, kRoomParamsMax, out.params, "enter.params_length", "enter.params");
      !e.ok()) {
    return e;
  }
  if (WireResult e =
          read_blob(r, kAnnounceMax, out.announce, "enter.announce_length", "enter.announce");
      !e.ok()) {
    return e;
  }
  return finish(r);
}

WireResult decode(std::span<const std::byte> packet, RelayEntered& out) {
  WireReader r(packet);
  if (WireResult e = read_type(r, RelayType::kEntered); !e.ok()) {
    return e;
  }
  if (!r.u8(out.self)) {
    return wire_error(DropReason::kTruncated, "entered.self");
  }
  if (!is_member(out.self)) {
    return wire_error(DropReason::kOutOfRange, "entered.self");
  }
  if (WireResult e =
          read_blob(r, kRoomParamsMax, out.params, "entered.params_length", "entered.params");
      !e.ok()) {
    return e;
  }
  if (!r.u8(out.count)) {
    return wire_error(DropReason::kTruncated, "entered.count");
  }
  if (out.count > out.members.size()) {
    return wire_error(DropReason::kOutOfRange, "entered.count");
  }
  // Ids seen so far (self included), to refuse duplicates.
  std::array<bool, 256> seen{};
  seen[out.self] = true;
  for (std::size_t i = 0; i < out.count; ++i) {
    RoomMember& m = out.members[i];
    if (!r.u8(m.id)) {
      return wire_error(DropReason::kTruncated, "entered.member");
    }
    if (!is_member(m.id)) {
      return wire_error(DropReason::kOutOfRange, "entered.member");
    }
    if (seen[m.id]) {
      return wire_error(DropReason::kDuplicateId, "entered.member");
    }
    seen[m.id] = true;
    if (WireResult e =
            read_blob(r, kAnnounceMax, m.announce, "entered.announce_length", "entered.announce");
        !e.ok()) {
      return e;
    }
  }
  return finish(r);
}

WireResult decode(std::span<const std::byte> packet, RelayJoined& out) {
  WireReader r(packet);
  if (WireResult e = read_type(r, RelayType::kJoined); !e.ok()) {
    return e;
  }
  if (!r.u8(out.member.id)) {
    return wire_error(DropReason::kTruncated, "joined.member");
  }
  if (!is_member(out.member.id)) {
    return wire_error(DropReason::kOutOfRange, "joined.member");
  }
  if (WireResult e = read_blob(r, kAnnounceMax, out.member.announce, "joined.announce_length",
                               "joined.announce");
      !e.ok()) {
    return e;
  }
  return finish(r);
}

WireResult decode(std::span<const std::byte> packet, RelayLeft& out) {
  WireReader r(packet);
  if (WireResult e = read_type(r, RelayType::kLeft); !e.ok()) {
    return e;
  }
  if (!r.u8(out.id)) {
    return wire_error(DropReason::kTruncated, "left.member");
  }
  if (!is_member(out.id)) {
    return wire_error(DropReason::kOutOfRange, "left.member");
  }
  return finish(r);
}

WireResult decode(std::span<const std::byte> packet, RelayRefused& out) {
  WireReader r(packet);
  if (WireResult e = read_header(r, RelayType::kRefused, out.version);
      !e.ok() && e.reason != DropReason::kWrongVersion) {
    return e;
  }
  // A refusal from a relay of another version is still read: it says why (often kVersion).
  std::uint8_t reason = 0;
  if (!r.u8(reason)) {
    return wire_error(DropReason::kTruncated, "refused.reason");
  }
  if (reason > kMaxRelayRefusal) {
    return wire_error(DropReason::kOutOfRange, "refused.reason");
  }
  out.reason = static_cast<RelayRefusal>(reason);
  return finish(r);
}

WireResult decode(std::span<const std::byte> packet, RelayForward& out) {
  return decode_payload_message(packet, RelayType::kForward, true, out.to, out.payload);
}

WireResult decode(std::span<const std::byte> packet, RelayForwarded& out) {
  return decode_payload_message(packet, RelayType::kForwarded, false, out.from, out.payload);
}

WireResult decode_keepalive(std::span<const std::byte> packet) {
  WireReader r(packet);
  if (WireResult e = read_type(r, RelayType::kKeepalive); !e.ok()) {
    return e;
  }
  return finish(r);
}

}  // namespace deixis::net
