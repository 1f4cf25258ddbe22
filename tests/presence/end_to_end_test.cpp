// The end-to-end check (the procedure is in deictic_check.h): a synthetic *test* subject
// (never the training subject) points at or touches object X in room A; in room B, where X stands
// elsewhere relative to the avatar, the remote avatar (translator with the authors' MoE weights +
// whole-avatar IK on the default skinned avatar) must finish the gesture at B's X:
//   pointing: horizontal and vertical errors of the avatar's eye-midpoint→fingertip ray ≤ 5°,
//   touching: fingertip within 3 cm of the object's surface,
// while copying the user's pose unchanged (the paper's baseline) misses by far more. For a
// right-handed subject, a left-handed one (left weights, decision 17), and an avatar 20 % smaller
// than the user. Errors are measured after IK, on the joints an observer in room B would see.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "avatar/avatar_loader.h"
#include "avatar/bcn_rig.h"  // tests/avatar
#include "avatar/default_avatar.h"
#include "capture/subject.h"
#include "deictic_check.h"
#include "presence/remote_avatar.h"
#include "test_support.h"

namespace deixis::presence {
namespace {

namespace fs = std::filesystem;

class EndToEnd : public ::testing::Test {
 protected:
  static ik::AvatarSolver avatar_of_height(float height) {
    avatar::AvatarParameters p;
    p.height = height;
    p.arm_length = 0.74f * height / 1.70f;
    const std::vector<std::uint8_t> glb = avatar::generate_default_avatar(p);
    return ik::AvatarSolver::build(avatar::load_avatar(glb, "generated avatar").rig);
  }
  static ik::AvatarSolver default_avatar() {
    return ik::AvatarSolver::build(
        avatar::load_avatar(fs::path(DEIXIS_SOURCE_DIR) / "assets/avatars/default.glb").rig);
  }

  // Runs `count` sequences of `category` by `subject` through the remote avatar in room B.
  // The authors' released weights (../shared/reference/weights) or the project's own.
  static fs::path authors_weights() { return testing::reference_dir() / "weights"; }
  static fs::path own_weights() { return fs::path(DEIXIS_SOURCE_DIR) / "assets/weights"; }

  static DeicticOutcome run(const std::string& subject, capture::Category category, int count,
                            const ik::AvatarSolver& solver,
                            const fs::path& weights_root = authors_weights()) {
    return run_deictic_check(subject, category, count, solver, weights_root);
  }
};

TEST_F(EndToEnd, RightHandedSubjectPointsAtRoomBsCopy) {
  const DeicticOutcome o = run("172", capture::Category::kPointingSingle, 6, default_avatar());
  report("172 pointing", o);
  expect_pointing(o);
}

TEST_F(EndToEnd, RightHandedSubjectTouchesRoomBsCopy) {
  const DeicticOutcome o = run("172", capture::Category::kTouchingSingle, 6, default_avatar());
  report("172 touching", o);
  expect_touching(o);
}

TEST_F(EndToEnd, LeftHandedSubjectPointsWithTheLeftWeights) {
  const DeicticOutcome o = run("173", capture::Category::kPointingSingle, 6, default_avatar());
  report("173 pointing", o);
  expect_pointing(o);
}

TEST_F(EndToEnd, LeftHandedSubjectTouches) {
  const DeicticOutcome o = run("173", capture::Category::kTouchingSingle, 6, default_avatar());
  report("173 touching", o);
  expect_touching(o);
}

TEST_F(EndToEnd, AnAvatarTwentyPercentSmallerThanTheUserStillPointsAndTouches) {
  const capture::Subject& subject = capture::find_subject("161");
  const ik::AvatarSolver small = avatar_of_height(0.8f * subject.height);
  const DeicticOutcome pointing = run("161", capture::Category::kPointingSingle, 6, small);
  report("161 pointing, avatar 20% smaller", pointing);
  expect_pointing(pointing);
  const DeicticOutcome touching = run("161", capture::Category::kTouchingSingle, 6, small);
  report("161 touching, avatar 20% smaller", touching);
  expect_touching(touching);
}

TEST_F(EndToEnd, AThirdPartyRigPointsAndTouchesToo) {
  // BCN_Epileptic (assimp-testmodels): another skeleton, other proportions, other bone names.
  const ik::AvatarSolver bcn = ik::AvatarSolver::build(avatar::load_avatar(testing::bcn_glb()).rig);
  const DeicticOutcome pointing = run("180", capture::Category::kPointingSingle, 6, bcn);
  report("180 pointing, BCN_Epileptic avatar", pointing);
  expect_pointing(pointing);
  const DeicticOutcome touching = run("180", capture::Category::kTouchingSingle, 6, bcn);
  report("180 touching, BCN_Epileptic avatar", touching);
  expect_touching(touching);
}

// Room B's copies stand 100–160° from the avatar's facing, behind its spot (what a site warns
// about, site/site_config.h): the networks, trained on targets in front of the body, point far
// off; with the body turn (presence/body_turn.h) the avatar turns toward the target and its
// pointing ends within the goal.
TEST_F(EndToEnd, PointingAtTargetsBehindTheAvatarsSpotTurnsTheBody) {
  DeicticLayout behind;
  behind.pointing_turn_deg = -100.0f;
  const DeicticOutcome turned = run_deictic_check("172", capture::Category::kPointingSingle, 6,
                                                  default_avatar(), authors_weights(), {}, behind);
  report("172 pointing behind the spot, body turn", turned);
  behind.body_turn = false;
  const DeicticOutcome fixed = run_deictic_check("172", capture::Category::kPointingSingle, 6,
                                                 default_avatar(), authors_weights(), {}, behind);
  report("172 pointing behind the spot, no body turn", fixed);
  expect_pointing(turned);
  EXPECT_GE(mean(fixed.ours.horizontal_deg), 3 * mean(turned.ours.horizontal_deg));
}

// Room B's pointing targets on its floor's furniture, 0.3 m high: 30–45° below the avatar's eyes,
// lower than anything the synthetic capture's first sequences point at (decision 89), where the
// networks alone end several degrees off. The person in room A points at their own targets
// within a few degrees, so pointing settling (presence/pointing_settle.h) turns the avatar's hand
// the rest of the way: every completion ends on room B's copy.
TEST_F(EndToEnd, PointingAtLowTargetsSettlesOntoThem) {
  DeicticLayout low;
  low.pointing_height = 0.3f;
  const DeicticOutcome o = run_deictic_check("172", capture::Category::kPointingSingle, 6,
                                             default_avatar(), own_weights(), {}, low);
  report("172 pointing at low targets, own weights", o);
  expect_pointing(o);
  const auto worst = [](const std::vector<double>& v) {
    return *std::max_element(v.begin(), v.end());
  };
  EXPECT_LE(worst(o.ours.horizontal_deg), 0.5);
  EXPECT_LE(worst(o.ours.vertical_deg), 0.5);
  // The networks alone are measurably off there: what settling corrected.
  EXPECT_GE(worst(o.network_only.vertical_deg), 2.0 * worst(o.ours.vertical_deg) + 1.0);
}

// A headset user's site knows no labels: it selects the targets from the tracking
// (gesture/target_selection.h). Selected so, the avatar still finishes at room B's copy.
TEST_F(EndToEnd, WithTargetsSelectedFromTheTracking) {
  const auto select = [](const capture::Sequence& s) { return with_selected_targets(s, s.frames); };
  for (const char* subject : {"172", "173"}) {
    const DeicticOutcome pointing =
        run_deictic_check(subject, capture::Category::kPointingSingle, 6, default_avatar(),
                          authors_weights(), select);
    report((std::string(subject) + " pointing, selected targets").c_str(), pointing);
    expect_pointing(pointing);
    const DeicticOutcome touching =
        run_deictic_check(subject, capture::Category::kTouchingSingle, 6, default_avatar(),
                          authors_weights(), select);
    report((std::string(subject) + " touching, selected targets").c_str(), touching);
    expect_touching(touching);
  }
}

TEST_F(EndToEnd, WithTheProjectsOwnWeights) {
  for (const char* hand : {"right", "left"}) {
    for (const char* file : {"MPNet(MoE)(AC)80.safetensors", "UGNet(MoE)(AC)120.safetensors"}) {
      if (!fs::exists(own_weights() / hand / file)) {
        GTEST_SKIP() << "assets/weights/" << hand << "/" << file
                     << " is not there yet: the project's own MoE weights are still training";
      }
    }
  }
  const ik::AvatarSolver solver = default_avatar();
  for (const char* subject : {"172", "173"}) {
    const DeicticOutcome pointing =
        run(subject, capture::Category::kPointingSingle, 6, solver, own_weights());
    report((std::string(subject) + " pointing, own weights").c_str(), pointing);
    expect_pointing(pointing);
    const DeicticOutcome touching =
        run(subject, capture::Category::kTouchingSingle, 6, solver, own_weights());
    report((std::string(subject) + " touching, own weights").c_str(), touching);
    expect_touching(touching);
  }
}

}  // namespace
}  // namespace deixis::presence
