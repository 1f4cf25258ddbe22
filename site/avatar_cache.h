#pragma once
// Avatar files that other people chose, kept on disk by content hash (docs/avatars.md, "A
// person's own avatar"), so that a file travels once per person and not once per session. A file
// is stored only after its bytes hashed to the name its hello gave (net/avatar_transfer.h), and is
// hashed again when read back: a file changed on disk is removed, never used. The cache keeps at
// most kMaxFiles files and kMaxBytes bytes, dropping the least recently stored first.
//
// The cache is a convenience, never a reason to fail: a directory that cannot be created or
// written leaves the site working from memory, with one warning.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

#include "net/avatar_transfer.h"

namespace deixis::site {

class AvatarCache {
 public:
  static constexpr std::size_t kMaxFiles = 64;
  static constexpr std::uintmax_t kMaxBytes = 256u * 1024u * 1024u;

  // `dir` empty: nothing is kept on disk.
  explicit AvatarCache(std::filesystem::path dir);

  // $XDG_CACHE_HOME/deixis/avatars, else $HOME/.cache/deixis/avatars; empty when neither is set.
  static std::filesystem::path default_dir();

  // The file named `hash`, if it is kept and its bytes still hash to it.
  std::optional<std::vector<std::byte>> find(const net::AvatarHash& hash) const;
  // Keeps `file` under `hash` (the caller checked that it hashes to it); false when it could not.
  bool store(const net::AvatarHash& hash, std::span<const std::byte> file);

  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path path_of(const net::AvatarHash& hash) const;
  void trim();

  std::filesystem::path dir_;
};

}  // namespace deixis::site
