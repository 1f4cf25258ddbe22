// TwoBoneJob: every validate() rule has a negative test; the end lands on reachable targets, the
// mid joint bends to the pole's side, unreachable targets are approached along the ray, flexion
// limits hold, and degenerate input gives no correction rather than NaN.

#include "ik/two_bone_job.h"

#include <gtest/gtest.h>

#include <random>

namespace deixis::ik {
namespace {

// A chain S(0,0,0) → E(0.3,0,0) → W(0.56,0,0) (a straight right arm), its hinge about +Z, under
// an arbitrary parent transform.
struct Chain {
  Pose start, mid, end;
  Pose mid_local;  // T_start_mid
  Pose end_local;  // T_mid_end
  Vec3 mid_axis = Vec3::UnitZ();
};

Chain make_chain(const Pose& parent = {}) {
  // Model poses with arbitrary joint frames; locals follow from them.
  Chain c;
  c.start = compose(parent, Pose{axis_angle(Vec3(1, 2, 3).normalized(), 0.9f), Vec3::Zero()});
  c.mid = compose(parent, Pose{axis_angle(Vec3::UnitY(), 0.4f), Vec3(0.3f, 0, 0)});
  c.end = compose(parent, Pose{axis_angle(Vec3::UnitX(), -0.7f), Vec3(0.56f, 0, 0)});
  c.mid_local = compose(inverse(c.start), c.mid);
  c.end_local = compose(inverse(c.mid), c.end);
  // +Z of the parent frame flexes the chain (bends the end toward +Y, the elbow toward −Y).
  c.mid_axis = c.mid.rotation.transpose() * parent.rotation * Vec3::UnitZ();
  return c;
}

struct Solved {
  bool ok;
  bool reached;
  Vec3 mid, end;
  Vec3 end_reported;
};

Solved solve(const Chain& c, TwoBoneJob job) {
  Mat3 qs, qm;
  bool reached = false;
  Vec3 end_reported;
  job.start_joint = &c.start;
  job.mid_joint = &c.mid;
  job.end_joint = &c.end;
  job.mid_axis = c.mid_axis;
  job.start_correction = &qs;
  job.mid_correction = &qm;
  job.reached = &reached;
  job.end_position = &end_reported;
  const bool ok = job.run();
  // Rebuild the corrected chain the way a caller applies the corrections.
  Pose start = c.start;
  start.rotation = start.rotation * qs;
  Pose mid_local = c.mid_local;
  mid_local.rotation = mid_local.rotation * qm;
  const Pose mid = compose(start, mid_local);
  const Pose end = compose(mid, c.end_local);
  return {ok, reached, mid.translation, end.translation, end_reported};
}

TEST(TwoBoneJob, ValidateRejectsEachBrokenRule) {
  const Chain c = make_chain();
  Mat3 q;
  const auto valid = [&] {
    TwoBoneJob job;
    job.start_joint = &c.start;
    job.mid_joint = &c.mid;
    job.end_joint = &c.end;
    job.start_correction = &q;
    job.mid_correction = &q;
    return job;
  };
  std::string_view why;
  ASSERT_TRUE(valid().validate(&why)) << why;
  const auto expect_invalid = [&](TwoBoneJob job, std::string_view expected) {
    std::string_view reason;
    EXPECT_FALSE(job.validate(&reason));
    EXPECT_EQ(reason, expected);
    EXPECT_FALSE(job.run());
  };
  TwoBoneJob j = valid();
  j.start_joint = nullptr;
  expect_invalid(j, "start_joint is not set");
  j = valid();
  j.mid_joint = nullptr;
  expect_invalid(j, "mid_joint is not set");
  j = valid();
  j.end_joint = nullptr;
  expect_invalid(j, "end_joint is not set");
  j = valid();
  j.start_correction = nullptr;
  expect_invalid(j, "start_correction output is not set");
  j = valid();
  j.mid_correction = nullptr;
  expect_invalid(j, "mid_correction output is not set");
  j = valid();
  j.mid_axis = Vec3(0, 0.7f, 0.7f);
  expect_invalid(j, "mid_axis is not a unit vector");
  j.mid_axis = Vec3(NAN, 0, 1);
  expect_invalid(j, "mid_axis is not a unit vector");
  j = valid();
  j.soften = 0.0f;
  expect_invalid(j, "soften is not in (0, 1]");
  j.soften = 1.5f;
  expect_invalid(j, "soften is not in (0, 1]");
  j = valid();
  j.flexion = {deg(10), deg(5)};
  expect_invalid(j, "flexion range is not ordered within [0, π]");
  j.flexion = {-0.1f, 1.0f};
  expect_invalid(j, "flexion range is not ordered within [0, π]");
  j.flexion = {0.0f, 4.0f};
  expect_invalid(j, "flexion range is not ordered within [0, π]");
}

TEST(TwoBoneJob, ReachesReachableTargetsUnderAnyParentTransform) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const Pose parents[] = {Pose{}, Pose{Mat3::Identity(), Vec3(0, 1.4f, 0)},
                          Pose{axis_angle(Vec3(0.3f, 1, -0.2f).normalized(), 2.0f), Vec3(1, 2, 3)}};
  for (const Pose& parent : parents) {
    const Chain c = make_chain(parent);
    const Vec3 S = c.start.translation;
    const Reach reach = reach_of(0.3f, 0.26f, HingeRange{0.0f, deg(145)});
    for (int i = 0; i < 500; ++i) {
      const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
      const float d = reach.min + (reach.max - reach.min) * 0.5f * (u(rng) + 1.0f) * 0.999f;
      TwoBoneJob job;
      job.target = S + d * dir;
      job.pole_vector = Vec3(u(rng), u(rng), u(rng));
      const Solved s = solve(c, job);
      ASSERT_TRUE(s.ok);
      EXPECT_TRUE(s.reached);
      EXPECT_LT((s.end - job.target).norm(), 1e-4f) << "target " << job.target.transpose();
      EXPECT_LT((s.end_reported - s.end).norm(), 1e-4f);
      // Bone lengths are kept.
      EXPECT_NEAR((s.mid - S).norm(), 0.3f, 1e-4f);
      EXPECT_NEAR((s.end - s.mid).norm(), 0.26f, 1e-4f);
    }
  }
}

TEST(TwoBoneJob, MidJointBendsTowardThePole) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const Chain c = make_chain(Pose{axis_angle(Vec3::UnitY(), 0.5f), Vec3(0.2f, 1.4f, 0)});
  const Vec3 S = c.start.translation;
  int bent = 0;
  for (int i = 0; i < 1000; ++i) {
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
    TwoBoneJob job;
    job.target = S + (0.2f + 0.3f * 0.5f * (u(rng) + 1.0f)) * dir;
    job.pole_vector = Vec3(u(rng), u(rng), u(rng)).normalized();
    const Vec3 pole_perp = job.pole_vector - job.pole_vector.dot(dir) * dir;
    if (pole_perp.norm() < 0.1f) {
      continue;  // a pole along the ray does not choose a side
    }
    const Solved s = solve(c, job);
    const Vec3 offset = (s.mid - S) - (s.mid - S).dot(dir) * dir;  // off the shoulder→target line
    EXPECT_GT(offset.dot(pole_perp.normalized()), 0.99f * offset.norm())
        << "the elbow is not on the pole's side";
    ++bent;
  }
  EXPECT_GT(bent, 800);
}

TEST(TwoBoneJob, UnreachableTargetsAreApproachedAlongTheRay) {
  const Chain c = make_chain(Pose{axis_angle(Vec3::UnitX(), 0.3f), Vec3(0, 1, 0)});
  const Vec3 S = c.start.translation;
  for (const Vec3& dir :
       {Vec3(0, 0, -1), Vec3(1, 1, 0).normalized(), Vec3(-0.2f, -1, 0.3f).normalized()}) {
    for (const float d : {0.6f, 1.0f, 5.0f, 1e4f}) {
      TwoBoneJob job;
      job.target = S + d * dir;
      job.soften = 0.97f;
      const Solved s = solve(c, job);
      EXPECT_FALSE(s.reached);
      const Vec3 reached = s.end - S;
      EXPECT_LT(std::atan2(reached.cross(dir).norm(), reached.dot(dir)), deg(0.01f));
      EXPECT_LE((s.end - S).norm(), 0.56f + 1e-5f);
      EXPECT_GT((s.end - S).norm(), 0.97f * 0.56f - 1e-5f);
    }
  }
}

TEST(TwoBoneJob, SofteningFallsBehindSmoothlyNearFullReach) {
  // soft_reach: identity below the start, continuous and increasing after it, never past max.
  float previous = 0.0f;
  for (float d = 0.0f; d < 2.0f; d += 0.001f) {
    const float r = soft_reach(d, 0.5f, 0.56f);
    EXPECT_LE(r, 0.56f);
    EXPECT_GE(r, previous);
    EXPECT_LT(r - previous, 0.0011f);
    if (d <= 0.5f) {
      EXPECT_EQ(r, d);
    }
    previous = r;
  }
  EXPECT_GT(soft_reach(0.56f, 0.5f, 0.56f), 0.53f);
}

TEST(TwoBoneJob, FlexionLimitsBoundTheDistance) {
  const Chain c = make_chain();
  const HingeRange flexion{deg(10), deg(120)};
  const Reach reach = reach_of(0.3f, 0.26f, flexion);
  for (const float d : {0.0f, 0.05f, 0.1f, 0.3f, 0.5f, 0.56f, 0.8f}) {
    TwoBoneJob job;
    job.target = Vec3(0, -d, 0);
    job.flexion = flexion;
    const Solved s = solve(c, job);
    const float flex =
        std::acos(std::clamp((s.mid).normalized().dot((s.end - s.mid).normalized()), -1.0f, 1.0f));
    EXPECT_GE(flex, flexion.min - 1e-3f) << d;
    EXPECT_LE(flex, flexion.max + 1e-3f) << d;
    EXPECT_EQ(s.reached, d >= reach.min && d <= reach.max) << d;
  }
}

TEST(TwoBoneJob, DegenerateInputGivesNoCorrectionNotNaN) {
  Chain c = make_chain();
  const auto expect_identity = [](const Chain& chain, const Vec3& target, const Vec3& pole) {
    Mat3 qs, qm;
    bool reached = true;
    TwoBoneJob job;
    job.start_joint = &chain.start;
    job.mid_joint = &chain.mid;
    job.end_joint = &chain.end;
    job.mid_axis = chain.mid_axis;
    job.target = target;
    job.pole_vector = pole;
    job.start_correction = &qs;
    job.mid_correction = &qm;
    job.reached = &reached;
    ASSERT_TRUE(job.run());
    EXPECT_TRUE(qs.isIdentity(1e-6f));
    EXPECT_TRUE(qm.isIdentity(1e-6f));
    EXPECT_FALSE(reached);
  };
  expect_identity(c, Vec3(NAN, 0, 0), Vec3::UnitY());
  expect_identity(c, Vec3(INFINITY, 0, 0), Vec3::UnitY());
  Chain collapsed = c;
  collapsed.mid.translation = collapsed.start.translation;  // zero-length upper bone
  expect_identity(collapsed, Vec3(0.3f, 0.3f, 0), Vec3::UnitY());

  // A target on the start joint, a pole along the ray or not finite: finite corrections.
  for (const auto& [target, pole] : {std::pair{Vec3(Vec3::Zero()), Vec3(Vec3::UnitY())},
                                     std::pair{Vec3(0.4f, 0, 0), Vec3(Vec3::UnitX())},
                                     std::pair{Vec3(0.2f, 0.2f, 0), Vec3(NAN, 1, 0)},
                                     std::pair{Vec3(0.2f, 0.2f, 0), Vec3(Vec3::Zero())}}) {
    TwoBoneJob job;
    job.target = target;
    job.pole_vector = pole;
    const Solved s = solve(c, job);
    EXPECT_TRUE(s.mid.allFinite() && s.end.allFinite());
  }
}

}  // namespace
}  // namespace deixis::ik
