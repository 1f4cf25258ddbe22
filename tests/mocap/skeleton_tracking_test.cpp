// Tracking from a skeleton (mocap/skeleton_tracking.h): known values at rest, the same motion in
// any Euler order gives the same tracking, a motion turned about the vertical gives tracking
// turned the same way, joint names (CMU, Mixamo, generic; a missing one named), calibration, and
// the Debian recordings.

#include "mocap/skeleton_tracking.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "core/error.h"
#include "mocap/humanoid.h"

namespace deixis::mocap {
namespace {

using testing::humanoid_bvh;
using testing::HumanoidFrame;
using testing::random_motion;

const std::filesystem::path kDebian = "/usr/share/assimp/models/BVH";

std::vector<TrackingFrame> track_all(const std::string& text, double scale = 0.01) {
  const Bvh b = parse_bvh(text, "t.bvh");
  SkeletonTracking s(b, scale);
  std::vector<TrackingFrame> out(b.frames());
  for (std::size_t i = 0; i < b.frames(); ++i) {
    s.track(i, out[i]);
  }
  return out;
}

void expect_near(const Vec3& a, const Vec3& b, float tolerance, const char* what) {
  EXPECT_LT((a - b).norm(), tolerance) << what << ": " << a.transpose() << " vs " << b.transpose();
}
void expect_near(const Mat3& a, const Mat3& b, float tolerance, const char* what) {
  EXPECT_LT((a - b).norm(), tolerance) << what << ":\n" << a << "\nvs\n" << b;
}

TEST(SkeletonTracking, KnownValuesAtRest) {
  HumanoidFrame rest;
  rest.rotation.assign(testing::humanoid().size(), Eigen::Matrix3d::Identity());
  const std::vector<TrackingFrame> f = track_all(humanoid_bvh({rest}));
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].valid, tracked::kAll);
  const float S = 1.73f;  // the humanoid's rest height
  // Facing +Z (the left hand on +X): H is the head top less 0.064 S, 0.05 S forward.
  expect_near(f[0].T_world_head.translation, Vec3(0, 0.95f + 0.78f - 0.064f * S, 0.05f * S), 1e-5f,
              "H");
  const Mat3 facing_plus_z = Vec3(-1, 1, -1).asDiagonal();
  expect_near(f[0].T_world_head.rotation, facing_plus_z, 1e-5f, "head");
  expect_near(f[0].gaze, Vec3(0, 0, 1), 1e-5f, "gaze");
  // A T-pose with palms down facing +Z: both wrist frames are the head's (docs/decisions.md §7).
  for (int h = 0; h < 2; ++h) {
    expect_near(f[0].T_world_wrist[h].rotation, facing_plus_z, 1e-5f, "wrist");
  }
  expect_near(f[0].T_world_wrist[0].translation, Vec3(0.71f, 1.40f, 0), 1e-5f, "left wrist");
  expect_near(f[0].T_world_wrist[1].translation, Vec3(-0.71f, 1.40f, 0), 1e-5f, "right wrist");
  // The left index chain's end; the right hand has no fingers: the tracker's offset, scaled.
  expect_near(f[0].index_tip[0], Vec3(0.88f, 1.40f, 0), 1e-5f, "left tip");
  expect_near(f[0].index_tip[1],
              Vec3(-0.71f, 1.40f, 0) + (S / 1.70f) * Vec3(-0.135f, -0.056f, 0.017f), 1e-5f,
              "right tip");
}

TEST(SkeletonTracking, AnyEulerOrderGivesTheSameTracking) {
  const auto motion = random_motion(20, 7);
  const auto zyx = track_all(humanoid_bvh(motion, {2, 1, 0}));
  for (const std::array<int, 3> order :
       {std::array<int, 3>{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {1, 0, 2}}) {
    const auto other = track_all(humanoid_bvh(motion, order));
    for (std::size_t i = 0; i < zyx.size(); ++i) {
      expect_near(other[i].T_world_head.translation, zyx[i].T_world_head.translation, 1e-5f, "H");
      expect_near(other[i].T_world_head.rotation, zyx[i].T_world_head.rotation, 1e-5f, "head");
      for (int h = 0; h < 2; ++h) {
        expect_near(other[i].T_world_wrist[h].translation, zyx[i].T_world_wrist[h].translation,
                    1e-5f, "wrist");
        expect_near(other[i].T_world_wrist[h].rotation, zyx[i].T_world_wrist[h].rotation, 1e-5f,
                    "wrist rotation");
        expect_near(other[i].index_tip[h], zyx[i].index_tip[h], 1e-5f, "tip");
      }
    }
  }
}

TEST(SkeletonTracking, AMotionTurnedAboutTheVerticalIsTrackedTurned) {
  auto motion = random_motion(20, 11);
  const auto original = track_all(humanoid_bvh(motion));
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (HumanoidFrame& f : motion) {
    f.root = turn * f.root;
    f.rotation[0] = turn * f.rotation[0];
  }
  const auto turned = track_all(humanoid_bvh(motion, {0, 2, 1}));
  const Mat3 R = turn.cast<float>();
  for (std::size_t i = 0; i < original.size(); ++i) {
    expect_near(turned[i].T_world_head.translation, R * original[i].T_world_head.translation, 1e-5f,
                "H");
    expect_near(turned[i].T_world_head.rotation, R * original[i].T_world_head.rotation, 1e-5f,
                "head");
    expect_near(turned[i].gaze, R * original[i].gaze, 1e-5f, "gaze");
    for (int h = 0; h < 2; ++h) {
      expect_near(turned[i].T_world_wrist[h].translation,
                  R * original[i].T_world_wrist[h].translation, 1e-5f, "wrist");
      expect_near(turned[i].T_world_wrist[h].rotation, R * original[i].T_world_wrist[h].rotation,
                  1e-5f, "wrist rotation");
      expect_near(turned[i].index_tip[h], R * original[i].index_tip[h], 1e-5f, "tip");
    }
  }
}

TEST(SkeletonTracking, UnitsScaleTheTrackingAndAutoFindsThem) {
  const auto motion = random_motion(5, 3);
  const auto cm = track_all(humanoid_bvh(motion), 0.01);
  const std::string in_inches = humanoid_bvh(motion, {2, 1, 0}, "", 1 / 2.54);
  const Bvh b = parse_bvh(in_inches, "inch.bvh");
  EXPECT_EQ(infer_unit(b), LengthUnit::kInch);
  const auto inch = track_all(in_inches, metres_per_unit(infer_unit(b)));
  for (std::size_t i = 0; i < cm.size(); ++i) {
    expect_near(inch[i].T_world_head.translation, cm[i].T_world_head.translation, 1e-5f, "H");
    expect_near(inch[i].index_tip[1], cm[i].index_tip[1], 1e-5f, "tip");
  }
}

TEST(SkeletonTracking, JointNamesByTableAndAMissingOneNamed) {
  const auto motion = random_motion(2, 5);
  const Bvh mixamo = parse_bvh(humanoid_bvh(motion, {2, 1, 0}, "mixamorig:"), "mixamo.bvh");
  const JointRoles r = find_roles(mixamo);
  EXPECT_EQ(mixamo.nodes[static_cast<std::size_t>(r.head)].name, "mixamorig:Head");
  EXPECT_EQ(mixamo.nodes[static_cast<std::size_t>(r.hand[0])].name, "mixamorig:LeftHand");
  EXPECT_EQ(mixamo.nodes[static_cast<std::size_t>(r.hand[1])].name, "mixamorig:RightHand");
  EXPECT_EQ(mixamo.nodes[static_cast<std::size_t>(r.elbow[0])].name, "mixamorig:LeftForeArm");
  EXPECT_TRUE(mixamo.nodes[static_cast<std::size_t>(r.index_tip[0])].end_site);
  EXPECT_EQ(r.index_tip[1], -1);
  std::string text = humanoid_bvh(motion);
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"LeftHand\n", "l_wrist\n"},
                                 {"JOINT RightHand\n", "JOINT Hand_R\n"}}) {
    text.replace(text.find(from), from.size(), to);
  }
  const Bvh generic = parse_bvh(text, "generic.bvh");
  const JointRoles g = find_roles(generic);
  EXPECT_EQ(generic.nodes[static_cast<std::size_t>(g.hand[0])].name, "l_wrist");
  EXPECT_EQ(generic.nodes[static_cast<std::size_t>(g.hand[1])].name, "Hand_R");
  std::string no_hand = humanoid_bvh(motion);
  no_hand.replace(no_hand.find("RightHand\n"), 10, "RightPaw\n");
  try {
    find_roles(parse_bvh(no_hand, "paw.bvh"));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no right hand joint"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("RightPaw"), std::string::npos) << e.what();
  }
}

TEST(SkeletonTracking, CalibrationFromTheFirstUprightFrame) {
  HumanoidFrame rest;
  rest.rotation.assign(testing::humanoid().size(), Eigen::Matrix3d::Identity());
  HumanoidFrame lying = rest;
  lying.rotation[0] = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Bvh b = parse_bvh(humanoid_bvh({lying, rest}), "c.bvh");
  SkeletonTracking s(b, 0.01);
  EXPECT_EQ(s.upright_frame(), 1u);
  const BodyCalibration c = s.calibrate();
  EXPECT_NEAR(c.height, 1.73f, 1e-5f);
  // The right arm: 0.28 + 0.25 m, and the estimated tip (the tracker's offset, scaled).
  EXPECT_NEAR(c.arm_length, 0.53f + (1.73f / 1.70f) * Vec3(0.135f, 0.056f, 0.017f).norm(), 1e-5f);
  // Facing +Z: the root's −Z is the world's +Z.
  expect_near(c.T_world_root.rotation * Vec3(0, 0, -1), Vec3(0, 0, 1), 1e-5f, "root");
  const Bvh never = parse_bvh(humanoid_bvh({lying}), "never.bvh");
  SkeletonTracking n(never, 0.01);
  EXPECT_THROW(n.calibrate(), Error);
}

// A recording rewritten with every joint's rotations in `order` (axis indices, 0 = X), turned by
// `yaw` about +Y at the root, its lengths multiplied by `factor`, and its first `frames` frames.
Bvh transformed(const Bvh& b, std::array<int, 3> order, double yaw, double factor,
                std::size_t frames) {
  Bvh t = b;
  t.motion.resize(frames * b.channels);
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (std::size_t n = 0; n < b.nodes.size(); ++n) {
    const BvhNode& from = b.nodes[n];
    BvhNode& to = t.nodes[n];
    to.offset = from.offset * factor;
    to.channels.clear();
    for (const Channel c : from.channels) {
      if (c <= Channel::kZposition) {
        to.channels.push_back(c);
      }
    }
    const bool rotates = to.channels.size() < from.channels.size();
    if (rotates) {
      for (const int a : order) {
        to.channels.push_back(static_cast<Channel>(static_cast<int>(Channel::kXrotation) + a));
      }
    }
    for (std::size_t f = 0; f < frames; ++f) {
      const std::span<const float> row = b.frame(f);
      float* out = t.motion.data() + f * b.channels + from.first_value;
      Eigen::Vector3d position = from.offset;
      for (std::size_t k = 0; k < from.channels.size(); ++k) {
        if (from.channels[k] <= Channel::kZposition) {
          position[static_cast<int>(from.channels[k])] +=
              static_cast<double>(row[static_cast<std::size_t>(from.first_value) + k]);
        }
      }
      Eigen::Matrix3d R = channel_rotation(from, row);
      if (from.parent < 0) {
        R = turn * R;
        position = turn * position;
      }
      std::size_t k = 0;
      for (; k < to.channels.size() && to.channels[k] <= Channel::kZposition; ++k) {
        const int axis = static_cast<int>(to.channels[k]);
        out[k] = static_cast<float>((position[axis] - from.offset[axis]) * factor);
      }
      if (rotates) {
        const Eigen::Vector3d e = R.eulerAngles(order[0], order[1], order[2]) * (180 / M_PI);
        for (int a = 0; a < 3; ++a, ++k) {
          out[k] = static_cast<float>(e[a]);
        }
      }
    }
  }
  return t;
}

TEST(SkeletonTracking, TransformedDebianRecordingsAgree) {
  const std::filesystem::path file = kDebian / "01_01.bvh";
  if (!std::filesystem::exists(file)) {
    GTEST_SKIP() << "no " << file << " (Debian's assimp-testmodels; tools/install-deps)";
  }
  const Bvh b = read_bvh(file);
  constexpr std::size_t kFrames = 600;
  SkeletonTracking original(b, metres_per_unit(infer_unit(b)));
  const double yaw = 0.7;
  const Mat3 turn = Eigen::AngleAxisf(static_cast<float>(yaw), Vec3::UnitY()).toRotationMatrix();
  // XYZ order, turned, in metres (written and read again as text); YXZ in centimetres.
  const Bvh metres = parse_bvh(
      write_bvh(transformed(b, {0, 1, 2}, yaw, metres_per_unit(LengthUnit::kCmu), kFrames)),
      "m.bvh");
  const Bvh cm = transformed(b, {1, 0, 2}, 0.0, metres_per_unit(LengthUnit::kCmu) * 100, kFrames);
  ASSERT_EQ(infer_unit(metres), LengthUnit::kMetre);
  ASSERT_EQ(infer_unit(cm), LengthUnit::kCentimetre);
  SkeletonTracking in_metres(metres, 1.0);
  SkeletonTracking in_cm(cm, 0.01);
  TrackingFrame a;
  TrackingFrame m;
  TrackingFrame c;
  for (std::size_t i = 0; i < kFrames; ++i) {
    original.track(i, a);
    in_metres.track(i, m);
    in_cm.track(i, c);
    expect_near(m.T_world_head.translation, turn * a.T_world_head.translation, 1e-4f, "H");
    expect_near(m.T_world_head.rotation, turn * a.T_world_head.rotation, 1e-4f, "head");
    expect_near(c.T_world_head.translation, a.T_world_head.translation, 1e-4f, "H");
    for (int h = 0; h < 2; ++h) {
      expect_near(m.T_world_wrist[h].translation, turn * a.T_world_wrist[h].translation, 1e-4f,
                  "wrist");
      expect_near(m.T_world_wrist[h].rotation, turn * a.T_world_wrist[h].rotation, 1e-4f,
                  "wrist rotation");
      expect_near(m.index_tip[h], turn * a.index_tip[h], 1e-4f, "tip");
      expect_near(c.T_world_wrist[h].rotation, a.T_world_wrist[h].rotation, 1e-4f, "wrist");
      expect_near(c.index_tip[h], a.index_tip[h], 1e-4f, "tip");
    }
    if (::testing::Test::HasFailure()) {
      FAIL() << "frame " << i;
    }
  }
}

TEST(SkeletonTracking, TheDebianRecordingsGivePlausibleTracking) {
  for (const char* name : {"01_01.bvh", "01_03.bvh", "Boxing_Toes.bvh"}) {
    if (!std::filesystem::exists(kDebian / name)) {
      GTEST_SKIP() << "no " << kDebian / name
                   << " (Debian's assimp-testmodels; tools/install-deps)";
    }
    const Bvh b = read_bvh(kDebian / name);
    SkeletonTracking s(b, metres_per_unit(infer_unit(b)));
    TrackingFrame f;
    for (std::size_t i = 0; i < b.frames(); ++i) {
      s.track(i, f);
      ASSERT_EQ(f.valid, tracked::kAll) << name << " frame " << i;
      ASSERT_TRUE(is_finite(f.T_world_head) && f.gaze.allFinite() && f.index_tip[0].allFinite() &&
                  f.index_tip[1].allFinite())
          << name << " frame " << i;
    }
    const BodyCalibration c = s.calibrate();
    EXPECT_GE(c.height, 1.4f) << name;
    EXPECT_LE(c.height, 2.1f) << name;
    EXPECT_GT(c.arm_length, 0.4f) << name;
    EXPECT_LT(c.arm_length, 1.0f) << name;
    s.track(s.upright_frame(), f);
    EXPECT_GT(f.T_world_head.translation.y(), f.T_world_wrist[0].translation.y()) << name;
    EXPECT_GT(f.T_world_head.translation.y(), f.T_world_wrist[1].translation.y()) << name;
    std::printf("%s: %zu frames, unit %s, height %.3f m, arm %.3f m, upright frame %zu\n", name,
                b.frames(), std::string(unit_name(infer_unit(b))).c_str(),
                static_cast<double>(c.height), static_cast<double>(c.arm_length),
                s.upright_frame());
  }
}

}  // namespace
}  // namespace deixis::mocap
