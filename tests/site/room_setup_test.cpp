// The room set up from the headset (site/room_setup.h): touching, pointing from two places,
// moving, resizing, cycling tools and objects, and the saved map read back.
#include "site/room_setup.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "core/error.h"
#include "test_support.h"

namespace deixis::site {
namespace {

TargetMap two_objects() {
  TargetMap map;
  map.site = "A";
  map.objects.push_back({1, "Jupiter", TargetKind::kSphere, Vec3(0, 1, -2), Vec3::Constant(0.4f)});
  map.objects.push_back({2, "Box", TargetKind::kBox, Vec3(1, 1, -1), Vec3(0.2f, 0.4f, 0.6f)});
  return map;
}

// The user's head at `eye` (looking along −Z) with the right fingertip at `tip`.
TrackingFrame user_at(const Vec3& eye, const Vec3& tip) {
  TrackingFrame f;
  f.T_world_head = Pose{Mat3::Identity(), eye};
  f.index_tip[index(Hand::kRight)] = tip;
  f.T_world_wrist[index(Hand::kRight)] = Pose{Mat3::Identity(), tip + Vec3(0, 0, 0.15f)};
  f.valid = tracked::kHead | tracked::kGaze | tracked::kRightHand;
  return f;
}

constexpr SetupControls kPress{.act = true, .act_pressed = true};
constexpr SetupControls kHeld{.act = true};
constexpr SetupControls kUp{};
constexpr SetupControls kNextTool{.next_tool = true};
constexpr SetupControls kNextObject{.next_object = true};

TEST(RoomSetup, TouchPutsTheNearSurfaceAtTheFingertip) {
  RoomSetup setup(two_objects(), Hand::kRight, "a.json");
  const Vec3 eye(0, 1.6f, 0);
  const Vec3 tip(0.5f, 1.2f, -0.5f);
  EXPECT_FALSE(setup.update(user_at(eye, tip), kPress));  // lands on release
  EXPECT_TRUE(setup.holding());
  EXPECT_TRUE(setup.update(user_at(eye, tip), kUp));
  const TargetObject& jupiter = setup.map().objects[0];
  // The sphere's centre 0.2 m beyond the fingertip along the eye → fingertip ray.
  const Vec3 expected = tip + (tip - eye).normalized() * 0.2f;
  EXPECT_LT((jupiter.position - expected).norm(), 1e-5f);
  EXPECT_LT((closest_surface_point(jupiter, tip) - tip).norm(), 1e-5f);
  EXPECT_EQ(setup.edits(), 1u);
  EXPECT_EQ(setup.message().rfind("placed Jupiter", 0), 0u) << setup.message();
}

TEST(RoomSetup, AGrabbedObjectFollowsTheFingertipKeepingItsOffset) {
  RoomSetup setup(two_objects(), Hand::kRight, "a.json");
  const Vec3 eye(0, 1.6f, 0);
  const Vec3 on_surface(0, 1.15f, -2);  // inside Jupiter, off its centre
  setup.update(user_at(eye, on_surface), kPress);
  EXPECT_LT((setup.current().position - Vec3(0, 1, -2)).norm(), 1e-6f) << "grabbed, not moved";
  setup.update(user_at(eye, on_surface + Vec3(0.3f, 0, 0.1f)), kHeld);
  setup.update(user_at(eye, on_surface + Vec3(0.6f, -0.1f, 0.2f)), kHeld);
  EXPECT_EQ(setup.edits(), 0u);
  EXPECT_TRUE(setup.update(user_at(eye, on_surface + Vec3(0.6f, -0.1f, 0.2f)), kUp));
  EXPECT_LT((setup.current().position - Vec3(0.6f, 0.9f, -1.8f)).norm(), 1e-5f);
}

TEST(RoomSetup, TwoRaysFromTwoPlacesTriangulateTheObject) {
  RoomSetup setup(two_objects(), Hand::kRight, "a.json");
  setup.update(user_at(Vec3(0, 1.6f, 0), Vec3(0, 1.6f, 0)), kNextTool);
  ASSERT_EQ(setup.tool(), SetupTool::kPoint);
  const Vec3 real(1.5f, 0.8f, -3.0f);  // where the real object is
  const Vec3 eye1(-0.5f, 1.6f, 0.0f);
  const Vec3 eye2(0.6f, 1.55f, 0.2f);
  auto towards = [&](const Vec3& eye) -> Vec3 { return eye + (real - eye).normalized() * 0.6f; };
  EXPECT_FALSE(setup.update(user_at(eye1, towards(eye1)), kPress));
  ASSERT_TRUE(setup.first_ray().has_value());
  // Too near the first place: refused, the first ray kept.
  EXPECT_FALSE(setup.update(user_at(eye1 + Vec3(0.1f, 0, 0), towards(eye1)), kPress));
  EXPECT_NE(setup.message().find("step 30 cm"), std::string::npos) << setup.message();
  EXPECT_TRUE(setup.update(user_at(eye2, towards(eye2)), kPress));
  EXPECT_LT((setup.current().position - real).norm(), 1e-4f);
  EXPECT_FALSE(setup.first_ray().has_value());
}

TEST(RoomSetup, RaysThatMissEachOtherPlaceNothing) {
  RoomSetup setup(two_objects(), Hand::kRight, "a.json");
  setup.update(user_at(Vec3::Zero(), Vec3::Zero()), kNextTool);
  const Vec3 eye1(-0.5f, 1.6f, 0.0f);
  const Vec3 eye2(0.6f, 1.6f, 0.0f);
  // Towards two points 0.5 m apart vertically: the rays pass 0.5 m (less, skewed) apart.
  setup.update(user_at(eye1, eye1 + (Vec3(1, 1.0f, -3) - eye1).normalized() * 0.6f), kPress);
  EXPECT_FALSE(
      setup.update(user_at(eye2, eye2 + (Vec3(1, 2.0f, -3) - eye2).normalized() * 0.6f), kPress));
  EXPECT_NE(setup.message().find("do not meet"), std::string::npos) << setup.message();
  EXPECT_TRUE(setup.first_ray().has_value()) << "the second ray becomes the first";
  EXPECT_LT((setup.current().position - Vec3(0, 1, -2)).norm(), 1e-6f);
  // Parallel rays never meet.
  EXPECT_FALSE(triangulate({Vec3::Zero(), Vec3(0, 0, -1)}, {Vec3(1, 0, 0), Vec3(0, 0, -1)}, 5.0f));
  // Rays that converge ahead meet; rays that would meet behind the user do not.
  EXPECT_TRUE(triangulate({Vec3::Zero(), Vec3(0.6f, 0, -0.8f)},
                          {Vec3(1, 0, 0), Vec3(-0.6f, 0, -0.8f)}, 5.0f));
  EXPECT_FALSE(triangulate({Vec3::Zero(), Vec3(-0.6f, 0, -0.8f)},
                           {Vec3(1, 0, 0), Vec3(0.6f, 0, -0.8f)}, 5.0f));
}

TEST(RoomSetup, ResizeScalesWithTheHandsDistanceFromTheCentre) {
  RoomSetup setup(two_objects(), Hand::kRight, "a.json");
  const Vec3 eye(0, 1.6f, 0);
  setup.update(user_at(eye, eye), kNextObject);  // the box
  setup.update(user_at(eye, eye), kNextTool);
  setup.update(user_at(eye, eye), kNextTool);
  ASSERT_EQ(setup.tool(), SetupTool::kResize);
  ASSERT_EQ(setup.current().name, "Box");
  const Vec3 centre(1, 1, -1);
  setup.update(user_at(eye, centre + Vec3(0.2f, 0, 0)), kPress);
  setup.update(user_at(eye, centre + Vec3(0.3f, 0, 0)), kHeld);
  EXPECT_TRUE(setup.update(user_at(eye, centre + Vec3(0.3f, 0, 0)), kUp));
  EXPECT_LT((setup.current().size - Vec3(0.3f, 0.6f, 0.9f)).norm(), 1e-5f);
  // Shrunk towards nothing: held at the smallest size.
  setup.update(user_at(eye, centre + Vec3(0.3f, 0, 0)), kPress);
  setup.update(user_at(eye, centre), kHeld);
  setup.update(user_at(eye, centre), kUp);
  EXPECT_TRUE((setup.current().size.array() >= RoomSetup::kMinSizeM - 1e-7f).all());
  EXPECT_LT((setup.current().position - centre).norm(), 1e-6f) << "resizing does not move it";
}

TEST(RoomSetup, ControlsCycleAndAnUntrackedHandIsToldNotGuessed) {
  RoomSetup setup(two_objects(), Hand::kRight, "a.json");
  EXPECT_EQ(setup.message(), "touch Jupiter and press select (hold to move it)");
  TrackingFrame lost = user_at(Vec3(0, 1.6f, 0), Vec3(0, 1, -1));
  lost.valid = tracked::kHead;
  EXPECT_FALSE(setup.update(lost, kPress));
  EXPECT_FALSE(setup.holding());
  EXPECT_NE(setup.message().find("right hand or your head is not tracked"), std::string::npos);
  setup.update(lost, kNextObject);
  setup.update(lost, kNextObject);
  EXPECT_EQ(setup.current_index(), 0u) << "wraps around";
  for (int i = 0; i < 3; ++i) {
    setup.update(lost, kNextTool);
  }
  EXPECT_EQ(setup.tool(), SetupTool::kTouch);
  // Changing object while moving one puts it down first (an edit).
  const Vec3 eye(0, 1.6f, 0);
  setup.update(user_at(eye, Vec3(0, 1, -2)), kPress);
  EXPECT_TRUE(setup.update(user_at(eye, Vec3(0, 1.1f, -2)), kNextObject));
  EXPECT_FALSE(setup.holding());
  EXPECT_EQ(setup.current().name, "Box");
}

TEST(RoomSetup, AMapWithoutObjectsIsRefusedNamingTheFile) {
  TargetMap empty;
  empty.site = "A";
  try {
    RoomSetup setup(empty, Hand::kRight, "rooms/a.json");
    FAIL() << "accepted a map with nothing to set up";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("rooms/a.json: objects: none", 0), 0u) << e.what();
  }
}

TEST(RoomSetup, TheSavedMapReadsBackAsEdited) {
  const testing::ScratchDir dir;
  RoomSetup setup(two_objects(), Hand::kRight, "a.json");
  const Vec3 eye(0, 1.6f, 0);
  setup.update(user_at(eye, Vec3(0.5f, 1.2f, -0.5f)), kPress);
  ASSERT_TRUE(setup.update(user_at(eye, Vec3(0.5f, 1.2f, -0.5f)), kUp));
  const std::filesystem::path path = dir.path() / "a.json";
  write_target_map(setup.map(), path);
  const TargetMap back = read_target_map(path);
  ASSERT_EQ(back.objects.size(), 2u);
  EXPECT_LT((back.objects[0].position - setup.map().objects[0].position).norm(), 1e-6f);
  EXPECT_EQ(back.objects[1].name, "Box");
  // Written through a temporary file: nothing else is left beside it.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1);
}

}  // namespace
}  // namespace deixis::site
