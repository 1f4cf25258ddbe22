#pragma once
// The rules a name must follow to travel on the wire (site names, object names, avatar model
// names), shared by net/ (which sends them) and by the file readers of gesture/ and app/ (which
// check them at load, so that a file that loads can never later make a session refuse to send).
// Header-only: gesture/ must not depend on net/, and the XR test runtime links neither.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace deixis {

// The longest name the wire carries, in bytes (net/protocol.h kMaxTextBytes is the same value;
// tests/io/json_reader_test.cpp checks that they agree).
inline constexpr std::size_t kMaxNameBytes = 64;

namespace text_rules_detail {

// What a UTF-8 lead byte says: how long the sequence is, its payload bits, and the smallest code
// point that needs that length (anything smaller is an overlong encoding).
struct Lead {
  std::size_t length = 0;  // 0: not a lead byte
  std::uint32_t bits = 0;
  std::uint32_t min_code = 0;
};

inline Lead lead(std::uint32_t b) {
  if ((b & 0xE0) == 0xC0) {
    return {2, b & 0x1F, 0x80};
  }
  if ((b & 0xF0) == 0xE0) {
    return {3, b & 0x0F, 0x800};
  }
  if ((b & 0xF8) == 0xF0) {
    return {4, b & 0x07, 0x10000};
  }
  return {};  // a continuation byte or 0xF8..0xFF where a character should start
}

}  // namespace text_rules_detail

// Names and site labels on the wire: valid UTF-8 (shortest form, no surrogates) without ASCII
// or C1 control characters, so that a log line or a rendered label can show them as they are.
inline bool is_wire_text(std::span<const std::byte> bytes) {
  std::size_t i = 0;
  while (i < bytes.size()) {
    const auto b0 = std::to_integer<std::uint32_t>(bytes[i]);
    if (b0 < 0x80) {
      if (b0 < 0x20 || b0 == 0x7F) {
        return false;  // ASCII control character
      }
      ++i;
      continue;
    }
    const text_rules_detail::Lead l = text_rules_detail::lead(b0);
    if (l.length == 0 || l.length > bytes.size() - i) {
      return false;
    }
    std::uint32_t code = l.bits;
    for (std::size_t k = 1; k < l.length; ++k) {
      const auto b = std::to_integer<std::uint32_t>(bytes[i + k]);
      if ((b & 0xC0) != 0x80) {
        return false;
      }
      code = (code << 6) | (b & 0x3F);
    }
    if (code < l.min_code || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF) ||
        (code >= 0x80 && code < 0xA0)) {
      return false;  // overlong, beyond Unicode, a surrogate, or a C1 control character
    }
    i += l.length;
  }
  return true;
}

inline bool is_wire_text(std::string_view s) {
  return is_wire_text(std::as_bytes(std::span(s.data(), s.size())));
}

}  // namespace deixis
