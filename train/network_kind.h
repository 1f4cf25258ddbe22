#pragma once
// Which network a training run fits. The paper's two networks and the alternatives of its
// Tables II–IV (docs/conventions.md#mpnet, #ugnet), plus the convolutional autoencoder whose
// latent codes define FMD (docs/eval.md#what-each-number-is). Names follow the authors' checkpoint
// files: "MPNet(MoE)", "UGNet(Diffusion)".

#include <optional>
#include <string>
#include <string_view>

#include "core/tracking.h"

namespace deixis::train {

enum class Family { kMpnet, kUgnet, kMotionAutoencoder };

enum class Network {
  kMpnetMoe,
  kMpnetMlp,
  kMpnetTransformer,
  kUgnetMoe,
  kUgnetMlp,
  kUgnetTransformer,
  kUgnetDiffusion,
  kMotionAutoencoder,
};

// Training data: all ten categories (AC) or the deictic-gesture categories only (DG, paper
// Table I "Ours_DG"; which categories count is docs/decisions.md).
enum class Variant { kAllCategories, kDeicticOnly };

using deixis::Hand;  // core/tracking.h

Family family_of(Network network);
std::string_view network_name(Network network);  // "MPNet(MoE)"
std::string_view variant_tag(Variant variant);   // "AC" / "DG"
std::string_view hand_name(Hand hand);           // "right" / "left"

// "MPNet(MoE)(AC)": the stem of the exported weights and manifest. The autoencoder has no
// variant: "AutoEncoder".
std::string weights_stem(Network network, Variant variant);

// The architecture names accepted on the command line ("moe", "mlp", "transformer",
// "diffusion"); nullopt for a name that family does not have.
std::optional<Network> parse_architecture(Family family, std::string_view name);

}  // namespace deixis::train
