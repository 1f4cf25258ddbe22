#include "capture/mirror.h"

namespace deixis::capture {

namespace {

struct Reflection {
  Pose T_world_root;
  Mat3 M;                                // the reflection in world coordinates
  Mat3 L = Vec3(-1, 1, 1).asDiagonal();  // and in local coordinates (x is the lateral axis)

  explicit Reflection(const Pose& root)
      : T_world_root(root),
        M(root.rotation * Vec3(-1, 1, 1).asDiagonal() * root.rotation.transpose()) {}

  Vec3 point(const Vec3& p) const {
    return M * (p - T_world_root.translation) + T_world_root.translation;
  }
  Vec3 direction(const Vec3& d) const { return M * d; }
  Pose pose(const Pose& T) const { return Pose{M * T.rotation * L, point(T.translation)}; }
};

}  // namespace

Sequence mirror(const Sequence& in) {
  const Reflection r(in.calibration.T_world_root);
  Sequence out = in;
  out.mirrored = !in.mirrored;
  out.dominant_eye = in.dominant_eye == Eye::kLeft ? Eye::kRight : Eye::kLeft;
  out.calibration.deictic_hand = other(in.calibration.deictic_hand);
  out.calibration.T_world_root = r.pose(in.calibration.T_world_root);
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    out.calibration.rest_wrist_in_root[index(other(h))] =
        in.calibration.rest_wrist_in_root[index(h)].cwiseProduct(Vec3(-1, 1, 1));
  }
  for (TargetObject& t : out.targets) {
    t.position = r.point(t.position);
  }
  for (std::size_t i = 0; i < in.size(); ++i) {
    const TrackingFrame& a = in.frames[i];
    TrackingFrame& b = out.frames[i];
    b.T_world_head = r.pose(a.T_world_head);
    b.gaze = r.direction(a.gaze);
    b.head_target_position = r.point(a.head_target_position);
    b.hand_target_position = r.point(a.hand_target_position);
    std::uint8_t valid = a.valid & (tracked::kHead | tracked::kGaze);
    for (const Hand h : {Hand::kLeft, Hand::kRight}) {
      const Hand m = other(h);
      b.T_world_wrist[index(m)] = r.pose(a.T_world_wrist[index(h)]);
      b.index_tip[index(m)] = r.point(a.index_tip[index(h)]);
      if (a.valid & tracked::hand(h)) {
        valid |= tracked::hand(m);
      }
    }
    b.valid = valid;
  }
  for (std::size_t i = 0; i < in.joints.size(); ++i) {
    const Joints& a = in.joints[i];
    Joints& b = out.joints[i];
    b.hip = r.point(a.hip);
    b.neck = r.point(a.neck);
    b.head = r.point(a.head);
    for (int s = 0; s < 2; ++s) {
      b.eye[1 - s] = r.point(a.eye[s]);
      b.shoulder[1 - s] = r.point(a.shoulder[s]);
      b.elbow[1 - s] = r.point(a.elbow[s]);
      b.wrist[1 - s] = r.point(a.wrist[s]);
      b.tip[1 - s] = r.point(a.tip[s]);
    }
  }
  return out;
}

}  // namespace deixis::capture
