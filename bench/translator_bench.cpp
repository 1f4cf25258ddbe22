// A full translator tick (features, MPNet, blend, UGNet, decode) for one remote person, one
// thread, and the whole remote avatar's tick (that, touch contact and the whole-avatar IK on the
// default avatar). Goals: tick ≤ 60 µs, IK ≤ 10 µs; the paper's MPNet + UGNet + IK took
// 6.7 ms.
//
// BM_PeopleTick/N: a site's whole tick for N remote people (presence::tick_people: the networks
// batched across people, then touch contact and IK per person), docs/scaling.md. Counters:
// us_per_person (CPU time of the tick / N), net_us_per_person (the batched MPNet + UGNet alone on
// the same N windows; mpnet_us and ugnet_us each network's part of it) and net_share (their part
// of the tick). Goal: at N = 64, us_per_person at most a third of N = 1's in the same run, and
// net_us_per_person ≤ 12 µs.
// With DEIXIS_PRODUCT_KERNEL=build in the environment the networks keep to the build's AVX2
// kernels, as on a CPU without AVX-512 (gesture/nn/batch.h; docs/scaling.md has both cases).

#include <benchmark/benchmark.h>

#include <cmath>
#include <ctime>
#include <filesystem>
#include <memory>
#include <vector>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#endif

#include "avatar/avatar_loader.h"
#include "gesture/translator.h"
#include "presence/people_tick.h"
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

// This thread's CPU time in seconds (the machine may be shared: wall time would count others).
double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void BM_PeopleTick(benchmark::State& state) {
  const auto people = static_cast<std::size_t>(state.range(0));
  const auto w = reference_dir() / "weights/right";
  const nn::Mpnet mpnet = nn::Mpnet::load(w / "MPNet(MoE)(AC)80.safetensors");
  const nn::Ugnet ugnet = nn::Ugnet::load(w / "UGNet(MoE)(AC)120.safetensors");
  const ik::AvatarSolver solver = ik::AvatarSolver::build(
      avatar::load_avatar(std::filesystem::path(DEIXIS_SOURCE_DIR) / "assets/avatars/default.glb")
          .rig);
  // Everyone on a ring around the room's middle, each at their own moment of the same motion.
  std::vector<std::unique_ptr<presence::RemoteAvatar>> avatars;
  for (std::size_t k = 0; k < people; ++k) {
    presence::RemoteAvatarConfig config;
    config.user.T_world_root = Pose{Mat3::Identity(), Vec3(0, 1.6f, 0)};
    const float yaw = 6.2832f * static_cast<float>(k) / static_cast<float>(people);
    config.T_world_floor = Pose{yaw_rotation(yaw), Vec3(3 * std::sin(yaw), 0, 3 * std::cos(yaw))};
    avatars.push_back(std::make_unique<presence::RemoteAvatar>(mpnet, ugnet, solver, config));
  }
  TargetMap room;
  room.objects.push_back(
      {1, "Jupiter", TargetKind::kSphere, Vec3(-1, 1.4f, -3), Vec3(0.4f, 0.4f, 0.4f)});
  const LocalTargets targets{&room, Vec3(0, 1.6f, -2)};
  std::vector<TrackingFrame> frames;
  for (int i = 0; i < 256; ++i) {
    frames.push_back(frame_at(i));
  }
  std::vector<presence::PersonTick> tick(people);
  presence::PeopleTickBuffers buffers;
  buffers.reserve(people, mpnet, ugnet);
  std::size_t i = 0;
  const auto one_tick = [&] {
    for (std::size_t k = 0; k < people; ++k) {
      tick[k] = {avatars[k].get(), &frames[(i + 37 * k) % frames.size()]};
    }
    presence::tick_people(tick, targets, buffers);
    ++i;
  };
  one_tick();  // everyone's first frame: the translators start

  const double start = thread_seconds();
  for (auto _ : state) {
    one_tick();
    benchmark::DoNotOptimize(avatars.back()->model_pose().data());
  }
  const double tick_seconds = (thread_seconds() - start) / static_cast<double>(state.iterations());

  // The networks alone on the windows of the last tick, batched as tick_people runs them.
  std::vector<float> mpnet_windows, ugnet_windows;
  for (const auto& avatar : avatars) {
    const Translator& t = avatar->translator();
    mpnet_windows.insert(mpnet_windows.end(), t.mpnet_window().begin(), t.mpnet_window().end());
    ugnet_windows.insert(ugnet_windows.end(), t.ugnet_window().begin(), t.ugnet_window().end());
  }
  std::vector<nn::MpnetOutput> progressions(people);
  std::vector<float> predictions(people * nn::kPoseSize);
  nn::BatchBuffers nets;
  const auto run_mpnet = [&] {
    mpnet.run_batch(mpnet_windows, progressions, nets);
    benchmark::DoNotOptimize(progressions.data());
  };
  const auto run_ugnet = [&] {
    ugnet.run_batch(ugnet_windows, {}, predictions, nets);
    benchmark::DoNotOptimize(predictions.data());
  };
  run_mpnet();
  run_ugnet();
  // Each network's seconds per batch, repeated as often as the tick was (at least ten times).
  const auto repeats = std::max<benchmark::IterationCount>(10, state.iterations() / 2);
  const auto seconds_of = [&](const auto& run) {
    const double start_of = thread_seconds();
    for (benchmark::IterationCount r = 0; r < repeats; ++r) {
      run();
    }
    return (thread_seconds() - start_of) / static_cast<double>(repeats);
  };
  const double mpnet_seconds = seconds_of(run_mpnet);
  const double ugnet_seconds = seconds_of(run_ugnet);
  const double net_seconds = mpnet_seconds + ugnet_seconds;

  const double n = static_cast<double>(people);
  state.counters["us_per_person"] = 1e6 * tick_seconds / n;
  state.counters["net_us_per_person"] = 1e6 * net_seconds / n;
  state.counters["mpnet_us"] = 1e6 * mpnet_seconds / n;
  state.counters["ugnet_us"] = 1e6 * ugnet_seconds / n;
  state.counters["net_share"] = net_seconds / tick_seconds;
}

// The product every batched layer is made of, at the size of UGNet MoE's first layer for 64
// people (64 × 264 inputs by the 264 × 1,296 outputs of its nine experts, in its panels of 48):
// the arithmetic rate the batched networks can reach (counter GFMA_per_s, of CPU time).
// UGNet's first expert layer for 64 people, through the build's kernels (0) or AVX-512's (1).
void BM_BatchProduct(benchmark::State& state) {
  constexpr int kRows = 64, kDepth = 264, kCols = 1296, kPanel = 48;
  const auto kernel = state.range(0) == 0 ? nn::ProductKernel::kBuild : nn::ProductKernel::kAvx512;
  if (!nn::product_kernel_available(kernel)) {
    state.SkipWithError("no AVX-512 kernels in this build or on this CPU (nn/batch.h)");
    return;
  }
  std::vector<float> a(kRows * kDepth), w(kDepth * kCols), c(kRows * kCols);
  for (std::size_t i = 0; i < a.size(); ++i) {
    a[i] = 0.001f * static_cast<float>(i % 97);
  }
  for (std::size_t i = 0; i < w.size(); ++i) {
    w[i] = 0.001f * static_cast<float>(i % 89);
  }
  for (auto _ : state) {
    for (int p = 0; p < kCols / kPanel; ++p) {
      nn::multiply_rows(kernel, a.data(), kDepth,
                        w.data() + static_cast<std::size_t>(p) * kDepth * kPanel, kPanel,
                        c.data() + p * kPanel, kCols, kRows, kDepth, kPanel);
    }
    benchmark::DoNotOptimize(c.data());
  }
  state.counters["GFMA_per_s"] = benchmark::Counter(1e-9 * kRows * kDepth * kCols,
                                                    benchmark::Counter::kIsIterationInvariantRate);
}

#if defined(__x86_64__) && defined(__AVX2__) && (defined(__GNUC__) || defined(__clang__))
// Divisions a second by 8-float (AVX2) and 16-float (AVX-512) vectors, eight independent chains:
// what bounds the GRU gates (Eigen's logistic and tanh divide once per value), and why they stay
// in the build's 8-float packets where 16-float ones divide no faster (decision 92).
void report_divisions(benchmark::State& state, int floats) {
  state.counters["G_divisions_per_s"] =
      benchmark::Counter(1e-9 * 64 * 8 * floats, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_GateDivisions_Avx2(benchmark::State& state) {
  __m256 c[8];
  const __m256 divisor = _mm256_set1_ps(1.0000001f);
  for (__m256& v : c) {
    v = _mm256_set1_ps(1.5f);
  }
  for (auto _ : state) {
    for (int k = 0; k < 64; ++k) {
      for (__m256& v : c) {
        v = _mm256_div_ps(v, divisor);
      }
    }
    benchmark::DoNotOptimize(c);
  }
  report_divisions(state, 8);
}

__attribute__((target("avx512f"))) void divide_in_16s(benchmark::State& state) {
  __m512 c[8];
  const __m512 divisor = _mm512_set1_ps(1.0000001f);
  for (__m512& v : c) {
    v = _mm512_set1_ps(1.5f);
  }
  for (auto _ : state) {
    for (int k = 0; k < 64; ++k) {
      for (__m512& v : c) {
        v = _mm512_div_ps(v, divisor);
      }
    }
    benchmark::DoNotOptimize(c);
  }
  report_divisions(state, 16);
}

void BM_GateDivisions_Avx512(benchmark::State& state) {
  if (!__builtin_cpu_supports("avx512f")) {
    state.SkipWithError("no AVX-512 on this CPU");
    return;
  }
  divide_in_16s(state);
}
#endif

}  // namespace

BENCHMARK(BM_BatchProduct)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
#if defined(__x86_64__) && defined(__AVX2__) && (defined(__GNUC__) || defined(__clang__))
BENCHMARK(BM_GateDivisions_Avx2);
BENCHMARK(BM_GateDivisions_Avx512);
#endif
BENCHMARK(BM_TranslatorTick)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RemoteAvatarTick)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PeopleTick)->Arg(1)->Arg(4)->Arg(16)->Arg(64)->Unit(benchmark::kMicrosecond);
