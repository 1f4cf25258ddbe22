#pragma once
// The reliable-channel messages (docs/protocol.md) as plain structs, with their encoders and
// bounded decoders. Decoders check every length against what is left of the packet, every float
// for finiteness and range, every enum and id against its range, and that nothing trails the last
// field; they return what was wrong and where, and never assert or throw. Encoders validate with
// the same rules, so a message that would be refused is never sent.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/target_map.h"
#include "core/tracking.h"
#include "net/protocol.h"

namespace deixis::net {

enum class AuthMode : std::uint8_t { kOpen = 0, kPassphrase = 1 };

// Argon2id cost of deriving the key from the passphrase; chosen by the host, sent in the welcome.
struct KdfCost {
  std::uint32_t opslimit = 2;              // crypto_pwhash_OPSLIMIT_INTERACTIVE
  std::uint32_t memlimit_kib = 64 * 1024;  // crypto_pwhash_MEMLIMIT_INTERACTIVE (64 MiB)
  bool operator==(const KdfCost&) const = default;
};
// What the welcome's format allows (a host must not make a joiner allocate gigabytes): MODERATE
// at most. Within it, a joiner also enforces a floor (SessionConfig::min_kdf, libsodium's
// INTERACTIVE by default), so that a fake host cannot collect a proof that is cheap to test
// passphrase guesses against.
inline constexpr std::uint32_t kMinKdfOps = 1;
inline constexpr std::uint32_t kMaxKdfOps = 4;
inline constexpr std::uint32_t kMinKdfMemKib = 8;
inline constexpr std::uint32_t kMaxKdfMemKib = 256 * 1024;
// libsodium's INTERACTIVE limits: the joiner's default floor.
inline constexpr KdfCost kInteractiveKdf{2, 64 * 1024};
// True when `cost` is at least `floor` in both passes and memory.
inline bool at_least(const KdfCost& cost, const KdfCost& floor) {
  return cost.opslimit >= floor.opslimit && cost.memlimit_kib >= floor.memlimit_kib;
}

using Salt = std::array<std::byte, kSaltBytes>;
using Challenge = std::array<std::byte, kChallengeBytes>;
using ExchangeKey = std::array<std::byte, kExchangeKeyBytes>;  // X25519 public key
using Proof = std::array<std::byte, kProofBytes>;

struct Welcome {  // host → joiner, first message after the transport connects
  std::uint16_t protocol_version = kProtocolVersion;
  AuthMode auth = AuthMode::kOpen;
  Salt salt{};        // zero when open
  KdfCost kdf{0, 0};  // zero when open
  Challenge host_challenge{};
  ExchangeKey host_key{};  // ephemeral, fresh per connection; zero when open
};

struct Join {  // joiner → host
  std::uint16_t protocol_version = kProtocolVersion;
  AuthMode auth = AuthMode::kOpen;
  Challenge joiner_challenge{};
  ExchangeKey joiner_key{};  // ephemeral, fresh per connection; zero when open
  Proof proof{};             // the joiner's site name, sealed; zero when open
};

struct Accept {   // host → joiner
  Proof proof{};  // the host's site name, sealed; zero when open
};

// Who is at the other end (docs/protocol.md §4.4): the avatar to show and the body it must move
// like.
struct AvatarDescription {
  std::string model;  // an avatar asset name; empty: the project's default avatar
  BodyCalibration body;
};

struct Hello {
  std::uint16_t protocol_version = kProtocolVersion;
  std::string site;  // 1..64 bytes of wire text
  AvatarDescription avatar;
};

struct Heartbeat {
  std::uint32_t count = 0;  // +1 per heartbeat sent on this connection
};

struct Bye {
  ByeReason reason = ByeReason::kLeaving;
};

// Sizes of the fixed-size messages.
// type, magic, version, auth: 8 bytes; then the fields.
inline constexpr std::size_t kWelcomeBytes =
    8 + kSaltBytes + 8 + kChallengeBytes + kExchangeKeyBytes;
inline constexpr std::size_t kJoinBytes = 8 + kChallengeBytes + kExchangeKeyBytes + kProofBytes;
inline constexpr std::size_t kAcceptBytes = 1 + kProofBytes;
static_assert(kWelcomeBytes == 96 && kJoinBytes == 153 && kAcceptBytes == 82);
inline constexpr std::size_t kHeartbeatBytes = 5;
inline constexpr std::size_t kByeBytes = 2;

// Encoders: the bytes of the message, appended to `out` (cleared first). The fixed-size ones
// cannot fail; hello and target map return the rule the struct breaks, and leave `out` empty.
void encode(const Welcome& m, std::vector<std::byte>& out);
void encode(const Join& m, std::vector<std::byte>& out);
void encode(const Accept& m, std::vector<std::byte>& out);
WireResult encode(const Hello& m, std::vector<std::byte>& out);
// "what: field: reason": one of our own messages that breaks a wire rule, as an error's text.
std::string wire_message(std::string_view what, WireResult why);
// Our hello replaced mid-session (a recalibration; docs/protocol.md §4.4): `next` keeps
// `current`'s site name (the handshake's proofs carried it; another one throws) and names
// `avatar_model` when that is not empty (the file we send stays the one we name). Returns it
// encoded; throws deixis::Error, its text starting with `who`, when it breaks a wire rule.
std::vector<std::byte> encode_replacement_hello(const Hello& current, Hello& next,
                                                std::string_view avatar_model,
                                                std::string_view who);
WireResult encode(const TargetMap& m, std::vector<std::byte>& out);
// Allocation-free, into a caller-owned span (heartbeats and byes are sent while streaming);
// return the bytes written, or 0 when `out` is too small.
std::size_t encode(const Heartbeat& m, std::span<std::byte> out);
std::size_t encode(const Bye& m, std::span<std::byte> out);

WireResult decode(std::span<const std::byte> packet, Welcome& out);
WireResult decode(std::span<const std::byte> packet, Join& out);
WireResult decode(std::span<const std::byte> packet, Accept& out);
WireResult decode(std::span<const std::byte> packet, Hello& out);
WireResult decode(std::span<const std::byte> packet, TargetMap& out);
WireResult decode(std::span<const std::byte> packet, Heartbeat& out);
WireResult decode(std::span<const std::byte> packet, Bye& out);

// The rules a hello or target map must follow (the encoder and the decoder both apply them).
WireResult validate(const Hello& m);
WireResult validate(const TargetMap& m);

}  // namespace deixis::net
