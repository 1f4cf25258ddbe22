// The per-tick calls of the C API allocate nothing (include/deixis/deixis.h says which): a
// translator's tick and its joint poses, the target selection, the networks' runs, moving a
// room's objects and people. The counter sees libdeixis.so's allocations too (it replaces malloc
// for the whole process; the first check proves it does). Not built under ASan
// (tests/CMakeLists.txt).
#include <gtest/gtest.h>

#include <vector>

#include "allocation_counter.h"
#include "api/tracking_csv.h"
#include "deixis/deixis.h"

namespace deixis::testing {
namespace {

TEST(CApiHotPath, TheCounterSeesTheLibrarysAllocations) {
  deixis_room* room = nullptr;
  ASSERT_EQ(deixis_room_create(DEIXIS_ABI_VERSION, nullptr, &room, nullptr), DEIXIS_OK);
  const deixis_target t{1, DEIXIS_TARGET_SPHERE, {0, 1, -2}, {0.3f, 0.3f, 0.3f}};
  AllocationCounter counter;
  ASSERT_EQ(deixis_room_set_target(room, &t, "a name longer than the small-string buffer"),
            DEIXIS_OK);  // a new object: the map grows
  EXPECT_GT(counter.count(), 0u);
  deixis_room_destroy(room);
}

TEST(CApiHotPath, TicksSelectionAndNetworkRunsAllocateNothing) {
  deixis_mpnet* mpnet = nullptr;
  deixis_ugnet* ugnet = nullptr;
  deixis_avatar* avatar = nullptr;
  deixis_room* room = nullptr;
  const std::string map = (examples_dir() / "data/room.json").string();
  ASSERT_EQ(deixis_mpnet_load(DEIXIS_ABI_VERSION, nullptr, &mpnet, nullptr), DEIXIS_OK);
  ASSERT_EQ(deixis_ugnet_load(DEIXIS_ABI_VERSION, nullptr, &ugnet, nullptr), DEIXIS_OK);
  ASSERT_EQ(deixis_avatar_load(DEIXIS_ABI_VERSION, nullptr, &avatar, nullptr), DEIXIS_OK);
  ASSERT_EQ(deixis_room_create(DEIXIS_ABI_VERSION, map.c_str(), &room, nullptr), DEIXIS_OK);
  std::vector<deixis_tracking_frame> frames =
      read_tracking_csv(examples_dir() / "data/pointing.csv");

  deixis_translator_config config;
  deixis_translator_config_init(&config);
  deixis_upright_body body;
  deixis_upright_body_init(&body);
  ASSERT_EQ(deixis_calibrate_upright(&frames[0], &body, &config.person, nullptr), DEIXIS_OK);
  deixis_translator* translator = nullptr;
  deixis_target_selector* selector = nullptr;
  ASSERT_EQ(deixis_translator_create(DEIXIS_ABI_VERSION, mpnet, ugnet, avatar, &config, &translator,
                                     nullptr),
            DEIXIS_OK);
  ASSERT_EQ(
      deixis_target_selector_create(DEIXIS_ABI_VERSION, &config.person, 0, &selector, nullptr),
      DEIXIS_OK);
  std::vector<deixis_pose> poses(deixis_avatar_joint_count(avatar));
  std::vector<float> mpnet_windows(4 * DEIXIS_WINDOW_ROWS * DEIXIS_MPNET_FEATURES, 0.1f);
  std::vector<float> ugnet_windows(4 * DEIXIS_WINDOW_ROWS * DEIXIS_UGNET_COLUMNS, 0.1f);
  std::vector<float> out(4 * DEIXIS_POSE_SIZE);
  deixis_avatar_frame frame_out{};
  ASSERT_EQ(deixis_translator_tick(translator, &frames[0], room, &frame_out), DEIXIS_OK);
  ASSERT_EQ(deixis_room_set_person(room, 2, {0, 1.6f, -2}), DEIXIS_OK);

  AllocationCounter counter;
  for (std::size_t i = 0; i < 3 * frames.size(); ++i) {
    deixis_tracking_frame& frame = frames[i % frames.size()];
    ASSERT_EQ(deixis_target_selector_select(selector, &frame, room, 1), DEIXIS_OK);
    ASSERT_EQ(deixis_translator_tick(translator, i % 40 == 9 ? nullptr : &frame, room, &frame_out),
              DEIXIS_OK);
    ASSERT_EQ(
        deixis_translator_joint_poses(translator, DEIXIS_SPACE_WORLD, poses.data(), poses.size()),
        DEIXIS_OK);
    const deixis_target moved{1, DEIXIS_TARGET_SPHERE, {1.1f, 1.2f, -2.6f}, {0.3f, 0.3f, 0.3f}};
    ASSERT_EQ(deixis_room_set_target(room, &moved, nullptr), DEIXIS_OK);
    ASSERT_EQ(deixis_room_set_person(room, 2, {0, 1.6f, -2.0f - 0.001f * static_cast<float>(i)}),
              DEIXIS_OK);
    deixis_room_set_partner_head(room, {0, 1.6f, -2});
  }
  ASSERT_EQ(deixis_mpnet_run(mpnet, mpnet_windows.data(), 4, out.data()), DEIXIS_OK);
  ASSERT_EQ(deixis_ugnet_run(ugnet, ugnet_windows.data(), nullptr, 4, out.data()), DEIXIS_OK);
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_EQ(frame_out.visible, 1);

  deixis_target_selector_destroy(selector);
  deixis_translator_destroy(translator);
  deixis_room_destroy(room);
  deixis_avatar_destroy(avatar);
  deixis_ugnet_destroy(ugnet);
  deixis_mpnet_destroy(mpnet);
}

}  // namespace
}  // namespace deixis::testing
