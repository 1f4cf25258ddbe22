// The simulator's pieces that need no window: what a mouse ray hits and where a drag goes, the
// scripted input file (its errors name the field) played into frames — clicks aimed at panel
// widgets, text typed into the panel — the live virtual user pointing and touching on command,
// and the panel's rings.

#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "capture/subject.h"
#include "core/error.h"
#include "sim/sim_history.h"
#include "sim/sim_input.h"
#include "sim/sim_pick.h"
#include "sim/sim_user.h"

namespace deixis::sim {
namespace {

using render::Ray;
using render::Vec2;

TargetMap two_objects() {
  TargetMap map;
  map.objects = {{1, "Ball", TargetKind::kSphere, Vec3(0, 1, -3), Vec3::Constant(0.4f)},
                 {2, "Box", TargetKind::kBox, Vec3(0, 1, -5), Vec3(1.0f, 1.0f, 0.2f)}};
  return map;
}

TEST(SimPickTest, TheNearestObjectOnTheRayIsPicked) {
  const TargetMap map = two_objects();
  // Straight down the −Z axis at 1 m: the ball hides the box behind it.
  EXPECT_EQ(pick_object(Ray{Vec3(0, 1, 0), Vec3(0, 0, -1)}, map), 1);
  EXPECT_NEAR(*ray_hit(Ray{Vec3(0, 1, 0), Vec3(0, 0, -1)}, map.objects[0]), 2.8f, 1e-5f);
  // 0.35 m to the side: past the ball's radius (0.2), within the box's half width (0.5).
  EXPECT_EQ(pick_object(Ray{Vec3(0.35f, 1, 0), Vec3(0, 0, -1)}, map), 2);
  EXPECT_NEAR(*ray_hit(Ray{Vec3(0.35f, 1, 0), Vec3(0, 0, -1)}, map.objects[1]), 4.9f, 1e-5f);
  EXPECT_EQ(pick_object(Ray{Vec3(0.6f, 1, 0), Vec3(0, 0, -1)}, map), kNoTarget);
  // Objects behind the ray's origin are not hit.
  EXPECT_EQ(pick_object(Ray{Vec3(0, 1, 0), Vec3(0, 0, 1)}, map), kNoTarget);
}

TEST(SimPickTest, ARayMeetsTheDragPlaneInFrontOnly) {
  const Ray down{Vec3(0, 2, 0), Vec3(0, -1, -1).normalized()};
  const auto p = ray_at_height(down, 1.0f);
  ASSERT_TRUE(p.has_value());
  EXPECT_TRUE(p->isApprox(Vec3(0, 1, -1), 1e-5f));
  EXPECT_FALSE(ray_at_height(down, 3.0f).has_value());                    // behind
  EXPECT_FALSE(ray_at_height(Ray{Vec3(0, 2, 0), Vec3(0, 0, -1)}, 1.0f));  // parallel
  EXPECT_FALSE(ray_at_height(Ray{Vec3(0, 2, 0), Vec3(0, -0.001f, -1).normalized()}, 1.0f));
}

std::string script(const std::string& events) {
  return R"({"format": "deixis-sim-input", "version": 1, "events": [)" + events + "]}";
}

std::string error_of(const std::string& text) {
  try {
    parse_input_script(text, "in.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(SimInputTest, BadFilesAreRefusedNamingTheField) {
  EXPECT_EQ(error_of("[1]"), "in.json: expected a JSON object");
  EXPECT_NE(error_of(R"({"format": "x", "version": 1, "events": []})").find("in.json: format"),
            std::string::npos);
  EXPECT_NE(error_of(script(R"({"t": 1, "type": "jump"})")).find("events[0].type: unknown type"),
            std::string::npos);
  EXPECT_NE(error_of(script(R"({"t": 1, "type": "move", "x": 1})"))
                .find("events[0]: missing "
                      "field 'y'"),
            std::string::npos);
  EXPECT_NE(error_of(script(R"({"t": 0, "type": "key", "key": "e"},
                               {"t": 1, "type": "press", "button": "side"})"))
                .find("events[1].button: expected left, right or middle"),
            std::string::npos);
  EXPECT_NE(error_of(script(R"({"t": -1, "type": "key", "key": "e"})")).find("events[0].t"),
            std::string::npos);
  EXPECT_NE(error_of(script(R"({"t": 1, "type": "key", "key": "x"})")).find("events[0].key"),
            std::string::npos);
  EXPECT_NE(error_of(script(R"({"t": 1, "type": "move", "x": 1, "y": 2, "z": 3})"))
                .find("unknown field 'z'"),
            std::string::npos);
  EXPECT_NE(error_of(script(R"({"t": 1, "type": "click", "widget": "Start", "x": 1, "y": 2})"))
                .find("events[0].widget: give either a widget or x and y"),
            std::string::npos);
  EXPECT_NE(error_of(script(R"({"t": 1, "type": "click", "widget": ""})")).find("events[0].widget"),
            std::string::npos);
  EXPECT_NE(error_of(script(R"({"t": 1, "type": "text", "text": ""})")).find("events[0].text"),
            std::string::npos);
  EXPECT_NE(error_of(script(R"({"t": 1, "type": "text", "text": "tab\there"})"))
                .find("events[0].text: only printable ASCII"),
            std::string::npos);
}

TEST(SimInputTest, ClicksAndDragsPlayAsAPersonWouldMakeThem) {
  const auto events = parse_input_script(
      script(R"({"t": 1.0, "type": "drag", "from": [10, 20], "to": [110, 20], "seconds": 0.5},
                {"t": 0.2, "type": "click", "x": 5, "y": 6, "shift": true},
                {"t": 0.2, "type": "key", "key": "e"})"),
      "in.json");
  ScriptedInput input(events);
  FrameInput f = input.next(0.0);
  EXPECT_FALSE(f.was_pressed(Button::kLeft));
  f = input.next(0.2);  // the click's press and the key, in time order
  EXPECT_TRUE(f.was_pressed(Button::kLeft));
  EXPECT_TRUE(f.shift);
  EXPECT_TRUE(f.pointer.isApprox(Vec2(5, 6)));
  ASSERT_EQ(f.key_count, 1u);
  EXPECT_EQ(f.keys[0], 'e');
  f = input.next(0.25);
  EXPECT_TRUE(f.is_down(Button::kLeft));
  EXPECT_FALSE(f.was_pressed(Button::kLeft));
  EXPECT_EQ(f.key_count, 0u);
  f = input.next(0.35);
  EXPECT_TRUE(f.was_released(Button::kLeft));
  f = input.next(1.0);
  EXPECT_TRUE(f.was_pressed(Button::kLeft));
  EXPECT_TRUE(f.pointer.isApprox(Vec2(10, 20)));
  f = input.next(1.25);  // half way
  EXPECT_TRUE(f.is_down(Button::kLeft));
  EXPECT_NEAR(f.pointer.x(), 60.0f, 7.0f);
  f = input.next(1.6);
  EXPECT_TRUE(f.was_released(Button::kLeft));
  EXPECT_TRUE(f.pointer.isApprox(Vec2(110, 20)));
  EXPECT_TRUE(input.finished());
}

TEST(SimInputTest, ClicksAimAtPanelWidgetsAndTextIsTypedAFrameAtATime) {
  const auto events = parse_input_script(script(R"({"t": 0.5, "type": "click", "widget": "Start"},
                {"t": 1.0, "type": "text", "text": "10.0.0.2:7350"},
                {"t": 1.0, "type": "text", "text": "blue whale"},
                {"t": 2.0, "type": "click", "widget": "Leave"})"),
                                         "in.json");
  const FindWidget panel = [](std::string_view label) -> std::optional<Vec2> {
    if (label == "Start") {
      return Vec2(900, 600);
    }
    return std::nullopt;  // no Leave: no session runs
  };
  ScriptedInput input(events);
  FrameInput f = input.next(0.5, panel);
  EXPECT_TRUE(f.pointer.isApprox(Vec2(900, 600)));  // at the widget's centre, pressed there
  EXPECT_TRUE(f.was_pressed(Button::kLeft));
  EXPECT_TRUE(f.text.empty());
  f = input.next(1.0, panel);  // one text a frame: the second waits for the next
  EXPECT_EQ(f.text, "10.0.0.2:7350");
  f = input.next(1.0, panel);
  EXPECT_EQ(f.text, "blue whale");
  f = input.next(1.1, panel);
  EXPECT_TRUE(f.text.empty());
  try {
    input.next(2.0, panel);
    ADD_FAILURE() << "a click at a widget the panel does not show was played";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("panel widget 'Leave'"), std::string::npos) << e.what();
  }
}

float angle(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0f, 1.0f));
}

SimUserScene room() {
  SimUserScene scene;
  scene.T_world_floor = Pose{Mat3::Identity(), Vec3::Zero()};
  scene.objects = {{1, "Lamp", TargetKind::kSphere, Vec3(1.5f, 1.8f, -2.5f), Vec3::Constant(0.3f)},
                   {2, "Cube", TargetKind::kBox, Vec3(0.3f, 1.0f, -0.4f), Vec3::Constant(0.14f)},
                   {3, "Far", TargetKind::kBox, Vec3(0.0f, 1.0f, -4.0f), Vec3::Constant(0.2f)}};
  scene.partner_head = Vec3(0, 1.6f, -2.2f);
  return scene;
}

TEST(SimUserTest, PointsAtWhatItIsToldToOverANaturalDuration) {
  SimUser user(capture::find_subject("172"), room(), 5);
  TrackingFrame f = user.sample(0.0);
  EXPECT_EQ(f.head_target, kPartnerTarget);
  EXPECT_EQ(f.valid, tracked::kAll);
  EXPECT_EQ(user.point(1.0, 1), "");
  const Hand hand = user.calibration().deictic_hand;
  const Vec3 lamp(1.5f, 1.8f, -2.5f);
  const auto pointing_error = [&](double t) {
    const TrackingFrame s = user.sample(t);
    return angle(s.index_tip[index(hand)] - s.T_world_head.translation,
                 lamp - s.T_world_head.translation);
  };
  const float before = pointing_error(1.0);
  EXPECT_GT(before, 0.5f);
  // A reach takes a few hundred ms, not an instant, and ends on the eye–fingertip ray.
  EXPECT_GT(pointing_error(1.2), 0.2f);
  EXPECT_LT(pointing_error(3.5), 0.09f);
  f = user.sample(3.5);
  EXPECT_EQ(f.hand_target, 1);
  EXPECT_EQ(f.head_target, 1);
  EXPECT_TRUE(f.hand_target_position.isApprox(lamp));
  EXPECT_GT(user.deictic(3.5), 0.99f);
  EXPECT_EQ(user.point(4.0, 9), "no object 9");
}

TEST(SimUserTest, TouchesWithinReachAndRefusesBeyond) {
  SimUser user(capture::find_subject("172"), room(), 5);
  EXPECT_EQ(user.touch(0.5, 3), "Far is out of reach");
  EXPECT_EQ(user.sample(3.0).hand_target, kPartnerTarget);  // the refusal planned nothing
  EXPECT_EQ(user.touch(0.5, 2), "");
  const Hand hand = user.calibration().deictic_hand;
  const Vec3 tip = user.sample(4.0).index_tip[index(hand)];
  EXPECT_LT((tip - closest_surface_point(room().objects[1], tip)).norm(), 0.02f);
}

TEST(SimUserTest, TheMouseTurnsHeadAndEyes) {
  SimUser user(capture::find_subject("172"), room(), 5);
  user.look({0.8f, 0.3f});  // left and up
  for (double t = 0.0; t < 2.0; t += 1.0 / 30.0) {
    user.update(t);
  }
  const TrackingFrame f = user.sample(2.0);
  const Vec3 wanted(-std::sin(0.8f) * std::cos(0.3f), std::sin(0.3f),
                    -std::cos(0.8f) * std::cos(0.3f));
  EXPECT_LT(angle(f.gaze, wanted), 0.05f);
  const Vec3 face = f.T_world_head.rotation * Vec3(0, 0, -1);
  EXPECT_LT(angle(face, wanted), 0.35f);  // the head takes most of it, the eyes the rest
  EXPECT_GT(angle(face, Vec3(0, 0, -1)), 0.5f);
  EXPECT_EQ(f.head_target, kPartnerTarget);  // a glance away keeps the head target
}

TEST(SimHistoryTest, RingsKeepTheLastValuesInOrderAndTheirQuantiles) {
  Ring ring;
  for (int i = 0; i < 10; ++i) {
    ring.push(static_cast<float>(i));
  }
  EXPECT_EQ(ring.count(), 10);
  EXPECT_EQ(ring.offset(), 0);
  EXPECT_FLOAT_EQ(ring.last(), 9.0f);
  EXPECT_FLOAT_EQ(ring.quantile(0.5f), 5.0f);
  for (std::size_t i = 0; i < Ring::kLength; ++i) {
    ring.push(100.0f + static_cast<float>(i));
  }
  EXPECT_EQ(ring.count(), static_cast<int>(Ring::kLength));
  EXPECT_FLOAT_EQ(ring.data()[ring.offset()], 100.0f);  // the oldest kept
  EXPECT_FLOAT_EQ(ring.quantile(1.0f), 100.0f + static_cast<float>(Ring::kLength - 1));
}

}  // namespace
}  // namespace deixis::sim
