#include "eval/metrics.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/math/rotation_6d.h"

namespace deixis::eval {

namespace {

constexpr double kDegrees = 180.0 / std::numbers::pi;
constexpr double kFramesPerSecond = 30.0;

// The mean of the head's and the hand's error (the paper's "per joint" over its two joints).
double mean_of_two(float head, float hand) {
  return 0.5 * (static_cast<double>(head) + static_cast<double>(hand));
}

double angle_deg(const Vec3& a, const Vec3& b) {
  const double cross = a.cross(b).norm();
  const double dot = a.dot(b);
  return std::atan2(cross, dot) * kDegrees;
}

// Zeroes one component and renormalises (a projection onto a coordinate plane).
Vec3 project(Vec3 v, int dropped) {
  v[dropped] = 0.0f;
  const float n = v.norm();
  return n > 0.0f ? Vec3(v / n) : v;
}

Mat3 rotation_of(std::span<const float, kEndEffectorSize> x, int forward_at, int up_at) {
  return decode_6d_unorthogonalised(get_vec3(x, forward_at), get_vec3(x, up_at));
}

using MatrixXd = Eigen::MatrixXd;
using VectorXd = Eigen::VectorXd;

void mean_and_covariance(std::span<const std::vector<double>> rows, VectorXd& mean,
                         MatrixXd& covariance) {
  const Eigen::Index n = static_cast<Eigen::Index>(rows.size());
  const Eigen::Index d = static_cast<Eigen::Index>(rows[0].size());
  MatrixXd data(n, d);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (static_cast<Eigen::Index>(rows[i].size()) != d) {
      throw Error("frechet_distance: embeddings of different sizes");
    }
    data.row(i) = Eigen::Map<const VectorXd>(rows[i].data(), d).transpose();
  }
  mean = data.colwise().mean().transpose();
  const MatrixXd centred = data.rowwise() - mean.transpose();
  covariance = centred.transpose() * centred / static_cast<double>(n - 1);
}

// The square root of a symmetric positive semi-definite matrix (negative round-off clipped).
MatrixXd sqrt_psd(const MatrixXd& m) {
  const Eigen::SelfAdjointEigenSolver<MatrixXd> solver(m);
  const VectorXd root = solver.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  return solver.eigenvectors() * root.asDiagonal() * solver.eigenvectors().transpose();
}

// The 18 columns of x the robustness and FMD metrics read: head 6D and position (root frame),
// hand 6D and position (head frame).
struct HeadAndHand {
  Mat3 head_rotation, hand_rotation;
  Vec3 head_position, hand_position;
};
HeadAndHand head_and_hand(const EndEffectors& x) {
  return {rotation_of(x, ee::kHeadForward, ee::kHeadUp),
          rotation_of(x, ee::kHandForward, ee::kHandUp), get_vec3(x, ee::kHeadPosition),
          get_vec3(x, ee::kHandPosition)};
}

}  // namespace

ProgressionError progression_error(std::span<const nn::Progression> predicted,
                                   std::span<const nn::Progression> labels) {
  if (predicted.size() != labels.size() || predicted.empty()) {
    throw Error("progression_error: " + std::to_string(predicted.size()) + " predictions for " +
                std::to_string(labels.size()) + " labels");
  }
  ProgressionError e;
  e.frames = predicted.size();
  for (std::size_t i = 0; i < predicted.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      e.channel[c] +=
          std::abs(static_cast<double>(predicted[i][c]) - static_cast<double>(labels[i][c]));
    }
  }
  for (double& c : e.channel) {
    c /= static_cast<double>(e.frames);
  }
  e.total = (e.channel[0] + e.channel[1] + e.channel[2]) / 3.0;
  return e;
}

DeicticChain deictic_chain(std::span<const float, kEndEffectorSize> x) {
  const Mat3 head_rotation = rotation_of(x, ee::kHeadForward, ee::kHeadUp);
  const Mat3 hand_rotation = rotation_of(x, ee::kHandForward, ee::kHandUp);
  const Vec3 head = get_vec3(x, ee::kHeadPosition);
  const Vec3 in_head = hand_rotation * get_vec3(x, ee::kFingertip) + get_vec3(x, ee::kHandPosition);
  return {head, head_rotation * in_head + head};
}

PointingError pointing_error(const DeicticChain& chain, const Vec3& target_in_root) {
  const Vec3 efr = (chain.fingertip - chain.head).normalized();
  const Vec3 et = (target_in_root - chain.head).normalized();
  return {angle_deg(project(efr, 1), project(et, 1)), angle_deg(project(efr, 0), project(et, 0))};
}

double touching_error_cm(const DeicticChain& chain, const Vec3& target_in_root) {
  return static_cast<double>((chain.fingertip - target_in_root).norm()) * 100.0;
}

double frechet_distance(std::span<const std::vector<double>> real,
                        std::span<const std::vector<double>> generated) {
  if (real.size() < 2 || generated.size() < 2) {
    throw Error("frechet_distance: needs at least two embeddings on each side, got " +
                std::to_string(real.size()) + " and " + std::to_string(generated.size()));
  }
  VectorXd mu_r, mu_g;
  MatrixXd sigma_r, sigma_g;
  mean_and_covariance(real, mu_r, sigma_r);
  mean_and_covariance(generated, mu_g, sigma_g);
  if (mu_r.size() != mu_g.size()) {
    throw Error("frechet_distance: real and generated embeddings differ in size");
  }
  const MatrixXd root_r = sqrt_psd(sigma_r);
  const MatrixXd inner = root_r * sigma_g * root_r;
  const Eigen::SelfAdjointEigenSolver<MatrixXd> solver((inner + inner.transpose()) / 2.0);
  const double trace_sqrt = solver.eigenvalues().cwiseMax(0.0).cwiseSqrt().sum();
  // A squared distance: with singular covariances (fewer segments than embedding dimensions)
  // the square roots of eigenvalues that rounding left near zero (≈ √ε of the largest) add up
  // a little above the traces, and identical sets come out just below 0 (≈ 2e-8 of the traces in
  // tests/eval/metrics_test.cpp). Only that is floored; further below 0 is a fault.
  const double traces = sigma_r.trace() + sigma_g.trace();
  const double d = (mu_r - mu_g).squaredNorm() + traces - 2.0 * trace_sqrt;
  if (d < -1e-6 * std::max(traces, 1.0)) {
    throw Error("frechet_distance: " + std::to_string(d) +
                " is below zero beyond rounding (covariance traces " + std::to_string(traces) +
                ")");
  }
  return std::max(d, 0.0);
}

Vec3 axis_angle(const Mat3& R) {
  Eigen::Quaternionf q(R);
  q.normalize();
  if (q.w() < 0.0f) {
    q.coeffs() = -q.coeffs();
  }
  const Vec3 v = q.vec();
  const float s = v.norm();
  if (s < 1e-7f) {
    return 2.0f * v;  // small angle: axis·angle ≈ 2·v
  }
  return v / s * (2.0f * std::atan2(s, q.w()));
}

MotionDeviation motion_deviation(std::span<const EndEffectors> clean,
                                 std::span<const EndEffectors> noisy) {
  if (clean.size() != noisy.size() || clean.size() < 2) {
    throw Error("motion_deviation: needs two runs of equal length ≥ 2, got " +
                std::to_string(clean.size()) + " and " + std::to_string(noisy.size()));
  }
  const std::size_t n = clean.size();
  MotionDeviation d;
  for (std::size_t t = 0; t < n; ++t) {
    const HeadAndHand c = head_and_hand(clean[t]);
    const HeadAndHand m = head_and_hand(noisy[t]);
    d.position_cm += mean_of_two((c.head_position - m.head_position).norm(),
                                 (c.hand_position - m.hand_position).norm());
    d.rotation_deg +=
        mean_of_two((axis_angle(c.head_rotation) - axis_angle(m.head_rotation)).norm(),
                    (axis_angle(c.hand_rotation) - axis_angle(m.hand_rotation)).norm());
    if (t + 1 < n) {
      const HeadAndHand c1 = head_and_hand(clean[t + 1]);
      const HeadAndHand m1 = head_and_hand(noisy[t + 1]);
      const auto velocity = [](const Vec3& a, const Vec3& b) { return Vec3(b - a); };
      const auto spin = [](const Mat3& a, const Mat3& b) { return axis_angle(b * a.transpose()); };
      const Vec3 head_velocity_error =
          velocity(c.head_position, c1.head_position) - velocity(m.head_position, m1.head_position);
      const Vec3 hand_velocity_error =
          velocity(c.hand_position, c1.hand_position) - velocity(m.hand_position, m1.hand_position);
      const Vec3 head_spin_error =
          spin(c.head_rotation, c1.head_rotation) - spin(m.head_rotation, m1.head_rotation);
      const Vec3 hand_spin_error =
          spin(c.hand_rotation, c1.hand_rotation) - spin(m.hand_rotation, m1.hand_rotation);
      d.linear_velocity_cm_s += mean_of_two(head_velocity_error.norm(), hand_velocity_error.norm());
      d.angular_velocity_deg_s += mean_of_two(head_spin_error.norm(), hand_spin_error.norm());
    }
  }
  d.position_cm *= 100.0 / static_cast<double>(n);
  d.rotation_deg *= kDegrees / static_cast<double>(n);
  d.linear_velocity_cm_s *= 100.0 * kFramesPerSecond / static_cast<double>(n - 1);
  d.angular_velocity_deg_s *= kDegrees * kFramesPerSecond / static_cast<double>(n - 1);
  return d;
}

}  // namespace deixis::eval
