#include "net/protocol.h"

#include "net/wire.h"

namespace deixis::net {

std::string_view message_name(std::uint8_t type) {
  switch (static_cast<MessageType>(type)) {
    case MessageType::kWelcome:
      return "welcome";
    case MessageType::kJoin:
      return "join";
    case MessageType::kAccept:
      return "accept";
    case MessageType::kHello:
      return "hello";
    case MessageType::kTargetMap:
      return "target map";
    case MessageType::kHeartbeat:
      return "heartbeat";
    case MessageType::kBye:
      return "bye";
    case MessageType::kTracking:
      return "tracking";
    case MessageType::kSealed:
      return "sealed";
  }
  return "unknown";
}

bool is_known_type(std::uint8_t type) {
  return message_name(type) != "unknown";
}

std::string_view bye_reason_name(ByeReason reason) {
  switch (reason) {
    case ByeReason::kLeaving:
      return "leaving";
    case ByeReason::kVersionMismatch:
      return "protocol version mismatch";
    case ByeReason::kPassphraseRequired:
      return "the host requires a passphrase";
    case ByeReason::kPassphraseUnexpected:
      return "the host has no passphrase";
    case ByeReason::kAuthenticationFailed:
      return "wrong passphrase";
    case ByeReason::kBusy:
      return "the host already has a peer";
    case ByeReason::kProtocolError:
      return "protocol error";
  }
  return "unknown";
}

bool is_refusal(ByeReason reason) {
  switch (reason) {
    case ByeReason::kVersionMismatch:
    case ByeReason::kPassphraseRequired:
    case ByeReason::kPassphraseUnexpected:
    case ByeReason::kAuthenticationFailed:
      return true;
    case ByeReason::kLeaving:
    case ByeReason::kBusy:
    case ByeReason::kProtocolError:
      return false;
  }
  return false;
}

std::string_view drop_reason_name(DropReason reason) {
  switch (reason) {
    case DropReason::kNone:
      return "none";
    case DropReason::kEmpty:
      return "empty packet";
    case DropReason::kTruncated:
      return "truncated";
    case DropReason::kTrailingBytes:
      return "trailing bytes";
    case DropReason::kUnknownType:
      return "unknown message type";
    case DropReason::kWrongChannel:
      return "wrong channel";
    case DropReason::kBadMagic:
      return "not a Deixis peer (bad magic)";
    case DropReason::kWrongVersion:
      return "wrong protocol version";
    case DropReason::kLengthBeyondPacket:
      return "length beyond the packet";
    case DropReason::kNonFinite:
      return "NaN or infinite number";
    case DropReason::kOutOfRange:
      return "value out of range";
    case DropReason::kBadText:
      return "text not UTF-8 or with control characters";
    case DropReason::kDuplicateId:
      return "duplicate id";
    case DropReason::kUnexpected:
      return "unexpected in this session state";
    case DropReason::kNotStreaming:
      return "tracking before the hello exchange";
    case DropReason::kUnauthenticated:
      return "not authenticated (passphrase session)";
    case DropReason::kDecryptFailed:
      return "does not authenticate";
    case DropReason::kReplayed:
      return "replayed";
    case DropReason::kUnknownPeer:
      return "from an unknown peer";
  }
  return "unknown";
}

namespace {

// What a UTF-8 lead byte says: how long the sequence is, its payload bits, and the smallest code
// point that needs that length (anything smaller is an overlong encoding).
struct Lead {
  std::size_t length = 0;  // 0: not a lead byte
  std::uint32_t bits = 0;
  std::uint32_t min_code = 0;
};

Lead lead(std::uint32_t b) {
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

}  // namespace

bool is_wire_text(std::span<const std::byte> bytes) {
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
    const Lead l = lead(b0);
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

}  // namespace deixis::net
