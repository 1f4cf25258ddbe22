#pragma once
// What a passphrase session derives (libsodium; docs/protocol.md, "Passphrase"):
//
//   master  = Argon2id(passphrase, salt, cost)          salt and cost: the host's, in its welcome
//   auth    = KDF(master, id 1, "DeixAuth")
//   join proof   = BLAKE2b-256(key = auth, "deixis join"   ‖ salt ‖ host challenge ‖ joiner
//   challenge) accept proof = BLAKE2b-256(key = auth, "deixis accept" ‖ salt ‖ host challenge ‖
//   joiner challenge) session = BLAKE2b-256(key = master, "deixis session" ‖ host challenge ‖
//   joiner challenge) host→joiner key = KDF(session, id 1, "DeixSess"), joiner→host key =
//   KDF(session, id 2, ...)
//
// The joiner proves first, and the host answers a wrong proof with a bye only, so a peer that
// does not know the passphrase learns nothing derived from it. Both challenges are fresh per
// connection, so the session keys are too, and a packet counter can be the AEAD nonce.

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>

#include "net/messages.h"

namespace deixis::net {

using Key = std::array<std::byte, 32>;

// The master key; nullopt when libsodium cannot allocate the memory the cost asks for.
std::optional<Key> derive_master_key(std::string_view passphrase, const Salt& salt,
                                     const KdfCost& cost);

Proof join_proof(const Key& master, const Salt& salt, const Challenge& host,
                 const Challenge& joiner);
Proof accept_proof(const Key& master, const Salt& salt, const Challenge& host,
                   const Challenge& joiner);
bool proofs_equal(const Proof& a, const Proof& b);  // constant time

struct SessionKeys {
  Key send{};
  Key receive{};
};
// `is_host` picks which direction this side sends on.
SessionKeys derive_session_keys(const Key& master, const Challenge& host, const Challenge& joiner,
                                bool is_host);

// Fresh random bytes (salts, challenges).
void random_bytes(std::span<std::byte> out);

// libsodium must be initialised before any of the above; idempotent and thread-safe.
bool sodium_ready();

}  // namespace deixis::net
