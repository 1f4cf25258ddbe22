// A full translator tick (features, MPNet, blend, UGNet, decode) for one remote person, one
// thread, and the whole remote avatar's tick (that, touch contact and the whole-avatar IK on the
// default avatar). Goals: tick ≤ 60 µs, IK ≤ 10 µs; the paper's MPNet + UGNet + IK took
// 6.7 ms.

#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>

#include "avatar/avatar_loader.h"
#include "gesture/translator.h"
#include "presence/remote_avatar.h"

namespace {

using namespace deixis;

std::filesystem::path reference_dir() {
  if (const char* env = std::getenv("DEIXIS_REFERENCE_DIR")) {
    return env;
  }
  return DEIXIS_REFERENCE_DIR;
}

// A person standing at the origin, slowly raising the right hand toward a target.
TrackingFrame frame_at(int i) {
  TrackingFrame f;
  const float s = 0.5f + 0.5f * std::sin(0.05f * static_cast<float>(i));
  f.T_world_head = Pose{yaw_rotation(0.1f * s), Vec3(0, 1.6f, 0)};
  f.gaze = Vec3(0.1f * s, 0, -1).normalized();
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    const float side = h == Hand::kRight ? 1.0f : -1.0f;
    f.T_world_wrist[index(h)] =
        Pose{Mat3::Identity(), Vec3(0.2f * side, 0.85f + 0.5f * s, -0.4f * s)};
    f.index_tip[index(h)] = f.T_world_wrist[index(h)].translation + Vec3(0, 0, -0.15f);
  }
  f.valid = tracked::kAll;
  f.head_target = f.hand_target = 1;
  f.head_target_position = f.hand_target_position = Vec3(0.5f, 1.5f, -2.0f);
  return f;
}

void BM_TranslatorTick(benchmark::State& state) {
  const auto w = reference_dir() / "weights/right";
  TranslatorConfig config;
  config.user.T_world_root = Pose{Mat3::Identity(), Vec3(0, 1.6f, 0)};
  config.T_world_avatar_root = Pose{yaw_rotation(0.7f), Vec3(2, 1.55f, -1)};
  config.avatar_height = 1.65f;
  Translator translator(nn::Mpnet::load(w / "MPNet(MoE)(AC)80.safetensors"),
                        nn::Ugnet::load(w / "UGNet(MoE)(AC)120.safetensors"), config);
  TargetMap room;
  room.objects.push_back(
      {1, "Jupiter", TargetKind::kSphere, Vec3(-1, 1.4f, -3), Vec3(0.4f, 0.4f, 0.4f)});
  const LocalTargets targets{&room, Vec3(0, 1.6f, -2)};
  std::vector<TrackingFrame> frames;
  for (int i = 0; i < 256; ++i) {
    frames.push_back(frame_at(i));
  }
  std::size_t i = 0;
  for (auto _ : state) {
    AvatarFrame a = translator.tick(&frames[i++ % frames.size()], targets);
    benchmark::DoNotOptimize(a);
  }
}

void BM_RemoteAvatarTick(benchmark::State& state) {
  const auto w = reference_dir() / "weights/right";
  const ik::AvatarSolver solver = ik::AvatarSolver::build(
      avatar::load_avatar(std::filesystem::path(DEIXIS_SOURCE_DIR) / "assets/avatars/default.glb")
          .rig);
  presence::RemoteAvatarConfig config;
  config.user.T_world_root = Pose{Mat3::Identity(), Vec3(0, 1.6f, 0)};
  config.T_world_floor = Pose{yaw_rotation(0.7f), Vec3(2, 0, -1)};
  presence::RemoteAvatar avatar(nn::Mpnet::load(w / "MPNet(MoE)(AC)80.safetensors"),
                                nn::Ugnet::load(w / "UGNet(MoE)(AC)120.safetensors"), solver,
                                config);
  TargetMap room;
  room.objects.push_back(
      {1, "Jupiter", TargetKind::kSphere, Vec3(-1, 1.4f, -3), Vec3(0.4f, 0.4f, 0.4f)});
  const LocalTargets targets{&room, Vec3(0, 1.6f, -2)};
  std::vector<TrackingFrame> frames;
  for (int i = 0; i < 256; ++i) {
    frames.push_back(frame_at(i));
  }
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(avatar.tick(&frames[i++ % frames.size()], targets));
    benchmark::DoNotOptimize(avatar.model_pose().data());
  }
}

}  // namespace

BENCHMARK(BM_TranslatorTick)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RemoteAvatarTick)->Unit(benchmark::kMicrosecond);
