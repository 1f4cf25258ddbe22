#pragma once
// A person's chosen avatar file, sent once to the sites that do not have it (docs/avatars.md,
// "A person's own avatar"; the messages in docs/protocol.md §4.10). The hello names the file by
// its content hash; a receiver whose cache lacks it sends an avatar request, and the sender
// answers with the file in avatar-data chunks, in order, paced so that a transfer never crowds out
// tracking or trips the peer's byte budget. The receiver assembles the chunks within fixed bounds
// and accepts the file only when its hash is the one the hello named: the bytes are then exactly
// what the sender chose, and the avatar loader still treats them as an untrusted file.
//
// Nothing here touches the network or the disk: the sessions carry the messages, and the site
// keeps the cache (site/avatar_cache.h).

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "net/protocol.h"

namespace deixis::net {

// BLAKE2b-256 of a whole avatar file.
using AvatarHash = std::array<std::byte, 32>;
AvatarHash avatar_hash(std::span<const std::byte> file);
// 64 lowercase hex digits: how a hello's avatar model names the file (docs/protocol.md §4.4).
std::string to_hex(const AvatarHash& hash);
// The hash a hello's avatar model names; nullopt for "" (the receiver's own choice) or anything
// that is not 64 lowercase hex digits.
std::optional<AvatarHash> parse_avatar_hash(std::string_view model);

// Bounds. A file larger than kAvatarFileMaxBytes is never offered nor accepted; chunks carry at
// most kAvatarChunkMaxBytes, which keeps a sealed chunk inside the largest padding bucket.
inline constexpr std::uint32_t kAvatarFileMaxBytes = 8u * 1024u * 1024u;
inline constexpr std::size_t kAvatarChunkMaxBytes = 16 * 1024;
// The sender's pace: avatar bytes a second to one peer (docs/protocol.md §6, "Budgets": the
// peer's byte budget is 256 KiB a second, so a transfer at this pace leaves tracking room).
inline constexpr std::uint32_t kAvatarBytesPerSecond = 128u * 1024u;

struct AvatarRequest {  // 0x08: "send me the file with this hash"
  AvatarHash hash{};
};

struct AvatarData {  // 0x09: one chunk of the file, in order
  AvatarHash hash{};
  std::uint32_t total = 0;           // the file's size in bytes, the same in every chunk
  std::uint32_t offset = 0;          // where this chunk starts
  std::span<const std::byte> bytes;  // 1..kAvatarChunkMaxBytes; decode: a view into the packet
};

inline constexpr std::size_t kAvatarRequestBytes = 1 + 32;
inline constexpr std::size_t kAvatarDataHeaderBytes = 1 + 32 + 4 + 4;

// Allocation-free encoders into a caller-owned span: the bytes written, 0 when `out` is too small
// or the message breaks a rule (an empty or oversized chunk, a chunk past the file's end).
std::size_t encode(const AvatarRequest& m, std::span<std::byte> out);
std::size_t encode(const AvatarData& m, std::span<std::byte> out);
WireResult decode(std::span<const std::byte> packet, AvatarRequest& out);
WireResult decode(std::span<const std::byte> packet, AvatarData& out);

// The sending side, for one file and any number of peers that asked for it. The caller sends the
// next chunk for a peer whenever next_chunk() gives one; the pace is kept per peer.
class AvatarSender {
 public:
  AvatarSender() = default;
  // Takes the file (at most kAvatarFileMaxBytes; throws deixis::Error naming `source` otherwise).
  AvatarSender(std::vector<std::byte> file, std::string_view source);

  bool has_file() const { return !file_.empty(); }
  const AvatarHash& hash() const { return hash_; }
  std::string model() const { return has_file() ? to_hex(hash_) : std::string(); }

  // A peer asked for `hash` at `now`: starts (or restarts) its transfer if it is our file.
  // False when it is not (a stale or wrong request: the caller counts it).
  bool on_request(std::uint32_t peer, const AvatarHash& hash, double now);
  // The next chunk due for `peer` at `now` (nullopt: none due, or no transfer); the span points
  // into the file and lives as long as the sender.
  std::optional<AvatarData> next_chunk(std::uint32_t peer, double now);
  void forget(std::uint32_t peer);  // the peer left

 private:
  struct Transfer {
    std::uint32_t peer = 0;
    std::uint32_t sent = 0;  // bytes sent so far
    double started = 0.0;    // when the request came
  };
  Transfer* find(std::uint32_t peer);

  std::vector<std::byte> file_;
  AvatarHash hash_{};
  std::vector<Transfer> transfers_;  // few peers: a linear search
};

// The receiving side, for one person's file.
enum class AvatarReceiveStatus : std::uint8_t {
  kIdle,       // nothing expected
  kReceiving,  // a request went out; chunks are coming
  kComplete,   // the whole file, with the expected hash
  kFailed,     // a chunk broke a rule or the hash did not match: the transfer was abandoned
};

class AvatarReceiver {
 public:
  // Expect the file named `hash` (from the person's hello); resets any earlier transfer.
  void expect(const AvatarHash& hash);
  void reset();

  // One chunk. Chunks for another hash are ignored (false: the caller counts them as unexpected);
  // a chunk that breaks the order or the bounds, or a file whose hash is not the expected one,
  // fails the transfer with a reason (failure()).
  bool on_data(const AvatarData& chunk);

  AvatarReceiveStatus status() const { return status_; }
  const AvatarHash& expected() const { return expected_; }
  std::uint32_t received() const { return static_cast<std::uint32_t>(file_.size()); }
  std::uint32_t total() const { return total_; }
  const std::string& failure() const { return failure_; }
  // The file, once complete (empty before).
  std::span<const std::byte> file() const;

 private:
  void fail(std::string reason);

  AvatarHash expected_{};
  AvatarReceiveStatus status_ = AvatarReceiveStatus::kIdle;
  std::uint32_t total_ = 0;
  std::vector<std::byte> file_;
  std::string failure_;
};

}  // namespace deixis::net
