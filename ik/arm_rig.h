#pragma once
// What the arm jobs need to know about one arm of a rig, derived once from its rest pose: the
// joints, the elbow's hinge axis, the forearm's axis, the index finger's flexion axes, the
// fingertip offset and where the tracker's wrist frame sits in the hand joint.
//
// The rest pose is assumed to be a T- or A-pose facing −Z with palms down (VRM and Mixamo rigs
// are): the back of the hand (dorsal) is +Y made perpendicular to the forearm. The tracker's
// wrist frame (docs/decisions.md §7) is x = distal for the right hand and proximal for the left,
// y = dorsal, z = x × y (ulnar).

#include <array>
#include <span>

#include "core/tracking.h"
#include "ik/humanoid.h"
#include "ik/joint_limits.h"

namespace deixis::ik {

struct ArmRig {
  Hand side = Hand::kRight;
  int upper = -1;                           // upper arm (the shoulder's ball joint)
  int lower = -1;                           // lower arm (elbow)
  int hand = -1;                            // hand (wrist)
  std::array<int, 3> index = {-1, -1, -1};  // proximal, intermediate, distal; index_count used
  int index_count = 0;
  Vec3 mid_axis = Vec3::UnitZ();      // elbow hinge in the lower arm's frame (+ flexes)
  Vec3 forearm_axis = Vec3::UnitX();  // elbow→wrist in the lower arm's frame
  std::array<Vec3, 3> index_axes = {Vec3::UnitZ(), Vec3::UnitZ(), Vec3::UnitZ()};  // + curls
  Vec3 tip_offset = Vec3::Zero();        // fingertip in the last index joint's frame (the hand's
                                         // when the rig has no index joints)
  Mat3 R_hand_wrist = Mat3::Identity();  // the tracker's wrist frame in the hand joint's frame
  HingeRange forearm_twist;              // pronation/supination as a twist about forearm_axis
  Vec3 pole = Vec3(0, -1, 0);            // the elbow's natural side, model space: down, out, back

  int tip_joint() const { return index_count > 0 ? index[index_count - 1] : hand; }
};

// Derives one arm from a rig and its rest model poses (rest_model[i] = T_model_joint at rest).
// Throws deixis::Error naming the bone when a required one is missing or a bone has no length.
ArmRig make_arm_rig(const HumanoidRig& rig, std::span<const Pose> rest_model, Hand side,
                    const IkLimits& limits);

// The arm's two bones bent so the wrist reaches `wrist_target` (model space; the caller has
// softened it already) with the elbow toward `pole`, then the hand turned toward `R_model_hand`
// within the wrist's limits. Rewrites the upper, lower and hand joints' local rotations and
// updates `model` from the upper arm to the hand. Shared by both arm jobs; allocates nothing.
void bend_arm_and_turn_hand(const Skeleton& skeleton, const ArmRig& arm, const IkLimits& limits,
                            const Vec3& wrist_target, const Vec3& pole, const Mat3& R_model_hand,
                            std::span<Pose> local, std::span<Pose> model);

}  // namespace deixis::ik
