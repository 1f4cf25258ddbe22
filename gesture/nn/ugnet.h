#pragma once
// UGNet, the Upper-body Gesture Network (paper §IV.B): a 30-row window of (end-effectors x,
// avatar target feature, progression) → the avatar's end-effectors x at the next tick. Only the
// newest row's x is read (docs/conventions.md#end-effectors). One class for the four architectures
// of paper Table IV, recognised from the checkpoint's tensor names.
//
// Like Mpnet, a Ugnet is a handle to shared read-only weights and run() is const, thread-safe,
// allocation-free and noexcept. The diffusion variant samples: its 30 Gaussian draws are supplied
// by the caller, so a run is exactly reproducible (docs/conventions.md#ugnet-diffusion); the other
// variants ignore them.

#include <filesystem>
#include <memory>
#include <string_view>

#include "core/io/safetensors.h"
#include "gesture/nn/batch.h"
#include "gesture/nn/shapes.h"

namespace deixis::nn {

enum class UgnetArchitecture { kMoe, kMlp, kTransformer, kDiffusion };
std::string_view architecture_name(UgnetArchitecture architecture);

// Intermediate values for parity tests; each architecture fills what it has.
struct UgnetTrace {
  std::array<float, 9> omega{};                                     // MoE gating softmax
  std::array<float, kDiffusionSteps * kPoseSize> denoised_steps{};  // diffusion x0 per step
};

class Ugnet {
 public:
  static Ugnet load(const SafetensorsFile& file);
  static Ugnet load(const std::filesystem::path& path);

  UgnetArchitecture architecture() const;
  bool needs_noise() const { return architecture() == UgnetArchitecture::kDiffusion; }
  // Whether run_batch() is faster than run() per window (its products batched).
  bool gains_from_batch() const {
    return needs_noise() || architecture() == UgnetArchitecture::kTransformer;
  }
  std::size_t parameter_count() const;

  // `noise` is read only by the diffusion variant: kDiffusionNoiseSize standard-normal draws
  // (shapes.h). Given fewer, it samples with all draws zero, which is deterministic.
  PoseVector run(UgnetWindow window, std::span<const float> noise = {},
                 UgnetTrace* trace = nullptr) const noexcept;

  // run() on `out.size() / kPoseSize` windows, for offline work over many sequences (deixis
  // eval): window i is windows[i·kUgnetWindowSize …], its draws noise[i·kDiffusionNoiseSize …]
  // (or none: `noise` empty), its prediction out[i·kPoseSize …]. The diffusion and Transformer
  // variants run the windows as one batch (matrix–matrix products; their results equal run()'s
  // up to float rounding), the others call run() per window. Unlike run(), it allocates; sizes
  // that do not fit together throw std::invalid_argument.
  void run_batch(std::span<const float> windows, std::span<const float> noise,
                 std::span<float> out) const;

  // The same for the runtime's batches, e.g. one window per remote person of a site
  // (presence::tick_people): the MoE runs them as one batch (batch.h; a window's result is
  // run()'s, bit for bit), the other architectures call run() per window. Allocates
  // nothing once `buffers` has held a batch this large (reserve_batch).
  void run_batch(std::span<const float> windows, std::span<const float> noise, std::span<float> out,
                 BatchBuffers& buffers) const;
  void reserve_batch(std::size_t count, BatchBuffers& buffers) const;

  // Whether both handles run the same loaded weights (a batch holds one network's windows).
  bool same_weights(const Ugnet& other) const { return networks_ == other.networks_; }

  struct Networks;  // the loaded weights of one architecture (ugnet.cpp)

 private:
  explicit Ugnet(std::shared_ptr<const Networks> networks) : networks_(std::move(networks)) {}
  std::shared_ptr<const Networks> networks_;
};

}  // namespace deixis::nn
