#include "net/room_keys.h"

#include <sodium.h>

#include <algorithm>

#include "net/wire.h"

namespace deixis::net {

namespace {

const unsigned char* uchars(std::span<const std::byte> s) {
  return reinterpret_cast<const unsigned char*>(s.data());
}
unsigned char* uchars(std::span<std::byte> s) {
  return reinterpret_cast<unsigned char*>(s.data());
}

bool all_zero(std::span<const std::byte> bytes) {
  return std::all_of(bytes.begin(), bytes.end(), [](std::byte b) { return b == std::byte{0}; });
}

// The common head of params and announces: magic, version, auth mode.
WireResult read_head(WireReader& r, const std::array<std::byte, 4>& magic, std::uint16_t& version,
                     AuthMode& auth, const char* what) {
  std::array<std::byte, 4> m{};
  std::uint8_t a = 0;
  if (!r.bytes(m) || !r.u16(version) || !r.u8(a)) {
    return wire_error(DropReason::kTruncated, what);
  }
  if (m != magic) {
    return wire_error(DropReason::kBadMagic, what);
  }
  if (version != kRoomProtocolVersion) {
    return wire_error(DropReason::kWrongVersion, what);
  }
  if (a > static_cast<std::uint8_t>(AuthMode::kPassphrase)) {
    return wire_error(DropReason::kOutOfRange, what);
  }
  auth = static_cast<AuthMode>(a);
  return wire_ok();
}

void write_head(WireWriter& w, const std::array<std::byte, 4>& magic, std::uint16_t version,
                AuthMode auth) {
  w.bytes(magic);
  w.u16(version);
  w.u8(static_cast<std::uint8_t>(auth));
}

// BLAKE2b-256, keyed or not, over pieces.
class Blake {
 public:
  explicit Blake(std::span<const std::byte> key = {}) {
    crypto_generichash_init(&state_, key.empty() ? nullptr : uchars(key), key.size(), 32);
  }
  Blake& add(std::span<const std::byte> bytes) {
    crypto_generichash_update(&state_, uchars(bytes), bytes.size());
    return *this;
  }
  Blake& add(std::string_view text) {
    return add(std::as_bytes(std::span(text.data(), text.size())));
  }
  Blake& add(std::uint8_t v) { return add(std::as_bytes(std::span(&v, 1))); }
  Key finish() {
    Key out{};
    crypto_generichash_final(&state_, uchars(std::span<std::byte>(out)), out.size());
    return out;
  }

 private:
  crypto_generichash_state state_{};
};

// The key that seals the key message `from` sends `to`: one per direction of the pair.
Key key_message_key(const Key& prk, RoomMemberId from, RoomMemberId to) {
  Key out{};
  crypto_kdf_derive_from_key(uchars(std::span<std::byte>(out)), out.size(), from < to ? 1 : 2,
                             "DxRoomKy", uchars(std::span<const std::byte>(prk)));
  return out;
}

using AeadNonce = std::array<unsigned char, crypto_aead_xchacha20poly1305_ietf_NPUBBYTES>;
constexpr std::size_t kGrantBytes = kProofNameBytes + sizeof(Key);

bool belongs_on(std::uint8_t type, Channel channel) {
  const bool tracking = type == static_cast<std::uint8_t>(MessageType::kTracking);
  const bool reliable = type == static_cast<std::uint8_t>(MessageType::kHello) ||
                        type == static_cast<std::uint8_t>(MessageType::kTargetMap) ||
                        type == static_cast<std::uint8_t>(MessageType::kHeartbeat) ||
                        type == static_cast<std::uint8_t>(MessageType::kBye) ||
                        type == static_cast<std::uint8_t>(MessageType::kAvatarRequest) ||
                        type == static_cast<std::uint8_t>(MessageType::kAvatarData);
  return channel == Channel::kTracking ? tracking : reliable;
}

}  // namespace

std::size_t encode(const RoomParams& params, std::span<std::byte> out) {
  if (out.size() < kRoomParamsBytes) {
    return 0;
  }
  WireWriter w(out.first(kRoomParamsBytes));
  write_head(w, kRoomParamsMagic, params.version, params.auth);
  w.bytes(params.salt);
  w.u32(params.kdf.opslimit);
  w.u32(params.kdf.memlimit_kib);
  return w.failed() ? 0 : w.size();
}

WireResult decode(std::span<const std::byte> bytes, RoomParams& out) {
  if (bytes.empty()) {
    return wire_error(DropReason::kEmpty, "room_params");
  }
  WireReader r(bytes);
  RoomParams p;
  if (WireResult e = read_head(r, kRoomParamsMagic, p.version, p.auth, "room_params.head");
      !e.ok()) {
    return e;
  }
  if (!r.bytes(p.salt) || !r.u32(p.kdf.opslimit) || !r.u32(p.kdf.memlimit_kib)) {
    return wire_error(DropReason::kTruncated, "room_params");
  }
  if (r.remaining() != 0) {
    return wire_error(DropReason::kTrailingBytes, "room_params");
  }
  if (p.auth == AuthMode::kPassphrase &&
      (p.kdf.opslimit < kMinKdfOps || p.kdf.opslimit > kMaxKdfOps ||
       p.kdf.memlimit_kib < kMinKdfMemKib || p.kdf.memlimit_kib > kMaxKdfMemKib)) {
    return wire_error(DropReason::kOutOfRange, "room_params.kdf");
  }
  if (p.auth == AuthMode::kOpen &&
      (!all_zero(p.salt) || p.kdf.opslimit != 0 || p.kdf.memlimit_kib != 0)) {
    return wire_error(DropReason::kOutOfRange, "room_params.open");
  }
  out = p;
  return wire_ok();
}

std::size_t encode(const Announce& announce, std::span<std::byte> out) {
  if (out.size() < kAnnounceBytes) {
    return 0;
  }
  WireWriter w(out.first(kAnnounceBytes));
  write_head(w, kAnnounceMagic, announce.version, announce.auth);
  w.bytes(announce.challenge);
  w.bytes(announce.key);
  return w.failed() ? 0 : w.size();
}

WireResult decode(std::span<const std::byte> bytes, Announce& out) {
  if (bytes.empty()) {
    return wire_error(DropReason::kEmpty, "announce");
  }
  WireReader r(bytes);
  Announce a;
  if (WireResult e = read_head(r, kAnnounceMagic, a.version, a.auth, "announce.head"); !e.ok()) {
    return e;
  }
  if (!r.bytes(a.challenge) || !r.bytes(a.key)) {
    return wire_error(DropReason::kTruncated, "announce");
  }
  if (r.remaining() != 0) {
    return wire_error(DropReason::kTrailingBytes, "announce");
  }
  if (a.auth == AuthMode::kOpen && !all_zero(a.key)) {
    return wire_error(DropReason::kOutOfRange, "announce.key");
  }
  out = a;
  return wire_ok();
}

RoomParams make_room_params(bool passphrase, const KdfCost& cost) {
  RoomParams p;
  if (passphrase) {
    p.auth = AuthMode::kPassphrase;
    random_bytes(p.salt);
    p.kdf = cost;
  }
  return p;
}

Entry make_entry(AuthMode auth) {
  Entry e;
  e.announce.auth = auth;
  random_bytes(e.announce.challenge);
  if (auth == AuthMode::kPassphrase) {
    e.keys = make_exchange_keys();
    e.announce.key = e.keys.public_key;
  }
  return e;
}

Key room_transcript(const RoomParams& params, RoomMemberId a, const Announce& a_announce,
                    RoomMemberId b, const Announce& b_announce) {
  const bool a_first = a < b;
  const Announce& low = a_first ? a_announce : b_announce;
  const Announce& high = a_first ? b_announce : a_announce;
  std::array<std::byte, kRoomParamsBytes> p{};
  std::array<std::byte, kAnnounceBytes> l{};
  std::array<std::byte, kAnnounceBytes> h{};
  encode(params, p);
  encode(low, l);
  encode(high, h);
  return Blake()
      .add("deixis room transcript")
      .add(p)
      .add(l)
      .add(h)
      .add(std::min(a, b))
      .add(std::max(a, b))
      .finish();
}

std::optional<Key> room_pair_secret(const Key& master, const Key& transcript, RoomMemberId self,
                                    const ExchangeKeyPair& ours, RoomMemberId peer,
                                    const ExchangeKey& theirs) {
  if (self == peer || !sodium_ready()) {
    return std::nullopt;
  }
  // Named from the lower id's (crypto_kx's client's) side, so that both hash the same bytes.
  Key client_rx{};
  Key client_tx{};
  const auto* our_public = uchars(std::span<const std::byte>(ours.public_key));
  const auto* our_secret = uchars(std::span<const std::byte>(ours.secret));
  const auto* their_public = uchars(std::span<const std::byte>(theirs));
  const int failed = self < peer
                         ? crypto_kx_client_session_keys(uchars(std::span<std::byte>(client_rx)),
                                                         uchars(std::span<std::byte>(client_tx)),
                                                         our_public, our_secret, their_public)
                         : crypto_kx_server_session_keys(uchars(std::span<std::byte>(client_tx)),
                                                         uchars(std::span<std::byte>(client_rx)),
                                                         our_public, our_secret, their_public);
  if (failed != 0) {
    return std::nullopt;
  }
  Key prk =
      Blake(master).add("deixis room keys").add(transcript).add(client_rx).add(client_tx).finish();
  wipe(client_rx);
  wipe(client_tx);
  return prk;
}

std::size_t seal_key_message(const Key& prk, const Key& transcript, RoomMemberId from,
                             RoomMemberId to, std::string_view site, const Key& sender_key,
                             std::span<std::byte> out) {
  if (out.size() < kKeyMessageBytes || site.size() > kMaxTextBytes) {
    return 0;
  }
  std::array<std::byte, kGrantBytes> plain{};
  plain[0] = static_cast<std::byte>(site.size());
  std::copy(site.begin(), site.end(),
            reinterpret_cast<char*>(plain.data() + 1));  // NOLINT: bytes of the name
  std::copy(sender_key.begin(), sender_key.end(), plain.begin() + kProofNameBytes);
  Key key = key_message_key(prk, from, to);
  const AeadNonce nonce{};  // each direction's key seals exactly one message
  out[0] = static_cast<std::byte>(kKeyMessageType);
  crypto_aead_xchacha20poly1305_ietf_encrypt(
      uchars(out.subspan(1)), nullptr, uchars(std::span<const std::byte>(plain)), plain.size(),
      uchars(transcript), transcript.size(), nullptr, nonce.data(),
      uchars(std::span<const std::byte>(key)));
  wipe(key);
  wipe(plain);
  return kKeyMessageBytes;
}

KeyGrant::~KeyGrant() {
  wipe(sender_key);
}

WireResult open_key_message(const Key& prk, const Key& transcript, RoomMemberId from,
                            RoomMemberId to, std::span<const std::byte> packet, KeyGrant& out) {
  if (packet.empty()) {
    return wire_error(DropReason::kEmpty, "key_message");
  }
  if (packet[0] != static_cast<std::byte>(kKeyMessageType)) {
    return wire_error(DropReason::kUnknownType, "key_message.type");
  }
  if (packet.size() < kKeyMessageBytes) {
    return wire_error(DropReason::kTruncated, "key_message");
  }
  if (packet.size() > kKeyMessageBytes) {
    return wire_error(DropReason::kTrailingBytes, "key_message");
  }
  std::array<std::byte, kGrantBytes> plain{};
  Key key = key_message_key(prk, from, to);
  const AeadNonce nonce{};
  const std::span<const std::byte> body = packet.subspan(1);
  const int failed = crypto_aead_xchacha20poly1305_ietf_decrypt(
      uchars(std::span<std::byte>(plain)), nullptr, nullptr, uchars(body), body.size(),
      uchars(transcript), transcript.size(), nonce.data(), uchars(std::span<const std::byte>(key)));
  wipe(key);
  if (failed != 0) {
    return wire_error(DropReason::kDecryptFailed, "key_message");
  }
  const auto n = std::to_integer<std::size_t>(plain[0]);
  const std::span<const std::byte> name = std::span(plain).subspan(1, kMaxTextBytes);
  const std::string_view site(reinterpret_cast<const char*>(name.data()),
                              std::min(n, kMaxTextBytes));
  if (n == 0 || n > kMaxTextBytes || !all_zero(name.subspan(std::min(n, kMaxTextBytes))) ||
      !is_wire_text(site)) {
    wipe(plain);
    return wire_error(DropReason::kBadText, "key_message.site");
  }
  out.site.assign(site);
  std::copy_n(plain.begin() + kProofNameBytes, out.sender_key.size(), out.sender_key.begin());
  wipe(plain);
  return wire_ok();
}

std::size_t RoomSealer::seal(Channel channel, std::span<const std::byte> inner,
                             std::span<std::byte> out) {
  if (channel == Channel::kTracking) {
    return sealer_.seal(channel, inner, out);
  }
  // Padded to a size bucket first, so that sizes do not tell name lengths.
  const std::size_t padded = pad(inner, padded_);
  return padded == 0 ? 0 : sealer_.seal(channel, std::span(padded_).first(padded), out);
}

WireResult RoomOpener::open(Channel channel, std::span<const std::byte> sealed,
                            std::span<std::byte> scratch, std::span<const std::byte>& inner) {
  std::span<const std::byte> plain;
  if (WireResult e = opener_.open(channel, sealed, scratch, plain); !e.ok()) {
    return e;
  }
  if (channel == Channel::kReliable) {
    plain = unpad(plain);
    if (plain.empty()) {
      return wire_error(DropReason::kOutOfRange, "sealed.padding");
    }
  }
  if (plain.empty() || !belongs_on(std::to_integer<std::uint8_t>(plain[0]), channel)) {
    return wire_error(plain.empty() ? DropReason::kEmpty : DropReason::kWrongChannel,
                      "sealed.inner");
  }
  inner = plain;
  return wire_ok();
}

}  // namespace deixis::net
