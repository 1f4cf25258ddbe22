#include "gesture/nn/mpnet.h"

#include <variant>

#include "core/error.h"
#include "gesture/nn/mpnet_architectures.h"

namespace deixis::nn {

struct Mpnet::Networks {
  std::variant<MpnetGruMoe, MpnetMlp, MpnetTransformer> net;
};

std::string_view architecture_name(MpnetArchitecture architecture) {
  switch (architecture) {
    case MpnetArchitecture::kGruMoe:
      return "GRU-MoE";
    case MpnetArchitecture::kMlp:
      return "MLP";
    case MpnetArchitecture::kTransformer:
      return "Transformer";
  }
  return "?";
}

namespace {

template <typename Net>
std::shared_ptr<Mpnet::Networks> load_as(const SafetensorsFile& file) {
  auto networks = std::make_shared<Mpnet::Networks>();
  networks->net.emplace<Net>().load(file);
  return networks;
}

}  // namespace

Mpnet Mpnet::load(const SafetensorsFile& file) {
  if (MpnetGruMoe::recognises(file)) {
    return Mpnet(load_as<MpnetGruMoe>(file));
  }
  if (MpnetMlp::recognises(file)) {
    return Mpnet(load_as<MpnetMlp>(file));
  }
  if (MpnetTransformer::recognises(file)) {
    return Mpnet(load_as<MpnetTransformer>(file));
  }
  throw Error(
      file.source() +
      ": not an MPNet checkpoint (expected the tensors of the GRU-MoE "
      "'gating_network.gru.*', 'gru.*', 'moe_network.*'; the MLP 'linear1.weight' [24, 330]; "
      "or the Transformer 'linear_input.*', 'transformer.layers.*')");
}

Mpnet Mpnet::load(const std::filesystem::path& path) {
  return load(SafetensorsFile::read(path));
}

MpnetArchitecture Mpnet::architecture() const {
  return static_cast<MpnetArchitecture>(networks_->net.index());
}

std::size_t Mpnet::parameter_count() const {
  return std::visit([](const auto& net) { return net.kParameters; }, networks_->net);
}

MpnetOutput Mpnet::run(MpnetWindow window, MpnetTrace* trace) const noexcept {
  return std::visit(
      [&](const auto& net) {
        if constexpr (std::is_same_v<std::decay_t<decltype(net)>, MpnetGruMoe>) {
          return net.run(window, trace);
        } else {
          return net.run(window);
        }
      },
      networks_->net);
}

}  // namespace deixis::nn
