#pragma once
// The relay's messages (docs/relay.md, "Wire"): types 0x30–0x3F, so that a direct-session peer
// and a relay tell each other apart (docs/protocol.md §3 holds the direct types, all below 0x30).
// Welcome, enter and refused start with the relay magic "DXRL" and the relay protocol version,
// so that a peer of another kind or version fails on its first message with a clear reason.
//
// Every decoder is strict (docs/protocol.md §7): bounds on every length, no trailing bytes, ids
// in range; a packet that breaks a rule is dropped whole and named by a DropReason and its field.
// Decoded messages point into the packet (spans, valid as long as it is): decoding allocates
// nothing, and neither does encoding into a caller's buffer.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "net/protocol.h"
#include "net/relay_client.h"

namespace deixis::net {

inline constexpr std::uint16_t kRelayVersion = 1;
inline constexpr std::array<std::byte, 4> kRelayMagic = {std::byte{'D'}, std::byte{'X'},
                                                         std::byte{'R'}, std::byte{'L'}};
// --max-people at most: a full entered message (every member's announce) stays well below
// kMaxPacketBytes.
inline constexpr std::size_t kMaxRoomPeople = 64;

enum class RelayType : std::uint8_t {
  kWelcome = 0x30,  // relay → client, reliable: magic, version, max people
  kEnter = 0x31,    // client → relay, reliable: magic, version, room token, params, announce
  kEntered = 0x32,  // relay → client, reliable: self id, the room's params, members + announces
  kJoined = 0x33,   // relay → client, reliable: a member and its announce
  kLeft = 0x34,     // relay → client, reliable: a member's id
  kRefused = 0x35,  // relay → client, reliable: magic, version, reason (then the relay hangs up)
  kForward = 0x36,  // client → relay, either channel: to, payload
  kForwarded = 0x37,  // relay → client, the sender's channel: from, payload
  kKeepalive = 0x38,  // either way, reliable: "still here"
};
inline constexpr std::uint8_t kRelayTypeFirst = 0x30;
inline constexpr std::uint8_t kRelayTypeLast = 0x3F;
std::string_view relay_message_name(std::uint8_t type);  // "relay welcome", …, "unknown"
bool is_relay_type(std::uint8_t type);                   // one of the above

// Sizes.
inline constexpr std::size_t kRelayHeaderBytes = 1 + 4 + 2;  // type, magic, version
inline constexpr std::size_t kRelayWelcomeBytes = kRelayHeaderBytes + 1;
inline constexpr std::size_t kRelayRefusedBytes = kRelayHeaderBytes + 1;
inline constexpr std::size_t kRelayLeftBytes = 2;
inline constexpr std::size_t kRelayKeepaliveBytes = 1;
inline constexpr std::size_t kRelayForwardHeaderBytes = 2;  // type, to/from
inline constexpr std::size_t kRelayEnterMaxBytes =
    kRelayHeaderBytes + 32 + 1 + kRoomParamsMax + 1 + kAnnounceMax;
inline constexpr std::size_t kRelayJoinedMaxBytes = 1 + 1 + 1 + kAnnounceMax;
inline constexpr std::size_t kRelayEnteredMaxBytes =
    1 + 1 + 1 + kRoomParamsMax + 1 + (kMaxRoomPeople - 1) * (1 + 1 + kAnnounceMax);
static_assert(kRelayEnteredMaxBytes < kMaxPacketBytes);
static_assert(kRelayForwardHeaderBytes + kRelayPayloadMax <= kMaxPacketBytes);

struct RelayWelcome {
  std::uint16_t version = kRelayVersion;
  std::uint8_t max_people = 8;  // 2 … kMaxRoomPeople
};
struct RelayEnter {
  std::uint16_t version = kRelayVersion;
  RoomToken room{};
  std::span<const std::uint8_t> params;    // ≤ kRoomParamsMax
  std::span<const std::uint8_t> announce;  // ≤ kAnnounceMax
};
struct RelayEntered {
  MemberId self = kNoMember;
  std::span<const std::uint8_t> params;
  std::uint8_t count = 0;  // members already there, < kMaxRoomPeople, ids distinct, ≠ self
  std::array<RoomMember, kMaxRoomPeople - 1> members{};
};
struct RelayJoined {
  RoomMember member;
};
struct RelayLeft {
  MemberId id = kNoMember;
};
struct RelayRefused {
  std::uint16_t version = kRelayVersion;
  RelayRefusal reason = RelayRefusal::kProtocol;
};
struct RelayForward {                  // client → relay
  MemberId to = kAllMembers;           // 1–254, or kAllMembers
  std::span<const std::byte> payload;  // 1 … kRelayPayloadMax bytes
};
struct RelayForwarded {       // relay → client
  MemberId from = kNoMember;  // 1–254
  std::span<const std::byte> payload;
};

// Encoders: the bytes written, 0 when `out` is too small or a field breaks a rule.
std::size_t encode(const RelayWelcome& m, std::span<std::byte> out);
std::size_t encode(const RelayEnter& m, std::span<std::byte> out);
std::size_t encode(const RelayEntered& m, std::span<std::byte> out);
std::size_t encode(const RelayJoined& m, std::span<std::byte> out);
std::size_t encode(const RelayLeft& m, std::span<std::byte> out);
std::size_t encode(const RelayRefused& m, std::span<std::byte> out);
std::size_t encode_keepalive(std::span<std::byte> out);
// A forward's or forwarded's two-byte header; the payload follows it.
std::size_t encode_forward(MemberId to, std::span<const std::byte> payload,
                           std::span<std::byte> out);
std::size_t encode_forwarded(MemberId from, std::span<const std::byte> payload,
                             std::span<std::byte> out);

// Decoders: wire_ok() or what was wrong. The header check (magic, then version) comes first, so
// that a relay of another version is told apart from garbage (kWrongVersion vs kBadMagic).
WireResult decode(std::span<const std::byte> packet, RelayWelcome& out);
WireResult decode(std::span<const std::byte> packet, RelayEnter& out);
WireResult decode(std::span<const std::byte> packet, RelayEntered& out);
WireResult decode(std::span<const std::byte> packet, RelayJoined& out);
WireResult decode(std::span<const std::byte> packet, RelayLeft& out);
WireResult decode(std::span<const std::byte> packet, RelayRefused& out);
WireResult decode(std::span<const std::byte> packet, RelayForward& out);
WireResult decode(std::span<const std::byte> packet, RelayForwarded& out);
WireResult decode_keepalive(std::span<const std::byte> packet);

// The channel a message travels on; forwards travel on either (true for both).
bool relay_channel_allowed(std::uint8_t type, Channel channel);

inline std::span<const std::uint8_t> as_u8(std::span<const std::byte> b) {
  return {reinterpret_cast<const std::uint8_t*>(b.data()), b.size()};
}
inline std::span<const std::byte> as_wire(std::span<const std::uint8_t> b) {
  return std::as_bytes(b);
}

}  // namespace deixis::net
