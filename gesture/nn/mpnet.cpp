#include "gesture/nn/mpnet.h"

#include <stdexcept>
#include <string>
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

void Mpnet::run_batch(std::span<const float> windows, std::span<MpnetOutput> out,
                      BatchBuffers& buffers) const {
  if (windows.size() != out.size() * kMpnetWindowSize) {
    throw std::invalid_argument("Mpnet::run_batch: " + std::to_string(windows.size()) +
                                " window values for " + std::to_string(out.size()) +
                                " outputs (windows of " + std::to_string(kMpnetWindowSize) + ")");
  }
  if (const auto* moe = std::get_if<MpnetGruMoe>(&networks_->net)) {
    moe->run_batch(windows.data(), static_cast<int>(out.size()), out.data(), buffers);
    return;
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = run(MpnetWindow(windows.subspan(i * kMpnetWindowSize, kMpnetWindowSize)));
  }
}

void Mpnet::reserve_batch(std::size_t count, BatchBuffers& buffers) const {
  if (std::holds_alternative<MpnetGruMoe>(networks_->net)) {
    MpnetGruMoe::reserve_batch(static_cast<int>(count), buffers);
  }
}

}  // namespace deixis::nn
