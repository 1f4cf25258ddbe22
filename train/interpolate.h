#pragma once
// Weight-space interpolation of two weight files of one network: (1 − α)·a + α·b, tensor by
// tensor. Blending a fine-tuned network with the weights it started from keeps most of what the
// fine-tuning gained on its new data and most of what the start did on the old (WiSE-FT,
// Wortsman et al., CVPR 2022); docs/training.md "Fine-tuning", docs/decisions.md 89.

#include <filesystem>

#include "core/io/safetensors.h"

namespace deixis::train {

// Throws deixis::Error naming the file and tensor when the two hold different tensors (count,
// names, dtype F32 only, shapes) or a non-finite value (SafetensorsFile::read_f32's checks), and
// when alpha is outside [0, 1]. The result
// keeps b's metadata and adds `interpolation_alpha`.
SafetensorsWriter interpolate_weights(const SafetensorsFile& a, const SafetensorsFile& b,
                                      double alpha);

// interpolate_weights of the files `a` and `b` written to `out`, with a manifest beside it
// (<out stem>.manifest.json): b's manifest if b has one beside it, its `weights` renamed, plus
// `interpolation`: alpha and both files with their SHA-256.
void write_interpolation(const std::filesystem::path& a, const std::filesystem::path& b,
                         double alpha, const std::filesystem::path& out);

}  // namespace deixis::train
