#pragma once
// MPNet, the Motion Progression Network (paper §IV.A): a 30-row window of the user's 11 features
// → progression (gaze, deictic, idle) in [0, 1]. One class for the three architectures the paper
// compares (Table III); the architecture is recognised from the checkpoint's tensor names.
//
// An Mpnet is a handle to read-only weights: copies share them, so every remote person can use the
// same loaded network. run() is const, thread-safe, allocation-free and noexcept; the networks keep
// no state between calls (the GRUs restart from zero on every window, docs/conventions.md#grus), so
// all per-person state is the input window the caller keeps.

#include <filesystem>
#include <memory>
#include <string_view>

#include "core/io/safetensors.h"
#include "gesture/nn/batch.h"
#include "gesture/nn/shapes.h"

namespace deixis::nn {

enum class MpnetArchitecture { kGruMoe, kMlp, kTransformer };
std::string_view architecture_name(MpnetArchitecture architecture);

struct MpnetOutput {
  Progression progression{};  // clamped to [0, 1]
  Progression preclamp{};     // the last layer's output before the clamp
};

// Intermediate values of the GRU-MoE, for parity tests; other architectures leave it untouched.
struct MpnetTrace {
  std::array<float, 9> omega{};  // gating softmax
  std::array<float, 24> z{};     // recurrent GRU's last output
};

class Mpnet {
 public:
  static Mpnet load(const SafetensorsFile& file);
  static Mpnet load(const std::filesystem::path& path);

  MpnetArchitecture architecture() const;
  std::size_t parameter_count() const;

  MpnetOutput run(MpnetWindow window, MpnetTrace* trace = nullptr) const noexcept;

  // run() on `out.size()` windows at once, e.g. one per remote person of a site
  // (presence::tick_people): window i is windows[i·kMpnetWindowSize …]. The GRU-MoE runs them as
  // one batch (batch.h; a window's result is run()'s, bit for bit); the MLP and
  // Transformer call run() per window. Allocates nothing once `buffers` has held a batch this
  // large (reserve_batch). Sizes that do not fit together throw std::invalid_argument.
  void run_batch(std::span<const float> windows, std::span<MpnetOutput> out,
                 BatchBuffers& buffers) const;
  void reserve_batch(std::size_t count, BatchBuffers& buffers) const;

  // Whether both handles run the same loaded weights (a batch holds one network's windows).
  bool same_weights(const Mpnet& other) const { return networks_ == other.networks_; }

  struct Networks;  // the loaded weights of one architecture (mpnet.cpp)

 private:
  explicit Mpnet(std::shared_ptr<const Networks> networks) : networks_(std::move(networks)) {}
  std::shared_ptr<const Networks> networks_;
};

}  // namespace deixis::nn
