// The IK jobs one by one, and the whole avatar's solve, on the procedural 1.70 m test rig
// (tests/ik/test_rig.h: 32 joints with legs, clavicles, thumbs, middle fingers and three-joint
// index fingers), one thread. Goal: full solve ≤ 10 µs; the paper's IK took 1.5 ms.
//
// Targets cycle through 64 prepared ticks so that branch predictors and caches see varied input.
// The per-job benchmarks start every run from the rest pose (BM_RestPose is that copy alone);
// the full solve does its own reset.

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "ik/avatar_solver.h"
#include "ik/eye_job.h"
#include "ik/index_finger_job.h"
#include "ik/lean_job.h"
#include "ik/spine_aim_job.h"
#include "ik/test_rig.h"
#include "ik/two_bone_job.h"
#include "ik/wrist_job.h"

namespace {

using namespace deixis;
using namespace deixis::ik;

constexpr int kTicks = 64;

struct Bench {
  Bench() : solver(AvatarSolver::build(testing::make_test_rig())) {
    local = solver.rig.skeleton.rest_local;
    model = solver.rest_model;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const auto random_rotation = [&](float max_angle) {
      return axis_angle(Vec3(u(rng), u(rng), u(rng)).normalized(), max_angle * u(rng));
    };
    for (int i = 0; i < kTicks; ++i) {
      AvatarTargets t;
      t.deictic_hand = i % 4 == 0 ? Hand::kLeft : Hand::kRight;
      t.deictic.T_world_head = {random_rotation(1.0f),
                                solver.eye_midpoint_rest + 0.04f * Vec3(u(rng), 0, u(rng))};
      t.deictic.gaze = t.deictic.T_world_head.rotation * Vec3(0.3f * u(rng), 0.2f * u(rng), -1);
      t.deictic.T_world_wrist = {random_rotation(2.0f), Vec3::Zero()};
      t.deictic.index_tip =
          Vec3(0.15f * (t.deictic_hand == Hand::kRight ? 1.0f : -1.0f), 1.4f, -0.35f) +
          0.25f * Vec3(u(rng), u(rng), u(rng));
      t.other.azimuth = 1.5f * u(rng);
      t.other.elevation = -0.8f + 0.6f * u(rng);
      t.other.distance = 0.55f + 0.1f * u(rng);
      t.other.R_root_wrist = random_rotation(1.0f);
      ticks.push_back(t);
    }
  }
  void reset() {
    std::copy(solver.rig.skeleton.rest_local.begin(), solver.rig.skeleton.rest_local.end(),
              local.begin());
    std::copy(solver.rest_model.begin(), solver.rest_model.end(), model.begin());
  }
  const AvatarTargets& tick(std::size_t i) const { return ticks[i % ticks.size()]; }
  int operator[](Bone b) const { return solver.rig[b]; }

  AvatarSolver solver;
  std::vector<Pose> local;
  std::vector<Pose> model;
  std::vector<AvatarTargets> ticks;
};

void BM_RestPose(benchmark::State& state) {
  Bench b;
  for (auto _ : state) {
    b.reset();
    benchmark::DoNotOptimize(b.model.data());
  }
}

void BM_TwoBoneJob(benchmark::State& state) {
  Bench b;
  const ArmRig& arm = b.solver.arms[index(Hand::kRight)];
  Mat3 qs, qm;
  bool reached = false;
  TwoBoneJob job;
  job.start_joint = &b.model[arm.upper];
  job.mid_joint = &b.model[arm.lower];
  job.end_joint = &b.model[arm.hand];
  job.pole_vector = arm.pole;
  job.mid_axis = arm.mid_axis;
  job.soften = 0.97f;
  job.start_correction = &qs;
  job.mid_correction = &qm;
  job.reached = &reached;
  std::size_t i = 0;
  for (auto _ : state) {
    job.target = b.tick(i++).deictic.index_tip;
    job.run();
    benchmark::DoNotOptimize(qs);
    benchmark::DoNotOptimize(qm);
  }
}

void BM_SpineAimJob(benchmark::State& state) {
  Bench b;
  const auto n = static_cast<std::size_t>(b.solver.aim_count);
  SpineAimJob job;
  job.skeleton = &b.solver.rig.skeleton;
  job.chain = std::span<const int>(b.solver.aim_chain.data(), n);
  job.weights = std::span<const float>(b.solver.aim_shares.data(), n);
  job.max_angles = std::span<const float>(b.solver.aim_limits.data(), n);
  job.local = b.local;
  job.model = b.model;
  const Mat3 head_rest = b.solver.rest_model[b[Bone::kHead]].rotation;
  std::size_t i = 0;
  for (auto _ : state) {
    b.reset();
    job.target = b.tick(i++).deictic.T_world_head.rotation * head_rest;
    job.run();
    benchmark::DoNotOptimize(b.local.data());
  }
}

void BM_LeanJob(benchmark::State& state) {
  Bench b;
  const auto n = static_cast<std::size_t>(b.solver.lean_count);
  LeanJob job;
  job.skeleton = &b.solver.rig.skeleton;
  job.chain = std::span<const int>(b.solver.lean_chain.data(), n);
  job.weights = std::span<const float>(b.solver.lean_shares.data(), n);
  job.max_angles = std::span<const float>(b.solver.lean_limits.data(), n);
  job.end_joint = b[Bone::kHead];
  job.end_offset = b.solver.rig.eye_midpoint_in_head;
  job.local = b.local;
  job.model = b.model;
  std::size_t i = 0;
  for (auto _ : state) {
    b.reset();
    job.target = b.tick(i++).deictic.T_world_head.translation;
    job.run();
    benchmark::DoNotOptimize(b.local.data());
  }
}

void BM_EyeJob(benchmark::State& state) {
  Bench b;
  const std::array<int, 2> eyes = {b[Bone::kLeftEye], b[Bone::kRightEye]};
  EyeJob job;
  job.skeleton = &b.solver.rig.skeleton;
  job.rest_model = b.solver.rest_model;
  job.head = b[Bone::kHead];
  job.eyes = eyes;
  job.local = b.local;
  job.model = b.model;
  std::size_t i = 0;
  for (auto _ : state) {
    b.reset();
    job.gaze = b.tick(i++).deictic.gaze;
    job.run();
    benchmark::DoNotOptimize(b.local.data());
  }
}

void BM_WristJob(benchmark::State& state) {
  Bench b;
  const ArmRig& arm = b.solver.arms[index(Hand::kRight)];
  WristJob job;
  job.skeleton = &b.solver.rig.skeleton;
  job.forearm = arm.lower;
  job.hand = arm.hand;
  job.forearm_axis = arm.forearm_axis;
  job.twist = arm.forearm_twist;
  job.local = b.local;
  job.model = b.model;
  std::size_t i = 0;
  for (auto _ : state) {
    b.reset();
    job.target = b.tick(i++).deictic.T_world_wrist.rotation * arm.R_hand_wrist.transpose();
    job.run();
    benchmark::DoNotOptimize(b.local.data());
  }
}

void BM_IndexFingerJob(benchmark::State& state) {
  Bench b;
  const ArmRig& arm = b.solver.arms[index(Hand::kRight)];
  const IkLimits limits;
  IndexFingerJob job;
  job.skeleton = &b.solver.rig.skeleton;
  job.chain = std::span<const int>(arm.index.data(), 3);
  job.flexion_axes = std::span<const Vec3>(arm.index_axes.data(), 3);
  job.flexion = limits.index;
  job.tip_offset = arm.tip_offset;
  job.local = b.local;
  job.model = b.model;
  // Targets the curled finger touches: 2 to 8 cm from the knuckle, below the finger's line.
  std::vector<Vec3> targets;
  const Vec3 knuckle = b.model[arm.index[0]].translation;
  for (int k = 0; k < kTicks; ++k) {
    const float a = 0.02f * static_cast<float>(k % 8);
    targets.push_back(knuckle + Vec3(0.06f - 0.5f * a, -0.02f - a, -0.01f));
  }
  std::size_t i = 0;
  for (auto _ : state) {
    b.reset();
    job.target = targets[i++ % targets.size()];
    job.run();
    benchmark::DoNotOptimize(b.local.data());
  }
}

void BM_DeicticArmJob(benchmark::State& state) {
  Bench b;
  const IkLimits limits;
  DeicticArmJob job;
  job.skeleton = &b.solver.rig.skeleton;
  job.arm = &b.solver.arms[index(Hand::kRight)];
  job.limits = &limits;
  job.pole = job.arm->pole;
  job.local = b.local;
  job.model = b.model;
  std::size_t i = 0;
  for (auto _ : state) {
    b.reset();
    const AvatarTargets& t = b.tick(i++);
    job.wrist_rotation = t.deictic.T_world_wrist.rotation;
    job.fingertip = t.deictic.index_tip;
    job.run();
    benchmark::DoNotOptimize(b.local.data());
  }
}

void BM_OtherArmJob(benchmark::State& state) {
  Bench b;
  OtherArmJob job;
  job.skeleton = &b.solver.rig.skeleton;
  job.arm = &b.solver.arms[index(Hand::kLeft)];
  job.limits = &b.solver.config.limits;
  job.cylinder = &b.solver.cylinder;
  job.chest = b.solver.cylinder_joint;
  job.head_position = b.solver.eye_midpoint_rest;
  job.pole = job.arm->pole;
  job.local = b.local;
  job.model = b.model;
  std::size_t i = 0;
  for (auto _ : state) {
    b.reset();
    job.target = b.tick(i++).other;
    job.run();
    benchmark::DoNotOptimize(b.local.data());
  }
}

void BM_AvatarSolve(benchmark::State& state) {
  Bench b;
  AvatarSolveReport report;
  AvatarSolveJob job;
  job.solver = &b.solver;
  job.T_world_root = Pose{};
  job.local = b.local;
  job.model = b.model;
  job.report = &report;
  std::size_t i = 0;
  for (auto _ : state) {
    job.targets = &b.tick(i++);
    job.run();
    benchmark::DoNotOptimize(b.model.data());
  }
}

}  // namespace

BENCHMARK(BM_RestPose)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_TwoBoneJob)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_SpineAimJob)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_LeanJob)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_EyeJob)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_WristJob)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_IndexFingerJob)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_DeicticArmJob)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_OtherArmJob)->Unit(benchmark::kNanosecond);
BENCHMARK(BM_AvatarSolve)->Unit(benchmark::kMicrosecond);
