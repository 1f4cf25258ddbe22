#pragma once
// The constants of the Deixis wire protocol (docs/protocol.md): version, channels, message types,
// size limits, bye reasons, and why a packet was dropped. Everything a decoder rejects is named by
// a DropReason and the field it was reading, so a log line says exactly what was wrong.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace deixis::net {

// 2: ephemeral X25519 in the handshake, site names bound by the proofs, padded reliable packets,
// the joiner's floor on the key cost. 3: avatar request and data messages, person targets in
// tracking frames (docs/protocol.md, "Versioning").
inline constexpr std::uint16_t kProtocolVersion = 3;
// The first bytes of welcome and join: "DEIX". A peer that is not Deixis fails here.
inline constexpr std::array<std::byte, 4> kMagic = {std::byte{'D'}, std::byte{'E'}, std::byte{'I'},
                                                    std::byte{'X'}};

// ENet channels. Tracking has its own so that a reliable packet being resent never holds it back.
enum class Channel : std::uint8_t { kReliable = 0, kTracking = 1 };
inline constexpr std::size_t kChannelCount = 2;

// The first byte of every packet.
enum class MessageType : std::uint8_t {
  kWelcome = 0x01,    // host → joiner, reliable, plain: version, auth, salt, cost, challenge, key
  kJoin = 0x02,       // joiner → host, reliable, plain: version, auth, challenge, key, proof
  kAccept = 0x03,     // host → joiner, reliable, plain: the host's proof
  kHello = 0x04,      // reliable: version, site name, avatar description
  kTargetMap = 0x05,  // reliable: the sender's room
  kHeartbeat = 0x06,  // reliable: "still here"
  kBye = 0x07,        // reliable: leaving, or refusing, with a reason
  kAvatarRequest = 0x08,  // reliable: "send me the avatar file with this hash"
  kAvatarData = 0x09,     // reliable: one chunk of the sender's avatar file
  kTracking = 0x10,       // tracking channel: one tracking frame
  kSealed = 0x20,  // either channel: an encrypted, authenticated packet (passphrase sessions)
};
std::string_view message_name(std::uint8_t type);  // "hello", ..., "unknown"
bool is_known_type(std::uint8_t type);

// Limits (bytes, counts). The largest packet is a full target map, well below kMaxPacketBytes,
// which is also what ENet is told to accept (maximumPacketSize).
inline constexpr std::size_t kMaxTextBytes = 64;  // site, avatar model and object names
inline constexpr std::size_t kMaxTargetObjects = 256;
inline constexpr std::int32_t kMaxTargetIdOnWire = 1'000'000;
inline constexpr std::size_t kMaxPacketBytes = 32 * 1024;
inline constexpr std::size_t kTrackingBytes = 82;      // a tracking message, fixed size
inline constexpr std::size_t kSealOverheadBytes = 21;  // type, counter, Poly1305 tag
inline constexpr std::size_t kSaltBytes = 16;
inline constexpr std::size_t kChallengeBytes = 32;
inline constexpr std::size_t kExchangeKeyBytes = 32;  // an X25519 public key (crypto_kx)
// A proof: a site name (u8 length, 64 bytes zero-padded) sealed with a handshake key, so that
// only a peer that knows the passphrase can make it, or read the name (docs/protocol.md §5).
inline constexpr std::size_t kProofNameBytes = 1 + kMaxTextBytes;
inline constexpr std::size_t kProofBytes = kProofNameBytes + 16;

// Sent in a bye (and as ENet's disconnect data when a host turns away a second peer).
enum class ByeReason : std::uint8_t {
  kLeaving = 0,
  kVersionMismatch = 1,
  kPassphraseRequired = 2,    // the host has a passphrase; the joiner has none
  kPassphraseUnexpected = 3,  // the joiner has a passphrase; the host has none
  kAuthenticationFailed = 4,  // a proof did not verify: the passphrases differ
  kBusy = 5,                  // the host already has a peer
  kProtocolError = 6,         // a message arrived out of order during the handshake
  kTryLater = 7,              // the host holds back this address after failed proofs
  kWeakKeyCost = 8,           // the welcome's key cost is outside what the joiner accepts
  kFlooding = 9,              // the peer sent more than its packet or byte budget
};
inline constexpr std::uint8_t kMaxByeReason = 9;
std::string_view bye_reason_name(ByeReason reason);
// Reasons that retrying cannot fix: a joiner that hears one stops reconnecting.
bool is_refusal(ByeReason reason);

// Why a received packet was dropped. Counted per reason; never trusted, never fatal.
enum class DropReason : std::uint8_t {
  kNone = 0,
  kEmpty,               // no bytes at all
  kTruncated,           // ended inside a field
  kTrailingBytes,       // bytes after the last field
  kUnknownType,         // first byte names no message
  kWrongChannel,        // a message on the other channel than its own
  kBadMagic,            // welcome/join not starting with "DEIX"
  kWrongVersion,        // another protocol version
  kLengthBeyondPacket,  // a length field larger than what is left of the packet
  kNonFinite,           // NaN or ±Inf in a float field
  kOutOfRange,          // a number, enum value or id outside its range
  kBadText,             // text that is not UTF-8 or holds control characters
  kDuplicateId,         // a target id listed twice
  kUnexpected,          // a valid message the session's state does not allow now
  kNotStreaming,        // tracking before the hello exchange finished
  kUnauthenticated,     // a plain packet where the passphrase requires a sealed one
  kDecryptFailed,       // a sealed packet that does not authenticate under the session key
  kReplayed,            // a sealed packet whose counter was already seen (or is too old)
  kUnknownPeer,         // from an ENet peer that is not this session's peer
};
inline constexpr std::size_t kDropReasonCount =
    static_cast<std::size_t>(DropReason::kUnknownPeer) + 1;
std::string_view drop_reason_name(DropReason reason);

// The result of decoding or validating: kNone, or what was wrong and where ("hello.height").
struct WireResult {
  DropReason reason = DropReason::kNone;
  const char* field = "";  // a string literal: naming the field allocates nothing

  bool ok() const { return reason == DropReason::kNone; }
};
inline constexpr WireResult wire_ok() {
  return {};
}
inline constexpr WireResult wire_error(DropReason reason, const char* field) {
  return {reason, field};
}

}  // namespace deixis::net
