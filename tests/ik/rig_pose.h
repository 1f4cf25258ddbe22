#pragma once
// The test rig, its solver data and a pose to run jobs on (rest to start with).

#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "ik/avatar_solver.h"
#include "test_rig.h"

namespace deixis::ik::testing {

struct RigPose {
  explicit RigPose(const TestRigOptions& options = {})
      : solver(AvatarSolver::build(make_test_rig(options))),
        local(solver.rig.skeleton.rest_local),
        model(solver.rest_model) {}

  const Skeleton& skeleton() const { return solver.rig.skeleton; }
  int operator[](Bone b) const { return solver.rig[b]; }
  void reset() {
    local = solver.rig.skeleton.rest_local;
    model = solver.rest_model;
  }

  AvatarSolver solver;
  std::vector<Pose> local;
  std::vector<Pose> model;
};

// A uniformly random rotation (normalised Gaussian quaternion).
inline Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<float> n(0.0f, 1.0f);
  Quat q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q.toRotationMatrix();
}

// A random rotation by at most `max_angle`.
inline Mat3 random_rotation(std::mt19937& rng, float max_angle) {
  std::normal_distribution<float> n(0.0f, 1.0f);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const Vec3 axis = Vec3(n(rng), n(rng), n(rng)).normalized();
  return axis_angle(axis, max_angle * u(rng));
}

inline Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<float> n(0.0f, 1.0f);
  return Vec3(n(rng), n(rng), n(rng)).normalized();
}

inline std::string to_text(const Vec3& v) {
  std::ostringstream o;
  o.precision(9);
  o << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return o.str();
}

inline float angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace deixis::ik::testing
