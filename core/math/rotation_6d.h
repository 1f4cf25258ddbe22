#pragma once
// The 6D rotation representation of the networks (Zhou et al. 2019 as the authors use it,
// docs/conventions.md#6d-rotations): 6D = (forward column, up column) = (third column z, second
// column y) of the rotation matrix, in the parent frame, in the *network* frame where +Z is
// forward. This header is the only place that converts; nobody writes it twice.

#include "core/math/pose.h"

namespace deixis {

struct Rotation6D {
  Vec3 forward;  // third column (z axis)
  Vec3 up;       // second column (y axis)
};

// (forward, up) = (R·e_z, R·e_y).
inline Rotation6D encode_6d(const Mat3& R) {
  return {R.col(2), R.col(1)};
}

// Decodes to a proper rotation (orthonormal, det +1) for any input: Gram–Schmidt that keeps the
// forward column's direction exact, then right = up × forward. Degenerate input (zero or
// non-finite forward, up parallel to forward) falls back to the nearest sensible frame instead of
// producing NaN: forward defaults to +Z, up to +Y (or +X when forward is vertical). This is what
// IK and rendering consume (docs/conventions.md#6d-rotations).
Mat3 decode_6d(const Vec3& forward, const Vec3& up);
inline Mat3 decode_6d(const Rotation6D& r) {
  return decode_6d(r.forward, r.up);
}

// The authors' recipe, kept only so that metrics reproduce theirs
// (docs/conventions.md#6d-rotations): each column is normalised separately, right = up × forward,
// and forward and up are *not* made orthogonal, so the result can be slightly non-orthogonal. Never
// feed this to IK or rendering.
Mat3 decode_6d_unorthogonalised(const Vec3& forward, const Vec3& up);

}  // namespace deixis
