// The IK hot path allocates nothing: after a warm-up, 1,000 full avatar solves (every job) over
// varied targets make zero heap allocations. Not built under ASan (tests/CMakeLists.txt).

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <vector>

#include "allocation_counter.h"
#include "ik/avatar_solver.h"
#include "rig_pose.h"

namespace deixis::ik {
namespace {

TEST(IkHotPath, CounterSeesAllocations) {
  // Positive control: a broken counter would make the zero below meaningless.
  deixis::testing::AllocationCounter counter;
  void* (*volatile allocate)(std::size_t) = std::malloc;
  void* p = allocate(64);
  std::free(p);
  EXPECT_EQ(counter.count(), 1u);
}

TEST(IkHotPath, AvatarSolvesAllocateNothing) {
  const AvatarSolver solver = AvatarSolver::build(testing::make_test_rig());
  std::vector<Pose> local(static_cast<std::size_t>(solver.joint_count()));
  std::vector<Pose> model(local.size());
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<AvatarTargets> ticks(64);
  for (AvatarTargets& t : ticks) {
    t.deictic_hand = u(rng) > 0 ? Hand::kRight : Hand::kLeft;
    t.deictic.T_world_head = {testing::random_rotation(rng, 1.0f),
                              solver.eye_midpoint_rest + 0.05f * Vec3(u(rng), u(rng), u(rng))};
    t.deictic.gaze = testing::random_unit(rng);
    t.deictic.T_world_wrist = {testing::random_rotation(rng), Vec3::Zero()};
    t.deictic.index_tip = Vec3(0, 1.4f, 0) + Vec3(u(rng), u(rng), u(rng));
    t.other.azimuth = 3 * u(rng);
    t.other.elevation = 1.5f * u(rng);
    t.other.distance = std::abs(u(rng));
    t.other.R_root_wrist = testing::random_rotation(rng);
  }
  AvatarSolveReport report;
  AvatarSolveJob job;
  job.solver = &solver;
  job.local = local;
  job.model = model;
  job.report = &report;
  for (int i = 0; i < 10; ++i) {
    job.targets = &ticks[i % ticks.size()];
    ASSERT_TRUE(job.run());
  }
  deixis::testing::AllocationCounter counter;
  for (int i = 0; i < 1000; ++i) {
    job.targets = &ticks[i % ticks.size()];
    job.run();
  }
  EXPECT_EQ(counter.count(), 0u);
  // A failed validation must not allocate either.
  job.local = {};
  EXPECT_FALSE(job.run());
  EXPECT_EQ(counter.count(), 0u);
}

}  // namespace
}  // namespace deixis::ik
