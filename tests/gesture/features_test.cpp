// The feature code shared by the runtime and the datasets (gesture/features.h): hand-computed
// cases for each of MPNet's 11 columns and the 24 end-effectors, the left-handed mirror image, and
// the round trips between tracking frames and end-effectors.
//
// Every scene is built in the person's root frame O and then placed in the world by a root that
// is turned and moved, so a feature computed in the wrong frame fails.

#include "gesture/features.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace deixis {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr float kTolerance = 2e-6f;

float deg(float degrees) {
  return degrees * kPi / 180.0f;
}

// A root turned 90° to the left (facing world −X) and standing away from the origin.
Pose placed_root() {
  return Pose{yaw_rotation(kPi / 2), Vec3(3.0f, 1.6f, 1.0f)};
}

Vec3 in_world(const Pose& T_world_root, const Vec3& p_root) {
  return transform_point(T_world_root, p_root);
}

// The angle scene: head at O looking along the root's forward axis; every angle of MPNet's row is
// a round number of degrees and each differs from the others, so swapped columns fail too.
struct AngleScene {
  BodyCalibration body;
  TrackingFrame frame;

  explicit AngleScene(Hand hand = Hand::kRight) {
    body.deictic_hand = hand;
    body.T_world_root = placed_root();
    const Pose& O = body.T_world_root;
    frame.T_world_head = O;                           // head at O, looking along the root's −Z
    frame.gaze = O.rotation * Vec3(-1, 0, 0);         // eyes 90° to the left
    const Vec3 head_target(-1, 0, -std::sqrt(3.0f));  // 30° to the left
    const Vec3 tip = 0.5f * Vec3(0, -std::sin(deg(20)), -std::cos(deg(20)));  // 20° below ahead
    const Vec3 hand_target = 2.0f * Vec3(0, std::sin(deg(25)), -std::cos(deg(25)));  // 25° up
    frame.head_target_position = in_world(O, head_target);
    frame.hand_target_position = in_world(O, hand_target);
    const int h = index(hand);
    frame.index_tip[h] = in_world(O, tip);
    // The deictic wrist near its rest position (0.17 m away, inside the 0.25 m of d).
    body.rest_wrist_in_root[h] = Vec3(hand == Hand::kRight ? 0.2f : -0.2f, -0.75f, 0.0f);
    frame.T_world_wrist[h] =
        Pose{O.rotation, in_world(O, body.rest_wrist_in_root[h] + Vec3(0.1f, 0.1f, 0.1f))};
    frame.valid = tracked::kAll;
  }
};

TEST(MpnetFeatures, EachAngleColumnIsHandComputed) {
  const AngleScene scene;
  const MpnetFeatureRow row = mpnet_features(scene.frame, scene.body);
  EXPECT_NEAR(row[mf::kEyeToHeadTarget], deg(60), kTolerance);   // gaze 90° left, target 30° left
  EXPECT_NEAR(row[mf::kHeadToHeadTarget], deg(30), kTolerance);  // head ahead, target 30° left
  EXPECT_NEAR(row[mf::kFingerToHandTarget], deg(45), kTolerance);  // 20° below vs 25° above
  EXPECT_NEAR(row[mf::kHeadToFinger], deg(20), kTolerance);        // fingertip 20° below ahead
  EXPECT_NEAR(row[mf::kFingerToDown], deg(70), kTolerance);  // 90° − 20° from straight down
}

TEST(MpnetFeatures, TargetColumnsAreThetaPhiAndClampedDistanceFromTheRoot) {
  const AngleScene scene;
  const MpnetFeatureRow row = mpnet_features(scene.frame, scene.body);
  // Head target, network frame (−1, 0, √3): θ = atan2(1, √3) = 30° (positive to the left),
  // φ = atan2(√3, 0) = 90°.
  EXPECT_NEAR(row[mf::kTarget + tf::kHeadTheta], deg(30), kTolerance);
  EXPECT_NEAR(row[mf::kTarget + tf::kHeadPhi], deg(90), kTolerance);
  // Hand target 2 m away, 25° up: θ = 0, φ = atan2(z, y) = 90° − 25° = 65°, r clamped to 1 m.
  EXPECT_NEAR(row[mf::kTarget + tf::kHandTheta], 0.0f, kTolerance);
  EXPECT_NEAR(row[mf::kTarget + tf::kHandPhi], deg(65), kTolerance);
  EXPECT_NEAR(row[mf::kTarget + tf::kHandDistance], 1.0f, kTolerance);

  // A near hand target, (0.3, −0.3, −0.3) in the root frame (right, below, ahead), network
  // frame (0.3, −0.3, 0.3): θ = atan2(−0.3, 0.3) = −45°, φ = atan2(0.3, −0.3) = 135°,
  // r = 0.3·√3 m (not clamped).
  AngleScene near = scene;
  near.frame.hand_target_position = in_world(near.body.T_world_root, Vec3(0.3f, -0.3f, -0.3f));
  const MpnetFeatureRow near_row = mpnet_features(near.frame, near.body);
  EXPECT_NEAR(near_row[mf::kTarget + tf::kHandTheta], deg(-45), kTolerance);
  EXPECT_NEAR(near_row[mf::kTarget + tf::kHandPhi], deg(135), kTolerance);
  EXPECT_NEAR(near_row[mf::kTarget + tf::kHandDistance], 0.3f * std::sqrt(3.0f), kTolerance);
}

TEST(MpnetFeatures, NearRestIsOneWithinAQuarterMetreOfTheUprightWrist) {
  AngleScene scene;
  const int h = index(scene.body.deictic_hand);
  const Pose& O = scene.body.T_world_root;
  EXPECT_EQ(mpnet_features(scene.frame, scene.body)[mf::kNearRest], 1.0f);  // 0.17 m away
  scene.frame.T_world_wrist[h].translation =
      in_world(O, scene.body.rest_wrist_in_root[h] + Vec3(0.2f, 0.2f, 0.0f));  // 0.28 m
  EXPECT_EQ(mpnet_features(scene.frame, scene.body)[mf::kNearRest], 0.0f);
  scene.frame.T_world_wrist[h].translation =
      in_world(O, scene.body.rest_wrist_in_root[h] + Vec3(0.0f, 0.0f, -0.24f));  // 0.24 m
  EXPECT_EQ(mpnet_features(scene.frame, scene.body)[mf::kNearRest], 1.0f);
  // The other hand far from its rest position does not matter.
  scene.frame.T_world_wrist[index(other(scene.body.deictic_hand))].translation = Vec3(9, 9, 9);
  EXPECT_EQ(mpnet_features(scene.frame, scene.body)[mf::kNearRest], 1.0f);
}

TEST(MpnetFeatures, UnsignedAngleCoversZeroToPi) {
  EXPECT_NEAR(unsigned_angle(Vec3(1, 0, 0), Vec3(2, 0, 0)), 0.0f, kTolerance);
  EXPECT_NEAR(unsigned_angle(Vec3(1, 0, 0), Vec3(0, 3, 0)), kPi / 2, kTolerance);
  EXPECT_NEAR(unsigned_angle(Vec3(1, 0, 0), Vec3(-1, 0, 0)), kPi, kTolerance);
  EXPECT_NEAR(unsigned_angle(Vec3(1, 1, 0), Vec3(-1, 0, 0)), deg(135), kTolerance);
  EXPECT_EQ(unsigned_angle(Vec3::Zero(), Vec3(1, 0, 0)), 0.0f);
}

// The end-effector scene: head, gaze, wrist and fingertip given in their parents' frames (world
// axes: −Z forward, +Y up); the expected network vectors are written out by hand.
struct EndEffectorScene {
  BodyCalibration body;
  TrackingFrame frame;

  EndEffectorScene() {
    body.deictic_hand = Hand::kRight;
    body.T_world_root = placed_root();
    // Head: turned 30° left of the root, 1 cm right, 2 cm down, 3 cm forward.
    const Pose T_root_head{yaw_rotation(deg(30)), Vec3(0.01f, -0.02f, -0.03f)};
    // Wrist in the head frame: 0.2 right, 0.3 down, 0.4 forward, turned 90° to the left.
    const Pose T_head_wrist{yaw_rotation(deg(90)), Vec3(0.2f, -0.3f, -0.4f)};
    const Vec3 tip_in_wrist(0.135f, -0.056f, -0.017f);
    const Vec3 gaze_in_head(0, -std::sin(deg(20)), -std::cos(deg(20)));  // 20° down

    frame.T_world_head = compose(body.T_world_root, T_root_head);
    const Pose T_world_wrist = compose(frame.T_world_head, T_head_wrist);
    frame.T_world_wrist[index(Hand::kRight)] = T_world_wrist;
    frame.index_tip[index(Hand::kRight)] = transform_point(T_world_wrist, tip_in_wrist);
    frame.gaze = frame.T_world_head.rotation * gaze_in_head;
    frame.valid = tracked::kAll;
  }
};

void expect_vec3(const EndEffectors& x, int offset, const Vec3& expected, const char* what) {
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(x[offset + k], expected[k], kTolerance) << what << " component " << k;
  }
}

TEST(EndEffectors, EachPartIsHandComputedInTheNetworkFrame) {
  const EndEffectorScene scene;
  const EndEffectors x = end_effectors(scene.frame, scene.body);
  // Gaze 20° down in the head frame; the network frame's forward is +Z.
  expect_vec3(x, ee::kGaze, Vec3(0, -std::sin(deg(20)), std::cos(deg(20))), "gaze");
  // Head turned 30° left of the root: forward column (−sin 30°, 0, cos 30°) (left is −x), up +Y;
  // position with z flipped.
  expect_vec3(x, ee::kHeadForward, Vec3(-0.5f, 0, std::cos(deg(30))), "head forward");
  expect_vec3(x, ee::kHeadUp, Vec3(0, 1, 0), "head up");
  expect_vec3(x, ee::kHeadPosition, Vec3(0.01f, -0.02f, 0.03f), "head position");
  // Wrist turned 90° left of the head: forward column (−1, 0, 0), up +Y, position z flipped.
  expect_vec3(x, ee::kHandForward, Vec3(-1, 0, 0), "hand forward");
  expect_vec3(x, ee::kHandUp, Vec3(0, 1, 0), "hand up");
  expect_vec3(x, ee::kHandPosition, Vec3(0.2f, -0.3f, 0.4f), "hand position");
  // The fingertip in the wrist frame, z flipped: the authors' (0.135, −0.056, 0.017).
  expect_vec3(x, ee::kFingertip, Vec3(0.135f, -0.056f, 0.017f), "fingertip");
}

TEST(EndEffectors, RootPlacementDoesNotMatter) {
  EndEffectorScene scene;
  const EndEffectors x = end_effectors(scene.frame, scene.body);
  // Move and turn the whole scene (person, root) in the world: nothing relative changes.
  const Pose T_new_old{yaw_rotation(-1.1f), Vec3(-4.0f, 0.3f, 2.0f)};
  EndEffectorScene moved = scene;
  moved.body.T_world_root = compose(T_new_old, scene.body.T_world_root);
  moved.frame.T_world_head = compose(T_new_old, scene.frame.T_world_head);
  moved.frame.T_world_wrist[1] = compose(T_new_old, scene.frame.T_world_wrist[1]);
  moved.frame.index_tip[1] = transform_point(T_new_old, scene.frame.index_tip[1]);
  moved.frame.gaze = T_new_old.rotation * scene.frame.gaze;
  const EndEffectors y = end_effectors(moved.frame, moved.body);
  for (int i = 0; i < kEndEffectorSize; ++i) {
    EXPECT_NEAR(x[i], y[i], 5e-6f) << "index " << i;
  }
}

// The mirror image of a person through their own sagittal plane (the root's y–z plane): a
// left-handed twin. Positions and directions negate their root-frame x; a rotation R becomes
// M·R·M (M = diag(−1, 1, 1) in root coordinates), which also carries the right wrist frame of
// docs/decisions.md §7 onto the left one; right and left hands swap.
struct Mirror {
  Pose T_world_root;
  Mat3 M_world;  // the reflection in world coordinates

  explicit Mirror(const Pose& root) : T_world_root(root) {
    M_world = root.rotation * Vec3(-1, 1, 1).asDiagonal() * root.rotation.transpose();
  }
  Vec3 point(const Vec3& p) const {
    return M_world * (p - T_world_root.translation) + T_world_root.translation;
  }
  Vec3 direction(const Vec3& d) const { return M_world * d; }
  Pose pose(const Pose& T) const {
    // Local axes are reflected too (M on the right, in local coordinates = diag(−1, 1, 1)).
    return Pose{M_world * T.rotation * Mat3(Vec3(-1, 1, 1).asDiagonal()), point(T.translation)};
  }
  TrackingFrame frame(const TrackingFrame& f) const {
    TrackingFrame out = f;
    out.T_world_head = pose(f.T_world_head);
    out.gaze = direction(f.gaze);
    for (const Hand h : {Hand::kLeft, Hand::kRight}) {
      out.T_world_wrist[index(other(h))] = pose(f.T_world_wrist[index(h)]);
      out.index_tip[index(other(h))] = point(f.index_tip[index(h)]);
    }
    out.head_target_position = point(f.head_target_position);
    out.hand_target_position = point(f.hand_target_position);
    return out;
  }
  BodyCalibration body(const BodyCalibration& b) const {
    BodyCalibration out = b;
    out.deictic_hand = other(b.deictic_hand);
    for (const Hand h : {Hand::kLeft, Hand::kRight}) {
      out.rest_wrist_in_root[index(other(h))] =
          b.rest_wrist_in_root[index(h)].cwiseProduct(Vec3(-1, 1, 1));
    }
    return out;
  }
};

TEST(LeftHanded, MirrorTwinIsProperAndHasTheAuthorsLeftFingertip) {
  const EndEffectorScene scene;
  const Mirror mirror(scene.body.T_world_root);
  const TrackingFrame twin = mirror.frame(scene.frame);
  const Pose& wrist = twin.T_world_wrist[index(Hand::kLeft)];
  EXPECT_NEAR(wrist.rotation.determinant(), 1.0f, 1e-5f);  // a rotation, not a reflection
  // Local fingertip of the left wrist: x proximal, so the fingertip has negative x.
  const Vec3 tip_local = transform_point(inverse(wrist), twin.index_tip[index(Hand::kLeft)]);
  EXPECT_TRUE(tip_local.isApprox(Vec3(-0.135f, -0.056f, -0.017f), 1e-5f)) << tip_local.transpose();
}

TEST(LeftHanded, TheMirrorTwinIsSeenAsTheMirrorImage) {
  // A left-handed person is seen as they are (docs/decisions.md §17): the mirror twin of a
  // right-handed person has the mirror image of its network columns, which is the view the
  // left-hand weights were trained on (mirrored right-handed data). Angles, d, φ and r are
  // mirror-invariant; both θ and the x of all eight 3-vectors change sign.
  const AngleScene right;
  const Mirror mirror(right.body.T_world_root);
  const BodyCalibration left_body = mirror.body(right.body);
  const TrackingFrame left_frame = mirror.frame(right.frame);
  ASSERT_EQ(left_body.deictic_hand, Hand::kLeft);
  const MpnetFeatureRow a = mpnet_features(right.frame, right.body);
  const MpnetFeatureRow b = mpnet_features(left_frame, left_body);
  for (int i = 0; i < kMpnetFeatureCount; ++i) {
    const bool theta = i == mf::kTarget + tf::kHeadTheta || i == mf::kTarget + tf::kHandTheta;
    EXPECT_NEAR(b[i], theta ? -a[i] : a[i], 5e-6f) << "column " << i;
  }

  const EndEffectorScene scene;
  const Mirror m2(scene.body.T_world_root);
  EndEffectors x = end_effectors(scene.frame, scene.body);
  const EndEffectors y = end_effectors(m2.frame(scene.frame), m2.body(scene.body));
  mirror_end_effectors(x);
  for (int i = 0; i < kEndEffectorSize; ++i) {
    EXPECT_NEAR(x[i], y[i], 5e-6f) << "index " << i;
  }
}

TEST(LeftHanded, TargetsAreSeenUnmirrored) {
  // Hand-computed: a target 30° to the person's left has θ = +30° whichever hand they use; φ 90°.
  const Pose root = placed_root();
  const Vec3 target = in_world(root, Vec3(-1, 0, -std::sqrt(3.0f)));
  const TargetFeature t = target_feature_from_root(root, target, target);
  EXPECT_NEAR(t[tf::kHeadTheta], deg(30), kTolerance);
  EXPECT_NEAR(t[tf::kHandTheta], deg(30), kTolerance);
  EXPECT_NEAR(t[tf::kHeadPhi], deg(90), kTolerance);
  EXPECT_NEAR(t[tf::kHandPhi], deg(90), kTolerance);
  EXPECT_NEAR(t[tf::kHandDistance], 1.0f, kTolerance);
}

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<float> n(0.0f, 1.0f);
  return Quat(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

Vec3 random_vec(std::mt19937& rng, float scale) {
  std::uniform_real_distribution<float> u(-scale, scale);
  return {u(rng), u(rng), u(rng)};
}

TEST(RoundTrip, DecodeOfEndEffectorsGivesBackTheTrackedPoses) {
  std::mt19937 rng(11);
  for (const Hand hand : {Hand::kRight, Hand::kLeft}) {
    for (int i = 0; i < 200; ++i) {
      BodyCalibration body;
      body.deictic_hand = hand;
      body.T_world_root = Pose{yaw_rotation(random_vec(rng, kPi).x()), random_vec(rng, 3.0f)};
      TrackingFrame f;
      f.T_world_head =
          Pose{random_rotation(rng), body.T_world_root.translation + random_vec(rng, 0.1f)};
      f.gaze = random_vec(rng, 1.0f).normalized();
      const int h = index(hand);
      f.T_world_wrist[h] =
          Pose{random_rotation(rng), f.T_world_head.translation + random_vec(rng, 0.7f)};
      f.index_tip[h] = transform_point(f.T_world_wrist[h], random_vec(rng, 0.15f));
      f.valid = tracked::kAll;

      const EndEffectorPoses back = decode_end_effectors(end_effectors(f, body), body.T_world_root);
      EXPECT_TRUE(back.T_world_head.rotation.isApprox(f.T_world_head.rotation, 1e-5f));
      EXPECT_LT((back.T_world_head.translation - f.T_world_head.translation).norm(), 1e-5f);
      EXPECT_TRUE(back.T_world_wrist.rotation.isApprox(f.T_world_wrist[h].rotation, 1e-5f));
      EXPECT_LT((back.T_world_wrist.translation - f.T_world_wrist[h].translation).norm(), 1e-5f);
      EXPECT_LT((back.index_tip - f.index_tip[h]).norm(), 1e-5f);
      EXPECT_LT((back.gaze - f.gaze).norm(), 1e-5f);
    }
  }
}

TEST(RoundTrip, EndEffectorsOfDecodedPosesGiveBackX) {
  // x built from proper rotations (what end_effectors produces) survives decode → encode.
  std::mt19937 rng(12);
  for (const Hand hand : {Hand::kRight, Hand::kLeft}) {
    for (int i = 0; i < 200; ++i) {
      EndEffectors x{};
      set_vec3(x, ee::kGaze, random_vec(rng, 1.0f).normalized());
      const Mat3 head = random_rotation(rng);
      const Mat3 wrist = random_rotation(rng);
      set_vec3(x, ee::kHeadForward, head.col(2));
      set_vec3(x, ee::kHeadUp, head.col(1));
      set_vec3(x, ee::kHeadPosition, random_vec(rng, 0.1f));
      set_vec3(x, ee::kHandForward, wrist.col(2));
      set_vec3(x, ee::kHandUp, wrist.col(1));
      set_vec3(x, ee::kHandPosition, random_vec(rng, 0.6f));
      set_vec3(x, ee::kFingertip, random_vec(rng, 0.15f));
      const Pose root{yaw_rotation(random_vec(rng, kPi).y()), random_vec(rng, 2.0f)};
      const EndEffectorPoses poses = decode_end_effectors(x, root);

      BodyCalibration body;
      body.deictic_hand = hand;
      body.T_world_root = root;
      TrackingFrame f;
      f.T_world_head = poses.T_world_head;
      f.gaze = poses.gaze;
      f.T_world_wrist[index(hand)] = poses.T_world_wrist;
      f.index_tip[index(hand)] = poses.index_tip;
      const EndEffectors y = end_effectors(f, body);
      for (int k = 0; k < kEndEffectorSize; ++k) {
        EXPECT_NEAR(x[k], y[k], 2e-5f) << "index " << k << " sample " << i;
      }
    }
  }
}

}  // namespace
}  // namespace deixis
