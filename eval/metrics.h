#pragma once
// The paper's metrics (§V.A, §V.C–D) exactly as the authors' evaluation code computes them
// (docs/eval.md#what-each-number-is): pure functions on network vectors and poses, so each can be
// checked against hand-computed cases (tests/eval/metrics_test.cpp). Angles are reported in degrees
// and positions in centimetres here only; everything upstream is radians and metres.

#include <array>
#include <span>
#include <vector>

#include "core/math/network_frame.h"
#include "gesture/nn/shapes.h"

namespace deixis::eval {

// ---- MPNet: motion progression error (docs/eval.md#what-each-number-is) --------------------

// Mean per-frame |p̂ − p| per channel (gaze, deictic, idle); Total is the mean of the three.
struct ProgressionError {
  std::array<double, 3> channel{};
  double total = 0.0;
  std::size_t frames = 0;
};
ProgressionError progression_error(std::span<const nn::Progression> predicted,
                                   std::span<const nn::Progression> labels);

// ---- DIP: deictic intention preservation (docs/eval.md#what-each-number-is) ----------------

// The head, hand and index fingertip of end-effectors x, composed with the authors' recipe
// (6D decoded without orthogonalisation, docs/conventions.md#6d-rotations): fingertip_O =
// R_head·(R_hand·f + p_hand) + p_head, all relative to root O in the network frame.
struct DeicticChain {
  Vec3 head;       // H relative to O
  Vec3 fingertip;  // index fingertip relative to O
};
DeicticChain deictic_chain(std::span<const float, kEndEffectorSize> x);

// Horizontal and vertical errors (degrees) between the eye–fingertip ray EFR = unit(fingertip −
// head) and the head–target ray ET = unit(target − head), each projected onto the root's x–z
// (horizontal) and y–z (vertical) planes and renormalised; unsigned.
struct PointingError {
  double horizontal_deg = 0.0;  // HE
  double vertical_deg = 0.0;    // VE
};
PointingError pointing_error(const DeicticChain& chain, const Vec3& target_in_root);

// Positional error (cm) between the fingertip and the touch target: PE.
double touching_error_cm(const DeicticChain& chain, const Vec3& target_in_root);

// ---- FMD: Fréchet motion distance (docs/eval.md#what-each-number-is) -----------------------

// |μ_r − μ_g|² + tr(Σ_r + Σ_g − 2·(Σ_r Σ_g)^½) between two sets of embeddings (rows), covariances
// with N − 1. The matrix square root's trace is computed as Σ √λ_i of Σ_r^½ Σ_g Σ_r^½ (symmetric
// positive semi-definite, so the trace equals that of the real part of scipy's sqrtm).
double frechet_distance(std::span<const std::vector<double>> real,
                        std::span<const std::vector<double>> generated);

// ---- Robustness to missed tracking (docs/eval.md#what-each-number-is) ----------------------

// Per-frame head and hand (root-relative head, head-relative hand: x[3..20]) of two runs, clean
// and noisy; errors are the mean over frames of the head and hand errors averaged.
struct MotionDeviation {
  double position_cm = 0.0;             // MPJPE
  double rotation_deg = 0.0;            // MPJRE: |axis-angle(clean) − axis-angle(noisy)|
  double linear_velocity_cm_s = 0.0;    // MPJLVE, velocities = 30 · frame differences
  double angular_velocity_deg_s = 0.0;  // MPJAVE, ω = 30 · axis-angle(R_{t+1} R_tᵀ)
};
MotionDeviation motion_deviation(std::span<const EndEffectors> clean,
                                 std::span<const EndEffectors> noisy);

// Rotation vector (axis · angle, radians) of a rotation matrix, via the quaternion as the
// authors' torchgeometry does; the angle is in [0, π].
Vec3 axis_angle(const Mat3& R);

}  // namespace deixis::eval
