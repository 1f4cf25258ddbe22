#pragma once
// Bounded little-endian reading and writing of byte spans: the only way net/ touches packet bytes.
// A reader never reads past its span and a writer never writes past its span; both fail sticky
// (every later call fails too), so a decoder checks once per field and names the field that broke.
// Nothing here allocates, asserts or throws.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string_view>

#include "core/io/text_rules.h"

namespace deixis::net {

class WireReader {
 public:
  explicit WireReader(std::span<const std::byte> bytes) : bytes_(bytes) {}

  bool u8(std::uint8_t& v) { return unsigned_le(v); }
  bool u16(std::uint16_t& v) { return unsigned_le(v); }
  bool u32(std::uint32_t& v) { return unsigned_le(v); }
  bool u64(std::uint64_t& v) { return unsigned_le(v); }
  // Six bytes, little-endian, into the low 48 bits.
  bool u48(std::uint64_t& v) {
    std::uint16_t low = 0;
    std::uint32_t high = 0;
    const bool ok = unsigned_le(low) && unsigned_le(high);
    v = ok ? (std::uint64_t{high} << 16) | low : 0;
    return ok;
  }
  bool i16(std::int16_t& v) {
    std::uint16_t u = 0;
    const bool ok = unsigned_le(u);
    v = std::bit_cast<std::int16_t>(u);
    return ok;
  }
  bool i32(std::int32_t& v) {
    std::uint32_t u = 0;
    const bool ok = unsigned_le(u);
    v = std::bit_cast<std::int32_t>(u);
    return ok;
  }
  // IEEE-754 binary32, any bit pattern (the caller checks finiteness and range).
  bool f32(float& v) {
    std::uint32_t u = 0;
    const bool ok = unsigned_le(u);
    v = std::bit_cast<float>(u);
    return ok;
  }
  // The next `out.size()` bytes, copied.
  bool bytes(std::span<std::byte> out) {
    const std::span<const std::byte> in = take(out.size());
    if (in.size() != out.size()) {
      return false;
    }
    if (!out.empty()) {
      std::memcpy(out.data(), in.data(), out.size());
    }
    return true;
  }
  // A view of the next `n` bytes (empty and failed when fewer remain).
  std::span<const std::byte> take(std::size_t n) {
    if (failed_ || n > remaining()) {
      failed_ = true;
      return {};
    }
    const std::span<const std::byte> view = bytes_.subspan(offset_, n);
    offset_ += n;
    return view;
  }

  std::size_t remaining() const { return bytes_.size() - offset_; }
  std::size_t offset() const { return offset_; }
  bool failed() const { return failed_; }

 private:
  template <typename U>
  bool unsigned_le(U& v) {
    const std::span<const std::byte> in = take(sizeof(U));
    if (in.size() != sizeof(U)) {
      v = 0;
      return false;
    }
    U value = 0;
    for (std::size_t i = 0; i < sizeof(U); ++i) {
      value = static_cast<U>(value | static_cast<U>(std::to_integer<U>(in[i]) << (8 * i)));
    }
    v = value;
    return true;
  }

  std::span<const std::byte> bytes_;
  std::size_t offset_ = 0;
  bool failed_ = false;
};

class WireWriter {
 public:
  explicit WireWriter(std::span<std::byte> out) : out_(out) {}

  bool u8(std::uint8_t v) { return unsigned_le(v); }
  bool u16(std::uint16_t v) { return unsigned_le(v); }
  bool u32(std::uint32_t v) { return unsigned_le(v); }
  bool u64(std::uint64_t v) { return unsigned_le(v); }
  // The low 48 bits of `v`, six bytes little-endian.
  bool u48(std::uint64_t v) {
    return unsigned_le(static_cast<std::uint16_t>(v & 0xFFFFu)) &&
           unsigned_le(static_cast<std::uint32_t>((v >> 16) & 0xFFFFFFFFu));
  }
  bool i16(std::int16_t v) { return unsigned_le(std::bit_cast<std::uint16_t>(v)); }
  bool i32(std::int32_t v) { return unsigned_le(std::bit_cast<std::uint32_t>(v)); }
  bool f32(float v) { return unsigned_le(std::bit_cast<std::uint32_t>(v)); }
  bool bytes(std::span<const std::byte> in) {
    if (failed_ || in.size() > out_.size() - offset_) {
      failed_ = true;
      return false;
    }
    if (!in.empty()) {
      std::memcpy(out_.data() + offset_, in.data(), in.size());
    }
    offset_ += in.size();
    return true;
  }
  bool text(std::string_view s) { return bytes(std::as_bytes(std::span(s.data(), s.size()))); }

  std::size_t size() const { return offset_; }
  bool failed() const { return failed_; }
  std::span<const std::byte> written() const { return out_.first(offset_); }

 private:
  template <typename U>
  bool unsigned_le(U v) {
    if (failed_ || sizeof(U) > out_.size() - offset_) {
      failed_ = true;
      return false;
    }
    for (std::size_t i = 0; i < sizeof(U); ++i) {
      out_[offset_ + i] = static_cast<std::byte>((v >> (8 * i)) & 0xFFu);
    }
    offset_ += sizeof(U);
    return true;
  }

  std::span<std::byte> out_;
  std::size_t offset_ = 0;
  bool failed_ = false;
};

// Names and site labels on the wire: core/io/text_rules.h, shared with the file readers so
// that a file that loads never holds a name the wire refuses.
using deixis::is_wire_text;

}  // namespace deixis::net
