#include "site/avatar_cache.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <system_error>
#include <utility>

namespace deixis::site {

namespace fs = std::filesystem;

AvatarCache::AvatarCache(fs::path dir) : dir_(std::move(dir)) {}

fs::path AvatarCache::default_dir() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg == '/') {
    return fs::path(xdg) / "deixis" / "avatars";
  }
  if (const char* home = std::getenv("HOME"); home != nullptr && *home == '/') {
    return fs::path(home) / ".cache" / "deixis" / "avatars";
  }
  return {};
}

fs::path AvatarCache::path_of(const net::AvatarHash& hash) const {
  return dir_ / (net::to_hex(hash) + ".glb");
}

std::optional<std::vector<std::byte>> AvatarCache::find(const net::AvatarHash& hash) const {
  if (dir_.empty()) {
    return std::nullopt;
  }
  const fs::path file = path_of(hash);
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec || size == 0 || size > net::kAvatarFileMaxBytes) {
    return std::nullopt;
  }
  std::ifstream in(file, std::ios::binary);
  std::vector<std::byte> bytes(static_cast<std::size_t>(size));
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!in || net::avatar_hash(bytes) != hash) {
    spdlog::warn("avatar cache: {} does not hold what its name says; removed", file.string());
    fs::remove(file, ec);
    return std::nullopt;
  }
  return bytes;
}

bool AvatarCache::store(const net::AvatarHash& hash, std::span<const std::byte> file) {
  if (dir_.empty()) {
    return false;
  }
  std::error_code ec;
  fs::create_directories(dir_, ec);
  const fs::path final_path = path_of(hash);
  const fs::path temporary = final_path.string() + ".part";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(file.data()),
              static_cast<std::streamsize>(file.size()));
    if (!out) {
      spdlog::warn("avatar cache: cannot write {}; avatars are kept in memory only",
                   temporary.string());
      fs::remove(temporary, ec);
      return false;
    }
  }
  // Renamed into place, so that a reader never sees half a file under a valid name.
  fs::rename(temporary, final_path, ec);
  if (ec) {
    fs::remove(temporary, ec);
    return false;
  }
  trim();
  return true;
}

void AvatarCache::trim() {
  struct Entry {
    fs::path path;
    fs::file_time_type time;
    std::uintmax_t size = 0;
  };
  std::vector<Entry> entries;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir_, ec)) {
    if (e.is_regular_file(ec) && e.path().extension() == ".glb") {
      entries.push_back({e.path(), e.last_write_time(ec), e.file_size(ec)});
    }
  }
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.time > b.time; });  // newest first
  std::uintmax_t bytes = 0;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    bytes += entries[i].size;
    if (i >= kMaxFiles || bytes > kMaxBytes) {
      fs::remove(entries[i].path, ec);
    }
  }
}

}  // namespace deixis::site
