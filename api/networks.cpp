// MPNet and UGNet through the C API: load any architecture, run windows one by one.
#include <span>

#include "api/boundary.h"
#include "api/data_dir.h"
#include "api/handles.h"

using namespace deixis;
using namespace deixis::api;

namespace {

// The shipped MoE weights: the right hand's serve left-handed people too, mirrored
// (docs/decisions.md 68).
std::filesystem::path weights_or_default(const char* path, const char* file_name) {
  if (path != nullptr) {
    return path;
  }
  return data_dir() / "weights" / "right" / file_name;
}

}  // namespace

extern "C" {

deixis_status deixis_mpnet_load(uint32_t abi_version, const char* path, deixis_mpnet** out,
                                deixis_error* error) {
  return create_guarded(error, DEIXIS_ERROR_FILE, [&] {
    check_abi(abi_version);
    require(out != nullptr, "deixis_mpnet_load: out is null");
    *out = nullptr;
    *out =
        new deixis_mpnet{nn::Mpnet::load(weights_or_default(path, "MPNet(MoE)(AC)80.safetensors"))};
  });
}

deixis_status deixis_ugnet_load(uint32_t abi_version, const char* path, deixis_ugnet** out,
                                deixis_error* error) {
  return create_guarded(error, DEIXIS_ERROR_FILE, [&] {
    check_abi(abi_version);
    require(out != nullptr, "deixis_ugnet_load: out is null");
    *out = nullptr;
    *out = new deixis_ugnet{
        nn::Ugnet::load(weights_or_default(path, "UGNet(MoE)(AC)120.safetensors"))};
  });
}

void deixis_mpnet_destroy(deixis_mpnet* mpnet) {
  delete mpnet;
}

void deixis_ugnet_destroy(deixis_ugnet* ugnet) {
  delete ugnet;
}

const char* deixis_mpnet_architecture(const deixis_mpnet* mpnet) {
  return mpnet == nullptr ? "" : nn::architecture_name(mpnet->network.architecture()).data();
}

const char* deixis_ugnet_architecture(const deixis_ugnet* ugnet) {
  return ugnet == nullptr ? "" : nn::architecture_name(ugnet->network.architecture()).data();
}

int deixis_ugnet_needs_noise(const deixis_ugnet* ugnet) {
  return ugnet != nullptr && ugnet->network.needs_noise() ? 1 : 0;
}

deixis_status deixis_mpnet_run(const deixis_mpnet* mpnet, const float* windows, size_t count,
                               float* out) {
  if (mpnet == nullptr || ((windows == nullptr || out == nullptr) && count > 0)) {
    return DEIXIS_ERROR_INVALID_ARGUMENT;
  }
  for (size_t i = 0; i < count; ++i) {
    const nn::MpnetWindow window(windows + i * nn::kMpnetWindowSize, nn::kMpnetWindowSize);
    const nn::Progression p = mpnet->network.run(window).progression;
    std::copy(p.begin(), p.end(), out + i * nn::kProgressionSize);
  }
  return DEIXIS_OK;
}

deixis_status deixis_ugnet_run(const deixis_ugnet* ugnet, const float* windows, const float* noise,
                               size_t count, float* out) {
  if (ugnet == nullptr || ((windows == nullptr || out == nullptr) && count > 0)) {
    return DEIXIS_ERROR_INVALID_ARGUMENT;
  }
  for (size_t i = 0; i < count; ++i) {
    const nn::UgnetWindow window(windows + i * nn::kUgnetWindowSize, nn::kUgnetWindowSize);
    std::span<const float> draws;
    if (noise != nullptr) {
      draws = {noise + i * nn::kDiffusionNoiseSize, nn::kDiffusionNoiseSize};
    }
    const nn::PoseVector x = ugnet->network.run(window, draws);
    std::copy(x.begin(), x.end(), out + i * nn::kPoseSize);
  }
  return DEIXIS_OK;
}

}  // extern "C"
