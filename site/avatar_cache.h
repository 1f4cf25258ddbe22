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
#include <cstdint>
#include <filesystem>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "avatar/avatar_loader.h"
#include "core/target_map.h"
#include "ik/avatar_solver.h"
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

// Which avatar a remote person wears here (session.json people[].avatar.source).
enum class AvatarSource : std::uint8_t {
  kDefault,   // the site's own (its file's remote_avatar.avatar)
  kChosen,    // the file the person chose, sent by their site
  kOverride,  // the one this site shows everyone in (--remote-avatar)
};
std::string_view avatar_source_name(AvatarSource source);

// An avatar file loaded for remote people to wear: its mesh and rig, and the solver built for
// the rig. Loaded once per file and session, shared by everyone who wears it, never changed.
struct PersonAvatar {
  AvatarSource source = AvatarSource::kChosen;
  net::AvatarHash hash{};
  avatar::Avatar avatar;
  ik::AvatarSolver solver;
};

// Loads `file` (read from `source`, untrusted) as an avatar people may wear; throws
// deixis::Error naming `source` when it is no usable avatar (load_avatar, AvatarSolver::build).
std::shared_ptr<const PersonAvatar> load_person_avatar(std::span<const std::byte> file,
                                                       const std::string& source,
                                                       AvatarSource kind);
// The same from a file on disk (at most net::kAvatarFileMaxBytes), with its bytes (what a site
// offers as its user's choice).
std::shared_ptr<const PersonAvatar> load_person_avatar(
    const std::filesystem::path& file, AvatarSource kind,
    std::shared_ptr<const std::vector<std::byte>>* bytes = nullptr);

// What a person's flags ask their site to wear and show (`--avatar` and `--remote-avatar` of
// host, join, sim and xr; docs/avatars.md): the file they chose, offered by its hash to the sites
// they meet, and the local override every remote person wears here. Empty paths: neither.
struct WornAvatars {
  std::shared_ptr<const std::vector<std::byte>> own_file{};
  std::shared_ptr<const PersonAvatar> override_avatar{};
};
// Loads both as every other site would load them (load_person_avatar), so that a file they
// could not show is refused before connecting rather than found out by each of them; throws
// deixis::Error naming the file.
WornAvatars load_worn_avatars(const std::filesystem::path& chosen,
                              const std::filesystem::path& override_file);

// The avatars remote people chose, from their hello's hash to an avatar they wear here
// (docs/avatars.md, "A person's own avatar"): looked up in the cache, else asked for (once per
// person and session) and stored once downloaded. Files are read, hashed and loaded on a
// thread of their own, so a site's 30 Hz tick never waits for a load; next() hands over what is
// due. A file that does not load leaves the person in the site's default avatar, with one
// warning naming the person and the reason (at most kMaxWarnings a session, then counted).
//
//   named(person, site, hash)   their hello (again)
//   next(update)                each tick: kRequest → ask their session for the file;
//                                          kWear → RemotePeople::wear
//   downloaded / download_failed as their session's download ends
class ChosenAvatars {
 public:
  static constexpr std::size_t kMaxAvatars = 32;   // distinct files loaded in a session
  static constexpr std::size_t kMaxRequests = 64;  // files asked for in a session
  static constexpr std::size_t kMaxWarnings = 8;

  struct Update {
    enum class Kind : std::uint8_t { kRequest, kWear };
    Kind kind = Kind::kWear;
    PersonId person = kNoPerson;
    std::shared_ptr<const PersonAvatar> avatar;  // kWear
  };

  // `cache_dir` empty: files are kept in memory for the session only.
  explicit ChosenAvatars(std::filesystem::path cache_dir);
  ~ChosenAvatars();  // waits for loads in progress
  ChosenAvatars(const ChosenAvatars&) = delete;
  ChosenAvatars& operator=(const ChosenAvatars&) = delete;

  // Person `id` (of site `site`) names `hash` in their hello; nullopt: none (they wear the
  // site's default). The same hash again changes nothing.
  void named(PersonId id, const std::string& site, const std::optional<net::AvatarHash>& hash);
  // The file asked for from person `id` arrived whole (its hash checked by net/avatar_transfer.h).
  void downloaded(PersonId id, std::span<const std::byte> file);
  // It did not (`reason`: the transfer's, or why it could not be asked for).
  void download_failed(PersonId id, const std::string& reason);
  void left(PersonId id);

  // The next thing the site must do, if any. Allocates nothing when nothing is due.
  bool next(Update& out);
  // Whether person `id` waits for a requested download.
  bool awaiting(PersonId id) const;

  std::uint64_t loaded() const { return loaded_count_; }
  std::uint64_t failures() const { return failures_; }
  const AvatarCache& cache() const { return cache_; }

 private:
  struct Person;
  struct Job;
  struct Result;
  Person* find(PersonId id);
  const Person* find(PersonId id) const;
  void start(Person& p, std::shared_ptr<const std::vector<std::byte>> file);
  void finish(Job& job);
  void fail(Person& p, const std::string& reason);
  std::shared_ptr<const PersonAvatar> known(const net::AvatarHash& hash) const;

  AvatarCache cache_;
  std::mutex cache_mutex_;  // the cache's files, between load threads
  std::vector<Person> people_;
  std::vector<Job> jobs_;
  std::vector<std::shared_ptr<const PersonAvatar>> avatars_;     // loaded this session
  std::vector<std::pair<net::AvatarHash, std::string>> broken_;  // files that did not load
  std::vector<Update> updates_;
  std::size_t updates_taken_ = 0;
  std::size_t requests_ = 0;
  std::uint64_t loaded_count_ = 0;
  std::uint64_t failures_ = 0;
  std::uint64_t warnings_ = 0;
};

}  // namespace deixis::site
