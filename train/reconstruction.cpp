#include "train/reconstruction.h"

#include <algorithm>
#include <cmath>

namespace deixis::train {
namespace {

constexpr double kPi = 3.14159265358979323846;

// [N, 30, 6] forward ++ up → their orthonormal frames' three axes, [N, 30, 3, 3].
torch::Tensor frames_of(const torch::Tensor& six_d) {
  const torch::Tensor forward = torch::nn::functional::normalize(
      six_d.slice(-1, 0, 3), torch::nn::functional::NormalizeFuncOptions().dim(-1));
  torch::Tensor up = six_d.slice(-1, 3, 6);
  up = up - (up * forward).sum(-1, true) * forward;
  up = torch::nn::functional::normalize(up, torch::nn::functional::NormalizeFuncOptions().dim(-1));
  return torch::stack({forward, up, torch::cross(forward, up, -1)}, -2);
}

// Geodesic angle (radians) between the rotations of two [.., 6] sets: acos((tr(AᵀB) − 1) / 2),
// with tr(AᵀB) the sum of the axes' dot products (the same whether 6D holds rows or columns).
torch::Tensor angles_between(const torch::Tensor& a, const torch::Tensor& b) {
  const torch::Tensor trace = (frames_of(a) * frames_of(b)).sum({-1, -2});
  return torch::acos(torch::clamp((trace - 1.0) / 2.0, -1.0, 1.0));
}

}  // namespace

ReconstructionError motion_errors(const torch::Tensor& real, const torch::Tensor& reconstructed) {
  const torch::Tensor r = real.to(torch::kFloat64);
  const torch::Tensor g = reconstructed.to(torch::kFloat64);
  // Columns within the 18: head 6D 0–5, head position 6–8, hand 6D 9–14, hand position 15–17.
  const torch::Tensor position =
      torch::cat({(r.slice(-1, 6, 9) - g.slice(-1, 6, 9)).norm(2, -1, true),
                  (r.slice(-1, 15, 18) - g.slice(-1, 15, 18)).norm(2, -1, true)},
                 -1);
  const torch::Tensor rotation =
      torch::stack({angles_between(r.slice(-1, 0, 6), g.slice(-1, 0, 6)),
                    angles_between(r.slice(-1, 9, 15), g.slice(-1, 9, 15))},
                   -1);
  ReconstructionError e;
  e.position_cm = 100.0 * position.mean().item<double>();
  e.rotation_deg = 180.0 / kPi * rotation.mean().item<double>();
  e.segments = static_cast<std::size_t>(real.size(0));
  return e;
}

ReconstructionError reconstruction_error(TrainableNetwork& autoencoder,
                                         const ExampleSet& segments) {
  if (segments.count == 0) {
    return {};
  }
  torch::NoGradGuard no_grad;
  autoencoder.eval();
  const auto count = static_cast<std::int64_t>(segments.count);
  const torch::Tensor all =
      torch::from_blob(const_cast<float*>(segments.values.data()),
                       {count, segments.rows, segments.columns}, torch::kFloat32);
  // In chunks, so the hidden activations of tens of thousands of segments never coexist.
  constexpr std::int64_t kChunk = 4096;
  std::vector<torch::Tensor> outputs;
  for (std::int64_t first = 0; first < count; first += kChunk) {
    outputs.push_back(autoencoder.forward(all.slice(0, first, std::min(count, first + kChunk))));
  }
  autoencoder.train();
  return motion_errors(all, torch::cat(outputs, 0));
}

}  // namespace deixis::train
