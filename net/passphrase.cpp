#include "net/passphrase.h"

#include <sodium.h>

#include <string_view>

#include "net/wire.h"

namespace deixis::net {

namespace {

unsigned char* bytes_of(std::span<std::byte> s) {
  return reinterpret_cast<unsigned char*>(s.data());
}
const unsigned char* bytes_of(std::span<const std::byte> s) {
  return reinterpret_cast<const unsigned char*>(s.data());
}

// A BLAKE2b-256 state keyed by `key` (or unkeyed when `key` is empty), fed piece by piece.
class Hash {
 public:
  explicit Hash(std::span<const std::byte> key) {
    crypto_generichash_init(&state_, key.empty() ? nullptr : bytes_of(key), key.size(), 32);
  }
  Hash& add(std::span<const std::byte> bytes) {
    crypto_generichash_update(&state_, bytes_of(bytes), bytes.size());
    return *this;
  }
  Hash& add(std::string_view text) {
    return add(std::as_bytes(std::span(text.data(), text.size())));
  }
  // Text with its length first, so that two fields can never run into each other.
  Hash& add_text(std::string_view text) {
    const std::byte length{static_cast<unsigned char>(text.size())};
    return add(std::span(&length, 1)).add(text);
  }
  // An unsigned integer as its little-endian bytes, as on the wire.
  template <typename T>
  Hash& add_le(T v) {
    std::array<std::byte, sizeof(T)> b{};
    for (std::size_t i = 0; i < sizeof(T); ++i) {
      b[i] = static_cast<std::byte>((v >> (8 * i)) & 0xFFu);
    }
    return add(b);
  }
  Key finish() {
    Key out{};
    crypto_generichash_final(&state_, bytes_of(std::span<std::byte>(out)), out.size());
    return out;
  }

 private:
  crypto_generichash_state state_{};
};

Key subkey(const Key& parent, std::uint64_t id, const char (&context)[9]) {
  static_assert(crypto_kdf_CONTEXTBYTES == 8);
  Key out{};
  crypto_kdf_derive_from_key(bytes_of(std::span<std::byte>(out)), out.size(), id, context,
                             bytes_of(std::span<const std::byte>(parent)));
  return out;
}

// The proofs' AEAD: each proof key is used for exactly one message, so a zero nonce is safe.
static_assert(crypto_aead_xchacha20poly1305_ietf_ABYTES == kProofBytes - kProofNameBytes);
using ProofNonce = std::array<unsigned char, crypto_aead_xchacha20poly1305_ietf_NPUBBYTES>;

Proof seal_name(const Key& key, std::string_view site, std::span<const std::byte> ad) {
  std::array<std::byte, kProofNameBytes> plain{};
  const std::size_t n = std::min(site.size(), kMaxTextBytes);
  plain[0] = static_cast<std::byte>(n);
  for (std::size_t i = 0; i < n; ++i) {
    plain[1 + i] = static_cast<std::byte>(site[i]);
  }
  Proof out{};
  const ProofNonce nonce{};
  crypto_aead_xchacha20poly1305_ietf_encrypt(
      bytes_of(std::span<std::byte>(out)), nullptr, bytes_of(std::span<const std::byte>(plain)),
      plain.size(), bytes_of(ad), ad.size(), nullptr, nonce.data(),
      bytes_of(std::span<const std::byte>(key)));
  return out;
}

std::optional<std::string> open_name(const Key& key, const Proof& proof,
                                     std::span<const std::byte> ad) {
  std::array<std::byte, kProofNameBytes> plain{};
  const ProofNonce nonce{};
  if (crypto_aead_xchacha20poly1305_ietf_decrypt(
          bytes_of(std::span<std::byte>(plain)), nullptr, nullptr,
          bytes_of(std::span<const std::byte>(proof)), proof.size(), bytes_of(ad), ad.size(),
          nonce.data(), bytes_of(std::span<const std::byte>(key))) != 0) {
    return std::nullopt;
  }
  const auto n = std::to_integer<std::size_t>(plain[0]);
  if (n == 0 || n > kMaxTextBytes) {
    return std::nullopt;
  }
  std::string site(reinterpret_cast<const char*>(plain.data() + 1), n);
  for (std::size_t i = 1 + n; i < plain.size(); ++i) {
    if (plain[i] != std::byte{0}) {
      return std::nullopt;  // the padding is part of the rule
    }
  }
  if (!is_wire_text(site)) {
    return std::nullopt;
  }
  return site;
}

// The accept proof's associated data: the transcript, then the joiner's site.
std::array<std::byte, 32 + kProofNameBytes> accept_ad(const Key& transcript,
                                                      std::string_view joiner_site) {
  std::array<std::byte, 32 + kProofNameBytes> ad{};
  std::copy(transcript.begin(), transcript.end(), ad.begin());
  const std::size_t n = std::min(joiner_site.size(), kMaxTextBytes);
  ad[32] = static_cast<std::byte>(n);
  for (std::size_t i = 0; i < n; ++i) {
    ad[33 + i] = static_cast<std::byte>(joiner_site[i]);
  }
  return ad;
}

}  // namespace

bool sodium_ready() {
  return sodium_init() >= 0;  // 0: initialised now, 1: already initialised
}

std::optional<Key> derive_master_key(std::string_view passphrase, const Salt& salt,
                                     const KdfCost& cost) {
  static_assert(crypto_pwhash_SALTBYTES == kSaltBytes);
  if (!sodium_ready()) {
    return std::nullopt;
  }
  Key key{};
  if (crypto_pwhash(bytes_of(std::span<std::byte>(key)), key.size(), passphrase.data(),
                    passphrase.size(), bytes_of(std::span<const std::byte>(salt)), cost.opslimit,
                    static_cast<std::size_t>(cost.memlimit_kib) * 1024u,
                    crypto_pwhash_ALG_ARGON2ID13) != 0) {
    return std::nullopt;
  }
  return key;
}

ExchangeKeyPair::~ExchangeKeyPair() {
  wipe(secret);
}

ExchangeKeyPair make_exchange_keys() {
  static_assert(crypto_kx_PUBLICKEYBYTES == kExchangeKeyBytes && crypto_kx_SECRETKEYBYTES == 32);
  ExchangeKeyPair keys;
  if (sodium_ready()) {
    crypto_kx_keypair(bytes_of(std::span<std::byte>(keys.public_key)),
                      bytes_of(std::span<std::byte>(keys.secret)));
  }
  return keys;
}

Key transcript_of(const Welcome& welcome, const Join& join) {
  return Hash({})
      .add("deixis transcript")
      .add_le(welcome.protocol_version)
      .add_le(static_cast<std::uint8_t>(welcome.auth))
      .add(welcome.salt)
      .add_le(welcome.kdf.opslimit)
      .add_le(welcome.kdf.memlimit_kib)
      .add(welcome.host_challenge)
      .add(welcome.host_key)
      .add_le(join.protocol_version)
      .add_le(static_cast<std::uint8_t>(join.auth))
      .add(join.joiner_challenge)
      .add(join.joiner_key)
      .finish();
}

std::optional<Key> handshake_secret(const Key& master, const Key& transcript,
                                    const ExchangeKeyPair& ours, const ExchangeKey& theirs,
                                    bool is_host) {
  static_assert(crypto_kx_SESSIONKEYBYTES == 32);
  // Named from the joiner's (crypto_kx's client's) side, so that both sides hash the same bytes.
  Key client_rx{};
  Key client_tx{};
  const auto* our_public = bytes_of(std::span<const std::byte>(ours.public_key));
  const auto* our_secret = bytes_of(std::span<const std::byte>(ours.secret));
  const auto* their_public = bytes_of(std::span<const std::byte>(theirs));
  const int failed = is_host
                         ? crypto_kx_server_session_keys(bytes_of(std::span<std::byte>(client_tx)),
                                                         bytes_of(std::span<std::byte>(client_rx)),
                                                         our_public, our_secret, their_public)
                         : crypto_kx_client_session_keys(bytes_of(std::span<std::byte>(client_rx)),
                                                         bytes_of(std::span<std::byte>(client_tx)),
                                                         our_public, our_secret, their_public);
  if (failed != 0) {
    return std::nullopt;
  }
  const Key prk =
      Hash(master).add("deixis keys").add(transcript).add(client_rx).add(client_tx).finish();
  wipe(client_rx);
  wipe(client_tx);
  return prk;
}

Proof seal_join_proof(const Key& prk, const Key& transcript, std::string_view joiner_site) {
  Key key = subkey(prk, 1, "DeixProf");
  const Proof proof = seal_name(key, joiner_site, transcript);
  wipe(key);
  return proof;
}

Proof seal_accept_proof(const Key& prk, const Key& transcript, std::string_view joiner_site,
                        std::string_view host_site) {
  Key key = subkey(prk, 2, "DeixProf");
  const auto ad = accept_ad(transcript, joiner_site);
  const Proof proof = seal_name(key, host_site, ad);
  wipe(key);
  return proof;
}

std::optional<std::string> open_join_proof(const Key& prk, const Key& transcript,
                                           const Proof& proof) {
  Key key = subkey(prk, 1, "DeixProf");
  auto site = open_name(key, proof, transcript);
  wipe(key);
  return site;
}

std::optional<std::string> open_accept_proof(const Key& prk, const Key& transcript,
                                             std::string_view joiner_site, const Proof& proof) {
  Key key = subkey(prk, 2, "DeixProf");
  const auto ad = accept_ad(transcript, joiner_site);
  auto site = open_name(key, proof, ad);
  wipe(key);
  return site;
}

SessionKeys::~SessionKeys() {
  wipe(send);
  wipe(receive);
}

SessionKeys derive_session_keys(const Key& prk, std::string_view joiner_site,
                                std::string_view host_site, bool is_host) {
  Key session = Hash(prk).add("deixis session").add_text(joiner_site).add_text(host_site).finish();
  SessionKeys keys;
  const Key host_to_joiner = subkey(session, 1, "DeixSess");
  const Key joiner_to_host = subkey(session, 2, "DeixSess");
  keys.send = is_host ? host_to_joiner : joiner_to_host;
  keys.receive = is_host ? joiner_to_host : host_to_joiner;
  wipe(session);
  return keys;
}

void random_bytes(std::span<std::byte> out) {
  if (sodium_ready()) {
    randombytes_buf(out.data(), out.size());
  }
}

void wipe(std::span<std::byte> secret) {
  sodium_memzero(secret.data(), secret.size());
}

}  // namespace deixis::net
