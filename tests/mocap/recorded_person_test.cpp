// A recording performed as a site's user (mocap/recorded_person.h): the recorded person's ground
// at the first frame lands on the spot facing where it faces, every frame keeps its shape, the
// frames are the player's at the site's times, the calibration moves with them, a stated body
// stands on the spot, and once-playback holds the last frame.

#include "mocap/recorded_person.h"

#include <gtest/gtest.h>

#include <cmath>

#include "mocap/humanoid.h"

namespace deixis::mocap {
namespace {

// The humanoid turned `yaw` about +Y at the root and standing upright (small joint rotations).
Bvh turned_humanoid(double yaw, int frames = 12) {
  auto motion = testing::random_motion(frames, 5, 8);
  for (testing::HumanoidFrame& f : motion) {
    f.rotation[0] = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
    f.root.y() = 95;
  }
  return parse_bvh(testing::humanoid_bvh(motion), "turned.bvh");
}

Pose spot(float x, float z, float yaw_degrees) {
  return {yaw_rotation(yaw_degrees * static_cast<float>(M_PI) / 180.0f), Vec3(x, 0.0f, z)};
}

TEST(RecordedPerson, TheGroundIsUnderTheHipsFacingWhereThePelvisFaces) {
  for (const double yaw : {0.0, 0.6, -2.0}) {
    const Bvh b = turned_humanoid(yaw);
    SkeletonTracking tracking(b, 0.01);
    const Pose ground = tracking.ground(3);
    // The humanoid faces +Z at rest; turned by `yaw` about +Y.
    const Vec3 facing = (Eigen::AngleAxisf(static_cast<float>(yaw), Vec3::UnitY()) * Vec3::UnitZ());
    EXPECT_LT((ground.rotation * Vec3(0, 0, -1) - facing).norm(), 1e-5f) << yaw;
    const Vec3 hips = tracking.poses().front().p.cast<float>();
    EXPECT_NEAR(ground.translation.x(), hips.x(), 1e-6f);
    EXPECT_NEAR(ground.translation.z(), hips.z(), 1e-6f);
    double low = 1e9;
    for (const JointPose& p : tracking.poses()) {
      low = std::min(low, p.p.y());
    }
    EXPECT_NEAR(ground.translation.y(), low, 1e-6);
    EXPECT_LT(ground.translation.y(), 0.05f) << "the feet are near y = 0";
  }
}

TEST(RecordedPerson, StandsOnTheSpotFacingItsWayAndKeepsItsShape) {
  const Bvh b = turned_humanoid(0.9);
  const Pose T_world_floor = spot(1.5f, -0.7f, 40.0f);
  RecordingPlay play;
  play.metres_per_unit = 0.01;
  const RecordedPerson person = perform_recording(b, play, T_world_floor, 0.0, 30.0);
  ASSERT_EQ(person.frames.size(), b.frames());  // the file's own rate here: one per frame
  SkeletonTracking tracking(b, 0.01);
  const Pose recorded_ground = tracking.ground(0);
  const Pose T = recording_placement(tracking, T_world_floor);
  // At the first frame the hips stand above the spot, the lowest node on its floor, and the
  // body (facing +Z at rest, turned 0.9 rad) faces where the spot faces.
  TrackingFrame first;
  tracking.track(0, first);
  const Vec3 hips = transform_point(T, tracking.poses().front().p.cast<float>());
  EXPECT_NEAR(hips.x(), 1.5f, 1e-5f);
  EXPECT_NEAR(hips.z(), -0.7f, 1e-5f);
  float low = 1e9f;
  float recorded_low = 1e9f;
  for (const JointPose& p : tracking.poses()) {
    low = std::min(low, transform_point(T, p.p.cast<float>()).y());
    recorded_low = std::min(recorded_low, static_cast<float>(p.p.y()));
  }
  EXPECT_NEAR(low, 0.0f, 1e-5f);
  EXPECT_GT(std::abs(recorded_low), 1e-3f) << "the test moves the recording vertically too";
  const Vec3 body_facing = T.rotation * (Eigen::AngleAxisf(0.9f, Vec3::UnitY()) * Vec3::UnitZ());
  EXPECT_LT((body_facing - T_world_floor.rotation * Vec3(0, 0, -1)).norm(), 1e-5f);
  // The move is a yaw and a translation only, and each frame keeps its shape.
  EXPECT_LT(std::abs((T.rotation * Vec3::UnitY()).dot(Vec3::UnitY()) - 1.0f), 1e-6f);
  for (std::size_t i = 0; i < b.frames(); ++i) {
    TrackingFrame recorded;
    tracking.track(i, recorded);
    const TrackingFrame& f = person.frames[i];
    EXPECT_EQ(f.valid, tracked::kAll);
    EXPECT_NEAR(f.time, static_cast<double>(i) / 30.0, 1e-9);
    EXPECT_NEAR((f.T_world_head.translation - f.index_tip[1]).norm(),
                (recorded.T_world_head.translation - recorded.index_tip[1]).norm(), 1e-5f);
    EXPECT_NEAR(f.T_world_head.translation.y(),
                recorded.T_world_head.translation.y() - recorded_low, 1e-5f);
    EXPECT_NEAR(f.gaze.dot(f.T_world_wrist[0].rotation.col(0)),
                recorded.gaze.dot(recorded.T_world_wrist[0].rotation.col(0)), 1e-5f);
    // Facing the spot's way: the head's yaw turned as the ground's was.
    const Vec3 gaze = T_world_floor.rotation * recorded_ground.rotation.transpose() * recorded.gaze;
    EXPECT_LT((f.gaze - gaze).norm(), 1e-5f);
  }
  // The body: measured from the upright frame, moved the same way.
  const BodyCalibration recorded_body = tracking.calibrate();
  EXPECT_FLOAT_EQ(person.body.height, recorded_body.height);
  EXPECT_FLOAT_EQ(person.body.arm_length, recorded_body.arm_length);
  const Pose root = compose(T, recorded_body.T_world_root);
  EXPECT_LT((person.body.T_world_root.translation - root.translation).norm(), 1e-5f);
  EXPECT_LT((person.body.T_world_root.rotation - root.rotation).norm(), 1e-5f);
  EXPECT_TRUE(person.body.rest_wrist_in_root[1].isApprox(recorded_body.rest_wrist_in_root[1]));
}

TEST(RecordedPerson, FramesAreThePlayersAtTheSitesRate) {
  const Bvh b = turned_humanoid(-0.3, 20);
  RecordingPlay play;
  play.metres_per_unit = 0.01;
  const Pose T_world_floor = spot(0.0f, 0.0f, 180.0f);
  const RecordedPerson person = perform_recording(b, play, T_world_floor, 0.0, 45.0);
  const double duration = 19.0 / 30.0;
  ASSERT_EQ(person.frames.size(), static_cast<std::size_t>(std::floor(duration * 45.0)) + 1);
  BvhPlayer player(b, 0.01, Playback::kOnce);
  const Pose T = recording_placement(player.tracking(), T_world_floor);
  for (std::size_t k = 0; k < person.frames.size(); ++k) {
    TrackingFrame expected;
    player.at(static_cast<double>(k) / 45.0, expected);
    place(T, expected);
    const TrackingFrame& f = person.frames[k];
    EXPECT_LT((f.T_world_head.translation - expected.T_world_head.translation).norm(), 1e-6f);
    EXPECT_LT((f.T_world_wrist[0].rotation - expected.T_world_wrist[0].rotation).norm(), 1e-6f);
    EXPECT_LT((f.index_tip[1] - expected.index_tip[1]).norm(), 1e-6f);
  }
}

TEST(RecordedPerson, OnceHoldsTheLastFrameAndLoopStartsAgain) {
  const Bvh b = turned_humanoid(0.2, 10);
  RecordingPlay play;
  play.metres_per_unit = 0.01;
  play.playback = Playback::kOnce;
  const RecordedPerson once = perform_recording(b, play, Pose{}, 2.0, 30.0);
  ASSERT_EQ(once.frames.size(), 61u);
  for (std::size_t k = 9; k < once.frames.size(); ++k) {
    EXPECT_LT(
        (once.frames[k].T_world_head.translation - once.frames[9].T_world_head.translation).norm(),
        1e-6f)
        << k;
    EXPECT_EQ(once.frames[k].valid, tracked::kAll);
  }
  play.playback = Playback::kLoop;
  const RecordedPerson loop = perform_recording(b, play, Pose{}, 2.0, 30.0);
  // Ten frames a loop: frame 23 is frame 3 again.
  EXPECT_LT((loop.frames[23].index_tip[0] - loop.frames[3].index_tip[0]).norm(), 1e-5f);
  EXPECT_GT((loop.frames[23].index_tip[0] - loop.frames[9].index_tip[0]).norm(), 1e-3f);
}

TEST(RecordedPerson, AStatedBodyStandsUprightOnTheSpot) {
  const Bvh b = turned_humanoid(0.0);
  RecordingPlay play;
  play.metres_per_unit = 0.01;
  play.body = StatedBody{1.82f, 0.79f};
  play.deictic_hand = Hand::kLeft;
  const Pose T_world_floor = spot(-1.0f, 2.0f, 90.0f);
  const RecordedPerson person = perform_recording(b, play, T_world_floor, 1.0, 30.0);
  EXPECT_FLOAT_EQ(person.body.height, 1.82f);
  EXPECT_FLOAT_EQ(person.body.arm_length, 0.79f);
  EXPECT_EQ(person.body.deictic_hand, Hand::kLeft);
  EXPECT_LT((person.body.T_world_root.translation - Vec3(-1.0f, 0.936f * 1.82f, 2.0f)).norm(),
            1e-5f);
  EXPECT_LT((person.body.T_world_root.rotation - T_world_floor.rotation).norm(), 1e-6f);
}

}  // namespace
}  // namespace deixis::mocap
