// What the C API's boundary costs (docs/embedding.md): the same remote person's tick through
// libdeixis.so (deixis_translator_tick: the C structs converted in and out, errors guarded) and
// through presence::RemoteAvatar in-tree, on the same recording (examples/data/pointing.csv,
// looped) with the same avatar and room. Goal: the boundary adds under 1 µs a tick.
//
// BM_CApiBoundary: both ticks alternating in one loop, each timed on this thread's CPU clock,
// so that the load of a shared machine falls on both alike; counters capi_us, in_tree_us and
// boundary_us (their difference) per tick.
//
// BM_CApiMpnetRun/B and BM_CApiUgnetRun/B: the networks through the C API on B windows, the
// figures bench/python_overhead.py subtracts from the Python module's per-call time.
#include <benchmark/benchmark.h>

#include <ctime>
#include <memory>
#include <vector>

#include "api/tracking_csv.h"
#include "avatar/avatar_loader.h"
#include "deixis/deixis.h"
#include "gesture/upright_calibration.h"
#include "presence/remote_avatar.h"

namespace {

using namespace deixis;

const std::filesystem::path kExamples = std::filesystem::path(DEIXIS_SOURCE_DIR) / "examples";

std::vector<deixis_tracking_frame> recording() {
  return testing::read_tracking_csv(kExamples / "data/pointing.csv");
}

// The examples' person through the C API: every handle, made once.
struct CApiPerson {
  deixis_mpnet* mpnet = nullptr;
  deixis_ugnet* ugnet = nullptr;
  deixis_avatar* avatar = nullptr;
  deixis_room* room = nullptr;
  deixis_translator* translator = nullptr;

  explicit CApiPerson(const deixis_tracking_frame& upright) {
    const std::string map = (kExamples / "data/room.json").string();
    deixis_translator_config config;
    deixis_translator_config_init(&config);
    deixis_upright_body body;
    deixis_upright_body_init(&body);
    deixis_mpnet_load(DEIXIS_ABI_VERSION, nullptr, &mpnet, nullptr);
    deixis_ugnet_load(DEIXIS_ABI_VERSION, nullptr, &ugnet, nullptr);
    deixis_avatar_load(DEIXIS_ABI_VERSION, nullptr, &avatar, nullptr);
    deixis_room_create(DEIXIS_ABI_VERSION, map.c_str(), &room, nullptr);
    deixis_calibrate_upright(&upright, &body, &config.person, nullptr);
    config.avatar_floor.position = {0.3f, 0.0f, -1.0f};
    deixis_translator_create(DEIXIS_ABI_VERSION, mpnet, ugnet, avatar, &config, &translator,
                             nullptr);
  }
  ~CApiPerson() {
    deixis_translator_destroy(translator);
    deixis_room_destroy(room);
    deixis_avatar_destroy(avatar);
    deixis_ugnet_destroy(ugnet);
    deixis_mpnet_destroy(mpnet);
  }
  CApiPerson(const CApiPerson&) = delete;
  CApiPerson& operator=(const CApiPerson&) = delete;
};

// The same person in-tree: presence::RemoteAvatar as the examples configure the translator.
struct InTreePerson {
  ik::AvatarSolver solver;
  TargetMap room;
  std::unique_ptr<presence::RemoteAvatar> remote;

  explicit InTreePerson(const TrackingFrame& upright) {
    const std::filesystem::path assets = std::filesystem::path(DEIXIS_SOURCE_DIR) / "assets";
    solver = ik::AvatarSolver::build(avatar::load_avatar(assets / "avatars/default.glb").rig);
    presence::RemoteAvatarConfig config;
    config.user = calibrate_upright(upright, UprightBody{});
    config.T_world_floor.translation = Vec3(0.3f, 0.0f, -1.0f);
    const auto w = assets / "weights/right";
    remote = std::make_unique<presence::RemoteAvatar>(
        nn::Mpnet::load(w / "MPNet(MoE)(AC)80.safetensors"),
        nn::Ugnet::load(w / "UGNet(MoE)(AC)120.safetensors"), solver, config);
    room = read_target_map(kExamples / "data/room.json");
  }
  // What an in-tree caller does each tick: build the targets view, tick, read the fingertip.
  Vec3 tick(const TrackingFrame& frame) {
    const LocalTargets targets{&room, Vec3::Zero()};
    remote->tick(&frame, targets);
    return remote->index_fingertip();
  }
};

double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void BM_CApiBoundary(benchmark::State& state) {
  const auto c_frames = recording();
  std::vector<TrackingFrame> frames;
  for (const deixis_tracking_frame& c : c_frames) {
    frames.push_back(testing::runtime_frame(c));
  }
  CApiPerson capi(c_frames[0]);
  InTreePerson in_tree(frames[0]);
  deixis_avatar_frame out{};
  double capi_seconds = 0.0, in_tree_seconds = 0.0;
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i % frames.size();
    // Which goes first alternates: the second of two ticks finds the caches as the first left
    // them.
    const bool capi_first = i % 2 == 0;
    const double t0 = thread_seconds();
    if (capi_first) {
      deixis_translator_tick(capi.translator, &c_frames[k], capi.room, &out);
    } else {
      benchmark::DoNotOptimize(in_tree.tick(frames[k]));
    }
    const double t1 = thread_seconds();
    if (capi_first) {
      benchmark::DoNotOptimize(in_tree.tick(frames[k]));
    } else {
      deixis_translator_tick(capi.translator, &c_frames[k], capi.room, &out);
    }
    const double t2 = thread_seconds();
    capi_seconds += capi_first ? t1 - t0 : t2 - t1;
    in_tree_seconds += capi_first ? t2 - t1 : t1 - t0;
    ++i;
    benchmark::DoNotOptimize(out.fingertip.x);
  }
  const auto ticks = static_cast<double>(state.iterations());
  state.counters["capi_us"] = 1e6 * capi_seconds / ticks;
  state.counters["in_tree_us"] = 1e6 * in_tree_seconds / ticks;
  state.counters["boundary_us"] = 1e6 * (capi_seconds - in_tree_seconds) / ticks;
}

void BM_TickThroughCApi(benchmark::State& state) {
  const auto frames = recording();
  CApiPerson capi(frames[0]);
  deixis_avatar_frame out{};
  std::size_t i = 0;
  for (auto _ : state) {
    deixis_translator_tick(capi.translator, &frames[i++ % frames.size()], capi.room, &out);
    benchmark::DoNotOptimize(out.fingertip.x);
  }
}

void BM_TickInTree(benchmark::State& state) {
  std::vector<TrackingFrame> frames;
  for (const deixis_tracking_frame& c : recording()) {
    frames.push_back(testing::runtime_frame(c));
  }
  InTreePerson in_tree(frames[0]);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(in_tree.tick(frames[i++ % frames.size()]));
  }
}

template <bool kMpnet>
void BM_CApiNetworkRun(benchmark::State& state) {
  const auto batch = static_cast<std::size_t>(state.range(0));
  deixis_mpnet* mpnet = nullptr;
  deixis_ugnet* ugnet = nullptr;
  deixis_mpnet_load(DEIXIS_ABI_VERSION, nullptr, &mpnet, nullptr);
  deixis_ugnet_load(DEIXIS_ABI_VERSION, nullptr, &ugnet, nullptr);
  const std::size_t columns = kMpnet ? DEIXIS_MPNET_FEATURES : DEIXIS_UGNET_COLUMNS;
  std::vector<float> windows(batch * DEIXIS_WINDOW_ROWS * columns, 0.1f);
  std::vector<float> out(batch * DEIXIS_POSE_SIZE);
  for (auto _ : state) {
    if constexpr (kMpnet) {
      deixis_mpnet_run(mpnet, windows.data(), batch, out.data());
    } else {
      deixis_ugnet_run(ugnet, windows.data(), nullptr, batch, out.data());
    }
    benchmark::DoNotOptimize(out.data());
  }
  deixis_ugnet_destroy(ugnet);
  deixis_mpnet_destroy(mpnet);
}

BENCHMARK(BM_CApiBoundary)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TickThroughCApi)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TickInTree)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_CApiNetworkRun, true)
    ->Name("BM_CApiMpnetRun")
    ->Arg(1)
    ->Arg(64)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_CApiNetworkRun, false)
    ->Name("BM_CApiUgnetRun")
    ->Arg(1)
    ->Arg(64)
    ->Unit(benchmark::kMicrosecond);

}  // namespace
