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
    case MessageType::kAvatarRequest:
      return "avatar request";
    case MessageType::kAvatarData:
      return "avatar data";
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
    case ByeReason::kTryLater:
      return "too many failed attempts from this address: try later";
    case ByeReason::kWeakKeyCost:
      return "the host's passphrase key cost is outside the accepted range";
    case ByeReason::kFlooding:
      return "sent more than the packet budget";
  }
  return "unknown";
}

bool is_refusal(ByeReason reason) {
  switch (reason) {
    case ByeReason::kVersionMismatch:
    case ByeReason::kPassphraseRequired:
    case ByeReason::kPassphraseUnexpected:
    case ByeReason::kAuthenticationFailed:
    case ByeReason::kWeakKeyCost:
      return true;
    case ByeReason::kLeaving:
    case ByeReason::kBusy:
    case ByeReason::kProtocolError:
    case ByeReason::kTryLater:
    case ByeReason::kFlooding:
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

}  // namespace deixis::net
