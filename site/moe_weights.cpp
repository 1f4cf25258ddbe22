#include "site/moe_weights.h"

#include "core/error.h"

namespace deixis::site {

MoeNetworks load_moe_networks(const std::filesystem::path& weights_dir, Hand hand) {
  const std::filesystem::path dir = weights_dir / (hand == Hand::kLeft ? "left" : "right");
  for (const char* name : {"MPNet(MoE)(AC)80.safetensors", "UGNet(MoE)(AC)120.safetensors"}) {
    if (!std::filesystem::is_regular_file(dir / name)) {
      throw Error((dir / name).string() +
                  ": no such weights file (--weights-dir, or set DEIXIS_REFERENCE_DIR)");
    }
  }
  return {nn::Mpnet::load(dir / "MPNet(MoE)(AC)80.safetensors"),
          nn::Ugnet::load(dir / "UGNet(MoE)(AC)120.safetensors")};
}

}  // namespace deixis::site
