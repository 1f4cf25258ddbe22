// The avatar cache (site/avatar_cache.h): files kept by content hash, checked again when read,
// bounded in count.

#include <gtest/gtest.h>

#include <fstream>

#include "site/avatar_cache.h"
#include "test_support.h"

namespace deixis::site {
namespace {

std::vector<std::byte> file_of(std::size_t n, int seed) {
  std::vector<std::byte> f(n);
  for (std::size_t i = 0; i < n; ++i) {
    f[i] = static_cast<std::byte>((i * 31 + static_cast<std::size_t>(seed) * 7) & 0xFFu);
  }
  return f;
}

TEST(AvatarCache, KeepsAFileUnderItsHashAndGivesItBack) {
  testing::ScratchDir dir;
  AvatarCache cache(dir.path() / "avatars");
  const std::vector<std::byte> file = file_of(5000, 1);
  const net::AvatarHash hash = net::avatar_hash(file);
  EXPECT_FALSE(cache.find(hash));
  ASSERT_TRUE(cache.store(hash, file));
  const auto back = cache.find(hash);
  ASSERT_TRUE(back);
  EXPECT_EQ(*back, file);
  EXPECT_FALSE(cache.find(net::avatar_hash(file_of(5000, 2))));
}

TEST(AvatarCache, AFileChangedOnDiskIsRemovedNotUsed) {
  testing::ScratchDir dir;
  AvatarCache cache(dir.path());
  const std::vector<std::byte> file = file_of(5000, 3);
  const net::AvatarHash hash = net::avatar_hash(file);
  ASSERT_TRUE(cache.store(hash, file));
  const auto path = dir.path() / (net::to_hex(hash) + ".glb");
  ASSERT_TRUE(std::filesystem::exists(path));
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(100);
    f.put('X');
  }
  EXPECT_FALSE(cache.find(hash));
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(AvatarCache, WithoutADirectoryNothingIsKept) {
  AvatarCache cache({});
  const std::vector<std::byte> file = file_of(100, 4);
  EXPECT_FALSE(cache.store(net::avatar_hash(file), file));
  EXPECT_FALSE(cache.find(net::avatar_hash(file)));
}

TEST(AvatarCache, KeepsAtMostItsNumberOfFiles) {
  testing::ScratchDir dir;
  AvatarCache cache(dir.path());
  for (int i = 0; i < static_cast<int>(AvatarCache::kMaxFiles) + 5; ++i) {
    const std::vector<std::byte> file = file_of(64, 100 + i);
    ASSERT_TRUE(cache.store(net::avatar_hash(file), file));
  }
  std::size_t kept = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) {
    ++kept;
  }
  EXPECT_EQ(kept, AvatarCache::kMaxFiles);
}

TEST(AvatarCache, DefaultDirectoryFollowsXdgThenHome) {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  const std::string saved = xdg != nullptr ? xdg : "";
  setenv("XDG_CACHE_HOME", "/tmp/xdg-cache", 1);
  EXPECT_EQ(AvatarCache::default_dir(), std::filesystem::path("/tmp/xdg-cache/deixis/avatars"));
  unsetenv("XDG_CACHE_HOME");
  if (const char* home = std::getenv("HOME"); home != nullptr && *home == '/') {
    EXPECT_EQ(AvatarCache::default_dir(),
              std::filesystem::path(home) / ".cache" / "deixis" / "avatars");
  }
  if (!saved.empty()) {
    setenv("XDG_CACHE_HOME", saved.c_str(), 1);
  }
}

}  // namespace
}  // namespace deixis::site
