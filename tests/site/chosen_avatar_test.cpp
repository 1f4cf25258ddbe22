// A person's own avatar at the receiving site (docs/avatars.md, "A person's own avatar"):
// RemotePeople dresses each person in their own rig (the default and the BCN test rig side by
// side, each posed with its own joint count); ChosenAvatars finds a file in the cache or asks for
// it once, keeps a downloaded file under its hash, and leaves a person whose file does not load
// in the site's default avatar with a warning naming them and the reason.

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

#include "avatar/avatar_loader.h"
#include "avatar/bcn_rig.h"  // tests/avatar
#include "capture/subject.h"
#include "capture/virtual_user.h"
#include "core/error.h"
#include "site/avatar_cache.h"
#include "site/remote_people.h"
#include "test_support.h"

namespace deixis::site {
namespace {

namespace fs = std::filesystem;

constexpr int kBcnJoints = 54;

std::vector<std::byte> read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::vector<char> chars((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::byte> bytes(chars.size());
  std::memcpy(bytes.data(), chars.data(), chars.size());
  return bytes;
}

// Polls until `done` or 20 s (loads run on their own threads); the updates seen meanwhile.
template <class Done>
std::vector<ChosenAvatars::Update> poll_until(ChosenAvatars& chosen, Done done) {
  std::vector<ChosenAvatars::Update> seen;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < until) {
    ChosenAvatars::Update u;
    while (chosen.next(u)) {
      seen.push_back(u);
    }
    if (done(seen)) {
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return seen;
}

bool has(const std::vector<ChosenAvatars::Update>& seen, ChosenAvatars::Update::Kind kind) {
  return std::any_of(seen.begin(), seen.end(), [&](const auto& u) { return u.kind == kind; });
}

// Captures what the default logger says while it lives.
class LogCapture {
 public:
  LogCapture() : sink_(std::make_shared<spdlog::sinks::ostream_sink_mt>(text_)) {
    spdlog::default_logger()->sinks().push_back(sink_);
  }
  ~LogCapture() {
    auto& sinks = spdlog::default_logger()->sinks();
    sinks.erase(std::remove(sinks.begin(), sinks.end(), sink_), sinks.end());
  }
  std::string text() const { return text_.str(); }

 private:
  std::ostringstream text_;
  std::shared_ptr<spdlog::sinks::ostream_sink_mt> sink_;
};

struct Room {
  SiteConfig config = read_site_config(deixis::testing::source_dir() / "assets/sites/c.json");
  std::array<MoeNetworks, 2> networks = {
      load_moe_networks(deixis::testing::reference_dir() / "weights", Hand::kLeft),
      load_moe_networks(deixis::testing::reference_dir() / "weights", Hand::kRight)};
  ik::AvatarSolver solver = ik::AvatarSolver::build(avatar::load_avatar(config.avatar_path).rig);
  std::vector<capture::ScriptPerformance> people;

  Room() {
    config.spots.push_back(Placement{Vec3(1.3f, 0.0f, -1.4f), 140.0f});
    for (const char* subject : {"172", "173"}) {
      std::vector<ScriptStep> script(2);
      script[0].action = script[1].action = ScriptStep::Action::kPoint;
      script[0].target = 1;
      script[1].target = 3;
      const capture::VirtualUserScene scene{config.user.T_world_floor(), config.target_map.objects,
                                            Vec3(0, 1.6f, -2.2f)};
      people.push_back(
          capture::perform_script(capture::find_subject(subject), script, scene, 3, 4.0));
    }
  }
  net::Hello hello(PersonId id) const {
    net::Hello h;
    h.site = std::string(1, static_cast<char>('A' + id - 1));
    h.avatar.body = people[id - 1].sequence.calibration;
    return h;
  }
  void tick(RemotePeople& remote, std::size_t i) const {
    LocalTargets room{&config.target_map, Vec3(0, 1.6f, 0)};
    room.people = remote.people_targets(9, room.partner_head);
    std::array<PersonFrame, 2> frames;
    for (PersonId id = 1; id <= 2; ++id) {
      const auto& f = people[id - 1].sequence.frames;
      frames[id - 1] =
          PersonFrame{id, &f[i % f.size()], static_cast<std::uint32_t>(i), &config.target_map};
    }
    remote.tick(frames, room, static_cast<double>(i) / 30.0);
    remote.end_tick();
  }
};

const Room& room() {
  static const Room r;
  return r;
}

std::shared_ptr<const PersonAvatar> bcn() {
  static const auto a = load_person_avatar(deixis::testing::bcn_glb(), AvatarSource::kChosen);
  return a;
}

TEST(ChosenAvatar, TwoRigsInOneRoomArePosedEachWithItsOwnJoints) {
  const Room& r = room();
  ASSERT_EQ(bcn()->solver.joint_count(), kBcnJoints);
  ASSERT_NE(r.solver.joint_count(), kBcnJoints) << "the test needs two different rigs";
  RemotePeople people(r.config, r.networks, r.solver, RemotePeopleOptions{64});
  people.meet(1, r.hello(1));
  people.meet(2, r.hello(2));
  for (std::size_t i = 0; i < 20; ++i) {
    r.tick(people, i);
  }
  const Vec3 before = people.avatar(1)->eye_midpoint();
  ASSERT_TRUE(people.wear(2, bcn()));
  EXPECT_EQ(people.wearing(2), bcn().get());
  EXPECT_EQ(people.wearing(1), nullptr);
  EXPECT_FALSE(people.avatar(2)->visible()) << "their avatar starts over in the new rig";
  for (std::size_t i = 20; i < 60; ++i) {
    r.tick(people, i);
  }
  ASSERT_EQ(people.visible().size(), 2u);
  const presence::RemoteAvatar& one = *people.avatar(1);
  const presence::RemoteAvatar& two = *people.avatar(2);
  EXPECT_EQ(one.model_pose().size(), static_cast<std::size_t>(r.solver.joint_count()));
  EXPECT_EQ(two.model_pose().size(), static_cast<std::size_t>(kBcnJoints));
  EXPECT_EQ(&two.solver(), &bcn()->solver);
  EXPECT_EQ(people.wearing(two), bcn().get());
  EXPECT_EQ(people.wearing(one), nullptr);
  // Person 1's avatar went on undisturbed (it was not reset: still visible and moving).
  EXPECT_TRUE(one.visible());
  EXPECT_GT((one.eye_midpoint() - before).norm(), 0.0f);
  // Person 2 is posed: not the BCN rig's rest pose everywhere.
  float moved = 0.0f;
  for (std::size_t j = 0; j < two.model_pose().size(); ++j) {
    moved = std::max(
        moved, (two.model_pose()[j].translation - bcn()->solver.rest_model[j].translation).norm());
  }
  EXPECT_GT(moved, 0.05f) << "the BCN avatar should point, not stand at rest";
  // session.json's people[].avatar.
  const std::vector<PersonRecord> records = people.records();
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0].avatar.source, "default");
  EXPECT_TRUE(records[0].avatar.hash.empty());
  EXPECT_EQ(records[0].avatar.joints, r.solver.joint_count());
  EXPECT_EQ(records[1].avatar.source, "chosen");
  EXPECT_EQ(records[1].avatar.hash, net::to_hex(bcn()->hash));
  EXPECT_EQ(records[1].avatar.joints, kBcnJoints);
  // Back to the default.
  ASSERT_TRUE(people.wear(2, nullptr));
  EXPECT_EQ(people.avatar(2)->model_pose().size(),
            static_cast<std::size_t>(r.solver.joint_count()));
}

TEST(ChosenAvatar, AnOverrideDressesEveryoneAndIgnoresTheirChoice) {
  const Room& r = room();
  RemotePeopleOptions options;
  options.override_avatar = load_person_avatar(deixis::testing::bcn_glb(), AvatarSource::kOverride);
  RemotePeople people(r.config, r.networks, r.solver, options);
  people.meet(1, r.hello(1));
  EXPECT_FALSE(people.wear(1, nullptr));
  EXPECT_EQ(people.avatar(1)->model_pose().size(), static_cast<std::size_t>(kBcnJoints));
  EXPECT_EQ(people.records()[0].avatar.source, "override");
}

TEST(ChosenAvatar, ADownloadedFileIsCachedUnderItsHashAndFoundThereNextTime) {
  deixis::testing::ScratchDir dir;
  const std::vector<std::byte> file = read_bytes(deixis::testing::bcn_glb());
  const net::AvatarHash hash = net::avatar_hash(file);
  {
    ChosenAvatars chosen(dir.path());
    chosen.named(3, "B", hash);
    auto seen = poll_until(chosen, [](const auto& s) { return !s.empty(); });
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_EQ(seen[0].kind, ChosenAvatars::Update::Kind::kRequest);
    EXPECT_EQ(seen[0].person, 3);
    EXPECT_TRUE(chosen.awaiting(3));
    chosen.downloaded(3, file);
    seen = poll_until(chosen, [](const auto& s) { return !s.empty(); });
    ASSERT_EQ(seen.size(), 1u);
    ASSERT_EQ(seen[0].kind, ChosenAvatars::Update::Kind::kWear);
    EXPECT_EQ(seen[0].avatar->solver.joint_count(), kBcnJoints);
    EXPECT_EQ(seen[0].avatar->hash, hash);
    // A second person naming the same file wears the same loaded avatar, without asking.
    chosen.named(4, "C", hash);
    const auto again = poll_until(chosen, [](const auto& s) { return !s.empty(); });
    ASSERT_EQ(again.size(), 1u);
    EXPECT_EQ(again[0].kind, ChosenAvatars::Update::Kind::kWear);
    EXPECT_EQ(again[0].avatar, seen[0].avatar);
  }
  EXPECT_TRUE(fs::exists(dir.path() / (net::to_hex(hash) + ".glb")));
  ChosenAvatars next_session(dir.path());
  next_session.named(1, "B", hash);
  const auto seen = poll_until(next_session, [](const auto& s) { return !s.empty(); });
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0].kind, ChosenAvatars::Update::Kind::kWear) << "found in the cache";
  EXPECT_EQ(seen[0].avatar->solver.joint_count(), kBcnJoints);
}

TEST(ChosenAvatar, ACorruptFileLeavesTheDefaultAndWarnsNamingThePerson) {
  deixis::testing::ScratchDir dir;
  std::vector<std::byte> file = read_bytes(deixis::testing::bcn_glb());
  ASSERT_GT(file.size(), 4096u);
  // The JSON chunk garbled: what the sender chose (the hash matches), but no avatar.
  for (std::size_t i = 40; i < 2000; ++i) {
    file[i] = static_cast<std::byte>(0xFF);
  }
  const net::AvatarHash hash = net::avatar_hash(file);
  const Room& r = room();
  RemotePeople people(r.config, r.networks, r.solver);
  people.meet(1, r.hello(1));
  people.meet(2, r.hello(2));
  LogCapture log;
  ChosenAvatars chosen(dir.path());
  chosen.named(2, "B", hash);
  auto seen = poll_until(chosen, [](const auto& s) { return !s.empty(); });
  ASSERT_TRUE(has(seen, ChosenAvatars::Update::Kind::kRequest));
  chosen.downloaded(2, file);
  seen = poll_until(chosen, [&](const auto&) { return chosen.failures() > 0; });
  EXPECT_FALSE(has(seen, ChosenAvatars::Update::Kind::kWear));
  EXPECT_EQ(chosen.failures(), 1u);
  EXPECT_EQ(people.wearing(2), nullptr);
  for (std::size_t i = 0; i < 40; ++i) {
    r.tick(people, i);
  }
  EXPECT_EQ(people.visible().size(), 2u) << "person B is shown, in the default avatar";
  EXPECT_EQ(people.avatar(2)->model_pose().size(),
            static_cast<std::size_t>(r.solver.joint_count()));
  const std::string text = log.text();
  EXPECT_NE(text.find("site B"), std::string::npos) << text;
  EXPECT_NE(text.find("default avatar"), std::string::npos) << text;
  EXPECT_NE(text.find(net::to_hex(hash).substr(0, 12)), std::string::npos) << text;
  // The same file again: nothing more (no second request, no second warning).
  chosen.named(2, "B", hash);
  seen = poll_until(chosen, [](const auto&) { return true; });
  EXPECT_TRUE(seen.empty());
  // Another file from the same person, not cached: not asked for twice in a session.
  chosen.named(2, "B", net::avatar_hash(read_bytes(deixis::testing::bcn_glb())));
  seen = poll_until(chosen, [&](const auto&) { return chosen.failures() > 1; });
  EXPECT_FALSE(has(seen, ChosenAvatars::Update::Kind::kRequest));
  EXPECT_EQ(chosen.failures(), 2u);
}

TEST(ChosenAvatar, AFileThatIsNoAvatarIsRefusedNamingIt) {
  deixis::testing::ScratchDir dir;
  const fs::path bad = dir.path() / "not-an-avatar.glb";
  std::ofstream(bad) << "hello";
  try {
    load_person_avatar(bad, AvatarSource::kChosen);
    FAIL() << "loaded a file that is no avatar";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not-an-avatar.glb"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace deixis::site
