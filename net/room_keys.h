#pragma once
// The cryptography of a room of several people behind an untrusted relay (docs/rooms-protocol.md):
// the room's parameters and each member's announce (opaque to the relay), the per-pair
// handshake secret, the key messages that prove the passphrase and hand over a sender key, and
// each sender's sealed packets.
//
//   master      = Argon2id(passphrase, room salt, room cost)           (key_derivation.h)
//   transcript  = BLAKE2b-256("deixis room transcript" ‖ params ‖ announce of the lower id
//                             ‖ announce of the higher id ‖ lower id ‖ higher id)
//   rx, tx      = crypto_kx session keys of the two announces' X25519 keys (lower id = client)
//   prk         = BLAKE2b-256(key = master, "deixis room keys" ‖ transcript ‖ rx ‖ tx)
//   key message = 0x40 ‖ AEAD(KDF(prk, 1 from the lower id | 2 from the higher, "DxRoomKy"),
//                             nonce 0, name(site) ‖ sender key, ad = transcript)
//
// A key message opens only under the same passphrase, room parameters, both announces and both
// member ids, in the direction it was sealed for: a relay that swaps the sender of a forward, or
// replays one member's key message to another, makes it fail. Afterwards each member seals each
// packet once with its own random sender key (the envelope of docs/protocol.md §4.9: a counter
// per channel, padded reliable packets), and every receiver keeps a replay window per sender and
// channel. Nothing here allocates except the site name a key message carries.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "net/messages.h"
#include "net/passphrase.h"
#include "net/protocol.h"
#include "net/sealing.h"

namespace deixis::net {

// The room protocol's own version, inside params and announces (the relay's version is its own).
inline constexpr std::uint16_t kRoomProtocolVersion = 1;
inline constexpr std::array<std::byte, 4> kRoomParamsMagic = {std::byte{'D'}, std::byte{'X'},
                                                              std::byte{'R'}, std::byte{'P'}};
inline constexpr std::array<std::byte, 4> kAnnounceMagic = {std::byte{'D'}, std::byte{'X'},
                                                            std::byte{'R'}, std::byte{'A'}};
// A member id as the room layer knows it: the relay's (1–254); 0 nobody.
using RoomMemberId = std::uint8_t;

// The room's parameters: the first member's, kept by the relay and handed to everyone who enters.
struct RoomParams {
  std::uint16_t version = kRoomProtocolVersion;
  AuthMode auth = AuthMode::kOpen;
  Salt salt{};        // zero when open
  KdfCost kdf{0, 0};  // zero when open
  bool operator==(const RoomParams&) const = default;
};
// magic 4, version 2, auth 1, salt 16, opslimit 4, memlimit 4
inline constexpr std::size_t kRoomParamsBytes = 4 + 2 + 1 + kSaltBytes + 4 + 4;
static_assert(kRoomParamsBytes == 31);

// What a member says about itself on entering, fresh per entry.
struct Announce {
  std::uint16_t version = kRoomProtocolVersion;
  AuthMode auth = AuthMode::kOpen;
  Challenge challenge{};
  ExchangeKey key{};  // ephemeral X25519 public key; zero when open
  bool operator==(const Announce&) const = default;
};
inline constexpr std::size_t kAnnounceBytes = 4 + 2 + 1 + kChallengeBytes + kExchangeKeyBytes;
static_assert(kAnnounceBytes == 71);

// Encoders write the fixed-size layout into `out`: the bytes written, or 0 when it is too small.
std::size_t encode(const RoomParams& params, std::span<std::byte> out);
std::size_t encode(const Announce& announce, std::span<std::byte> out);
// Strict decoders: exact size, magic, version, auth mode; a passphrase room's cost within
// docs/protocol.md §4.1's bounds (1–4 passes, 8–262,144 KiB), an open room's salt and cost zero;
// an open announce's key zero.
WireResult decode(std::span<const std::byte> bytes, RoomParams& out);
WireResult decode(std::span<const std::byte> bytes, Announce& out);

// The room's parameters for a member that creates it: a fresh salt when `passphrase`.
RoomParams make_room_params(bool passphrase, const KdfCost& cost);
// A fresh announce and its X25519 pair (zero key when open).
struct Entry {
  Announce announce;
  ExchangeKeyPair keys;
};
Entry make_entry(AuthMode auth);

// The hash of what a pair of members said; the same whichever member computes it.
Key room_transcript(const RoomParams& params, RoomMemberId a, const Announce& a_announce,
                    RoomMemberId b, const Announce& b_announce);
// The pair's handshake secret `prk`; nullopt when the peer's key is unusable (a low-order point)
// or the ids are equal.
std::optional<Key> room_pair_secret(const Key& master, const Key& transcript, RoomMemberId self,
                                    const ExchangeKeyPair& ours, RoomMemberId peer,
                                    const ExchangeKey& theirs);

// The key message: type, then name(site) (65 bytes) and the sender key (32), sealed (+16).
inline constexpr std::uint8_t kKeyMessageType = 0x40;
inline constexpr std::size_t kKeyMessageBytes = 1 + kProofNameBytes + sizeof(Key) + 16;
static_assert(kKeyMessageBytes == 114);

// Seals the key message `from` sends `to`; the bytes written (kKeyMessageBytes), 0 when `out`
// is too small.
std::size_t seal_key_message(const Key& prk, const Key& transcript, RoomMemberId from,
                             RoomMemberId to, std::string_view site, const Key& sender_key,
                             std::span<std::byte> out);
struct KeyGrant {
  std::string site;
  Key sender_key{};
  ~KeyGrant();
};
// Opens the key message `from` sent `to`: kDecryptFailed when it does not open (another
// passphrase, transcript or direction), kBadText when the name breaks the wire rules.
WireResult open_key_message(const Key& prk, const Key& transcript, RoomMemberId from,
                            RoomMemberId to, std::span<const std::byte> packet, KeyGrant& out);

// One sender's sealing: each packet sealed once (reliable ones padded to their bucket), for
// everyone who holds the sender key. Allocation-free.
class RoomSealer {
 public:
  explicit RoomSealer(const Key& sender_key) : sealer_(sender_key) {}
  // The sealed packet's size in `out`, or 0 when it does not fit or the counter is used up.
  std::size_t seal(Channel channel, std::span<const std::byte> inner, std::span<std::byte> out);

 private:
  PacketSealer sealer_;
  std::array<std::byte, kMaxPacketBytes> padded_{};
};

// One sender's packets as a receiver opens them: a replay window per channel; the inner packet
// must be unpadded correctly, not empty, not sealed again, and belong on its channel
// (tracking on the tracking channel, the rest on the reliable one). Allocation-free.
class RoomOpener {
 public:
  explicit RoomOpener(const Key& sender_key) : opener_(sender_key) {}
  WireResult open(Channel channel, std::span<const std::byte> sealed, std::span<std::byte> scratch,
                  std::span<const std::byte>& inner);

 private:
  PacketOpener opener_;
};

}  // namespace deixis::net
