// A site's virtual user (capture/virtual_user.h) performing the demo's kind of script in a demo
// room: the steps happen in order and as scripted, pointing ends with the dominant eye's ray
// through the target, touching ends on the object's surface, every frame is a finite tracker
// frame at 30 Hz, and a script repeats to cover a longer run.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "capture/virtual_user.h"
#include "core/error.h"
#include "gesture/features.h"
#include "test_support.h"

namespace deixis::capture {
namespace {

using Action = ScriptStep::Action;
constexpr float kDegree = 3.14159265f / 180.0f;

TargetMap room_a() {
  return read_target_map(deixis::testing::source_dir() / "assets/rooms/a.json");
}

// Site A of the demo: a look at the partner, a point at Jupiter, explaining, a touch of the cube.
std::vector<ScriptStep> demo_script() {
  return {{Action::kLookAt, kPartnerTarget, 1.0f},
          {Action::kPoint, 1, 1.0f},
          {Action::kRest, kNoTarget, 0.5f},
          {Action::kExplain, kNoTarget, 2.0f},
          {Action::kTouch, 4, 1.0f},
          {Action::kRest, kNoTarget, 0.5f}};
}

ScriptPerformance perform_demo(const std::string& subject, const TargetMap& room,
                               double min_seconds = 0.0) {
  const VirtualUserScene scene{Pose{}, room.objects, Vec3(0.0f, 1.6f, -2.2f)};
  return perform_script(find_subject(subject), demo_script(), scene, 11, min_seconds);
}

std::size_t frame_at(double t) {
  return static_cast<std::size_t>(std::ceil(t * kFrameRate));  // the first frame at or after t
}

const StepTiming& step_of(const ScriptPerformance& p, Action action) {
  for (const StepTiming& s : p.steps) {
    if (s.action == action) {
      return s;
    }
  }
  ADD_FAILURE() << "no step " << action_name(action);
  return p.steps.front();
}

TEST(VirtualUser, StepsHappenInOrderAndTheRecordingCoversThem) {
  const TargetMap room = room_a();
  const ScriptPerformance p = perform_demo("172", room);
  const std::vector<ScriptStep> script = demo_script();
  ASSERT_EQ(p.steps.size(), script.size());
  for (std::size_t i = 0; i < p.steps.size(); ++i) {
    const StepTiming& s = p.steps[i];
    SCOPED_TRACE(i);
    EXPECT_EQ(s.step, i);
    EXPECT_EQ(s.action, script[i].action);
    EXPECT_LE(s.start, s.complete);
    EXPECT_LE(s.complete, s.end);
    if (i > 0) {
      EXPECT_DOUBLE_EQ(s.start, p.steps[i - 1].end);
    }
    if (s.action != Action::kExplain) {
      EXPECT_NEAR(s.end - s.complete, static_cast<double>(script[i].seconds), 1e-9);
    }
  }
  EXPECT_GE(static_cast<double>(p.sequence.size()) / kFrameRate, p.steps.back().end);
  // The hand and head designate what each step is about by its completion state.
  const StepTiming& point = step_of(p, Action::kPoint);
  const TrackingFrame& pointing = p.sequence.frames[frame_at(point.complete)];
  EXPECT_EQ(pointing.hand_target, 1);
  EXPECT_EQ(pointing.head_target, 1);
  EXPECT_GE(p.sequence.labels[frame_at(point.complete)][1], 0.99f);
  const StepTiming& look = step_of(p, Action::kLookAt);
  EXPECT_EQ(p.sequence.frames[frame_at(look.complete)].head_target, kPartnerTarget);
  EXPECT_GE(p.sequence.labels[frame_at(look.complete)][0], 0.99f);
  const StepTiming& touch = step_of(p, Action::kTouch);
  EXPECT_EQ(p.sequence.frames[frame_at(touch.complete)].hand_target, 4);
  // Upright and idle at the end of the last rest.
  EXPECT_GE(p.sequence.labels[frame_at(p.steps.back().end)][2], 0.99f);
}

TEST(VirtualUser, PointingEndsWithTheDominantEyeRayThroughTheTarget) {
  const TargetMap room = room_a();
  for (const char* subject : {"172", "173"}) {  // right- and left-handed
    SCOPED_TRACE(subject);
    const ScriptPerformance p = perform_demo(subject, room);
    const StepTiming& point = step_of(p, Action::kPoint);
    const Sequence& s = p.sequence;
    const int hand = index(s.calibration.deictic_hand);
    EXPECT_EQ(s.calibration.deictic_hand, find_subject(subject).handedness);
    const Vec3 target = room.find(1)->position;
    // Through the hold: from the completion state to the end of the step.
    for (std::size_t i = frame_at(point.complete); i < frame_at(point.end); ++i) {
      const Vec3 eye = s.joints[i].eye[static_cast<std::size_t>(s.dominant_eye)];
      ASSERT_LT(unsigned_angle(s.frames[i].index_tip[hand] - eye, target - eye), 1.0f * kDegree)
          << "frame " << i;
    }
  }
}

TEST(VirtualUser, TouchingEndsOnTheSurface) {
  const TargetMap room = room_a();
  for (const char* subject : {"172", "173"}) {
    SCOPED_TRACE(subject);
    const ScriptPerformance p = perform_demo(subject, room);
    const StepTiming& touch = step_of(p, Action::kTouch);
    const Sequence& s = p.sequence;
    const Vec3 tip =
        s.frames[frame_at(touch.complete)].index_tip[index(s.calibration.deictic_hand)];
    const TargetObject& cube = *room.find(4);
    EXPECT_LT((tip - closest_surface_point(cube, tip)).norm(), 0.01f);
  }
}

TEST(VirtualUser, FramesAreFiniteTrackerFramesAt30Hz) {
  const ScriptPerformance p = perform_demo("173", room_a());
  const Sequence& s = p.sequence;
  ASSERT_GT(s.size(), 100u);
  ASSERT_EQ(s.labels.size(), s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    const TrackingFrame& f = s.frames[i];
    SCOPED_TRACE(i);
    EXPECT_DOUBLE_EQ(f.time, static_cast<double>(i) / kFrameRate);
    EXPECT_EQ(f.valid, tracked::kAll);
    ASSERT_TRUE(is_finite(f.T_world_head) && f.gaze.allFinite() && is_finite(f.T_world_wrist[0]) &&
                is_finite(f.T_world_wrist[1]) && f.index_tip[0].allFinite() &&
                f.index_tip[1].allFinite() && f.head_target_position.allFinite() &&
                f.hand_target_position.allFinite());
    EXPECT_NE(f.head_target, kNoTarget);  // the translator needs targets in every frame
    EXPECT_NE(f.hand_target, kNoTarget);
  }
  // The person stands where the scene puts them, facing −Z: H above the floor point.
  const Vec3& root = s.calibration.T_world_root.translation;
  EXPECT_LT(std::hypot(root.x(), root.z()), 0.1f);
}

TEST(VirtualUser, RepeatsTheScriptToCoverALongerRun) {
  const TargetMap room = room_a();
  const ScriptPerformance once = perform_demo("172", room);
  const double length = once.steps.back().end;
  const ScriptPerformance longer = perform_demo("172", room, 2.5 * length);
  EXPECT_GE(static_cast<double>(longer.sequence.size()) / kFrameRate, 2.5 * length);
  EXPECT_EQ(longer.steps.back().cycle, 2);
  EXPECT_EQ(longer.steps.size(), 3 * demo_script().size());
}

TEST(VirtualUser, ATouchOutOfReachIsAnErrorNamingTheStep) {
  TargetMap room = room_a();
  room.objects.push_back({9, "Far", TargetKind::kBox, Vec3(0, 1.0f, -3.0f), Vec3::Constant(0.1f)});
  const VirtualUserScene scene{Pose{}, room.objects, Vec3(0.0f, 1.6f, -2.2f)};
  const std::vector<ScriptStep> script = {{Action::kTouch, 9, 1.0f}};
  try {
    perform_script(find_subject("172"), script, scene, 1);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("script[0] (touch)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("out of reach"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace deixis::capture
