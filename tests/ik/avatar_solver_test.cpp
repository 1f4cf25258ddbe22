// AvatarSolver: building from rigs (and the errors that name what is wrong), the whole solve's
// geometry (head, eyes, fingertip, free hand), rigs without the optional bones, and a randomised
// sweep of 10⁵ inputs, random and adversarial, that must never produce NaN or leave a limit.

#include "ik/avatar_solver.h"

#include <gtest/gtest.h>

#include <sstream>

#include "core/error.h"
#include "ik/two_bone_job.h"
#include "limit_check.h"
#include "rig_pose.h"

namespace deixis::ik {
namespace {

using testing::angle_between;
using testing::make_test_rig;
using testing::TestRigOptions;

std::string build_error(const HumanoidRig& rig, const AvatarSolverConfig& config = {}) {
  try {
    AvatarSolver::build(rig, config);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(AvatarSolver, BuildNamesWhatIsWrong) {
  HumanoidRig rig = make_test_rig();
  rig.joint[static_cast<int>(Bone::kRightLowerArm)] = -1;
  EXPECT_EQ(build_error(rig), "avatar rig: required bone 'rightLowerArm' is missing");
  rig = make_test_rig();
  rig.joint[static_cast<int>(Bone::kNeck)] = 500;
  EXPECT_EQ(build_error(rig),
            "avatar rig: bone 'neck' maps to joint 500, not a joint of the skeleton");
  rig = make_test_rig();
  std::swap(rig.joint[static_cast<int>(Bone::kChest)], rig.joint[static_cast<int>(Bone::kNeck)]);
  EXPECT_EQ(build_error(rig), "avatar rig: bone 'neck' is not below the spine bone before it");
  rig = make_test_rig();
  rig.joint[static_cast<int>(Bone::kLeftEye)] = rig[Bone::kLeftHand];
  EXPECT_EQ(build_error(rig), "avatar rig: bone 'leftEye' is not below 'head'");
  rig = make_test_rig();
  rig.skeleton.rest_local[rig[Bone::kLeftLowerArm]].translation = Vec3::Zero();
  EXPECT_EQ(build_error(rig), "avatar rig: bone 'leftUpperArm' has no length in the rest pose");
  rig = make_test_rig();
  rig.eye_midpoint_in_head.x() = NAN;
  EXPECT_EQ(build_error(rig), "avatar rig: the eye midpoint is not finite");
  rig = make_test_rig();
  rig.skeleton.parents[3] = 7;
  EXPECT_NE(build_error(rig).find("depth-first order"), std::string::npos);
  AvatarSolverConfig config;
  config.limits.neck = -1.0f;
  EXPECT_EQ(build_error(make_test_rig(), config), "IK limits: neck: not an angle in [0, π]");
  config = {};
  config.neck_share = 2.0f;
  EXPECT_EQ(build_error(make_test_rig(), config),
            "IK config: spine, chest, neck and lean shares must lie in [0, 1]");
  config = {};
  config.cylinder_margin = 0.05f;
  EXPECT_EQ(build_error(make_test_rig(), config),
            "IK config: cylinder_margin puts the shoulders inside the chest cylinder");
  config = {};
  config.soften = 0.0f;
  EXPECT_EQ(build_error(make_test_rig(), config),
            "IK config: soften must lie in (0, 1] and cylinder_margin be ≥ 0");
  EXPECT_EQ(build_error(make_test_rig()), "");
}

TEST(AvatarSolver, LimitsCheckNamesTheBadField) {
  IkLimits l;
  EXPECT_EQ(check(l), "");
  l.spine = NAN;
  EXPECT_EQ(check(l), "spine: not an angle in [0, π]");
  l = {};
  l.chest = 4.0f;
  EXPECT_EQ(check(l), "chest: not an angle in [0, π]");
  l = {};
  l.head = -0.1f;
  EXPECT_EQ(check(l), "head: not an angle in [0, π]");
  l = {};
  l.elbow = {-0.1f, 1.0f};
  EXPECT_EQ(check(l), "elbow: flexion range not within [0, π] and ordered");
  l = {};
  l.supination = 5.0f;
  EXPECT_EQ(check(l), "pronation/supination: not an angle in [0, π]");
  l = {};
  l.wrist_twist = -1.0f;
  EXPECT_EQ(check(l), "wrist_swing/wrist_twist: not an angle in [0, π]");
  l = {};
  l.index[1] = {1.0f, 0.0f};
  EXPECT_EQ(check(l), "index: flexion range not within [−π, π] and ordered");
  l = {};
  l.eyes.down = deg(90);
  EXPECT_EQ(check(l), "eyes: yaw not in [0, π] or up/down not in [0, π/2)");
}

struct Avatar {
  explicit Avatar(const TestRigOptions& options = {})
      : solver(AvatarSolver::build(make_test_rig(options))),
        local(static_cast<std::size_t>(solver.joint_count())),
        model(static_cast<std::size_t>(solver.joint_count())) {}

  bool solve(const Pose& T_world_root, const AvatarTargets& targets) {
    AvatarSolveJob job;
    job.solver = &solver;
    job.T_world_root = T_world_root;
    job.targets = &targets;
    job.local = local;
    job.model = model;
    job.report = &report;
    return job.run();
  }
  Pose world(const Pose& T_world_root, int joint) const {
    return compose(T_world_root, model[joint]);
  }
  Vec3 tip(const Pose& T_world_root, Hand hand) const {
    const ArmRig& a = solver.arms[index(hand)];
    return transform_point(world(T_world_root, a.tip_joint()), a.tip_offset);
  }
  int operator[](Bone b) const { return solver.rig[b]; }

  AvatarSolver solver;
  std::vector<Pose> local;
  std::vector<Pose> model;
  AvatarSolveReport report;
};

// A person standing upright at the root, arms relaxed: the targets of a quiet tick.
AvatarTargets quiet_targets(const AvatarSolver& s, const Pose& T_world_root) {
  AvatarTargets t;
  t.deictic.T_world_head = compose(T_world_root, Pose{Mat3::Identity(), s.eye_midpoint_rest});
  t.deictic.gaze = T_world_root.rotation * Vec3(0, 0, -1);
  const ArmRig& right = s.arms[index(Hand::kRight)];
  const Vec3 rest_tip = transform_point(s.rest_model[right.tip_joint()], right.tip_offset);
  t.deictic.T_world_wrist =
      compose(T_world_root, Pose{s.rest_model[right.hand].rotation * right.R_hand_wrist,
                                 s.rest_model[right.hand].translation});
  t.deictic.index_tip = transform_point(T_world_root, rest_tip);
  return t;
}

TEST(AvatarSolver, ValidateRejectsEachBrokenRule) {
  Avatar a;
  const AvatarTargets targets = quiet_targets(a.solver, Pose{});
  AvatarSolveJob job;
  job.solver = &a.solver;
  job.targets = &targets;
  job.local = a.local;
  job.model = a.model;
  std::string_view why;
  ASSERT_TRUE(job.validate(&why)) << why;
  const auto expect_invalid = [&](const AvatarSolveJob& j, std::string_view expected) {
    std::string_view reason;
    EXPECT_FALSE(j.validate(&reason));
    EXPECT_EQ(reason, expected);
    EXPECT_FALSE(j.run());
  };
  AvatarSolveJob j = job;
  j.solver = nullptr;
  expect_invalid(j, "solver and targets must be set");
  j = job;
  j.targets = nullptr;
  expect_invalid(j, "solver and targets must be set");
  j = job;
  j.local = std::span<Pose>(a.local.data(), a.local.size() - 1);
  expect_invalid(j, "local and model must hold one pose per skeleton joint");
  j = job;
  j.T_world_root.translation.y() = NAN;
  expect_invalid(j, "T_world_root must be finite with a rotation matrix");
  j = job;
  j.T_world_root.rotation *= 1.1f;
  expect_invalid(j, "T_world_root must be finite with a rotation matrix");
  j = job;
  j.T_world_root.rotation = -Mat3::Identity();  // a reflection
  expect_invalid(j, "T_world_root must be finite with a rotation matrix");
}

TEST(AvatarSolver, RootFromOriginPutsTheRestEyesAtO) {
  Avatar a;
  const Pose O{yaw_rotation(0.8f), Vec3(1, 1.6f, -2)};
  const Pose root = T_world_root_from_origin(a.solver, O);
  EXPECT_LT((transform_point(root, a.solver.eye_midpoint_rest) - O.translation).norm(), 1e-6f);
  EXPECT_TRUE(root.rotation.isApprox(O.rotation));
}

TEST(AvatarSolver, QuietTargetsGiveTheRestPose) {
  Avatar a;
  const Pose root{yaw_rotation(-1.2f), Vec3(3, 0, 1)};
  ASSERT_TRUE(a.solve(root, quiet_targets(a.solver, root)));
  for (int j = 0; j < a.solver.joint_count(); ++j) {
    if (is_ancestor(a.solver.rig.skeleton, a[Bone::kLeftShoulder], j) ||
        is_ancestor(a.solver.rig.skeleton, a[Bone::kRightShoulder], j)) {
      continue;  // the arms follow their own targets (a straight arm is beyond the soft reach)
    }
    EXPECT_LT(rotation_angle(a.local[j].rotation.transpose() *
                             a.solver.rig.skeleton.rest_local[j].rotation),
              deg(0.05f))
        << a.solver.rig.skeleton.joint_names[j];
  }
  EXPECT_TRUE(a.report.head_reached);
  EXPECT_LT(a.report.head_position_error, 1e-4f);
  EXPECT_TRUE(a.report.eyes_reached);
}

// Targets of a pointing, looking person in the room, reachable by this avatar: the head turned
// and leaning a little, the gaze within the eyes' range, the deictic arm in a pose the arm job
// can produce (found from the solved shoulder), the free hand somewhere around the body.
struct Scene {
  Pose root;
  AvatarTargets targets;
  Mat3 R_world_H;
  Vec3 lean;  // H's offset from where the head orientation alone puts it
};

Scene reachable_scene(Avatar& a, std::mt19937& rng, Hand deictic) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Scene s;
  s.root = Pose{yaw_rotation(3.0f * u(rng)), Vec3(2 * u(rng), 0.1f * u(rng), 2 * u(rng))};
  AvatarTargets& t = s.targets;
  t.deictic_hand = deictic;
  s.R_world_H = s.root.rotation * axis_angle(Vec3::UnitY(), deg(60) * u(rng)) *
                axis_angle(Vec3::UnitX(), deg(30) * u(rng)) *
                axis_angle(Vec3::UnitZ(), deg(10) * u(rng));
  const float yaw = deg(30) * u(rng), pitch = deg(20) * u(rng);
  t.deictic.gaze = s.R_world_H * Vec3(-std::sin(yaw) * std::cos(pitch), std::sin(pitch),
                                      -std::cos(yaw) * std::cos(pitch));
  // Where H is when the head turns without a lean (people's eyes move when they look up or
  // around), then a lean of a few centimetres, mostly sideways and forward or back (a lean
  // hardly raises or lowers the eyes).
  t.deictic.T_world_head = Pose{s.R_world_H, Vec3(NAN, 0, 0)};
  t.deictic.index_tip = Vec3(NAN, 0, 0);  // only the spine matters for now
  a.solve(s.root, t);
  const int head = a[Bone::kHead];
  s.lean = s.root.rotation * Vec3(0.04f * u(rng), 0.005f * u(rng), 0.04f * u(rng));
  t.deictic.T_world_head.translation =
      transform_point(a.world(s.root, head), a.solver.rig.eye_midpoint_in_head) + s.lean;
  t.other.azimuth = (deictic == Hand::kRight ? 1.0f : -1.0f) * deg(40) * (1.2f + u(rng));
  t.other.elevation = deg(-50) + deg(30) * u(rng);
  t.other.distance = 0.55f + 0.1f * u(rng);
  t.other.R_root_wrist = testing::random_rotation(rng, deg(40));
  a.solve(s.root, t);

  // A pose of the deictic arm from its solved shoulder.
  const ArmRig& arm = a.solver.arms[index(deictic)];
  std::vector<Pose> local = a.local, model = a.model;
  const Vec3 S = model[arm.upper].translation;
  const float upper = (model[arm.lower].translation - S).norm();
  const float lower = (model[arm.hand].translation - model[arm.lower].translation).norm();
  const Reach reach = reach_of(upper, lower, a.solver.config.limits.elbow);
  Mat3 qs, qm;
  TwoBoneJob two_bone;
  two_bone.start_joint = &model[arm.upper];
  two_bone.mid_joint = &model[arm.lower];
  two_bone.end_joint = &model[arm.hand];
  const Vec3 dir = (Vec3(0.3f * u(rng), 0.5f * u(rng), -1.0f)).normalized();
  two_bone.target =
      S + (reach.min + 0.05f + (0.9f * reach.max - reach.min) * 0.5f * (1 + u(rng))) * dir;
  two_bone.pole_vector = arm.pole;
  two_bone.mid_axis = arm.mid_axis;
  two_bone.flexion = a.solver.config.limits.elbow;
  two_bone.start_correction = &qs;
  two_bone.mid_correction = &qm;
  two_bone.run();
  local[arm.upper].rotation *= qs;
  local[arm.lower].rotation *= qm;
  local[arm.lower].rotation *= axis_angle(
      arm.forearm_axis, deg(40) * u(rng) + (deictic == Hand::kRight ? deg(30) : -deg(30)));
  const Vec3 hand_axis =
      a.solver.rig.skeleton.rest_local[arm.hand].rotation.transpose() * arm.forearm_axis;
  local[arm.hand].rotation = a.solver.rig.skeleton.rest_local[arm.hand].rotation *
                             axis_angle(frame_from(hand_axis, testing::random_unit(rng)).col(1),
                                        deg(40) * std::abs(u(rng)));
  local_to_model(a.solver.rig.skeleton, local, model);
  t.deictic.T_world_wrist = compose(
      s.root, Pose{model[arm.hand].rotation * arm.R_hand_wrist, model[arm.hand].translation});
  t.deictic.index_tip = transform_point(compose(s.root, model[arm.tip_joint()]), arm.tip_offset);
  return s;
}

TEST(AvatarSolver, HeadEyesFingertipAndFreeHandReachTheirTargets) {
  std::mt19937 rng(41);
  for (const bool bone_aligned : {false, true}) {
    Avatar a(TestRigOptions{.bone_aligned = bone_aligned});
    float worst_tip = 0.0f;
    double lean_sum = 0.0, error_sum = 0.0;
    int lean_given_up = 0;
    for (int i = 0; i < 400; ++i) {
      const Hand deictic = i % 2 == 0 ? Hand::kRight : Hand::kLeft;
      const Scene scene = reachable_scene(a, rng, deictic);
      ASSERT_TRUE(a.solve(scene.root, scene.targets));
      // Head: exactly its orientation.
      const int head = a[Bone::kHead];
      const Mat3 R_world_H =
          a.world(scene.root, head).rotation * a.solver.rest_model[head].rotation.transpose();
      EXPECT_TRUE(a.report.head_reached);
      EXPECT_LT(rotation_angle(R_world_H * scene.R_world_H.transpose()), deg(0.01f));
      // H: leaning takes it most of the way (a lean tilts the body about the spine, which
      // cannot keep the eyes' height exactly), never farther than not leaning at all. Where the
      // head's orientation needs what the lean used, the solver gives the lean up ("the
      // orientation comes first", ik/avatar_solver.cpp): those scenes may keep more than half
      // the lean, and must stay rare.
      EXPECT_LT(a.report.head_position_error, scene.lean.norm() + 2e-3f);
      if (!(a.report.head_position_error < 0.5f * scene.lean.norm() + 2e-3f)) {
        ++lean_given_up;
      }
      lean_sum += static_cast<double>(scene.lean.norm());
      error_sum += static_cast<double>(a.report.head_position_error);
      // Eyes: along the gaze.
      for (const Bone eye : {Bone::kLeftEye, Bone::kRightEye}) {
        const int j = a[eye];
        const Vec3 sight = a.world(scene.root, j).rotation *
                           a.solver.rest_model[j].rotation.transpose() * Vec3(0, 0, -1);
        EXPECT_LT(angle_between(sight, scene.targets.deictic.gaze), deg(0.01f));
      }
      // Fingertip.
      worst_tip = std::max(worst_tip,
                           (a.tip(scene.root, deictic) - scene.targets.deictic.index_tip).norm());
      EXPECT_TRUE(a.report.deictic.reached);
      // The free hand: out of the chest.
      const Pose T_cyl =
          compose(a.model[a.solver.cylinder_joint], a.solver.cylinder.T_chest_cylinder);
      const Vec3 q = transform_point(
          inverse(T_cyl), a.model[a.solver.arms[index(other(deictic))].hand].translation);
      EXPECT_FALSE(inside(a.solver.cylinder, q * (1.0f + 1e-3f)));
      ASSERT_EQ(testing::check_limits(a.solver, a.local, a.model), "");
    }
    EXPECT_LT(worst_tip, 1e-3f);
    EXPECT_LT(error_sum, 0.15 * lean_sum);
    EXPECT_LE(lean_given_up, 4) << "of 400 scenes kept more than half their lean";
  }
}

TEST(AvatarSolver, RigsWithoutOptionalBonesStillSolve) {
  std::mt19937 rng(43);
  const std::array<TestRigOptions, 4> rigs = {TestRigOptions{.with_chest = false},
                                              TestRigOptions{.with_neck = false},
                                              TestRigOptions{.with_eyes = false, .index_joints = 1},
                                              TestRigOptions{.bone_aligned = true,
                                                             .with_chest = false,
                                                             .with_neck = false,
                                                             .with_eyes = false,
                                                             .index_joints = 0}};
  for (const TestRigOptions& options : rigs) {
    Avatar a(options);
    for (int i = 0; i < 50; ++i) {
      const Scene scene = reachable_scene(a, rng, Hand::kRight);
      ASSERT_TRUE(a.solve(scene.root, scene.targets));
      EXPECT_LT((a.tip(scene.root, Hand::kRight) - scene.targets.deictic.index_tip).norm(), 1e-3f);
      for (const Pose& p : a.model) {
        ASSERT_TRUE(is_finite(p));
      }
      ASSERT_EQ(testing::check_limits(a.solver, a.local, a.model), "");
    }
  }
}

TEST(AvatarSolver, SmallerAvatarsPointAlongTheEyeRayBeyondTheirReach) {
  // Pointing is the ray from the eyes through the fingertip (paper §III.A): a target beyond the
  // arm's reach puts the fingertip on the avatar's own eye→target ray, the arm stretched.
  Avatar a(TestRigOptions{.height = 1.36f});  // 20 % smaller
  std::mt19937 rng(47);
  for (int i = 0; i < 200; ++i) {
    Scene scene = reachable_scene(a, rng, Hand::kRight);
    const Vec3 S = a.world(scene.root, a[Bone::kRightUpperArm]).translation;
    const Vec3 dir = scene.root.rotation * Vec3(0.5f, 0.2f, -1).normalized();
    const Vec3 target = S + 2.5f * dir;
    scene.targets.deictic.index_tip = target;
    ASSERT_TRUE(a.solve(scene.root, scene.targets));
    EXPECT_TRUE(a.report.deictic.beyond_reach);
    const Vec3 eyes =
        transform_point(a.world(scene.root, a[Bone::kHead]), a.solver.rig.eye_midpoint_in_head);
    EXPECT_LT(angle_between(a.tip(scene.root, Hand::kRight) - eyes, target - eyes), deg(0.5f));
    EXPECT_LT(angle_between(a.tip(scene.root, Hand::kRight) - S, dir), deg(25));
  }
}

// ---- the sweep ----

float pick(std::mt19937& rng, std::initializer_list<float> values) {
  std::uniform_int_distribution<std::size_t> k(0, values.size() - 1);
  return *(values.begin() + k(rng));
}

// A value that is sometimes poison: NaN, ±Inf, huge, zero.
float adversarial(std::mt19937& rng, float ordinary) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  if (u(rng) > 0.04f) {
    return ordinary;
  }
  return pick(rng, {NAN, INFINITY, -INFINITY, 1e30f, -1e30f, 0.0f, 1e-30f});
}

Vec3 adversarial(std::mt19937& rng, const Vec3& v) {
  return {adversarial(rng, v.x()), adversarial(rng, v.y()), adversarial(rng, v.z())};
}

Mat3 adversarial_rotation(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  switch (std::uniform_int_distribution<int>(0, 9)(rng)) {
    case 0:
      return Mat3::Zero();
    case 1: {
      Mat3 garbage;
      for (int i = 0; i < 9; ++i) {
        garbage(i / 3, i % 3) = 10 * u(rng);
      }
      return garbage;
    }
    case 2: {
      Mat3 R = testing::random_rotation(rng);
      R(std::uniform_int_distribution<int>(0, 2)(rng), 1) = adversarial(rng, NAN);
      return R;
    }
    default:
      return testing::random_rotation(rng);
  }
}

AvatarTargets random_targets(const Avatar& a, const Pose& root, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  AvatarTargets t;
  t.deictic_hand = u(rng) > 0 ? Hand::kRight : Hand::kLeft;
  const Vec3 H = transform_point(root, a.solver.eye_midpoint_rest);
  const Vec3 shoulder = transform_point(
      root, a.solver.rest_model[a.solver.arms[index(t.deictic_hand)].upper].translation);
  t.deictic.T_world_head = Pose{adversarial_rotation(rng),
                                adversarial(rng, Vec3(H + 0.5f * Vec3(u(rng), u(rng), u(rng))))};
  const float gaze_kind = u(rng);
  t.deictic.gaze = gaze_kind < -0.9f ? Vec3::Zero() : adversarial(rng, testing::random_unit(rng));
  t.deictic.T_world_wrist = Pose{adversarial_rotation(rng), Vec3::Zero()};
  const float tip_kind = u(rng);
  t.deictic.index_tip =
      tip_kind < -0.9f   ? shoulder                                           // at the shoulder
      : tip_kind < -0.8f ? H                                                  // at the eyes
      : tip_kind < -0.7f ? Vec3(shoulder + 1e4f * testing::random_unit(rng))  // very far
                         : adversarial(rng, Vec3(shoulder + 1.2f * Vec3(u(rng), u(rng), u(rng))));
  t.other.azimuth = adversarial(rng, deg(180) * u(rng));
  t.other.elevation = adversarial(rng, deg(90) * u(rng));
  t.other.distance = adversarial(rng, u(rng) > -0.8f ? 0.9f * std::abs(u(rng)) : -0.3f);
  t.other.R_root_wrist = adversarial_rotation(rng);
  return t;
}

// Enough to replay a failing solve.
std::string describe(const Pose& root, const AvatarTargets& t) {
  std::ostringstream o;
  o.precision(9);
  const auto matrix = [&](const Mat3& R) {
    o << "[";
    for (int k = 0; k < 9; ++k) {
      o << R(k / 3, k % 3) << (k < 8 ? ", " : "]");
    }
  };
  o << "root yaw " << yaw_of(root.rotation, Vec3(0, 0, -1)) << " at "
    << testing::to_text(root.translation) << "; deictic "
    << (t.deictic_hand == Hand::kRight ? "right" : "left") << "; head ";
  matrix(t.deictic.T_world_head.rotation);
  o << " at " << testing::to_text(t.deictic.T_world_head.translation) << "; gaze "
    << testing::to_text(t.deictic.gaze) << "; wrist ";
  matrix(t.deictic.T_world_wrist.rotation);
  o << "; tip " << testing::to_text(t.deictic.index_tip) << "; other " << t.other.azimuth << " "
    << t.other.elevation << " " << t.other.distance << " ";
  matrix(t.other.R_root_wrist);
  return o.str();
}

TEST(AvatarSolver, RandomisedSweepNeverGivesNaNOrLeavesALimit) {
  // 10⁵ solves over two rigs (model-axis and bone-aligned frames): 2 s in the release suite; a
  // tenth of them under the sanitizers, which check each solve's memory, not the sweep's reach.
#ifdef DEIXIS_SANITIZED
  constexpr int kSolves = 10000;
#else
  constexpr int kSolves = 100000;
#endif
  std::mt19937 rng(1234);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::array<Avatar, 2> avatars = {
      Avatar(TestRigOptions{}),
      Avatar(TestRigOptions{.height = 1.85f, .arm_scale = 1.1f, .bone_aligned = true})};
  int failures = 0;
  for (int i = 0; i < kSolves && failures < 5; ++i) {
    Avatar& a = avatars[i % 2];
    const Pose root{yaw_rotation(4 * u(rng)), Vec3(5 * u(rng), 0.2f * u(rng), 5 * u(rng))};
    const AvatarTargets targets = random_targets(a, root, rng);
    ASSERT_TRUE(a.solve(root, targets));
    std::string problem;
    if (!std::isfinite(a.report.head_position_error) ||
        !std::isfinite(a.report.deictic.tip_error) || !a.report.other.wrist_target.allFinite()) {
      problem = "a non-finite report";
    }
    for (int j = 0; j < a.solver.joint_count() && problem.empty(); ++j) {
      if (!is_finite(a.local[j]) || !is_finite(a.model[j])) {
        problem = "joint " + a.solver.rig.skeleton.joint_names[j] + " is not finite";
      } else if (!(a.local[j].rotation.transpose() * a.local[j].rotation).isIdentity(1e-4f)) {
        problem = "joint " + a.solver.rig.skeleton.joint_names[j] + " has no rotation matrix";
      }
    }
    if (problem.empty()) {
      problem = testing::check_limits(a.solver, a.local, a.model);
    }
    const Pose T_cyl =
        compose(a.model[a.solver.cylinder_joint], a.solver.cylinder.T_chest_cylinder);
    const Vec3 q = transform_point(
        inverse(T_cyl),
        a.model[a.solver.arms[index(other(targets.deictic_hand))].hand].translation);
    if (problem.empty() && inside(a.solver.cylinder, q * (1.0f + 1e-3f))) {
      problem = "the free hand is inside the chest cylinder, at " + testing::to_text(q);
    }
    if (!problem.empty()) {
      ++failures;
      ADD_FAILURE() << "solve " << i << ": " << problem << "\n" << describe(root, targets);
    }
  }
  EXPECT_EQ(failures, 0);
}

}  // namespace
}  // namespace deixis::ik
