// The C API of include/deixis/deixis.h through libdeixis.so: its answers equal the runtime's own
// (the networks, the translator with IK), and every misuse a caller can make (wrong ABI, missing
// or corrupt files, null pointers, NaN, out-of-range ids) is a status and a message, never a
// crash or an exception.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <string>

#include "api/tracking_csv.h"
#include "deixis/deixis.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "test_support.h"

namespace deixis::testing {
namespace {

namespace fs = std::filesystem;

const fs::path kWeights = source_dir() / "assets/weights/right";

std::string weights(const char* name) {
  return (kWeights / name).string();
}

// RAII for the tests only: each handle destroyed at scope exit.
struct Loaded {
  deixis_mpnet* mpnet = nullptr;
  deixis_ugnet* ugnet = nullptr;
  deixis_avatar* avatar = nullptr;
  deixis_room* room = nullptr;
  Loaded() {
    deixis_error e{};
    EXPECT_EQ(deixis_mpnet_load(DEIXIS_ABI_VERSION, nullptr, &mpnet, &e), DEIXIS_OK) << e.message;
    EXPECT_EQ(deixis_ugnet_load(DEIXIS_ABI_VERSION, nullptr, &ugnet, &e), DEIXIS_OK) << e.message;
    EXPECT_EQ(deixis_avatar_load(DEIXIS_ABI_VERSION, nullptr, &avatar, &e), DEIXIS_OK) << e.message;
    const std::string map = (examples_dir() / "data/room.json").string();
    EXPECT_EQ(deixis_room_create(DEIXIS_ABI_VERSION, map.c_str(), &room, &e), DEIXIS_OK)
        << e.message;
  }
  ~Loaded() {
    deixis_room_destroy(room);
    deixis_avatar_destroy(avatar);
    deixis_ugnet_destroy(ugnet);
    deixis_mpnet_destroy(mpnet);
  }
};

deixis_translator_config config_for(const deixis_tracking_frame& upright) {
  deixis_translator_config config;
  deixis_translator_config_init(&config);
  deixis_upright_body body;
  deixis_upright_body_init(&body);
  deixis_error e{};
  EXPECT_EQ(deixis_calibrate_upright(&upright, &body, &config.person, &e), DEIXIS_OK) << e.message;
  config.avatar_floor.position = {0.3f, 0.0f, -1.0f};
  return config;
}

// A translator of the person of the examples' recording, calibrated on `upright`; null (and a
// test failure) when refused.
deixis_translator* translator_for(const Loaded& loaded, const deixis_tracking_frame& upright) {
  const deixis_translator_config config = config_for(upright);
  deixis_translator* translator = nullptr;
  deixis_error e{};
  EXPECT_EQ(deixis_translator_create(DEIXIS_ABI_VERSION, loaded.mpnet, loaded.ugnet, loaded.avatar,
                                     &config, &translator, &e),
            DEIXIS_OK)
      << e.message;
  return translator;
}

// The examples' recording (examples/data/pointing.csv) with a translator of its person,
// calibrated on its first frame; everything destroyed at scope exit.
struct Playing : Loaded {
  std::vector<deixis_tracking_frame> frames =
      read_tracking_csv(examples_dir() / "data/pointing.csv");
  deixis_translator* translator = translator_for(*this, frames.front());
  Playing() = default;
  Playing(const Playing&) = delete;
  Playing& operator=(const Playing&) = delete;
  ~Playing() { deixis_translator_destroy(translator); }
};

TEST(CApi, VersionAndAbiMatchTheHeader) {
  EXPECT_EQ(deixis_abi_version(), static_cast<uint32_t>(DEIXIS_ABI_VERSION));
  const std::string expected = std::to_string(DEIXIS_VERSION_MAJOR) + "." +
                               std::to_string(DEIXIS_VERSION_MINOR) + "." +
                               std::to_string(DEIXIS_VERSION_PATCH);
  EXPECT_EQ(std::string(deixis_version()), expected);
  EXPECT_STREQ(deixis_status_name(DEIXIS_ERROR_FILE), "file error");
  EXPECT_STREQ(deixis_status_name(static_cast<deixis_status>(6)), "unknown status");
}

// What a site does by default, the C config does by default: touch contact, gaze and pointing
// settling on (pointing_settle is ABI 2's field; presence/pointing_settle.h).
TEST(CApi, TheTranslatorConfigStartsWithContactAndSettlingOn) {
  deixis_translator_config config;
  std::memset(&config, 0x5a, sizeof config);
  deixis_translator_config_init(&config);
  EXPECT_EQ(config.touch_contact, 1);
  EXPECT_EQ(config.gaze_settle, 1);
  EXPECT_EQ(config.pointing_settle, 1);
  EXPECT_EQ(DEIXIS_ABI_VERSION, 2);
}

TEST(CApi, AnotherAbiIsRefusedAtCreation) {
  deixis_error e{};
  deixis_mpnet* mpnet = reinterpret_cast<deixis_mpnet*>(&e);  // must be reset to null
  EXPECT_EQ(deixis_mpnet_load(DEIXIS_ABI_VERSION + 1, nullptr, &mpnet, &e), DEIXIS_ERROR_ABI);
  EXPECT_EQ(e.status, DEIXIS_ERROR_ABI);
  EXPECT_NE(std::string(e.message).find("ABI 2"), std::string::npos) << e.message;
  deixis_room* room = nullptr;
  EXPECT_EQ(deixis_room_create(0, nullptr, &room, nullptr), DEIXIS_ERROR_ABI);
  EXPECT_EQ(room, nullptr);
}

TEST(CApi, MissingAndCorruptFilesAreFileErrorsNamingTheFile) {
  const ScratchDir dir;
  deixis_error e{};
  deixis_mpnet* mpnet = nullptr;
  const std::string missing = (dir.path() / "none.safetensors").string();
  EXPECT_EQ(deixis_mpnet_load(DEIXIS_ABI_VERSION, missing.c_str(), &mpnet, &e), DEIXIS_ERROR_FILE);
  EXPECT_EQ(mpnet, nullptr);
  EXPECT_NE(std::string(e.message).find("none.safetensors"), std::string::npos) << e.message;

  const fs::path garbage = dir.path() / "garbage.bin";
  std::ofstream(garbage) << "this is not a safetensors file, nor a glTF one";
  deixis_ugnet* ugnet = nullptr;
  EXPECT_EQ(deixis_ugnet_load(DEIXIS_ABI_VERSION, garbage.c_str(), &ugnet, &e), DEIXIS_ERROR_FILE);
  EXPECT_NE(std::string(e.message).find("garbage.bin"), std::string::npos) << e.message;
  deixis_avatar* avatar = nullptr;
  EXPECT_EQ(deixis_avatar_load(DEIXIS_ABI_VERSION, garbage.c_str(), &avatar, &e),
            DEIXIS_ERROR_FILE);
  EXPECT_NE(std::string(e.message).find("garbage.bin"), std::string::npos) << e.message;
  deixis_room* room = nullptr;
  EXPECT_EQ(deixis_room_create(DEIXIS_ABI_VERSION, garbage.c_str(), &room, &e), DEIXIS_ERROR_FILE);
  EXPECT_NE(std::string(e.message).find("garbage.bin"), std::string::npos) << e.message;

  // An MPNet file given as UGNet: the tensors are not UGNet's.
  EXPECT_EQ(deixis_ugnet_load(DEIXIS_ABI_VERSION, weights("MPNet(MoE)(AC)80.safetensors").c_str(),
                              &ugnet, &e),
            DEIXIS_ERROR_FILE);
  EXPECT_GT(std::strlen(e.message), 0u);
}

TEST(CApi, ALongMessageIsCutOnACharacterBoundary) {
  // A path of 600 two-byte characters: the message must end inside the buffer, NUL-terminated,
  // and not in the middle of a character.
  std::string path = "/";
  for (int i = 0; i < 600; ++i) {
    path += "\xc3\xa9";  // é
  }
  deixis_error e{};
  deixis_mpnet* mpnet = nullptr;
  EXPECT_EQ(deixis_mpnet_load(DEIXIS_ABI_VERSION, path.c_str(), &mpnet, &e), DEIXIS_ERROR_FILE);
  const std::size_t n = std::strlen(e.message);
  ASSERT_LT(n, static_cast<std::size_t>(DEIXIS_ERROR_MESSAGE_SIZE));
  ASSERT_GT(n, 0u);
  // The last byte is not a lead byte whose continuation was cut off.
  const auto last = static_cast<unsigned char>(e.message[n - 1]);
  EXPECT_FALSE((last & 0xE0u) == 0xC0u) << "cut after a lead byte";
}

TEST(CApi, NullPointersAreInvalidArguments) {
  EXPECT_EQ(deixis_mpnet_load(DEIXIS_ABI_VERSION, nullptr, nullptr, nullptr),
            DEIXIS_ERROR_INVALID_ARGUMENT);
  float out[3];
  EXPECT_EQ(deixis_mpnet_run(nullptr, out, 1, out), DEIXIS_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(deixis_translator_tick(nullptr, nullptr, nullptr, nullptr),
            DEIXIS_ERROR_INVALID_ARGUMENT);
  deixis_translator* translator = nullptr;
  deixis_error e{};
  EXPECT_EQ(deixis_translator_create(DEIXIS_ABI_VERSION, nullptr, nullptr, nullptr, nullptr,
                                     &translator, &e),
            DEIXIS_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(e.message).find("must not be null"), std::string::npos);
  EXPECT_EQ(deixis_avatar_joint_count(nullptr), 0u);
  EXPECT_EQ(deixis_avatar_joint_name(nullptr, 0), nullptr);
  EXPECT_EQ(deixis_room_target_count(nullptr), 0u);
  deixis_mpnet_destroy(nullptr);
  deixis_translator_destroy(nullptr);
}

TEST(CApi, TheDataDirectoryHoldsTheShippedFilesAndItsEnvironmentVariableIsChecked) {
  char buffer[4096];
  std::size_t length = 0;
  ASSERT_EQ(deixis_data_dir(buffer, sizeof buffer, &length), DEIXIS_OK);
  EXPECT_EQ(length, std::strlen(buffer) + 1);
  EXPECT_TRUE(fs::exists(fs::path(buffer) / "avatars/default.glb"));
  EXPECT_EQ(deixis_data_dir(buffer, 2, &length), DEIXIS_ERROR_INVALID_ARGUMENT);
  EXPECT_GT(length, 2u);

  const ScratchDir dir;
  ASSERT_EQ(setenv("DEIXIS_DATA_DIR", dir.path().c_str(), 1), 0);
  EXPECT_EQ(deixis_data_dir(buffer, sizeof buffer, &length), DEIXIS_ERROR_FILE);
  deixis_error e{};
  deixis_mpnet* mpnet = nullptr;
  EXPECT_EQ(deixis_mpnet_load(DEIXIS_ABI_VERSION, nullptr, &mpnet, &e), DEIXIS_ERROR_FILE);
  EXPECT_NE(std::string(e.message).find("DEIXIS_DATA_DIR"), std::string::npos) << e.message;
  unsetenv("DEIXIS_DATA_DIR");
}

// The C API runs the very networks the runtime runs: every shipped architecture, windows in a
// batch, equal to nn::Mpnet / nn::Ugnet run() one by one.
TEST(CApi, NetworksEqualTheRuntimesOnEveryShippedArchitecture) {
  std::mt19937 rng(7);
  std::normal_distribution<float> normal(0.0f, 0.5f);
  for (const char* name : {"MPNet(MoE)(AC)80", "MPNet(MLP)(AC)80", "MPNet(Transformer)(AC)80"}) {
    SCOPED_TRACE(name);
    const std::string path = weights(name) + ".safetensors";
    deixis_mpnet* mpnet = nullptr;
    deixis_error e{};
    ASSERT_EQ(deixis_mpnet_load(DEIXIS_ABI_VERSION, path.c_str(), &mpnet, &e), DEIXIS_OK)
        << e.message;
    const nn::Mpnet ours = nn::Mpnet::load(fs::path(path));
    EXPECT_EQ(std::string(deixis_mpnet_architecture(mpnet)),
              std::string(nn::architecture_name(ours.architecture())));
    std::vector<float> windows(3 * nn::kMpnetWindowSize);
    for (float& x : windows) {
      x = normal(rng);
    }
    std::vector<float> out(3 * 3);
    ASSERT_EQ(deixis_mpnet_run(mpnet, windows.data(), 3, out.data()), DEIXIS_OK);
    for (int i = 0; i < 3; ++i) {
      const nn::Progression p =
          ours.run(nn::MpnetWindow(windows.data() + i * nn::kMpnetWindowSize, nn::kMpnetWindowSize))
              .progression;
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(out[static_cast<std::size_t>(3 * i + k)], p[static_cast<std::size_t>(k)]);
      }
    }
    deixis_mpnet_destroy(mpnet);
  }
  for (const char* name : {"UGNet(MoE)(AC)120", "UGNet(MLP)(AC)120", "UGNet(Transformer)(AC)2",
                           "UGNet(Diffusion)(AC)120"}) {
    SCOPED_TRACE(name);
    const std::string path = weights(name) + ".safetensors";
    deixis_ugnet* ugnet = nullptr;
    deixis_error e{};
    ASSERT_EQ(deixis_ugnet_load(DEIXIS_ABI_VERSION, path.c_str(), &ugnet, &e), DEIXIS_OK)
        << e.message;
    const nn::Ugnet ours = nn::Ugnet::load(fs::path(path));
    EXPECT_EQ(deixis_ugnet_needs_noise(ugnet), ours.needs_noise() ? 1 : 0);
    std::vector<float> windows(2 * nn::kUgnetWindowSize), noise(2 * nn::kDiffusionNoiseSize);
    for (float& x : windows) {
      x = normal(rng);
    }
    for (float& x : noise) {
      x = normal(rng);
    }
    std::vector<float> out(2 * nn::kPoseSize);
    ASSERT_EQ(deixis_ugnet_run(ugnet, windows.data(), noise.data(), 2, out.data()), DEIXIS_OK);
    for (int i = 0; i < 2; ++i) {
      const nn::PoseVector x =
          ours.run(nn::UgnetWindow(windows.data() + i * nn::kUgnetWindowSize, nn::kUgnetWindowSize),
                   std::span<const float>(noise.data() + i * nn::kDiffusionNoiseSize,
                                          nn::kDiffusionNoiseSize));
      for (int k = 0; k < nn::kPoseSize; ++k) {
        EXPECT_EQ(out[static_cast<std::size_t>(nn::kPoseSize * i + k)],
                  x[static_cast<std::size_t>(k)]);
      }
    }
    deixis_ugnet_destroy(ugnet);
  }
}

// The translator through the C API and presence::RemoteAvatar in-tree, on the examples'
// recording: the same fingertip, tick for tick.
TEST(CApi, TheTranslatorEqualsTheInTreeRemoteAvatar) {
  const std::vector<PrintedTick> expected = parse_ticks(
      in_tree_fingertips(examples_dir() / "data/pointing.csv", examples_dir() / "data/room.json"));
  const Playing playing;
  const std::vector<deixis_tracking_frame>& frames = playing.frames;
  deixis_translator* translator = playing.translator;
  ASSERT_NE(translator, nullptr);
  ASSERT_EQ(expected.size(), frames.size());
  ASSERT_GT(frames.size(), 100u);
  const Loaded& loaded = playing;
  float furthest = 0.0f;  // how far the fingertip travels: the test must see a gesture
  for (std::size_t i = 0; i < frames.size(); ++i) {
    deixis_avatar_frame out{};
    ASSERT_EQ(deixis_translator_tick(translator, &frames[i], loaded.room, &out), DEIXIS_OK);
    const Vec3 tip(out.fingertip.x, out.fingertip.y, out.fingertip.z);
    EXPECT_LT((tip - expected[i].fingertip).norm(), 2e-5f) << "tick " << i;
    EXPECT_EQ(out.visible, expected[i].visible);
    EXPECT_EQ(out.held, expected[i].held);
    furthest = std::max(furthest, (tip - expected.front().fingertip).norm());
  }
  EXPECT_GT(furthest, 0.3f);
  deixis_translator_stats stats{};
  ASSERT_EQ(deixis_translator_stats_get(translator, &stats), DEIXIS_OK);
  EXPECT_EQ(stats.ticks, frames.size());
}

TEST(CApi, JointPosesAreTheSkeletonInEachSpace) {
  const Playing playing;
  const Loaded& loaded = playing;
  const std::vector<deixis_tracking_frame>& frames = playing.frames;
  deixis_translator* translator = playing.translator;
  ASSERT_NE(translator, nullptr);
  deixis_avatar_frame out{};
  for (std::size_t i = 0; i < 60; ++i) {
    ASSERT_EQ(deixis_translator_tick(translator, &frames[i], loaded.room, &out), DEIXIS_OK);
  }
  const std::size_t n = deixis_avatar_joint_count(loaded.avatar);
  ASSERT_GT(n, 20u);
  std::vector<deixis_pose> world(n), model(n), local(n);
  ASSERT_EQ(deixis_translator_joint_poses(translator, DEIXIS_SPACE_WORLD, world.data(), n),
            DEIXIS_OK);
  ASSERT_EQ(deixis_translator_joint_poses(translator, DEIXIS_SPACE_MODEL, model.data(), n),
            DEIXIS_OK);
  ASSERT_EQ(deixis_translator_joint_poses(translator, DEIXIS_SPACE_LOCAL, local.data(), n),
            DEIXIS_OK);
  EXPECT_EQ(deixis_translator_joint_poses(translator, DEIXIS_SPACE_WORLD, world.data(), n - 1),
            DEIXIS_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(deixis_translator_joint_poses(translator, 9, world.data(), n),
            DEIXIS_ERROR_INVALID_ARGUMENT);
  deixis_pose T_world_model{};
  ASSERT_EQ(deixis_translator_model_pose(translator, &T_world_model), DEIXIS_OK);

  const auto to_pose = [](const deixis_pose& p) {
    return Pose{
        Quat(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z).toRotationMatrix(),
        Vec3(p.position.x, p.position.y, p.position.z)};
  };
  for (std::size_t j = 0; j < n; ++j) {
    SCOPED_TRACE(deixis_avatar_joint_name(loaded.avatar, j));
    // world = T_world_model · model, and model = model(parent) · local.
    const Pose w = compose(to_pose(T_world_model), to_pose(model[j]));
    EXPECT_LT((w.translation - to_pose(world[j]).translation).norm(), 1e-4f);
    const int parent = deixis_avatar_joint_parent(loaded.avatar, j);
    ASSERT_LT(parent, static_cast<int>(j));
    const Pose m =
        parent < 0 ? to_pose(local[j])
                   : compose(to_pose(model[static_cast<std::size_t>(parent)]), to_pose(local[j]));
    EXPECT_LT((m.translation - to_pose(model[j]).translation).norm(), 1e-4f);
  }
  // The fingertip of the frame is at the tip of the deictic index chain, near the hand joints.
  const Vec3 tip(out.fingertip.x, out.fingertip.y, out.fingertip.z);
  float nearest = 1e9f;
  for (const deixis_pose& p : world) {
    nearest = std::min(nearest, (Vec3(p.position.x, p.position.y, p.position.z) - tip).norm());
  }
  EXPECT_LT(nearest, 0.05f);
}

TEST(CApi, NonFiniteOrMissingTrackingIsHeldOverAndCounted) {
  const Playing playing;
  const Loaded& loaded = playing;
  const std::vector<deixis_tracking_frame>& frames = playing.frames;
  deixis_translator* translator = playing.translator;
  ASSERT_NE(translator, nullptr);
  deixis_avatar_frame out{};
  // Nothing before the first valid frame: hidden.
  ASSERT_EQ(deixis_translator_tick(translator, nullptr, loaded.room, &out), DEIXIS_OK);
  EXPECT_EQ(out.visible, 0);
  ASSERT_EQ(deixis_translator_tick(translator, &frames[0], loaded.room, &out), DEIXIS_OK);
  EXPECT_EQ(out.visible, 1);

  deixis_tracking_frame bad = frames[1];
  bad.head.position.y = std::nanf("");
  ASSERT_EQ(deixis_translator_tick(translator, &bad, loaded.room, &out), DEIXIS_OK);
  EXPECT_EQ(out.held, 1);
  bad = frames[1];
  bad.wrist[DEIXIS_HAND_RIGHT].orientation = {0, 0, 0, 0};  // not a rotation
  ASSERT_EQ(deixis_translator_tick(translator, &bad, loaded.room, &out), DEIXIS_OK);
  EXPECT_EQ(out.held, 1);
  for (float v : {out.fingertip.x, out.fingertip.y, out.fingertip.z, out.head.position.x,
                  out.gaze.x, out.wrist.orientation.w}) {
    EXPECT_TRUE(std::isfinite(v));
  }
  deixis_translator_stats stats{};
  ASSERT_EQ(deixis_translator_stats_get(translator, &stats), DEIXIS_OK);
  EXPECT_EQ(stats.rejected_frames, 2u);
  EXPECT_GE(stats.held, 2u);
}

TEST(CApi, AConfigOutOfRangeIsRefusedNamingTheField) {
  const Loaded loaded;
  deixis_translator_config config;
  deixis_translator_config_init(&config);
  const auto refused = [&](const char* field) {
    deixis_translator* translator = nullptr;
    deixis_error e{};
    EXPECT_EQ(deixis_translator_create(DEIXIS_ABI_VERSION, loaded.mpnet, loaded.ugnet,
                                       loaded.avatar, &config, &translator, &e),
              DEIXIS_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(translator, nullptr);
    EXPECT_NE(std::string(e.message).find(field), std::string::npos) << e.message;
  };
  config.person.height = std::nanf("");
  refused("person.height");
  deixis_translator_config_init(&config);
  config.person.deictic_hand = 2;
  refused("deictic_hand");
  deixis_translator_config_init(&config);
  config.avatar_floor.orientation = {0, 0, 0, 0};
  refused("avatar_floor");
  deixis_translator_config_init(&config);
  config.mirror = 5;
  refused("mirror");
}

TEST(CApi, ARoomsTargetsAndPeopleCanBeEdited) {
  deixis_room* room = nullptr;
  const std::string map = (examples_dir() / "data/room.json").string();
  ASSERT_EQ(deixis_room_create(DEIXIS_ABI_VERSION, map.c_str(), &room, nullptr), DEIXIS_OK);
  ASSERT_EQ(deixis_room_target_count(room), 2u);
  deixis_target t{};
  ASSERT_EQ(deixis_room_target(room, 0, &t), DEIXIS_OK);
  EXPECT_EQ(t.id, 1);
  EXPECT_EQ(t.kind, DEIXIS_TARGET_SPHERE);
  EXPECT_FLOAT_EQ(t.position.x, 1.1f);
  EXPECT_EQ(deixis_room_target(room, 2, &t), DEIXIS_ERROR_INVALID_ARGUMENT);

  t.position = {5, 1, 5};
  ASSERT_EQ(deixis_room_set_target(room, &t, nullptr), DEIXIS_OK);  // moves id 1
  EXPECT_EQ(deixis_room_target_count(room), 2u);
  deixis_target box{7, DEIXIS_TARGET_BOX, {0, 1, -1}, {0.1f, 0.1f, 0.1f}};
  ASSERT_EQ(deixis_room_set_target(room, &box, "cup"), DEIXIS_OK);
  EXPECT_EQ(deixis_room_target_count(room), 3u);
  ASSERT_EQ(deixis_room_target(room, 0, &t), DEIXIS_OK);
  EXPECT_FLOAT_EQ(t.position.x, 5.0f);

  deixis_target bad = box;
  bad.id = 0;
  EXPECT_EQ(deixis_room_set_target(room, &bad, nullptr), DEIXIS_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(deixis_room_last_error(room)).find("1..1000000"), std::string::npos);
  bad = box;
  bad.size.y = std::nanf("");
  EXPECT_EQ(deixis_room_set_target(room, &bad, nullptr), DEIXIS_ERROR_INVALID_ARGUMENT);
  bad = box;
  bad.kind = 9;
  EXPECT_EQ(deixis_room_set_target(room, &bad, nullptr), DEIXIS_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(deixis_room_remove_target(room, 7), DEIXIS_OK);
  EXPECT_EQ(deixis_room_remove_target(room, 7), DEIXIS_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(deixis_room_target_count(room), 2u);

  EXPECT_EQ(deixis_room_set_person(room, 3, {0, 1.6f, -2}), DEIXIS_OK);
  EXPECT_EQ(deixis_room_set_person(room, 3, {1, 1.6f, -2}), DEIXIS_OK);  // moves person 3
  EXPECT_EQ(deixis_room_set_person(room, 0, {0, 1.6f, -2}), DEIXIS_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(deixis_room_set_person(room, 255, {0, 1.6f, -2}), DEIXIS_ERROR_INVALID_ARGUMENT);
  for (int p = 1; p <= 254; ++p) {  // every id fits at once
    ASSERT_EQ(deixis_room_set_person(room, static_cast<uint8_t>(p), {0, 1.6f, 0}), DEIXIS_OK);
  }
  EXPECT_EQ(deixis_room_remove_person(room, 3), DEIXIS_OK);
  EXPECT_EQ(deixis_room_remove_person(room, 3), DEIXIS_ERROR_INVALID_ARGUMENT);
  deixis_room_destroy(room);
}

TEST(CApi, UprightCalibrationAndTargetSelectionFromALiveUsersTracking) {
  deixis_tracking_frame frame;
  deixis_tracking_frame_init(&frame);
  deixis_upright_body body;
  deixis_upright_body_init(&body);
  deixis_body_calibration user{};
  deixis_error e{};
  // Nothing tracked: refused, with the reason.
  EXPECT_EQ(deixis_calibrate_upright(&frame, &body, &user, &e), DEIXIS_ERROR_INVALID_ARGUMENT);
  EXPECT_GT(std::strlen(e.message), 0u);

  frame.valid = DEIXIS_TRACKED_HEAD | DEIXIS_TRACKED_GAZE;
  frame.head.position = {0, 1.6f, 0};
  ASSERT_EQ(deixis_calibrate_upright(&frame, &body, &user, &e), DEIXIS_OK) << e.message;
  EXPECT_NEAR(user.height, 1.6f / 0.936f, 0.01f);
  EXPECT_EQ(user.deictic_hand, DEIXIS_HAND_RIGHT);
  body.deictic_hand = 7;
  EXPECT_EQ(deixis_calibrate_upright(&frame, &body, &user, &e), DEIXIS_ERROR_INVALID_ARGUMENT);

  deixis_room* room = nullptr;
  const std::string map = (examples_dir() / "data/room.json").string();
  ASSERT_EQ(deixis_room_create(DEIXIS_ABI_VERSION, map.c_str(), &room, nullptr), DEIXIS_OK);
  deixis_target_selector* selector = nullptr;
  ASSERT_EQ(deixis_target_selector_create(DEIXIS_ABI_VERSION, &user, 0, &selector, nullptr),
            DEIXIS_OK);
  // Look at the globe (id 1, at (1.1, 1.25, -2.6)), then at the screen (id 2).
  for (const auto& [target, where] :
       {std::pair{1, Vec3(1.1f, 1.25f, -2.6f)}, std::pair{2, Vec3(-1.4f, 1.5f, -3.4f)}}) {
    const Vec3 gaze = (where - Vec3(0, 1.6f, 0)).normalized();
    frame.gaze = {gaze.x(), gaze.y(), gaze.z()};
    ASSERT_EQ(deixis_target_selector_select(selector, &frame, room, 1), DEIXIS_OK);
    EXPECT_EQ(frame.head_target, target);
    EXPECT_FLOAT_EQ(frame.head_target_position.x, where.x());
  }
  EXPECT_EQ(deixis_target_selector_select(selector, nullptr, room, 1),
            DEIXIS_ERROR_INVALID_ARGUMENT);
  EXPECT_GT(std::strlen(deixis_target_selector_last_error(selector)), 0u);
  deixis_target_selector_destroy(selector);
  deixis_room_destroy(room);
}

}  // namespace
}  // namespace deixis::testing
