// A site's virtual user driven by a BVH recording (site/site_config.h `virtual_user.bvh`,
// site/recorded_user.h, docs/bvh.md#driving-a-site): the config is read with the recording
// resolved beside it; every bad field and a bad file are named; the tracking the site sends is
// mocap's tracking of the file at the same times, placed on the user's spot, and the body in the
// site's hello is the recording's, placed the same way.

#include "site/recorded_user.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "core/error.h"
#include "mocap/humanoid.h"
#include "mocap/player.h"
#include "mocap/skeleton_tracking.h"
#include "site/site_session.h"
#include "test_support.h"

namespace deixis::site {
namespace {

namespace fs = std::filesystem;
const fs::path kCmu = "/usr/share/assimp/models/BVH/01_01.bvh";

// A site file in `dir` whose virtual user is `virtual_user` (JSON text); the room is the demo's.
fs::path site_file(const fs::path& dir, const std::string& virtual_user) {
  const fs::path assets = testing::source_dir() / "assets";
  const fs::path path = dir / "site.json";
  std::ofstream(path) << R"({
    "format": "deixis-site", "version": 1, "site": "T",
    "target_map": ")" << (assets / "rooms/a.json").string()
                      << R"(",
    "user": { "floor": [0.5, 0, -0.3], "yaw_degrees": 30 },
    "remote_avatar": { "floor": [0, 0, -2.2], "yaw_degrees": 180, "avatar": "x.glb" },
    "virtual_user": )" << virtual_user
                      << "}";
  return path;
}

// The tests' humanoid (tests/mocap/humanoid.h), 30 frames at 30 Hz, in centimetres.
void write_humanoid(const fs::path& path, int frames = 30, bool lying = false) {
  auto motion = mocap::testing::random_motion(frames, 3, 10);
  if (lying) {
    for (auto& f : motion) {
      f.rotation[0] = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
    }
  }
  std::ofstream(path) << mocap::testing::humanoid_bvh(motion);
}

TEST(RecordedUser, TheConfigResolvesTheRecordingBesideItAndReadsItsFields) {
  testing::ScratchDir dir;
  fs::create_directories(dir.path() / "takes");
  write_humanoid(dir.path() / "takes/walk.bvh");
  const SiteConfig site = read_site_config(site_file(dir.path(), R"({
      "bvh": "takes/walk.bvh", "playback": "once", "unit": "cm", "from": 0.2, "to": 0.7,
      "deictic_hand": "left", "body": { "height": 1.8, "arm_length": 0.75 } })"));
  ASSERT_TRUE(site.virtual_user.has_value());
  ASSERT_TRUE(site.virtual_user->recording.has_value());
  EXPECT_TRUE(site.virtual_user->subject.empty());
  EXPECT_TRUE(site.virtual_user->script.empty());
  const RecordedUser& r = *site.virtual_user->recording;
  EXPECT_EQ(r.path, dir.path() / "takes/walk.bvh");
  EXPECT_EQ(r.play.playback, mocap::Playback::kOnce);
  EXPECT_DOUBLE_EQ(r.play.metres_per_unit, 0.01);
  EXPECT_EQ(r.play.deictic_hand, Hand::kLeft);
  ASSERT_TRUE(r.play.body.has_value());
  EXPECT_FLOAT_EQ(r.play.body->height, 1.8f);
  // 0.2 s to 0.7 s at 30 Hz: frames 6 to 21.
  EXPECT_EQ(r.bvh->frames(), 16u);
  const mocap::Bvh whole = mocap::read_bvh(dir.path() / "takes/walk.bvh");
  EXPECT_EQ(r.bvh->frame(0)[5], whole.frame(6)[5]);
  EXPECT_EQ(r.bvh->frame(15)[7], whole.frame(21)[7]);
  // The defaults: loop, the unit from the rest pose (1.73 m in cm), the right hand, measured.
  const SiteConfig plain = read_site_config(site_file(dir.path(), R"({"bvh": "takes/walk.bvh"})"));
  const RecordedUser& p = *plain.virtual_user->recording;
  EXPECT_EQ(p.play.playback, mocap::Playback::kLoop);
  EXPECT_EQ(p.unit, mocap::LengthUnit::kCentimetre);
  EXPECT_EQ(p.play.deictic_hand, Hand::kRight);
  EXPECT_FALSE(p.play.body.has_value());
  EXPECT_EQ(p.bvh->frames(), 30u);
}

TEST(RecordedUser, BadFieldsAndFilesAreNamed) {
  testing::ScratchDir dir;
  write_humanoid(dir.path() / "walk.bvh");
  write_humanoid(dir.path() / "lying.bvh", 10, true);
  std::ofstream(dir.path() / "bad.bvh")
      << "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 1 Xposition\n}\nMOTION\nFrames: 2\n"
         "Frame Time: 0.1\n0\nx\n";
  const std::pair<std::string, std::string> cases[] = {
      {R"({"bvh": "walk.bvh", "subject": "172"})",
       "virtual_user: give either a subject (the synthetic capture) or a bvh (a recording), not "
       "both"},
      {R"({"seed": 3})",
       "virtual_user: give either a subject (the synthetic capture) or a bvh (a "
       "recording), not neither"},
      {R"({"bvh": "walk.bvh", "script": [ { "action": "rest" } ]})",
       "virtual_user.script: a recording (bvh) plays what was recorded: it takes no script or "
       "seed"},
      {R"({"bvh": "walk.bvh", "seed": 4})", "virtual_user.seed: a recording (bvh) plays"},
      {R"({"subject": "172", "playback": "once", "script": [ { "action": "rest" } ]})",
       "virtual_user.playback: only a recording (bvh) takes it"},
      {R"({"bvh": "walk.bvh", "playback": "twice"})",
       "virtual_user.playback: expected loop or once, found 'twice'"},
      {R"({"bvh": "walk.bvh", "unit": "feet"})",
       "virtual_user.unit: unknown unit 'feet' (m, cm, mm, inch, cmu or auto)"},
      {R"({"bvh": "walk.bvh", "deictic_hand": "both"})",
       "virtual_user.deictic_hand: expected right or left, found 'both'"},
      {R"({"bvh": "walk.bvh", "from": 2})",
       "virtual_user.from: beyond the end: the recording runs from 0 to 0.967 s"},
      {R"({"bvh": "walk.bvh", "to": 1.5})", "virtual_user.to: beyond the end"},
      {R"({"bvh": "walk.bvh", "from": 0.5, "to": 0.5})",
       "virtual_user.to: must come after from (at least one frame time later)"},
      {R"({"bvh": "walk.bvh", "body": { "height": 3.0, "arm_length": 0.7 }})",
       "virtual_user.body.height: expected a number in"},
      {R"({"bvh": "walk.bvh", "body": { "height": 1.7 }})",
       "virtual_user.body: missing field 'arm_length'"},
      {R"({"bvh": "walk.bvh", "speed": 2})", "unknown field 'speed'"},
      {R"({"bvh": "missing.bvh"})", "virtual_user.bvh: " + (dir.path() / "missing.bvh").string()},
      {R"({"bvh": "/dev/zero"})", "virtual_user.bvh: /dev/zero: cannot read"},
      {R"({"bvh": "bad.bvh"})", "virtual_user.bvh: " + (dir.path() / "bad.bvh").string() + ":11: "},
      {R"({"bvh": "lying.bvh"})",
       "virtual_user.bvh: " + (dir.path() / "lying.bvh").string() +
           ": no upright frame (spine within 30° of vertical, head above both wrists) to "
           "calibrate the body from (or state the body: virtual_user.body)"},
  };
  for (const auto& [virtual_user, expected] : cases) {
    const fs::path path = site_file(dir.path(), virtual_user);
    try {
      read_site_config(path);
      ADD_FAILURE() << "accepted: " << virtual_user;
    } catch (const deixis::Error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u) << message;
      EXPECT_NE(message.find(expected), std::string::npos) << message;
    }
  }
  // A stated body plays a recording without an upright frame.
  EXPECT_NO_THROW(read_site_config(site_file(
      dir.path(), R"({"bvh": "lying.bvh", "body": { "height": 1.7, "arm_length": 0.74 }})")));
}

// What the site sends, against mocap's tracking of the Debian recording at the same times: the
// 30 Hz ticks fall on every fourth of its 120 Hz frames, from `from` on (once: the file's frame
// time, .0083333, puts the last tick a hair past the last frame, which a loop would blend toward
// the first); the move onto the spot is the first played frame's ground onto the user spot.
TEST(RecordedUser, TheSiteSendsTheRecordingsTrackingPlacedOnItsSpot) {
  if (!fs::exists(kCmu)) {
    GTEST_SKIP() << "no " << kCmu << " (Debian's assimp-testmodels; tools/install-deps)";
  }
  testing::ScratchDir dir;
  const SiteConfig site = read_site_config(site_file(
      dir.path(),
      R"({"bvh": ")" + kCmu.string() + R"(", "from": 1.0, "to": 4.0, "playback": "once"})"));
  const ScriptedUser user = play_recorded_user(site, 0.0);
  ASSERT_EQ(user.frames.size(), 91u);  // 3 s at 30 Hz, both ends
  EXPECT_EQ(user.deictic.size(), user.frames.size());
  EXPECT_TRUE(user.steps.empty());

  const mocap::Bvh file = mocap::read_bvh(kCmu);
  const double unit = mocap::metres_per_unit(mocap::LengthUnit::kCmu);
  mocap::SkeletonTracking tracking(file, unit);
  mocap::BvhPlayer player(file, unit, mocap::Playback::kOnce);
  const Pose spot = site.user.T_world_floor();
  const Pose T = compose(spot, inverse(tracking.ground(120)));  // 1.0 s at 120 Hz
  const double start = 120 * file.frame_time;
  for (std::size_t k = 0; k < user.frames.size(); ++k) {
    // The whole file's player at the same time, within a hair of the recorded frame there (the
    // file's rounded frame time drifts 4e-7 of a frame a frame); the last tick, a hair past `to`,
    // is `to`'s frame itself (once: held).
    TrackingFrame expected;
    TrackingFrame recorded;
    tracking.track(120 + 4 * k, recorded);
    if (k + 1 < user.frames.size()) {
      player.at(start + static_cast<double>(k) / 30.0, expected);
    } else {
      expected = recorded;
    }
    EXPECT_LT((expected.index_tip[1] - recorded.index_tip[1]).norm(), 1e-3f) << k;
    const TrackingFrame& f = user.frames[k];
    EXPECT_EQ(f.valid, tracked::kAll) << k;
    EXPECT_EQ(f.hand_target, kNoTarget);
    EXPECT_NEAR(f.time, static_cast<double>(k) / 30.0, 1e-9);
    EXPECT_LT(
        (f.T_world_head.translation - transform_point(T, expected.T_world_head.translation)).norm(),
        2e-5f)
        << k;
    EXPECT_LT((f.T_world_head.rotation - T.rotation * expected.T_world_head.rotation).norm(),
              2e-5f);
    EXPECT_LT((f.gaze - T.rotation * expected.gaze).norm(), 2e-5f);
    for (std::size_t h = 0; h < 2; ++h) {
      EXPECT_LT((f.index_tip[h] - transform_point(T, expected.index_tip[h])).norm(), 2e-5f);
      EXPECT_LT(
          (f.T_world_wrist[h].rotation - T.rotation * expected.T_world_wrist[h].rotation).norm(),
          2e-5f);
    }
  }
  // The person stands on the spot: at the first tick H is above it (within a step) at a
  // standing height.
  const Vec3 H = user.frames[0].T_world_head.translation;
  EXPECT_LT(std::hypot(H.x() - 0.5f, H.z() + 0.3f), 0.35f);
  EXPECT_GT(H.y(), 1.2f);
  // The hello carries the body measured at the recording's first upright frame, placed alike.
  const mocap::Bvh played = mocap::slice(file, 120, 481);
  mocap::SkeletonTracking played_tracking(played, mocap::metres_per_unit(mocap::LengthUnit::kCmu));
  const BodyCalibration measured = played_tracking.calibrate();
  const BodyCalibration sent = site_hello(site, user.body).avatar.body;
  EXPECT_FLOAT_EQ(sent.height, measured.height);
  EXPECT_FLOAT_EQ(sent.arm_length, measured.arm_length);
  EXPECT_LT((sent.T_world_root.translation - transform_point(T, measured.T_world_root.translation))
                .norm(),
            1e-4f);
  EXPECT_LT((sent.T_world_root.rotation - T.rotation * measured.T_world_root.rotation).norm(),
            1e-5f);
  EXPECT_GT(sent.height, 1.4f);
}

// The shipped example (assets/sites/a-recorded.json): the boxer of Debian's Boxing_Toes.bvh,
// 0 to 23 s, on site A's user spot.
TEST(RecordedUser, TheExampleSiteLoads) {
  const fs::path boxing = "/usr/share/assimp/models/BVH/Boxing_Toes.bvh";
  if (!fs::exists(boxing)) {
    GTEST_SKIP() << "no " << boxing << " (Debian's assimp-testmodels; tools/install-deps)";
  }
  const SiteConfig site = read_site_config(testing::source_dir() / "assets/sites/a-recorded.json");
  ASSERT_TRUE(site.virtual_user && site.virtual_user->recording);
  const RecordedUser& r = *site.virtual_user->recording;
  EXPECT_EQ(r.unit, mocap::LengthUnit::kCentimetre);
  EXPECT_EQ(r.bvh->frames(), 2301u);
  const ScriptedUser user = play_recorded_user(site, 2.0);
  EXPECT_EQ(user.frames.size(), 61u);
  EXPECT_GT(user.body.height, 1.6f);
  EXPECT_LT(user.body.height, 1.8f);
}

TEST(RecordedUser, OncePlaybackHoldsTheLastFrameForALongerRun) {
  testing::ScratchDir dir;
  write_humanoid(dir.path() / "walk.bvh");
  const SiteConfig site =
      read_site_config(site_file(dir.path(), R"({"bvh": "walk.bvh", "playback": "once"})"));
  const ScriptedUser user = play_recorded_user(site, 3.0);
  ASSERT_EQ(user.frames.size(), 91u);
  const TrackingFrame& last = user.frames[29];  // the recording's last frame, at 29/30 s
  for (std::size_t k = 29; k < user.frames.size(); ++k) {
    EXPECT_EQ(user.frames[k].valid, tracked::kAll);
    EXPECT_LT((user.frames[k].index_tip[1] - last.index_tip[1]).norm(), 1e-6f) << k;
  }
  EXPECT_GT((user.frames[28].index_tip[1] - last.index_tip[1]).norm(), 1e-4f);
}

}  // namespace
}  // namespace deixis::site
