// StepTeam (train/step_team.h), the threads behind deixis-train --threads: every member
// runs each task once, on distinct threads, member 0 on the caller's; run() returns only when all
// are done (their writes are visible); a member's exception reaches the caller after the others
// finished, and the team keeps working afterwards.

#include "train/step_team.h"

#include <gtest/gtest.h>

#include <atomic>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/error.h"

namespace deixis::train {
namespace {

TEST(StepTeam, EveryMemberRunsEachTaskOnceOnItsOwnThread) {
  StepTeam team(3);
  ASSERT_EQ(team.size(), 3);
  std::vector<std::thread::id> ran_on(3);
  std::vector<int> sums(3, 0);
  for (int round = 1; round <= 200; ++round) {
    team.run([&](int m) {
      ran_on[static_cast<std::size_t>(m)] = std::this_thread::get_id();
      sums[static_cast<std::size_t>(m)] += round;  // plain writes: run() must publish them
    });
  }
  for (int m = 0; m < 3; ++m) {
    EXPECT_EQ(sums[static_cast<std::size_t>(m)], 200 * 201 / 2) << "member " << m;
  }
  EXPECT_EQ(ran_on[0], std::this_thread::get_id());
  EXPECT_EQ(std::set<std::thread::id>(ran_on.begin(), ran_on.end()).size(), 3u);
}

TEST(StepTeam, RunWaitsForTheSlowestMember) {
  StepTeam team(2);
  std::atomic<bool> slow_done{false};
  team.run([&](int m) {
    if (m == 1) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      slow_done = true;
    }
  });
  EXPECT_TRUE(slow_done);
}

TEST(StepTeam, AMembersExceptionReachesTheCallerAndTheTeamGoesOn) {
  StepTeam team(2);
  int finished = 0;
  EXPECT_THROW(team.run([&](int m) {
    if (m == 1) {
      throw std::runtime_error("member 1 failed");
    }
    ++finished;
  }),
               std::runtime_error);
  EXPECT_EQ(finished, 1);
  std::atomic<int> ran{0};
  team.run([&](int) { ++ran; });
  EXPECT_EQ(ran, 2);
}

TEST(StepTeam, TheCallersOwnExceptionComesFirstAndEveryMemberFinishes) {
  StepTeam team(3);
  std::atomic<int> finished{0};
  try {
    team.run([&](int m) {
      ++finished;
      throw std::runtime_error("member " + std::to_string(m));
    });
    FAIL() << "nothing was thrown";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "member 0");
  }
  EXPECT_EQ(finished, 3);
}

TEST(StepTeam, OneMemberIsAPlainCallAndNoneIsRefused) {
  StepTeam team(1);
  std::thread::id on;
  team.run([&](int) { on = std::this_thread::get_id(); });
  EXPECT_EQ(on, std::this_thread::get_id());
  EXPECT_THROW(StepTeam(0), Error);
}

}  // namespace
}  // namespace deixis::train
