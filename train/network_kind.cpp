#include "train/network_kind.h"

namespace deixis::train {

Family family_of(Network network) {
  switch (network) {
    case Network::kMpnetMoe:
    case Network::kMpnetMlp:
    case Network::kMpnetTransformer:
      return Family::kMpnet;
    case Network::kUgnetMoe:
    case Network::kUgnetMlp:
    case Network::kUgnetTransformer:
    case Network::kUgnetDiffusion:
      return Family::kUgnet;
    case Network::kMotionAutoencoder:
      return Family::kMotionAutoencoder;
  }
  return Family::kMpnet;
}

std::string_view network_name(Network network) {
  switch (network) {
    case Network::kMpnetMoe:
      return "MPNet(MoE)";
    case Network::kMpnetMlp:
      return "MPNet(MLP)";
    case Network::kMpnetTransformer:
      return "MPNet(Transformer)";
    case Network::kUgnetMoe:
      return "UGNet(MoE)";
    case Network::kUgnetMlp:
      return "UGNet(MLP)";
    case Network::kUgnetTransformer:
      return "UGNet(Transformer)";
    case Network::kUgnetDiffusion:
      return "UGNet(Diffusion)";
    case Network::kMotionAutoencoder:
      return "AutoEncoder";
  }
  return "?";
}

std::string_view variant_tag(Variant variant) {
  return variant == Variant::kDeicticOnly ? "DG" : "AC";
}

std::string_view hand_name(Hand hand) {
  return hand == Hand::kLeft ? "left" : "right";
}

std::string weights_stem(Network network, Variant variant) {
  std::string stem(network_name(network));
  if (family_of(network) != Family::kMotionAutoencoder) {
    stem += "(";
    stem += variant_tag(variant);
    stem += ")";
  }
  return stem;
}

std::optional<Network> parse_architecture(Family family, std::string_view name) {
  switch (family) {
    case Family::kMpnet:
      if (name == "moe")
        return Network::kMpnetMoe;
      if (name == "mlp")
        return Network::kMpnetMlp;
      if (name == "transformer")
        return Network::kMpnetTransformer;
      return std::nullopt;
    case Family::kUgnet:
      if (name == "moe")
        return Network::kUgnetMoe;
      if (name == "mlp")
        return Network::kUgnetMlp;
      if (name == "transformer")
        return Network::kUgnetTransformer;
      if (name == "diffusion")
        return Network::kUgnetDiffusion;
      return std::nullopt;
    case Family::kMotionAutoencoder:
      if (name == "conv")
        return Network::kMotionAutoencoder;
      return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace deixis::train
