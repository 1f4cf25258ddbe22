#pragma once
// Sealed packets (docs/protocol.md, "Sealed packets"): XChaCha20-Poly1305 (IETF) with one key per
// direction, a 32-bit counter per channel as the nonce, and a replay window per channel.
//
//   0x20 | counter u32 | ciphertext of the inner packet | 16-byte tag
//   nonce = counter (u32 LE) ‖ channel (u8) ‖ 19 zero bytes;  associated data = the first 5 bytes
//
// Opening checks the replay window before decrypting (cheap refusal) and records the counter only
// after the tag verified, so forged packets cannot move the window. Nothing here allocates.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "net/passphrase.h"
#include "net/protocol.h"

namespace deixis::net {

// Padding of sealed reliable packets (docs/protocol.md §4.9), so that sizes do not tell name
// lengths: the inner packet, then 0x80, then zeros up to the next size bucket. Tracking packets
// are all the same size and are not padded.
inline constexpr std::array<std::size_t, 6> kPaddingBuckets = {64, 256, 1024, 4096, 16384, 25600};
// The padded size of an inner packet of `n` bytes (n + 1 above the largest bucket).
std::size_t padded_size(std::size_t n);
// Writes `inner` padded into `out`; the padded size, or 0 when `out` is too small.
std::size_t pad(std::span<const std::byte> inner, std::span<std::byte> out);
// The inner packet of a padded one; empty when the padding breaks the rule.
std::span<const std::byte> unpad(std::span<const std::byte> padded);

// Remembers the last 64 counters below the highest one seen.
class ReplayWindow {
 public:
  static constexpr std::uint32_t kSize = 64;
  // kNone if `counter` was not seen and is not older than the window, else kReplayed.
  DropReason check(std::uint32_t counter) const;
  void record(std::uint32_t counter);

 private:
  bool any_ = false;
  std::uint32_t highest_ = 0;
  std::uint64_t seen_ = 0;  // bit i: highest_ − i was seen
};

class PacketSealer {
 public:
  explicit PacketSealer(const Key& key) : key_(key) {}
  ~PacketSealer();
  PacketSealer(const PacketSealer&) = delete;
  PacketSealer& operator=(const PacketSealer&) = delete;

  // The sealed packet's size, or 0 when `out` is too small or the channel's counter is used up
  // (2^32 packets: the session must reconnect for fresh keys).
  std::size_t seal(Channel channel, std::span<const std::byte> plain, std::span<std::byte> out);

 private:
  Key key_;
  std::uint32_t next_[kChannelCount] = {0, 0};
  bool exhausted_[kChannelCount] = {false, false};
};

class PacketOpener {
 public:
  explicit PacketOpener(const Key& key) : key_(key) {}
  ~PacketOpener();
  PacketOpener(const PacketOpener&) = delete;
  PacketOpener& operator=(const PacketOpener&) = delete;

  // Decrypts into `scratch`; on success `plain` views the inner packet inside it.
  WireResult open(Channel channel, std::span<const std::byte> sealed, std::span<std::byte> scratch,
                  std::span<const std::byte>& plain);

 private:
  Key key_;
  ReplayWindow window_[kChannelCount];
};

}  // namespace deixis::net
