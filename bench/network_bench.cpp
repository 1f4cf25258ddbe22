// Every network of the paper, batch 1, one thread, on real windows from the authors' fixtures.
// The paper's goal for this code base: MPNet MoE + UGNet MoE ≤ 40 µs per tick on one core (the
// authors' PyTorch networks: 0.82 + 0.66 ms on the same machine; docs/conventions.md#goals).

#include <benchmark/benchmark.h>

#include <filesystem>
#include <vector>

#include "core/io/safetensors.h"
#include "gesture/nn/amnet.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"

namespace {

namespace fs = std::filesystem;
using namespace deixis;

fs::path reference_dir() {
  if (const char* env = std::getenv("DEIXIS_REFERENCE_DIR")) {
    return env;
  }
  return DEIXIS_REFERENCE_DIR;
}

// The first window of a fixture's `tensor`.
std::vector<float> fixture_window(const std::string& fixture, const std::string& tensor,
                                  std::size_t size) {
  const SafetensorsFile file = SafetensorsFile::read(reference_dir() / "fixtures" / fixture);
  std::vector<float> values = file.read_f32(tensor, file.shape_of(tensor));
  values.resize(size);
  return values;
}

void mpnet_bench(benchmark::State& state, const char* checkpoint, const char* fixture) {
  const nn::Mpnet net = nn::Mpnet::load(reference_dir() / "weights/right" / checkpoint);
  const std::vector<float> window = fixture_window(fixture, "input", nn::kMpnetWindowSize);
  for (auto _ : state) {
    nn::MpnetOutput out = net.run(nn::MpnetWindow(window.data(), nn::kMpnetWindowSize));
    benchmark::DoNotOptimize(out);
  }
}

void ugnet_bench(benchmark::State& state, const char* checkpoint, const char* fixture) {
  const nn::Ugnet net = nn::Ugnet::load(reference_dir() / "weights/right" / checkpoint);
  const std::vector<float> window = fixture_window(fixture, "input", nn::kUgnetWindowSize);
  std::vector<float> noise(nn::kDiffusionNoiseSize, 0.1f);
  for (auto _ : state) {
    nn::PoseVector out = net.run(nn::UgnetWindow(window.data(), nn::kUgnetWindowSize), noise);
    benchmark::DoNotOptimize(out);
  }
}

// A UGNet on 64 copies of a fixture window at once (Ugnet::run_batch, what deixis eval's chains
// use for the diffusion and Transformer variants); the time per iteration is for all 64, so
// divide by 64 for a window's share.
void ugnet_batch_of_64_bench(benchmark::State& state, const char* checkpoint, const char* fixture) {
  constexpr std::size_t kBatch = 64;
  const nn::Ugnet net = nn::Ugnet::load(reference_dir() / "weights/right" / checkpoint);
  const std::vector<float> window = fixture_window(fixture, "input", nn::kUgnetWindowSize);
  std::vector<float> windows, noise(net.needs_noise() ? kBatch * nn::kDiffusionNoiseSize : 0, 0.1f);
  for (std::size_t i = 0; i < kBatch; ++i) {
    windows.insert(windows.end(), window.begin(), window.end());
  }
  std::vector<float> out(kBatch * nn::kPoseSize);
  for (auto _ : state) {
    net.run_batch(windows, noise, out);
    benchmark::DoNotOptimize(out.data());
  }
}

// One translator tick's networks: MPNet MoE then UGNet MoE (the goal: ≤ 40 µs together).
void BM_MpnetMoePlusUgnetMoe(benchmark::State& state) {
  const fs::path w = reference_dir() / "weights/right";
  const nn::Mpnet mpnet = nn::Mpnet::load(w / "MPNet(MoE)(AC)80.safetensors");
  const nn::Ugnet ugnet = nn::Ugnet::load(w / "UGNet(MoE)(AC)120.safetensors");
  const std::vector<float> mpnet_window =
      fixture_window("MPNet_MoE_right.safetensors", "input", nn::kMpnetWindowSize);
  std::vector<float> ugnet_window =
      fixture_window("UGNet_MoE_right.safetensors", "input", nn::kUgnetWindowSize);
  for (auto _ : state) {
    const nn::MpnetOutput p = mpnet.run(nn::MpnetWindow(mpnet_window.data(), nn::kMpnetWindowSize));
    std::copy(p.progression.begin(), p.progression.end(), ugnet_window.end() - 3);
    nn::PoseVector x = ugnet.run(nn::UgnetWindow(ugnet_window.data(), nn::kUgnetWindowSize));
    benchmark::DoNotOptimize(x);
  }
}

void BM_Amnet(benchmark::State& state) {
  const nn::Amnet net =
      nn::Amnet::load(reference_dir() / "weights/right/ISMAR2023(Hard)629.safetensors");
  const std::vector<float> local =
      fixture_window("AMNet_ISMAR2023_right.safetensors", "local", nn::kAmnetWindowSize);
  const std::vector<float> remote =
      fixture_window("AMNet_ISMAR2023_right.safetensors", "remote", nn::kAmnetWindowSize);
  using Window = std::span<const float, nn::kAmnetWindowSize>;
  for (auto _ : state) {
    auto out = net.run(Window(local.data(), nn::kAmnetWindowSize),
                       Window(remote.data(), nn::kAmnetWindowSize));
    benchmark::DoNotOptimize(out);
  }
}

}  // namespace

BENCHMARK_CAPTURE(mpnet_bench, MPNet_GRU_MoE, "MPNet(MoE)(AC)80.safetensors",
                  "MPNet_MoE_right.safetensors")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(mpnet_bench, MPNet_MLP, "MPNet(MLP)(AC)80.safetensors",
                  "MPNet_MLP_right.safetensors")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(mpnet_bench, MPNet_Transformer, "MPNet(Transformer)(AC)80.safetensors",
                  "MPNet_Transformer_right.safetensors")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(ugnet_bench, UGNet_MoE, "UGNet(MoE)(AC)120.safetensors",
                  "UGNet_MoE_right.safetensors")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(ugnet_bench, UGNet_MLP, "UGNet(MLP)(AC)120.safetensors",
                  "UGNet_MLP_right.safetensors")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(ugnet_bench, UGNet_Transformer, "UGNet(Transformer)(AC)120.safetensors",
                  "UGNet_Transformer_right.safetensors")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(ugnet_bench, UGNet_Diffusion, "UGNet(Diffusion)(AC)120.safetensors",
                  "UGNet_Diffusion_right.safetensors")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(ugnet_batch_of_64_bench, UGNet_Diffusion_BatchOf64,
                  "UGNet(Diffusion)(AC)120.safetensors", "UGNet_Diffusion_right.safetensors")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(ugnet_batch_of_64_bench, UGNet_Transformer_BatchOf64,
                  "UGNet(Transformer)(AC)120.safetensors", "UGNet_Transformer_right.safetensors")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Amnet)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MpnetMoePlusUgnetMoe)->Unit(benchmark::kMicrosecond);
