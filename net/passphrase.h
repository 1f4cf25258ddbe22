#pragma once
// What a passphrase session derives (libsodium; docs/protocol.md §5, "Passphrase"):
//
//   master      = Argon2id(passphrase, salt, cost)              salt, cost: the host's welcome
//   transcript  = BLAKE2b-256("deixis transcript" ‖ version ‖ auth ‖ salt ‖ cost ‖ challenges
//                             ‖ both ephemeral X25519 public keys)
//   shared      = X25519 session keys of the two ephemeral key pairs (crypto_kx, joiner = client)
//   prk         = BLAKE2b-256(key = master, "deixis keys" ‖ transcript ‖ shared)
//   join proof  = AEAD(KDF(prk, 1, "DeixProf"), the joiner's site name, ad = transcript)
//   accept proof= AEAD(KDF(prk, 2, "DeixProf"), the host's site name, ad = transcript ‖ joiner
//   site) session     = BLAKE2b-256(key = prk, "deixis session" ‖ joiner site ‖ host site)
//   host→joiner = KDF(session, 1, "DeixSess"), joiner→host = KDF(session, 2, "DeixSess")
//
// A proof is the sender's site name, padded to 64 bytes and sealed: only a peer that knows the
// passphrase can make one that opens, or read the name, and it binds the protocol version, the
// key cost, both challenges, both ephemeral keys and both site names. The ephemeral keys give
// forward secrecy (a recorded session stays unreadable if the passphrase leaks later) and keep a
// passive eavesdropper from testing passphrase guesses against a recorded handshake. The joiner
// proves first; a host answers a wrong proof with a bye only, so a peer that does not know the
// passphrase learns nothing derived from it.

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "net/messages.h"

namespace deixis::net {

using Key = std::array<std::byte, 32>;

// The master key; nullopt when libsodium cannot allocate the memory the cost asks for.
std::optional<Key> derive_master_key(std::string_view passphrase, const Salt& salt,
                                     const KdfCost& cost);

// An ephemeral X25519 key pair, fresh per connection; the secret is wiped on destruction.
struct ExchangeKeyPair {
  ExchangeKey public_key{};
  std::array<std::byte, 32> secret{};

  ExchangeKeyPair() = default;
  ExchangeKeyPair(const ExchangeKeyPair&) = default;
  ExchangeKeyPair& operator=(const ExchangeKeyPair&) = default;
  ~ExchangeKeyPair();
};
ExchangeKeyPair make_exchange_keys();

// The hash of what welcome and join said (everything but the proof).
Key transcript_of(const Welcome& welcome, const Join& join);

// The handshake secret `prk`; nullopt when the peer's public key is unusable (a low-order point).
std::optional<Key> handshake_secret(const Key& master, const Key& transcript,
                                    const ExchangeKeyPair& ours, const ExchangeKey& theirs,
                                    bool is_host);

// Proofs: `site` sealed. The accept proof's associated data also binds the joiner's site.
Proof seal_join_proof(const Key& prk, const Key& transcript, std::string_view joiner_site);
Proof seal_accept_proof(const Key& prk, const Key& transcript, std::string_view joiner_site,
                        std::string_view host_site);
// The site name inside a proof, or nullopt when it does not open (another passphrase, another
// transcript) or holds no valid wire text.
std::optional<std::string> open_join_proof(const Key& prk, const Key& transcript,
                                           const Proof& proof);
std::optional<std::string> open_accept_proof(const Key& prk, const Key& transcript,
                                             std::string_view joiner_site, const Proof& proof);

struct SessionKeys {
  Key send{};
  Key receive{};
  ~SessionKeys();
};
// `is_host` picks which direction this side sends on.
SessionKeys derive_session_keys(const Key& prk, std::string_view joiner_site,
                                std::string_view host_site, bool is_host);

// Fresh random bytes (salts, challenges).
void random_bytes(std::span<std::byte> out);
// Overwrites secret bytes so that they do not linger in memory.
void wipe(std::span<std::byte> secret);

// libsodium must be initialised before any of the above; idempotent and thread-safe.
bool sodium_ready();

}  // namespace deixis::net
