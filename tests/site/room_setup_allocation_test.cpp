// The headset's setup frames allocate nothing between events (site/room_setup.h, app/xr_setup.h):
// idle frames, carrying an object, resizing one, and its outline drawn into lines made once.
#include <gtest/gtest.h>

#include <vector>

#include "allocation_counter.h"
#include "render/outline.h"
#include "site/room_setup.h"

namespace deixis::site {
namespace {

TrackingFrame user_with_tip(const Vec3& tip) {
  TrackingFrame f;
  f.T_world_head = Pose{Mat3::Identity(), Vec3(0, 1.6f, 0)};
  f.index_tip[index(Hand::kRight)] = tip;
  f.valid = tracked::kHead | tracked::kRightHand;
  return f;
}

TEST(RoomSetupAllocation, IdleCarryingAndResizingFramesAllocateNothing) {
  TargetMap map;
  map.site = "A";
  map.objects.push_back({1, "Jupiter", TargetKind::kSphere, Vec3(0, 1, -1), Vec3::Constant(0.4f)});
  map.objects.push_back({2, "TV", TargetKind::kScreen, Vec3(1, 1, -2), Vec3(1.2f, 0.7f, 0.05f)});
  RoomSetup setup(map, Hand::kRight, "a.json");
  std::vector<render::DebugLine> lines(map.objects.size() * render::kMaxOutlineLines);
  const auto frame = [&](const TrackingFrame& user, const SetupControls& controls) {
    setup.update(user, controls);
    std::size_t n = 0;
    for (const TargetObject& o : setup.map().objects) {
      n += render::outline(o, render::Colour(1, 1, 1, 1), std::span(lines).subspan(n));
    }
    EXPECT_GT(n, 0u);
  };
  frame(user_with_tip(Vec3(0, 1, -0.85f)), {.act = true, .act_pressed = true});  // grabbed
  {
    const testing::AllocationCounter counter;
    for (int i = 0; i < 60; ++i) {  // carried
      frame(user_with_tip(Vec3(0.01f * static_cast<float>(i), 1, -0.85f)), {.act = true});
    }
    EXPECT_EQ(counter.count(), 0u) << "carrying";
  }
  frame(user_with_tip(Vec3(0.6f, 1, -0.85f)), {});  // put down (an event: its message)
  frame(user_with_tip(Vec3(0.6f, 1, -0.85f)), {.next_tool = true});
  frame(user_with_tip(Vec3(0.6f, 1, -0.85f)), {.next_tool = true});
  ASSERT_EQ(setup.tool(), SetupTool::kResize);
  frame(user_with_tip(Vec3(0.8f, 1, -0.85f)), {.act = true, .act_pressed = true});
  {
    const testing::AllocationCounter counter;
    for (int i = 0; i < 30; ++i) {  // resized
      frame(user_with_tip(Vec3(0.8f + 0.005f * static_cast<float>(i), 1, -0.85f)), {.act = true});
    }
    EXPECT_EQ(counter.count(), 0u) << "resizing";
  }
  frame(user_with_tip(Vec3(0.95f, 1, -0.85f)), {});  // released (an event)
  const testing::AllocationCounter idle;
  for (int i = 0; i < 60; ++i) {
    frame(user_with_tip(Vec3(0.2f, 1.2f, -0.3f)), {});
  }
  EXPECT_EQ(idle.count(), 0u) << "idle";
}

}  // namespace
}  // namespace deixis::site
