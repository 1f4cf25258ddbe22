#include "net/sealing.h"

#include <sodium.h>

#include <algorithm>

#include "net/wire.h"

namespace deixis::net {

namespace {

constexpr std::size_t kHeaderBytes = 5;  // type, counter
constexpr std::size_t kTagBytes = crypto_aead_xchacha20poly1305_ietf_ABYTES;
static_assert(kHeaderBytes + kTagBytes == kSealOverheadBytes);
static_assert(crypto_aead_xchacha20poly1305_ietf_KEYBYTES == sizeof(Key));

using Nonce = std::array<unsigned char, crypto_aead_xchacha20poly1305_ietf_NPUBBYTES>;

Nonce nonce_for(std::uint32_t counter, Channel channel) {
  Nonce n{};
  for (std::size_t i = 0; i < 4; ++i) {
    n[i] = static_cast<unsigned char>((counter >> (8 * i)) & 0xFFu);
  }
  n[4] = static_cast<unsigned char>(channel);
  return n;
}

const unsigned char* uchars(std::span<const std::byte> s) {
  return reinterpret_cast<const unsigned char*>(s.data());
}
unsigned char* uchars(std::span<std::byte> s) {
  return reinterpret_cast<unsigned char*>(s.data());
}

std::size_t channel_index(Channel channel) {
  return static_cast<std::size_t>(channel) < kChannelCount ? static_cast<std::size_t>(channel) : 0;
}

}  // namespace

std::size_t padded_size(std::size_t n) {
  for (const std::size_t bucket : kPaddingBuckets) {
    if (n + 1 <= bucket) {
      return bucket;
    }
  }
  return n + 1;
}

std::size_t pad(std::span<const std::byte> inner, std::span<std::byte> out) {
  const std::size_t size = padded_size(inner.size());
  if (out.size() < size) {
    return 0;
  }
  std::copy(inner.begin(), inner.end(), out.begin());
  out[inner.size()] = std::byte{0x80};
  std::fill(out.begin() + static_cast<std::ptrdiff_t>(inner.size()) + 1,
            out.begin() + static_cast<std::ptrdiff_t>(size), std::byte{0});
  return size;
}

std::span<const std::byte> unpad(std::span<const std::byte> padded) {
  std::size_t end = padded.size();
  while (end > 0 && padded[end - 1] == std::byte{0}) {
    --end;
  }
  if (end == 0 || padded[end - 1] != std::byte{0x80} || padded_size(end - 1) != padded.size()) {
    return {};
  }
  return padded.first(end - 1);
}

DropReason ReplayWindow::check(std::uint32_t counter) const {
  if (!any_ || counter > highest_) {
    return DropReason::kNone;
  }
  const std::uint32_t age = highest_ - counter;
  if (age >= kSize || ((seen_ >> age) & 1u) != 0) {
    return DropReason::kReplayed;
  }
  return DropReason::kNone;
}

void ReplayWindow::record(std::uint32_t counter) {
  if (!any_) {
    any_ = true;
    highest_ = counter;
    seen_ = 1;
    return;
  }
  if (counter > highest_) {
    const std::uint32_t shift = counter - highest_;
    seen_ = shift >= kSize ? 1u : (seen_ << shift) | 1u;
    highest_ = counter;
    return;
  }
  const std::uint32_t age = highest_ - counter;
  if (age < kSize) {
    seen_ |= std::uint64_t{1} << age;
  }
}

PacketSealer::~PacketSealer() {
  sodium_memzero(key_.data(), key_.size());
}

std::size_t PacketSealer::seal(Channel channel, std::span<const std::byte> plain,
                               std::span<std::byte> out) {
  const std::size_t c = channel_index(channel);
  const std::size_t size = kHeaderBytes + plain.size() + kTagBytes;
  if (exhausted_[c] || out.size() < size) {
    return 0;
  }
  const std::uint32_t counter = next_[c];
  WireWriter header(out.first(kHeaderBytes));
  header.u8(static_cast<std::uint8_t>(MessageType::kSealed));
  header.u32(counter);
  const Nonce nonce = nonce_for(counter, channel);
  unsigned long long cipher_bytes = 0;
  crypto_aead_xchacha20poly1305_ietf_encrypt(
      uchars(out.subspan(kHeaderBytes)), &cipher_bytes, uchars(plain), plain.size(),
      uchars(out.first(kHeaderBytes)), kHeaderBytes, nullptr, nonce.data(),
      uchars(std::span<const std::byte>(key_)));
  if (counter == UINT32_MAX) {
    exhausted_[c] = true;
  } else {
    next_[c] = counter + 1;
  }
  return kHeaderBytes + static_cast<std::size_t>(cipher_bytes);
}

PacketOpener::~PacketOpener() {
  sodium_memzero(key_.data(), key_.size());
}

WireResult PacketOpener::open(Channel channel, std::span<const std::byte> sealed,
                              std::span<std::byte> scratch, std::span<const std::byte>& plain) {
  if (sealed.empty()) {
    return wire_error(DropReason::kEmpty, "sealed");
  }
  if (sealed[0] != static_cast<std::byte>(MessageType::kSealed)) {
    return wire_error(DropReason::kUnauthenticated, "sealed.type");
  }
  if (sealed.size() < kSealOverheadBytes) {
    return wire_error(DropReason::kTruncated, "sealed");
  }
  const std::size_t plain_size = sealed.size() - kSealOverheadBytes;
  if (plain_size > scratch.size()) {
    return wire_error(DropReason::kOutOfRange, "sealed.length");
  }
  WireReader header(sealed.first(kHeaderBytes));
  std::uint8_t type = 0;
  std::uint32_t counter = 0;
  header.u8(type);
  header.u32(counter);
  ReplayWindow& window = window_[channel_index(channel)];
  if (window.check(counter) != DropReason::kNone) {
    return wire_error(DropReason::kReplayed, "sealed.counter");
  }
  const Nonce nonce = nonce_for(counter, channel);
  unsigned long long opened = 0;
  const std::span<const std::byte> body = sealed.subspan(kHeaderBytes);
  if (crypto_aead_xchacha20poly1305_ietf_decrypt(uchars(scratch), &opened, nullptr, uchars(body),
                                                 body.size(), uchars(sealed.first(kHeaderBytes)),
                                                 kHeaderBytes, nonce.data(),
                                                 uchars(std::span<const std::byte>(key_))) != 0) {
    return wire_error(DropReason::kDecryptFailed, "sealed");
  }
  window.record(counter);
  plain = scratch.first(static_cast<std::size_t>(opened));
  return wire_ok();
}

}  // namespace deixis::net
