#include "core/math/rotation_6d.h"

#include <cmath>

namespace deixis {
namespace {

constexpr float kTinyLength = 1e-6f;

bool usable(const Vec3& v) {
  return v.allFinite() && v.norm() > kTinyLength;
}

}  // namespace

Mat3 decode_6d(const Vec3& forward, const Vec3& up) {
  const Vec3 f = usable(forward) ? Vec3(forward.normalized()) : Vec3::UnitZ();
  // Remove from `up` its component along forward; if nothing is left, borrow +Y, or +X when
  // forward is (nearly) vertical.
  Vec3 u = usable(up) ? Vec3(up - up.dot(f) * f) : Vec3::Zero();
  if (!(u.norm() > kTinyLength)) {
    const Vec3 fallback = std::abs(f.y()) < 0.9f ? Vec3::UnitY() : Vec3::UnitX();
    u = fallback - fallback.dot(f) * f;
  }
  u.normalize();
  Mat3 R;
  R.col(0) = u.cross(f);  // right = up × forward, so det R = +1
  R.col(1) = u;
  R.col(2) = f;
  return R;
}

Mat3 decode_6d_unorthogonalised(const Vec3& forward, const Vec3& up) {
  const Vec3 f = forward.normalized();
  const Vec3 u = up.normalized();
  Mat3 R;
  R.col(0) = u.cross(f);
  R.col(1) = u;
  R.col(2) = f;
  return R;
}

}  // namespace deixis
