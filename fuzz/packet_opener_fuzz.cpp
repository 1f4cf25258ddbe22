// libFuzzer target for sealed packets (net/sealing.h) under a fixed key:
//   byte 0, bit 0 clear — open: the rest is a list of packets [flags: bit 0 channel] [u16 length]
//     [bytes], each given to one PacketOpener in turn. Opening refuses with a reason and a field or
//     succeeds; success on bytes not sealed under the key would be a forgery (the seeds hold real
//     sealed packets, so the fuzzer can reach success by keeping them intact), the inner packet is
//     the sealed size less the overhead, and the same bytes never open twice (replay window).
//   byte 0, bit 0 set — seal and mutate: [flags: bit 0 channel] [u8 packets sealed first] then the
//     plain packet up to a 0xFF 0xFE marker (or the end), then mutations [kind] [u16 position]
//     [u8 value] (0 flip bits, 1 set, 2 truncate, 3 append, 4 swap channel, 5 reorder (open an
//     older one), else none). The packet is sealed by a PacketSealer under the key; a fresh opener
//     opens it as sealed and gives back the plain bytes exactly; the mutated packet never opens
//     unless the mutations left it as it was.
//   The padding (pad/unpad) of the plain bytes: unpad(pad(x)) is x, and whatever unpad accepts
//   pads back to its input.
// Built with libFuzzer by the `fuzz` preset; in ordinary builds packet_opener_replay replays the
// committed corpus fuzz/corpus/packet_opener/.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <vector>

#include "net/passphrase.h"
#include "net/protocol.h"
#include "net/sealing.h"

namespace {

using namespace deixis;
using namespace deixis::net;

void check(bool holds, const char* invariant) {
  if (!holds) {
    std::fprintf(stderr, "packet_opener_fuzz: invariant violated: %s\n", invariant);
    __builtin_trap();
  }
}

// The fixed key every seed was sealed under (fuzz/corpus/packet_opener/README.md).
Key fuzz_key() {
  Key key{};
  for (std::size_t i = 0; i < key.size(); ++i) {
    key[i] = static_cast<std::byte>(0xA0 + i);
  }
  return key;
}

constexpr std::size_t kMaxPlain = 2048;
constexpr std::size_t kMaxSealed = kMaxPlain + kSealOverheadBytes + 64;

class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> data) : data_(data) {}
  bool empty() const { return at_ >= data_.size(); }
  std::uint8_t u8() { return at_ < data_.size() ? data_[at_++] : 0; }
  std::uint16_t u16() {
    const std::uint16_t lo = u8();
    return static_cast<std::uint16_t>(lo | (u8() << 8));
  }
  std::span<const std::uint8_t> bytes(std::size_t n) {
    n = std::min(n, data_.size() - at_);
    const std::span<const std::uint8_t> s = data_.subspan(at_, n);
    at_ += n;
    return s;
  }
  // The bytes up to 0xFF 0xFE (not included; the marker is skipped) or the end.
  std::span<const std::uint8_t> until_marker() {
    const std::size_t start = at_;
    for (; at_ + 1 < data_.size(); ++at_) {
      if (data_[at_] == 0xFF && data_[at_ + 1] == 0xFE) {
        const std::span<const std::uint8_t> s = data_.subspan(start, at_ - start);
        at_ += 2;
        return s;
      }
    }
    at_ = data_.size();
    return data_.subspan(start);
  }

 private:
  std::span<const std::uint8_t> data_;
  std::size_t at_ = 0;
};

std::span<const std::byte> as_bytes(std::span<const std::uint8_t> s) {
  return std::as_bytes(s);
}

Channel channel_of(std::uint8_t flags) {
  return (flags & 1u) != 0 ? Channel::kTracking : Channel::kReliable;
}
Channel other(Channel c) {
  return c == Channel::kTracking ? Channel::kReliable : Channel::kTracking;
}

void check_refusal(const WireResult& r) {
  check(!r.ok(), "a refusal");
  check(r.field[0] != '\0', "a refusal names its field");
  check(static_cast<std::size_t>(r.reason) < kDropReasonCount, "a known reason");
}

void open_arbitrary(Reader& in) {
  PacketOpener opener(fuzz_key());
  std::array<std::byte, kMaxSealed> scratch{};
  while (!in.empty()) {
    const Channel channel = channel_of(in.u8());
    const std::span<const std::byte> packet = as_bytes(in.bytes(in.u16()));
    std::span<const std::byte> plain;
    const WireResult r = opener.open(channel, packet, scratch, plain);
    if (!r.ok()) {
      check_refusal(r);
      continue;
    }
    check(packet.size() >= kSealOverheadBytes, "an opened packet holds the overhead");
    check(plain.size() == packet.size() - kSealOverheadBytes, "the inner packet's size");
    check(plain.data() == scratch.data(), "the inner packet lies in the scratch buffer");
    std::span<const std::byte> again;
    const WireResult replay = opener.open(channel, packet, scratch, again);
    check(!replay.ok() && replay.reason == DropReason::kReplayed, "a packet opens once");
  }
}

void seal_and_mutate(Reader& in) {
  const std::uint8_t flags = in.u8();
  const Channel channel = channel_of(flags);
  const std::uint8_t before = in.u8();
  const std::span<const std::byte> plain_in = as_bytes(in.until_marker());
  const std::span<const std::byte> plain = plain_in.first(std::min(plain_in.size(), kMaxPlain));

  PacketSealer sealer(fuzz_key());
  std::vector<std::vector<std::byte>> sealed_packets;
  for (unsigned i = 0; i <= before % 4u; ++i) {
    std::vector<std::byte> out(kMaxSealed);
    const std::size_t n = sealer.seal(channel, plain, out);
    check(n == plain.size() + kSealOverheadBytes, "sealing adds the overhead");
    out.resize(n);
    sealed_packets.push_back(std::move(out));
  }
  {
    std::array<std::byte, 4> tiny{};
    check(
        plain.size() + kSealOverheadBytes <= tiny.size() || sealer.seal(channel, plain, tiny) == 0,
        "sealing into too small a buffer writes nothing");
  }
  const std::vector<std::byte>& sealed = sealed_packets.back();

  std::array<std::byte, kMaxSealed> scratch{};
  {
    PacketOpener opener(fuzz_key());
    std::span<const std::byte> opened;
    const WireResult r = opener.open(channel, sealed, scratch, opened);
    check(r.ok(), "a sealed packet opens");
    check(std::equal(opened.begin(), opened.end(), plain.begin(), plain.end()),
          "opening gives the sealed bytes back");
  }

  std::vector<std::byte> mutated = sealed;
  Channel open_on = channel;
  while (!in.empty()) {
    const std::uint8_t kind = in.u8();
    const std::uint16_t position = in.u16();
    const auto value = static_cast<std::byte>(in.u8());
    switch (kind % 8u) {
      case 0:
        if (!mutated.empty()) {
          mutated[position % mutated.size()] ^= value;
        }
        break;
      case 1:
        if (!mutated.empty()) {
          mutated[position % mutated.size()] = value;
        }
        break;
      case 2:
        mutated.resize(std::min<std::size_t>(mutated.size(), position % (mutated.size() + 1)));
        break;
      case 3:
        if (mutated.size() < kMaxSealed - 1) {
          mutated.push_back(value);
        }
        break;
      case 4:
        open_on = other(open_on);
        break;
      case 5:
        mutated = sealed_packets[position % sealed_packets.size()];
        break;
      default:
        break;
    }
  }
  const bool unchanged = open_on == channel && mutated == sealed;
  PacketOpener opener(fuzz_key());
  std::span<const std::byte> opened;
  const WireResult r = opener.open(open_on, mutated, scratch, opened);
  if (unchanged) {
    check(r.ok(), "an unchanged packet opens");
    check(std::equal(opened.begin(), opened.end(), plain.begin(), plain.end()),
          "opening gives the sealed bytes back");
  } else if (r.ok()) {
    // Another packet of the same sealer (case 5) is genuine: it opens, as itself.
    const bool genuine =
        open_on == channel &&
        std::find(sealed_packets.begin(), sealed_packets.end(), mutated) != sealed_packets.end();
    check(genuine, "a mutated packet never opens");
    check(std::equal(opened.begin(), opened.end(), plain.begin(), plain.end()),
          "a genuine packet opens as sealed");
  } else {
    check_refusal(r);
  }
}

void check_padding(std::span<const std::byte> bytes) {
  std::vector<std::byte> padded(padded_size(bytes.size()));
  check(padded.size() > bytes.size(), "padding adds at least the marker");
  check(pad(bytes, padded) == padded.size(), "padding fits its size");
  const std::span<const std::byte> back = unpad(padded);
  check(std::equal(back.begin(), back.end(), bytes.begin(), bytes.end()), "unpad(pad(x)) is x");
  const std::span<const std::byte> inner = unpad(bytes);
  if (!inner.empty()) {
    std::vector<std::byte> again(padded_size(inner.size()));
    check(again.size() == bytes.size(), "an accepted padding has its bucket's size");
    pad(inner, again);
    check(std::equal(again.begin(), again.end(), bytes.begin(), bytes.end()),
          "an accepted padding pads back to itself");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool ready = sodium_ready();
  check(ready, "libsodium initialises");
  if (size == 0) {
    return 0;
  }
  const std::span<const std::uint8_t> input(data, size);
  check_padding(as_bytes(input.subspan(1)));
  Reader in(input.subspan(1));
  if ((data[0] & 1u) == 0) {
    open_arbitrary(in);
  } else {
    seal_and_mutate(in);
  }
  return 0;
}
