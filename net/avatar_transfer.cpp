#include "net/avatar_transfer.h"

#include <sodium.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.h"
#include "net/wire.h"

namespace deixis::net {

namespace {

constexpr std::uint8_t kRequestType = static_cast<std::uint8_t>(MessageType::kAvatarRequest);
constexpr std::uint8_t kDataType = static_cast<std::uint8_t>(MessageType::kAvatarData);

bool chunk_fits(const AvatarData& m) {
  return !m.bytes.empty() && m.bytes.size() <= kAvatarChunkMaxBytes && m.total > 0 &&
         m.total <= kAvatarFileMaxBytes && m.offset < m.total &&
         m.bytes.size() <= m.total - m.offset;
}

WireResult read_type(WireReader& r, std::uint8_t expected) {
  std::uint8_t type = 0;
  if (!r.u8(type)) {
    return wire_error(DropReason::kEmpty, "type");
  }
  return type == expected ? wire_ok() : wire_error(DropReason::kUnknownType, "type");
}

}  // namespace

AvatarHash avatar_hash(std::span<const std::byte> file) {
  AvatarHash h{};
  crypto_generichash(reinterpret_cast<unsigned char*>(h.data()), h.size(),
                     reinterpret_cast<const unsigned char*>(file.data()), file.size(), nullptr, 0);
  return h;
}

std::string to_hex(const AvatarHash& hash) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s;
  s.reserve(2 * hash.size());
  for (const std::byte b : hash) {
    const auto v = std::to_integer<unsigned>(b);
    s.push_back(kDigits[v >> 4]);
    s.push_back(kDigits[v & 15u]);
  }
  return s;
}

std::optional<AvatarHash> parse_avatar_hash(std::string_view model) {
  if (model.size() != 64) {
    return std::nullopt;
  }
  const auto nibble = [](char c) -> int {
    if (c >= '0' && c <= '9') {
      return c - '0';
    }
    if (c >= 'a' && c <= 'f') {
      return c - 'a' + 10;
    }
    return -1;
  };
  AvatarHash h{};
  for (std::size_t i = 0; i < h.size(); ++i) {
    const int hi = nibble(model[2 * i]);
    const int lo = nibble(model[2 * i + 1]);
    if (hi < 0 || lo < 0) {
      return std::nullopt;
    }
    h[i] = static_cast<std::byte>(hi * 16 + lo);
  }
  return h;
}

std::size_t encode(const AvatarRequest& m, std::span<std::byte> out) {
  WireWriter w(out);
  w.u8(kRequestType);
  w.bytes(m.hash);
  return w.failed() ? 0 : w.size();
}

std::size_t encode(const AvatarData& m, std::span<std::byte> out) {
  if (!chunk_fits(m)) {
    return 0;
  }
  WireWriter w(out);
  w.u8(kDataType);
  w.bytes(m.hash);
  w.u32(m.total);
  w.u32(m.offset);
  w.bytes(m.bytes);
  return w.failed() ? 0 : w.size();
}

WireResult decode(std::span<const std::byte> packet, AvatarRequest& out) {
  WireReader r(packet);
  if (const WireResult t = read_type(r, kRequestType); !t.ok()) {
    return t;
  }
  if (!r.bytes(out.hash)) {
    return wire_error(DropReason::kTruncated, "avatar_request.hash");
  }
  return r.remaining() == 0 ? wire_ok() : wire_error(DropReason::kTrailingBytes, "avatar_request");
}

WireResult decode(std::span<const std::byte> packet, AvatarData& out) {
  WireReader r(packet);
  if (const WireResult t = read_type(r, kDataType); !t.ok()) {
    return t;
  }
  if (!r.bytes(out.hash)) {
    return wire_error(DropReason::kTruncated, "avatar_data.hash");
  }
  if (!r.u32(out.total)) {
    return wire_error(DropReason::kTruncated, "avatar_data.total");
  }
  if (!r.u32(out.offset)) {
    return wire_error(DropReason::kTruncated, "avatar_data.offset");
  }
  out.bytes = r.take(r.remaining());
  if (out.total == 0 || out.total > kAvatarFileMaxBytes) {
    return wire_error(DropReason::kOutOfRange, "avatar_data.total");
  }
  if (out.bytes.empty() || out.bytes.size() > kAvatarChunkMaxBytes) {
    return wire_error(DropReason::kOutOfRange, "avatar_data.bytes");
  }
  if (out.offset >= out.total || out.bytes.size() > out.total - out.offset) {
    return wire_error(DropReason::kOutOfRange, "avatar_data.offset");
  }
  return wire_ok();
}

// ---------------------------------------------------------------- sender

AvatarSender::AvatarSender(std::vector<std::byte> file, std::string_view source)
    : file_(std::move(file)) {
  if (file_.empty()) {
    throw Error(std::string(source) + ": the avatar file is empty");
  }
  if (file_.size() > kAvatarFileMaxBytes) {
    throw Error(std::string(source) + ": the avatar file has " + std::to_string(file_.size()) +
                " bytes; at most " + std::to_string(kAvatarFileMaxBytes) +
                " travel to other sites (docs/avatars.md)");
  }
  hash_ = avatar_hash(file_);
}

AvatarSender::Transfer* AvatarSender::find(std::uint32_t peer) {
  const auto it = std::find_if(transfers_.begin(), transfers_.end(),
                               [&](const Transfer& t) { return t.peer == peer; });
  return it == transfers_.end() ? nullptr : &*it;
}

bool AvatarSender::on_request(std::uint32_t peer, const AvatarHash& hash, double now) {
  if (!has_file() || hash != hash_) {
    return false;
  }
  if (Transfer* t = find(peer)) {
    *t = Transfer{peer, 0, now};
  } else {
    transfers_.push_back(Transfer{peer, 0, now});
  }
  return true;
}

std::optional<AvatarData> AvatarSender::next_chunk(std::uint32_t peer, double now) {
  Transfer* t = find(peer);
  if (t == nullptr || t->sent >= file_.size()) {
    return std::nullopt;
  }
  // The pace: by `now`, at most kAvatarBytesPerSecond · elapsed bytes, plus the first chunk at
  // once. A chunk goes out when the budget has room for all of it.
  const double elapsed = std::max(0.0, now - t->started);
  const double allowed =
      static_cast<double>(kAvatarChunkMaxBytes) + kAvatarBytesPerSecond * elapsed;
  const std::size_t n = std::min<std::size_t>(kAvatarChunkMaxBytes, file_.size() - t->sent);
  if (static_cast<double>(t->sent + n) > allowed) {
    return std::nullopt;
  }
  AvatarData chunk;
  chunk.hash = hash_;
  chunk.total = static_cast<std::uint32_t>(file_.size());
  chunk.offset = t->sent;
  chunk.bytes = std::span<const std::byte>(file_).subspan(t->sent, n);
  t->sent += static_cast<std::uint32_t>(n);
  return chunk;
}

void AvatarSender::forget(std::uint32_t peer) {
  std::erase_if(transfers_, [&](const Transfer& t) { return t.peer == peer; });
}

// ---------------------------------------------------------------- receiver

void AvatarReceiver::expect(const AvatarHash& hash) {
  reset();
  expected_ = hash;
  status_ = AvatarReceiveStatus::kReceiving;
}

void AvatarReceiver::reset() {
  status_ = AvatarReceiveStatus::kIdle;
  total_ = 0;
  file_.clear();
  file_.shrink_to_fit();
  failure_.clear();
}

void AvatarReceiver::fail(std::string reason) {
  status_ = AvatarReceiveStatus::kFailed;
  failure_ = std::move(reason);
  file_.clear();
  file_.shrink_to_fit();
}

bool AvatarReceiver::on_data(const AvatarData& chunk) {
  if (status_ != AvatarReceiveStatus::kReceiving || chunk.hash != expected_) {
    return false;
  }
  if (!chunk_fits(chunk)) {
    fail("a chunk outside the file's bounds");
    return true;
  }
  if (file_.empty() && total_ == 0) {
    total_ = chunk.total;
    file_.reserve(total_);  // once per transfer, bounded by kAvatarFileMaxBytes
  }
  if (chunk.total != total_) {
    fail("chunks disagree on the file's size (" + std::to_string(total_) + " then " +
         std::to_string(chunk.total) + " bytes)");
    return true;
  }
  if (chunk.offset != file_.size()) {
    fail("a chunk out of order (at byte " + std::to_string(chunk.offset) + ", expected " +
         std::to_string(file_.size()) + ")");
    return true;
  }
  file_.insert(file_.end(), chunk.bytes.begin(), chunk.bytes.end());
  if (file_.size() == total_) {
    if (avatar_hash(file_) != expected_) {
      fail("the file's hash is not the one its hello named");
    } else {
      status_ = AvatarReceiveStatus::kComplete;
    }
  }
  return true;
}

std::span<const std::byte> AvatarReceiver::file() const {
  return status_ == AvatarReceiveStatus::kComplete ? std::span<const std::byte>(file_)
                                                   : std::span<const std::byte>();
}

}  // namespace deixis::net
