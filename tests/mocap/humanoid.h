#pragma once
// A small humanoid in centimetres for the mocap tests, facing +Z in its rest T-pose as CMU and
// Mixamo files do: its joints' rotations given as matrices and written in any Euler order.

#include <array>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace deixis::mocap::testing {

struct HumanoidJoint {
  const char* name;
  int parent;
  Eigen::Vector3d offset;
  bool end_site = false;
};

inline const std::vector<HumanoidJoint>& humanoid() {
  static const std::vector<HumanoidJoint> joints = {
      {"Hips", -1, {0, 0, 0}},          {"Spine", 0, {0, 10, 0}},
      {"Neck", 1, {0, 40, 0}},          {"Head", 2, {0, 10, 0}},
      {"", 3, {0, 18, 0}, true},        {"LeftArm", 1, {18, 35, 0}},
      {"LeftForeArm", 5, {28, 0, 0}},   {"LeftHand", 6, {25, 0, 0}},
      {"LeftHandIndex1", 7, {8, 0, 0}}, {"", 8, {9, 0, 0}, true},
      {"RightArm", 1, {-18, 35, 0}},    {"RightForeArm", 10, {-28, 0, 0}},
      {"RightHand", 11, {-25, 0, 0}},   {"", 12, {-18, 0, 0}, true},
      {"LeftUpLeg", 0, {10, -5, 0}},    {"LeftLeg", 14, {0, -45, 0}},
      {"LeftFoot", 15, {0, -42, 0}},    {"", 16, {0, -3, 12}, true},
      {"RightUpLeg", 0, {-10, -5, 0}},  {"RightLeg", 18, {0, -45, 0}},
      {"RightFoot", 19, {0, -42, 0}},   {"", 20, {0, -3, 12}, true},
  };
  return joints;
}

struct HumanoidFrame {
  Eigen::Vector3d root = {0, 95, 0};
  std::vector<Eigen::Matrix3d> rotation;  // per humanoid() entry (end sites ignored)
};

inline std::vector<HumanoidFrame> random_motion(int frames, unsigned seed, double degrees = 40) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(-degrees * M_PI / 180, degrees * M_PI / 180);
  std::vector<HumanoidFrame> motion(static_cast<std::size_t>(frames));
  for (HumanoidFrame& f : motion) {
    f.root = {angle(rng) * 20, 95 + angle(rng) * 5, angle(rng) * 20};
    for (std::size_t j = 0; j < humanoid().size(); ++j) {
      f.rotation.push_back((Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitX()) *
                            Eigen::AngleAxisd(angle(rng) / 2, Eigen::Vector3d::UnitY()))
                               .toRotationMatrix());
    }
  }
  return motion;
}

// The humanoid as BVH text: every joint's rotation channels in the axis order `order` (0 = X),
// `prefix` before every name (e.g. "mixamorig:"), `scale` applied to lengths (1: cm).
inline std::string humanoid_bvh(const std::vector<HumanoidFrame>& motion,
                                std::array<int, 3> order = {2, 1, 0},
                                const std::string& prefix = "", double scale = 1.0) {
  const char* axis[3] = {"Xrotation", "Yrotation", "Zrotation"};
  const auto& joints = humanoid();
  std::ostringstream t;
  t.precision(9);
  t << "HIERARCHY\n";
  std::vector<int> open;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    while (!open.empty() && open.back() != joints[i].parent) {
      t << "}\n";
      open.pop_back();
    }
    const HumanoidJoint& j = joints[i];
    if (j.end_site) {
      t << "End Site";
    } else {
      t << (j.parent < 0 ? "ROOT " : "JOINT ") << prefix << j.name;
    }
    t << "\n{\nOFFSET " << j.offset.x() * scale << ' ' << j.offset.y() * scale << ' '
      << j.offset.z() * scale << '\n';
    if (!j.end_site) {
      t << (j.parent < 0 ? "CHANNELS 6 Xposition Yposition Zposition" : "CHANNELS 3");
      for (const int a : order) {
        t << ' ' << axis[a];
      }
      t << '\n';
    }
    open.push_back(static_cast<int>(i));
  }
  while (!open.empty()) {
    t << "}\n";
    open.pop_back();
  }
  t << "MOTION\nFrames: " << motion.size() << "\nFrame Time: 0.0333333333\n";
  for (const HumanoidFrame& f : motion) {
    t << f.root.x() * scale << ' ' << f.root.y() * scale << ' ' << f.root.z() * scale;
    for (std::size_t i = 0; i < joints.size(); ++i) {
      if (joints[i].end_site) {
        continue;
      }
      const Eigen::Vector3d e = f.rotation[i].eulerAngles(order[0], order[1], order[2]);
      for (int k = 0; k < 3; ++k) {
        t << ' ' << e[k] * 180 / M_PI;
      }
    }
    t << '\n';
  }
  return t.str();
}

}  // namespace deixis::mocap::testing
