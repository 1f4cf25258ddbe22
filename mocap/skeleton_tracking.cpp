#include "mocap/skeleton_tracking.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "core/error.h"

namespace deixis::mocap {

namespace {

// Anthropometric ratios of stature S (docs/bvh.md#tracking): the eyes 0.064 S below the top of
// the head (eye height 0.936 S, as gesture/upright_calibration.cpp) and 0.05 S in front of the
// head's vertical axis; a head top 0.12 S above the head joint when the file has none.
constexpr double kEyesBelowTop = 1.0 - 0.936;
constexpr double kEyesForward = 0.05;
constexpr double kHeadTopAboveJoint = 0.12;
// The authors' tracker's right index fingertip in the wrist frame at 1.70 m (capture/body.cpp).
const Eigen::Vector3d kTipInRightWrist(0.135, -0.056, -0.017);
constexpr double kReferenceHeight = 1.70;
const Vec3 kDefaultRestWrist(0.2f, -0.75f, 0.0f);  // right; BodyCalibration's default

std::string base_name(const std::string& name) {
  std::string s = name.substr(std::min(name.size(), name.find_last_of(":|") + 1));
  std::string out;
  for (const char c : s) {
    if (c != '_' && c != ' ' && c != '-' && c != '.') {
      out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
    }
  }
  return out;
}

bool contains(const std::string& s, const char* part) {
  return s.find(part) != std::string::npos;
}

// "lefthand", "handleft", "lhand", "handl", "leftwrist", ... for (left, {"hand", "wrist"}).
bool is_side_part(const std::string& b, Hand side, const char* part) {
  const std::string word = side == Hand::kLeft ? "left" : "right";
  const std::string letter = side == Hand::kLeft ? "l" : "r";
  for (const std::string& s : {word, letter}) {
    if (b == s + part || b == part + s) {
      return true;
    }
  }
  return false;
}

Mat3 to_float(const Eigen::Matrix3d& R) {
  return R.cast<float>();
}

Eigen::Matrix3d frame_from(const Eigen::Vector3d& a, const Eigen::Vector3d& hint) {
  const Eigen::Vector3d x = a.normalized();
  const Eigen::Vector3d y = (hint - hint.dot(x) * x).normalized();
  Eigen::Matrix3d R;
  R.col(0) = x;
  R.col(1) = y;
  R.col(2) = x.cross(y);
  return R;
}

std::string some_names(const Bvh& b) {
  std::string s;
  for (std::size_t i = 0; i < b.nodes.size() && i < 40; ++i) {
    if (!b.nodes[i].end_site) {
      s += (s.empty() ? "" : ", ") + b.nodes[i].name;
    }
  }
  return s;
}

bool is_below(const Bvh& b, int node, int ancestor) {
  for (int p = node; p >= 0; p = b.nodes[static_cast<std::size_t>(p)].parent) {
    if (p == ancestor) {
      return true;
    }
  }
  return false;
}

int chain_end(const Bvh& b, int from) {
  int cur = from;
  while (true) {
    int first_child = -1;
    for (std::size_t i = static_cast<std::size_t>(cur) + 1; i < b.nodes.size(); ++i) {
      if (b.nodes[i].parent == cur) {
        if (b.nodes[i].end_site) {
          return static_cast<int>(i);
        }
        if (first_child < 0) {
          first_child = static_cast<int>(i);
        }
      }
    }
    if (first_child < 0) {
      return cur;
    }
    cur = first_child;
  }
}

}  // namespace

JointRoles find_roles(const Bvh& b) {
  JointRoles r;
  std::vector<std::string> base(b.nodes.size());
  for (std::size_t i = 0; i < b.nodes.size(); ++i) {
    base[i] = b.nodes[i].end_site ? "" : base_name(b.nodes[i].name);
  }
  auto first = [&](auto&& matches) {
    for (std::size_t i = 0; i < base.size(); ++i) {
      if (!b.nodes[i].end_site && matches(base[i], static_cast<int>(i))) {
        return static_cast<int>(i);
      }
    }
    return -1;
  };
  r.head = first([](const std::string& s, int) { return s == "head"; });
  if (r.head < 0) {
    r.head = first([](const std::string& s, int) {
      return contains(s, "head") && !contains(s, "top") && !contains(s, "end") &&
             !contains(s, "nub");
    });
  }
  if (r.head < 0) {
    throw Error(b.source +
                ": no head joint (a joint named Head, mixamorig:Head or containing "
                "'head'); the joints: " +
                some_names(b));
  }
  for (std::size_t i = static_cast<std::size_t>(r.head) + 1; i < b.nodes.size(); ++i) {
    if (b.nodes[i].parent == r.head &&
        (b.nodes[i].end_site || contains(base[i], "top") || contains(base[i], "end"))) {
      r.head_top = static_cast<int>(i);
      break;
    }
  }
  std::vector<JointPose> rest(b.nodes.size());
  const std::vector<float> zeros(b.channels, 0.0f);
  forward_kinematics(b, zeros, 1.0, rest);
  auto apart = [&](int a, int c) {
    return (rest[static_cast<std::size_t>(a)].p - rest[static_cast<std::size_t>(c)].p).norm() >
           1e-9;
  };
  auto ancestor_apart = [&](int node) {
    int p = node < 0 ? -1 : b.nodes[static_cast<std::size_t>(node)].parent;
    while (p >= 0 && !apart(p, node)) {
      p = b.nodes[static_cast<std::size_t>(p)].parent;
    }
    return p;
  };
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    const auto k = static_cast<std::size_t>(index(h));
    r.hand[k] = first([&](const std::string& s, int) { return is_side_part(s, h, "hand"); });
    if (r.hand[k] < 0) {
      r.hand[k] = first([&](const std::string& s, int) { return is_side_part(s, h, "wrist"); });
    }
    if (r.hand[k] < 0) {
      const char* side = h == Hand::kLeft ? "left" : "right";
      throw Error(b.source + ": no " + side + " hand joint (" +
                  (h == Hand::kLeft
                       ? "LeftHand, mixamorig:LeftHand, LeftWrist, l_hand, Hand_L"
                       : "RightHand, mixamorig:RightHand, RightWrist, r_hand, Hand_R") +
                  "); the joints: " + some_names(b));
    }
    r.elbow[k] = ancestor_apart(r.hand[k]);
    r.shoulder[k] = ancestor_apart(r.elbow[k]);
    if (r.elbow[k] < 0) {
      throw Error(b.source + ": the hand joint " + b.nodes[k].name + " has no forearm above it");
    }
    int finger = first([&](const std::string& s, int i) {
      return is_below(b, i, r.hand[k]) && contains(s, "index");
    });
    if (finger < 0) {
      finger = first([&](const std::string& s, int i) {
        return is_below(b, i, r.hand[k]) && contains(s, "finger") && !contains(s, "thumb");
      });
    }
    if (finger >= 0) {
      r.index_tip[k] = chain_end(b, finger);
    }
  }
  return r;
}

SkeletonTracking::SkeletonTracking(const Bvh& bvh, double metres_per_unit)
    : bvh_(bvh), scale_(metres_per_unit), roles_(find_roles(bvh)), poses_(bvh.nodes.size()) {
  const std::vector<float> zeros(bvh.channels, 0.0f);
  forward_kinematics(bvh, zeros, scale_, poses_);
  auto at = [&](int i) { return poses_[static_cast<std::size_t>(i)].p; };
  stature_ = rest_height(bvh) * scale_;
  // The rest pose's facing from its sides (CMU and Mixamo face +Z; whatever a file does, the
  // left hand is on the left).
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  Eigen::Vector3d left = at(roles_.hand[0]) - at(roles_.hand[1]);
  left.y() = 0;
  if (left.norm() < 1e-9) {
    left = Eigen::Vector3d::UnitX();
  }
  left.normalize();
  const Eigen::Vector3d forward = left.cross(up);
  rest_frame_.col(0) = -left;
  rest_frame_.col(1) = up;
  rest_frame_.col(2) = -forward;
  head_top_in_head_ = roles_.head_top >= 0 ? Eigen::Vector3d(at(roles_.head_top) - at(roles_.head))
                                           : Eigen::Vector3d(up * kHeadTopAboveJoint * stature_);
  const double k = stature_ / kReferenceHeight;
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    const auto i = static_cast<std::size_t>(index(h));
    const Eigen::Vector3d distal = (at(roles_.hand[i]) - at(roles_.elbow[i])).normalized();
    // A BVH rest pose is a T-pose with the palms down: dorsal is up.
    wrist_in_hand_[i] = frame_from(h == Hand::kRight ? distal : Eigen::Vector3d(-distal), up);
    tip_in_wrist_[i] =
        k * Eigen::Vector3d(h == Hand::kRight ? kTipInRightWrist.x() : -kTipInRightWrist.x(),
                            kTipInRightWrist.y(), kTipInRightWrist.z());
  }
}

void SkeletonTracking::track(std::size_t i, TrackingFrame& out) {
  track_row(bvh_.frame(i), static_cast<double>(i) * bvh_.frame_time, out);
}

void SkeletonTracking::track_row(std::span<const float> row, double time, TrackingFrame& out) {
  forward_kinematics(bvh_, row, scale_, poses_);
  const JointPose& head = poses_[static_cast<std::size_t>(roles_.head)];
  const Eigen::Matrix3d R_head = head.R * rest_frame_;
  const Eigen::Vector3d top = head.p + head.R * head_top_in_head_;
  const Eigen::Vector3d H =
      top - R_head.col(1) * (kEyesBelowTop * stature_) - R_head.col(2) * (kEyesForward * stature_);
  out.time = time;
  out.T_world_head = Pose{to_float(R_head), H.cast<float>()};
  out.gaze = (-R_head.col(2)).cast<float>();
  out.valid = tracked::kHead | tracked::kGaze;
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    const auto k = static_cast<std::size_t>(index(h));
    const JointPose& hand = poses_[static_cast<std::size_t>(roles_.hand[k])];
    const Eigen::Matrix3d R_wrist = hand.R * wrist_in_hand_[k];
    out.T_world_wrist[k] = Pose{to_float(R_wrist), hand.p.cast<float>()};
    const Eigen::Vector3d tip = roles_.index_tip[k] >= 0
                                    ? poses_[static_cast<std::size_t>(roles_.index_tip[k])].p
                                    : Eigen::Vector3d(hand.p + R_wrist * tip_in_wrist_[k]);
    out.index_tip[k] = tip.cast<float>();
    if (is_finite(out.T_world_wrist[k]) && out.index_tip[k].allFinite()) {
      out.valid |= tracked::hand(h);
    }
  }
  if (!is_finite(out.T_world_head) || !out.gaze.allFinite()) {
    out.valid &= static_cast<std::uint8_t>(~(tracked::kHead | tracked::kGaze));
  }
}

std::size_t SkeletonTracking::upright_frame() {
  const double cos_limit = std::cos(30.0 * M_PI / 180.0);
  TrackingFrame f;
  for (std::size_t i = 0; i < bvh_.frames(); ++i) {
    track(i, f);
    const Eigen::Vector3d spine = poses_[static_cast<std::size_t>(roles_.head)].p - poses_[0].p;
    const float head_y = f.T_world_head.translation.y();
    if (spine.norm() > 0 && spine.normalized().y() >= cos_limit &&
        head_y > f.T_world_wrist[0].translation.y() &&
        head_y > f.T_world_wrist[1].translation.y()) {
      return i;
    }
  }
  throw Error(bvh_.source +
              ": no upright frame (spine within 30° of vertical, head above both "
              "wrists) to calibrate the body from");
}

Pose SkeletonTracking::ground(std::size_t i) {
  forward_kinematics(bvh_, bvh_.frame(i), scale_, poses_);
  double low = poses_.front().p.y();
  for (const JointPose& p : poses_) {
    low = std::min(low, p.p.y());
  }
  // The root's rotation is the identity in the rest pose (its channels all zero), so the rest
  // frame's back axis turned by it is where the pelvis faces now.
  Eigen::Vector3d forward = -(poses_.front().R * rest_frame_.col(2));
  if (std::hypot(forward.x(), forward.z()) < 1e-3) {
    forward = -(poses_[static_cast<std::size_t>(roles_.head)].R * rest_frame_.col(2));
  }
  const Eigen::Vector3d& root = poses_.front().p;
  return Pose{
      yaw_rotation(static_cast<float>(std::atan2(-forward.x(), -forward.z()))),
      Vec3(static_cast<float>(root.x()), static_cast<float>(low), static_cast<float>(root.z()))};
}

BodyCalibration SkeletonTracking::calibrate(Hand deictic_hand) {
  const std::size_t i = upright_frame();
  TrackingFrame f;
  track(i, f);
  double low = poses_.front().p.y();
  for (const JointPose& p : poses_) {
    low = std::min(low, p.p.y());
  }
  const JointPose& head = poses_[static_cast<std::size_t>(roles_.head)];
  const double top = (head.p + head.R * head_top_in_head_).y();
  BodyCalibration c;
  c.deictic_hand = deictic_hand;
  c.height = static_cast<float>(top - low);
  // The arm from the rest pose: shoulder → elbow → wrist → fingertip.
  const std::vector<float> zeros(bvh_.channels, 0.0f);
  TrackingFrame rest;
  track_row(zeros, 0.0, rest);
  const auto d = static_cast<std::size_t>(index(deictic_hand));
  auto at = [&](int n) { return poses_[static_cast<std::size_t>(n)].p; };
  double arm = (at(roles_.elbow[d]) - at(roles_.hand[d])).norm() +
               (rest.index_tip[d].cast<double>() - at(roles_.hand[d])).norm();
  if (roles_.shoulder[d] >= 0) {
    arm += (at(roles_.shoulder[d]) - at(roles_.elbow[d])).norm();
  }
  c.arm_length = static_cast<float>(arm);
  const Vec3 forward = f.T_world_head.rotation * Vec3(0, 0, -1);
  c.T_world_root =
      Pose{yaw_rotation(std::atan2(-forward.x(), -forward.z())), f.T_world_head.translation};
  const Pose T_root_world = inverse(c.T_world_root);
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    const auto k = static_cast<std::size_t>(index(h));
    const Vec3& wrist = f.T_world_wrist[k].translation;
    const bool hanging = f.T_world_head.translation.y() - wrist.y() >= 0.26f * c.height;
    const Vec3 fallback(h == Hand::kLeft ? -kDefaultRestWrist.x() : kDefaultRestWrist.x(),
                        kDefaultRestWrist.y(), kDefaultRestWrist.z());
    c.rest_wrist_in_root[k] =
        hanging ? transform_point(T_root_world, wrist) : Vec3(fallback * (c.height / 1.70f));
  }
  track(i, f);  // poses() again of the upright frame
  return c;
}

}  // namespace deixis::mocap
