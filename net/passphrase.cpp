#include "net/passphrase.h"

#include <sodium.h>

#include <string_view>

namespace deixis::net {

namespace {

unsigned char* bytes_of(std::span<std::byte> s) {
  return reinterpret_cast<unsigned char*>(s.data());
}
const unsigned char* bytes_of(std::span<const std::byte> s) {
  return reinterpret_cast<const unsigned char*>(s.data());
}

// BLAKE2b-256 keyed by `key` over the concatenation of `parts`.
template <typename... Parts>
std::array<std::byte, 32> keyed_hash(const Key& key, std::string_view label,
                                     const Parts&... parts) {
  crypto_generichash_state state;
  crypto_generichash_init(&state, bytes_of(std::span<const std::byte>(key)), key.size(), 32);
  crypto_generichash_update(&state, reinterpret_cast<const unsigned char*>(label.data()),
                            label.size());
  (crypto_generichash_update(&state, bytes_of(std::span<const std::byte>(parts)), parts.size()),
   ...);
  std::array<std::byte, 32> out{};
  crypto_generichash_final(&state, bytes_of(std::span<std::byte>(out)), out.size());
  return out;
}

Key subkey(const Key& parent, std::uint64_t id, const char (&context)[9]) {
  static_assert(crypto_kdf_CONTEXTBYTES == 8);
  Key out{};
  crypto_kdf_derive_from_key(bytes_of(std::span<std::byte>(out)), out.size(), id, context,
                             bytes_of(std::span<const std::byte>(parent)));
  return out;
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

Proof join_proof(const Key& master, const Salt& salt, const Challenge& host,
                 const Challenge& joiner) {
  return keyed_hash(subkey(master, 1, "DeixAuth"), "deixis join", salt, host, joiner);
}

Proof accept_proof(const Key& master, const Salt& salt, const Challenge& host,
                   const Challenge& joiner) {
  return keyed_hash(subkey(master, 1, "DeixAuth"), "deixis accept", salt, host, joiner);
}

bool proofs_equal(const Proof& a, const Proof& b) {
  static_assert(kProofBytes == crypto_verify_32_BYTES);
  return crypto_verify_32(bytes_of(std::span<const std::byte>(a)),
                          bytes_of(std::span<const std::byte>(b))) == 0;
}

SessionKeys derive_session_keys(const Key& master, const Challenge& host, const Challenge& joiner,
                                bool is_host) {
  const Key session = keyed_hash(master, "deixis session", host, joiner);
  const Key host_to_joiner = subkey(session, 1, "DeixSess");
  const Key joiner_to_host = subkey(session, 2, "DeixSess");
  return is_host ? SessionKeys{host_to_joiner, joiner_to_host}
                 : SessionKeys{joiner_to_host, host_to_joiner};
}

void random_bytes(std::span<std::byte> out) {
  if (sodium_ready()) {
    randombytes_buf(out.data(), out.size());
  }
}

}  // namespace deixis::net
