// RemoteAvatar's contract: hidden until the first valid frame, placed where this room says, poses
// always finite (missed tracking included), and a tick allocates nothing (a separate executable
// outside sanitizer builds checks that: remote_avatar_allocation_test.cpp).

#include "presence/remote_avatar.h"

#include <gtest/gtest.h>

#include <limits>

#include "avatar/avatar_loader.h"
#include "gesture/tracking_frames.h"
#include "test_support.h"

namespace deixis::presence {
namespace {

namespace fs = std::filesystem;

bool all_finite(std::span<const Pose> poses) {
  for (const Pose& p : poses) {
    if (!is_finite(p)) {
      return false;
    }
  }
  return true;
}

class RemoteAvatarTest : public ::testing::Test {
 protected:
  RemoteAvatarTest()
      : solver(ik::AvatarSolver::build(
            avatar::load_avatar(fs::path(DEIXIS_SOURCE_DIR) / "assets/avatars/default.glb").rig)),
        avatar(nn::Mpnet::load(weights() / "MPNet(MoE)(AC)80.safetensors"),
               nn::Ugnet::load(weights() / "UGNet(MoE)(AC)120.safetensors"), solver, config()) {
    room.site.assign(1, 'B');  // not = "B": GCC 12 -O3 reports a false -Wrestrict there
    // Jupiter 2.5 m in front of the avatar, as the user's target is in front of them.
    room.objects.push_back({1, "Jupiter", TargetKind::kSphere,
                            transform_point(floor, Vec3(0, 1.5f, -2.5f)), Vec3::Constant(0.3f)});
    targets.map = &room;
    targets.partner_head = Vec3(0, 1.6f, 0);
  }
  static fs::path weights() { return testing::reference_dir() / "weights/right"; }
  RemoteAvatarConfig config() const {
    RemoteAvatarConfig c;
    c.user = person.body;
    c.T_world_floor = floor;
    return c;
  }

  testing::StandingPerson person;
  Pose floor{yaw_rotation(2.0f), Vec3(0.5f, 0.0f, -2.2f)};
  ik::AvatarSolver solver;
  RemoteAvatar avatar;
  TargetMap room;
  LocalTargets targets;
};

TEST_F(RemoteAvatarTest, HiddenUntilTheFirstValidFrameAndAtRestMeanwhile) {
  EXPECT_FALSE(avatar.tick(nullptr, targets));
  EXPECT_FALSE(avatar.visible());
  for (std::size_t i = 0; i < avatar.model_pose().size(); ++i) {
    EXPECT_TRUE(avatar.model_pose()[i].translation.isApprox(solver.rest_model[i].translation));
  }
  EXPECT_TRUE(avatar.tick(&person.frame, targets));
  EXPECT_TRUE(avatar.visible());
}

TEST_F(RemoteAvatarTest, TheModelFrameIsTheFloorPlacementAndOriginIsTheRestEyes) {
  EXPECT_TRUE(avatar.T_world_model().translation.isApprox(floor.translation, 1e-5f));
  EXPECT_TRUE(avatar.T_world_model().rotation.isApprox(floor.rotation, 1e-5f));
  const Pose O = avatar_origin(solver, floor);
  EXPECT_TRUE(O.translation.isApprox(transform_point(floor, solver.eye_midpoint_rest), 1e-5f));
  EXPECT_GT(O.translation.y(), 1.4f);  // a 1.70 m avatar's eyes
}

TEST_F(RemoteAvatarTest, StandingStillTheAvatarStandsWhereItWasPut) {
  for (int i = 0; i < 30; ++i) {
    avatar.tick(&person.frame, targets);
  }
  const Vec3 eyes = avatar.eye_midpoint();
  const Vec3 expected = avatar_origin(solver, floor).translation;
  EXPECT_LT((eyes - expected).norm(), 0.10f) << eyes.transpose();
  // The hand hangs at the side: below the chest, within an arm of the eyes.
  const Vec3 tip = avatar.index_fingertip();
  EXPECT_LT(tip.y(), eyes.y() - 0.5f);
  EXPECT_LT((tip - eyes).norm(), 1.0f);
}

TEST_F(RemoteAvatarTest, MissedAndBrokenTrackingNeverBreaksThePose) {
  avatar.tick(&person.frame, targets);
  TrackingFrame broken = person.frame;
  broken.T_world_head.translation.x() = std::numeric_limits<float>::quiet_NaN();
  broken.index_tip[index(Hand::kRight)] = Vec3::Constant(std::numeric_limits<float>::infinity());
  for (int i = 0; i < 10; ++i) {
    EXPECT_TRUE(avatar.tick(i % 2 == 0 ? &broken : nullptr, targets));
    EXPECT_TRUE(all_finite(avatar.model_pose()));
    EXPECT_TRUE(all_finite(avatar.local_pose()));
  }
  EXPECT_EQ(avatar.stats().held, 10u);
  EXPECT_EQ(avatar.stats().rejected_frames, 5u);
}

}  // namespace
}  // namespace deixis::presence
