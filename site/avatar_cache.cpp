#include "site/avatar_cache.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <system_error>
#include <utility>

#include "core/error.h"

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

std::string_view avatar_source_name(AvatarSource source) {
  switch (source) {
    case AvatarSource::kDefault:
      return "default";
    case AvatarSource::kChosen:
      return "chosen";
    case AvatarSource::kOverride:
      return "override";
  }
  return "default";
}

std::shared_ptr<const PersonAvatar> load_person_avatar(std::span<const std::byte> file,
                                                       const std::string& source,
                                                       AvatarSource kind) {
  auto loaded = std::make_shared<PersonAvatar>();
  loaded->source = kind;
  loaded->hash = net::avatar_hash(file);
  loaded->avatar =
      avatar::load_avatar(std::span<const std::uint8_t>(
                              reinterpret_cast<const std::uint8_t*>(file.data()), file.size()),
                          source);
  try {
    loaded->solver = ik::AvatarSolver::build(loaded->avatar.rig);
  } catch (const Error& e) {
    throw Error(source + ": " + e.what());
  }
  return loaded;
}

std::shared_ptr<const PersonAvatar> load_person_avatar(
    const fs::path& file, AvatarSource kind, std::shared_ptr<const std::vector<std::byte>>* bytes) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec) {
    throw Error(file.string() + ": cannot read the avatar file (" + ec.message() + ")");
  }
  if (size == 0 || size > net::kAvatarFileMaxBytes) {
    throw Error(file.string() + ": " + std::to_string(size) +
                " bytes; an avatar file has 1 byte to 8 MiB (docs/avatars.md)");
  }
  auto data = std::make_shared<std::vector<std::byte>>(static_cast<std::size_t>(size));
  std::ifstream in(file, std::ios::binary);
  in.read(reinterpret_cast<char*>(data->data()), static_cast<std::streamsize>(data->size()));
  if (!in) {
    throw Error(file.string() + ": cannot read the avatar file");
  }
  std::shared_ptr<const PersonAvatar> loaded = load_person_avatar(*data, file.string(), kind);
  if (bytes != nullptr) {
    *bytes = std::move(data);
  }
  return loaded;
}

WornAvatars load_worn_avatars(const fs::path& chosen, const fs::path& override_file) {
  WornAvatars worn;
  if (!chosen.empty()) {
    load_person_avatar(chosen, AvatarSource::kChosen, &worn.own_file);
  }
  if (!override_file.empty()) {
    worn.override_avatar = load_person_avatar(override_file, AvatarSource::kOverride);
  }
  return worn;
}

// ---------------------------------------------------------------- ChosenAvatars

struct ChosenAvatars::Person {
  enum class State : std::uint8_t {
    kNone,         // names no file
    kLoading,      // looked up in the cache and loaded, on a load thread
    kDownloading,  // asked for; the session's download runs
    kWearing,      // handed over (kWear)
    kFailed,       // keeps the default for this file
  };
  PersonId id = kNoPerson;
  std::string site;
  std::optional<net::AvatarHash> hash;
  State state = State::kNone;
  bool asked = false;  // a file was asked for from this person (once per person and session)
};

struct ChosenAvatars::Result {
  enum class Kind : std::uint8_t { kLoaded, kNotCached, kBroken };
  Kind kind = Kind::kBroken;
  std::shared_ptr<const PersonAvatar> avatar;
  std::string error;
  double ms = 0.0;
  std::size_t bytes = 0;
};

struct ChosenAvatars::Job {
  net::AvatarHash hash{};
  std::string site;
  std::future<Result> result;
};

ChosenAvatars::ChosenAvatars(fs::path cache_dir) : cache_(std::move(cache_dir)) {
  people_.reserve(16);
  jobs_.reserve(8);
  updates_.reserve(16);
}

ChosenAvatars::~ChosenAvatars() {
  jobs_.clear();  // each future waits for its load thread, which uses the cache
}

ChosenAvatars::Person* ChosenAvatars::find(PersonId id) {
  for (Person& p : people_) {
    if (p.id == id) {
      return &p;
    }
  }
  return nullptr;
}

const ChosenAvatars::Person* ChosenAvatars::find(PersonId id) const {
  return const_cast<ChosenAvatars*>(this)->find(id);
}

std::shared_ptr<const PersonAvatar> ChosenAvatars::known(const net::AvatarHash& hash) const {
  for (const auto& a : avatars_) {
    if (a->hash == hash) {
      return a;
    }
  }
  return nullptr;
}

void ChosenAvatars::named(PersonId id, const std::string& site,
                          const std::optional<net::AvatarHash>& hash) {
  Person* p = find(id);
  if (p == nullptr) {
    p = &people_.emplace_back();
    p->id = id;
  }
  p->site = site;
  if (p->hash == hash) {
    return;  // the same file again (a new hello, a reconnect): what was begun goes on
  }
  p->hash = hash;
  p->state = Person::State::kNone;
  if (!hash) {
    return;
  }
  if (std::shared_ptr<const PersonAvatar> avatar = known(*hash)) {
    p->state = Person::State::kWearing;
    updates_.push_back({Update::Kind::kWear, id, std::move(avatar)});
    return;
  }
  for (const auto& [broken, reason] : broken_) {
    if (broken == *hash) {
      fail(*p, reason);
      return;
    }
  }
  p->state = Person::State::kLoading;
  const bool running =
      std::any_of(jobs_.begin(), jobs_.end(), [&](const Job& j) { return j.hash == *hash; });
  if (!running) {
    start(*p, nullptr);  // the cache first
  }
}

// A load thread: the file from the cache (`file` null) or as downloaded (then kept in the cache),
// hashed and loaded as the untrusted file it is.
void ChosenAvatars::start(Person& p, std::shared_ptr<const std::vector<std::byte>> file) {
  const net::AvatarHash hash = *p.hash;
  const std::string source =
      "the avatar file of site " + p.site + " (" + net::to_hex(hash).substr(0, 12) + ")";
  auto load = [this, hash, source, file = std::move(file)]() {
    Result r;
    std::optional<std::vector<std::byte>> cached;
    std::span<const std::byte> bytes;
    {
      const std::lock_guard<std::mutex> lock(cache_mutex_);
      if (file) {
        cache_.store(hash, *file);
        bytes = *file;
      } else if ((cached = cache_.find(hash))) {
        bytes = *cached;
      } else {
        r.kind = Result::Kind::kNotCached;
        return r;
      }
    }
    r.bytes = bytes.size();
    const auto t0 = std::chrono::steady_clock::now();
    try {
      r.avatar = load_person_avatar(bytes, source, AvatarSource::kChosen);
      r.kind = Result::Kind::kLoaded;
    } catch (const std::exception& e) {
      r.kind = Result::Kind::kBroken;
      r.error = e.what();
    }
    r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return r;
  };
  jobs_.push_back({hash, p.site, std::async(std::launch::async, std::move(load))});
}

void ChosenAvatars::finish(Job& job) {
  Result r = job.result.get();
  if (r.kind == Result::Kind::kLoaded && avatars_.size() >= kMaxAvatars) {
    r.kind = Result::Kind::kBroken;
    r.error = "more than " + std::to_string(kMaxAvatars) + " different avatars this session";
  }
  if (r.kind == Result::Kind::kLoaded) {
    avatars_.push_back(r.avatar);
    ++loaded_count_;
    spdlog::info("avatar of site {} ({}): loaded in {:.1f} ms, {} bytes, {} joints, bones by {}",
                 job.site, net::to_hex(job.hash).substr(0, 12), r.ms, r.bytes,
                 r.avatar->solver.joint_count(), r.avatar->avatar.bone_source);
  } else if (r.kind == Result::Kind::kBroken && broken_.size() < kMaxAvatars) {
    broken_.emplace_back(job.hash, r.error);
  }
  for (Person& p : people_) {
    if (p.hash != job.hash || p.state != Person::State::kLoading) {
      continue;
    }
    switch (r.kind) {
      case Result::Kind::kLoaded:
        p.state = Person::State::kWearing;
        updates_.push_back({Update::Kind::kWear, p.id, r.avatar});
        break;
      case Result::Kind::kBroken:
        fail(p, r.error);
        break;
      case Result::Kind::kNotCached:
        if (p.asked || requests_ >= kMaxRequests) {
          fail(p, p.asked ? "a file was asked for from this person already this session"
                          : "too many avatar files asked for this session");
          break;
        }
        p.asked = true;
        ++requests_;
        p.state = Person::State::kDownloading;
        updates_.push_back({Update::Kind::kRequest, p.id, nullptr});
        break;
    }
  }
}

void ChosenAvatars::downloaded(PersonId id, std::span<const std::byte> file) {
  Person* p = find(id);
  if (p == nullptr || p->state != Person::State::kDownloading) {
    return;
  }
  if (std::shared_ptr<const PersonAvatar> avatar = known(*p->hash)) {
    p->state = Person::State::kWearing;  // someone else's copy of the same file came first
    updates_.push_back({Update::Kind::kWear, id, std::move(avatar)});
    return;
  }
  p->state = Person::State::kLoading;
  start(*p, std::make_shared<const std::vector<std::byte>>(file.begin(), file.end()));
}

void ChosenAvatars::download_failed(PersonId id, const std::string& reason) {
  Person* p = find(id);
  if (p != nullptr && p->state == Person::State::kDownloading) {
    fail(*p, "the download failed: " + reason);
  }
}

void ChosenAvatars::left(PersonId id) {
  people_.erase(
      std::remove_if(people_.begin(), people_.end(), [id](const Person& p) { return p.id == id; }),
      people_.end());
}

void ChosenAvatars::fail(Person& p, const std::string& reason) {
  // The reason may quote the file's bytes (a parser's message): printable ASCII only in the log.
  std::string said = reason.substr(0, 400);
  for (char& c : said) {
    if (c < ' ' || c > '~') {
      c = '?';
    }
  }
  p.state = Person::State::kFailed;
  ++failures_;
  if (warnings_ >= kMaxWarnings) {
    return;
  }
  ++warnings_;
  spdlog::warn(
      "the avatar site {} chose (person {}, file {}) is not shown: {}; they wear this "
      "site's default avatar{}",
      p.site, static_cast<int>(p.id), net::to_hex(*p.hash).substr(0, 12), said,
      warnings_ == kMaxWarnings ? " (further avatar warnings are only counted)" : "");
}

bool ChosenAvatars::next(Update& out) {
  for (std::size_t i = 0; i < jobs_.size();) {
    if (jobs_[i].result.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
      finish(jobs_[i]);
      jobs_.erase(jobs_.begin() + static_cast<std::ptrdiff_t>(i));
    } else {
      ++i;
    }
  }
  if (updates_taken_ == updates_.size()) {
    return false;
  }
  out = std::move(updates_[updates_taken_++]);
  if (updates_taken_ == updates_.size()) {
    updates_.clear();
    updates_taken_ = 0;
  }
  return true;
}

bool ChosenAvatars::awaiting(PersonId id) const {
  const Person* p = find(id);
  return p != nullptr && p->state == Person::State::kDownloading;
}

}  // namespace deixis::site
