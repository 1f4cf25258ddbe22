#include "gesture/nn/ugnet.h"

#include <stdexcept>
#include <string>
#include <variant>

#include "core/error.h"
#include "gesture/nn/ugnet_architectures.h"

namespace deixis::nn {

struct Ugnet::Networks {
  std::variant<UgnetMoe, UgnetMlp, UgnetTransformer, UgnetDiffusion> net;
};

std::string_view architecture_name(UgnetArchitecture architecture) {
  switch (architecture) {
    case UgnetArchitecture::kMoe:
      return "MoE";
    case UgnetArchitecture::kMlp:
      return "MLP";
    case UgnetArchitecture::kTransformer:
      return "Transformer";
    case UgnetArchitecture::kDiffusion:
      return "Diffusion";
  }
  return "?";
}

namespace {

template <typename Net>
std::shared_ptr<Ugnet::Networks> load_as(const SafetensorsFile& file) {
  auto networks = std::make_shared<Ugnet::Networks>();
  networks->net.emplace<Net>().load(file);
  return networks;
}

}  // namespace

Ugnet Ugnet::load(const SafetensorsFile& file) {
  if (UgnetMoe::recognises(file)) {
    return Ugnet(load_as<UgnetMoe>(file));
  }
  if (UgnetMlp::recognises(file)) {
    return Ugnet(load_as<UgnetMlp>(file));
  }
  if (UgnetTransformer::recognises(file)) {
    return Ugnet(load_as<UgnetTransformer>(file));
  }
  if (UgnetDiffusion::recognises(file)) {
    return Ugnet(load_as<UgnetDiffusion>(file));
  }
  throw Error(file.source() +
              ": not a UGNet checkpoint (expected the tensors of the MoE 'gating_network.gru.*', "
              "'moe_network.*'; the MLP 'linear1.weight' [1056, 264]; the Transformer "
              "'linear_input_pose.*', 'transformer.layers.*'; or the Diffusion 'model.fin.*', "
              "'time_mlp.*', 'sigma')");
}

Ugnet Ugnet::load(const std::filesystem::path& path) {
  return load(SafetensorsFile::read(path));
}

UgnetArchitecture Ugnet::architecture() const {
  return static_cast<UgnetArchitecture>(networks_->net.index());
}

std::size_t Ugnet::parameter_count() const {
  return std::visit([](const auto& net) { return net.kParameters; }, networks_->net);
}

PoseVector Ugnet::run(UgnetWindow window, std::span<const float> noise,
                      UgnetTrace* trace) const noexcept {
  return std::visit(
      [&](const auto& net) {
        using Net = std::decay_t<decltype(net)>;
        if constexpr (std::is_same_v<Net, UgnetMoe>) {
          return net.run(window, trace);
        } else if constexpr (std::is_same_v<Net, UgnetDiffusion>) {
          return net.run(window, noise, trace);
        } else {
          return net.run(window);
        }
      },
      networks_->net);
}

namespace {

void check_batch_sizes(std::span<const float> windows, std::span<const float> noise,
                       std::span<float> out) {
  const std::size_t count = out.size() / kPoseSize;
  if (out.size() % kPoseSize != 0 || windows.size() != count * kUgnetWindowSize ||
      (!noise.empty() && noise.size() != count * kDiffusionNoiseSize)) {
    throw std::invalid_argument("Ugnet::run_batch: " + std::to_string(windows.size()) +
                                " window values, " + std::to_string(noise.size()) + " draws and " +
                                std::to_string(out.size()) + " outputs are not whole windows (" +
                                std::to_string(kUgnetWindowSize) + "), draws (" +
                                std::to_string(kDiffusionNoiseSize) + " or none) and poses (" +
                                std::to_string(kPoseSize) + ") of one count");
  }
}

}  // namespace

void Ugnet::run_batch(std::span<const float> windows, std::span<const float> noise,
                      std::span<float> out) const {
  check_batch_sizes(windows, noise, out);
  const std::size_t count = out.size() / kPoseSize;
  if (const auto* diffusion = std::get_if<UgnetDiffusion>(&networks_->net)) {
    diffusion->run_batch(windows, noise, out);
    return;
  }
  if (const auto* transformer = std::get_if<UgnetTransformer>(&networks_->net)) {
    transformer->run_batch(windows, out);
    return;
  }
  for (std::size_t i = 0; i < count; ++i) {
    const PoseVector x = run(UgnetWindow(windows.subspan(i * kUgnetWindowSize, kUgnetWindowSize)));
    std::copy(x.begin(), x.end(), out.begin() + static_cast<std::ptrdiff_t>(i * kPoseSize));
  }
}

void Ugnet::run_batch(std::span<const float> windows, std::span<const float> noise,
                      std::span<float> out, BatchBuffers& buffers) const {
  check_batch_sizes(windows, noise, out);
  const std::size_t count = out.size() / kPoseSize;
  if (const auto* moe = std::get_if<UgnetMoe>(&networks_->net)) {
    moe->run_batch(windows.data(), static_cast<int>(count), out.data(), buffers);
    return;
  }
  for (std::size_t i = 0; i < count; ++i) {
    const PoseVector x =
        run(UgnetWindow(windows.subspan(i * kUgnetWindowSize, kUgnetWindowSize)),
            noise.empty() ? noise : noise.subspan(i * kDiffusionNoiseSize, kDiffusionNoiseSize));
    std::copy(x.begin(), x.end(), out.begin() + static_cast<std::ptrdiff_t>(i * kPoseSize));
  }
}

void Ugnet::reserve_batch(std::size_t count, BatchBuffers& buffers) const {
  if (std::holds_alternative<UgnetMoe>(networks_->net)) {
    UgnetMoe::reserve_batch(static_cast<int>(count), buffers);
  }
}

}  // namespace deixis::nn
