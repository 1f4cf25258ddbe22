// The networks' hot path allocates nothing: after warm-up, 1,000 ticks of MPNet + UGNet (every
// architecture) make zero heap allocations.

#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <vector>

#include "allocation_counter.h"
#include "gesture/nn/amnet.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "test_support.h"

namespace deixis {
namespace {

namespace fs = std::filesystem;
constexpr int kWarmUp = 10;
constexpr int kTicks = 1000;

std::vector<float> random_values(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> v(n);
  for (float& x : v) {
    x = u(rng);
  }
  return v;
}

TEST(AllocationCounter, SeesAllocations) {
  // Positive control: without it, a broken counter would make every zero below meaningless.
  // The calls go through volatile pointers and an opaque asm so the compiler cannot elide them.
  testing::AllocationCounter counter;
  void* (*volatile allocate)(std::size_t) = std::malloc;
  void* p = allocate(64);
  std::free(p);
  std::vector<int> v(100);
  asm volatile("" : : "g"(v.data()) : "memory");
  EXPECT_EQ(counter.count(), 2u);
}

TEST(HotPath, MpnetAndUgnetTicksAllocateNothing) {
  const fs::path w = testing::reference_dir() / "weights/right";
  const nn::Mpnet mpnet = nn::Mpnet::load(w / "MPNet(MoE)(AC)80.safetensors");
  const nn::Ugnet ugnet = nn::Ugnet::load(w / "UGNet(MoE)(AC)120.safetensors");
  const std::vector<float> mpnet_window = random_values(nn::kMpnetWindowSize, 1);
  std::vector<float> ugnet_window = random_values(nn::kUgnetWindowSize, 2);
  float sink = 0.0f;
  const auto tick = [&] {
    const nn::MpnetOutput p = mpnet.run(nn::MpnetWindow(mpnet_window.data(), nn::kMpnetWindowSize));
    ugnet_window[nn::kUgnetWindowSize - 1] = p.progression[2];
    const nn::PoseVector x = ugnet.run(nn::UgnetWindow(ugnet_window.data(), nn::kUgnetWindowSize));
    sink += x[0];
  };
  for (int i = 0; i < kWarmUp; ++i) {
    tick();
  }
  testing::AllocationCounter counter;
  for (int i = 0; i < kTicks; ++i) {
    tick();
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_TRUE(std::isfinite(sink));
}

TEST(HotPath, EveryAlternativeArchitectureAllocatesNothing) {
  const fs::path w = testing::reference_dir() / "weights/left";
  const std::vector<nn::Mpnet> mpnets = {
      nn::Mpnet::load(w / "MPNet(MLP)(AC)80.safetensors"),
      nn::Mpnet::load(w / "MPNet(Transformer)(AC)80.safetensors")};
  const std::vector<nn::Ugnet> ugnets = {
      nn::Ugnet::load(w / "UGNet(MLP)(AC)120.safetensors"),
      nn::Ugnet::load(w / "UGNet(Transformer)(AC)120.safetensors"),
      nn::Ugnet::load(w / "UGNet(Diffusion)(AC)120.safetensors")};
  const nn::Amnet amnet = nn::Amnet::load(w / "ISMAR2023(Hard)629.safetensors");
  const std::vector<float> mpnet_window = random_values(nn::kMpnetWindowSize, 3);
  const std::vector<float> ugnet_window = random_values(nn::kUgnetWindowSize, 4);
  const std::vector<float> noise = random_values(nn::kDiffusionNoiseSize, 5);
  const std::vector<float> amnet_window = random_values(nn::kAmnetWindowSize, 6);
  using AmnetWindow = std::span<const float, nn::kAmnetWindowSize>;
  float sink = 0.0f;
  const auto tick = [&] {
    for (const nn::Mpnet& m : mpnets) {
      sink += m.run(nn::MpnetWindow(mpnet_window.data(), nn::kMpnetWindowSize)).progression[0];
    }
    for (const nn::Ugnet& u : ugnets) {
      sink += u.run(nn::UgnetWindow(ugnet_window.data(), nn::kUgnetWindowSize), noise)[0];
    }
    sink += amnet.run(AmnetWindow(amnet_window.data(), nn::kAmnetWindowSize),
                      AmnetWindow(amnet_window.data(), nn::kAmnetWindowSize))[0];
  };
  for (int i = 0; i < kWarmUp; ++i) {
    tick();
  }
  testing::AllocationCounter counter;
  // The Transformer and Diffusion variants cost ~1 ms each, so fewer ticks keep the suite fast;
  // an allocation would show on the first one.
  for (int i = 0; i < 100; ++i) {
    tick();
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_TRUE(std::isfinite(sink));
}

}  // namespace
}  // namespace deixis
