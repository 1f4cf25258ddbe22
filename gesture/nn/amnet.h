#pragma once
// AMNet (AngleNet + MotionNet, Kang et al., ISMAR 2023), the paper's state-of-the-art baseline
// (Table I), from the authors' checkpoint `ISMAR2023(Hard)629` (docs/conventions.md#amnet). It maps
// paired windows of the user ("local") and the avatar ("remote"), 20 rows × 16 (12 angle features,
// target θ, φ, r, scale), directly to the avatar's 21 end-effectors: head forward, up, position;
// hand forward, up, position (root frame); fingertip (hand frame).
//
//   ω_local, ω_remote = softmax(GRU2(target)) at every row (6 experts)
//   z = GRU2(Enc(local angles; ω_local) + Enc(remote angles; ω_remote)), last row
//   y = Dec(z ++ scale of the newest remote row; ω_remote of the newest row)
// Enc and Dec are 2-layer expert MLPs with BatchNorm (running statistics) and ELU after layer 1.

#include <array>
#include <filesystem>
#include <memory>
#include <span>

#include "core/io/safetensors.h"

namespace deixis::nn {

inline constexpr int kAmnetWindowRows = 20;
inline constexpr int kAmnetColumns = 16;
inline constexpr int kAmnetWindowSize = kAmnetWindowRows * kAmnetColumns;
inline constexpr int kAmnetOutputSize = 21;

class Amnet {
 public:
  static Amnet load(const SafetensorsFile& file);
  static Amnet load(const std::filesystem::path& path);

  std::array<float, kAmnetOutputSize> run(
      std::span<const float, kAmnetWindowSize> local,
      std::span<const float, kAmnetWindowSize> remote) const noexcept;

  struct Network;  // the loaded weights (amnet.cpp)

 private:
  explicit Amnet(std::shared_ptr<const Network> network) : network_(std::move(network)) {}
  std::shared_ptr<const Network> network_;
};

}  // namespace deixis::nn
