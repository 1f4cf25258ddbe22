#include "gesture/target_selection.h"

#include <cmath>
#include <limits>

namespace deixis {

namespace {

constexpr float kDegPerRad = 57.2957795f;

float angle_deg(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * kDegPerRad;
}

Vec3 position_of(TargetId id, const TargetMap& room, const Vec3& partner_head) {
  if (id == kPartnerTarget) {
    return partner_head;
  }
  const TargetObject* object = room.find(id);
  return object != nullptr ? object->position : partner_head;
}

// What a person designates with: a ray from `origin` along `direction` (none for a hand held
// too near the body), and optionally a fingertip that designates whatever surface it touches.
struct Designation {
  Vec3 origin = Vec3::Zero();
  Vec3 direction = Vec3::Zero();
  bool has_ray = true;
  const Vec3* fingertip = nullptr;
  float touch_m = 0.0f;
};

// How far a candidate is from being designated, in degrees: 0 when the fingertip touches it,
// else its angle off the ray, ∞ without a ray. `object` is null for the other person.
float angle_to(const Designation& d, const TargetObject* object, const Vec3& centre) {
  if (d.fingertip != nullptr && object != nullptr &&
      (*d.fingertip - closest_surface_point(*object, *d.fingertip)).norm() <= d.touch_m) {
    return 0.0f;
  }
  return d.has_ray ? angle_deg(d.direction, centre - d.origin)
                   : std::numeric_limits<float>::infinity();
}

struct Nearest {
  TargetId id = kNoTarget;
  float angle_deg = std::numeric_limits<float>::infinity();
};

// The candidate nearest to being designated (the first of equals), and its angle.
Nearest nearest(const Designation& d, const TargetMap& room, const Vec3& partner_head) {
  Nearest best{kPartnerTarget, angle_to(d, nullptr, partner_head)};
  for (const TargetObject& object : room.objects) {
    const float a = angle_to(d, &object, object.position);
    if (a < best.angle_deg) {
      best = {object.id, a};
    }
  }
  return best;
}

// The current target's angle (∞ when it no longer exists in this room).
float current_angle(TargetId current, const Designation& d, const TargetMap& room,
                    const Vec3& partner_head) {
  if (current == kPartnerTarget) {
    return angle_to(d, nullptr, partner_head);
  }
  const TargetObject* object = room.find(current);
  return object != nullptr ? angle_to(d, object, object->position)
                           : std::numeric_limits<float>::infinity();
}

// Whether `best` takes over from `current`, with the hysteresis margin.
bool takes_over(const Nearest& best, float current, const TargetSelectionConfig& c) {
  return best.angle_deg <= c.acquire_deg && best.angle_deg + c.switch_margin_deg < current;
}

}  // namespace

TargetSelectionConfig target_selection_for(const BodyCalibration& body) {
  TargetSelectionConfig c;
  c.deictic_hand = body.deictic_hand;
  c.pointing_reach_m = 0.6f * body.arm_length;
  return c;
}

void TargetSelector::select(TrackingFrame& frame, const TargetMap& room, const Vec3& partner_head) {
  const Vec3 head = frame.T_world_head.translation;
  const bool head_tracked = (frame.valid & tracked::kHead) != 0;
  if (head_tracked) {
    const Vec3 gaze = (frame.valid & tracked::kGaze) != 0
                          ? frame.gaze
                          : Vec3(frame.T_world_head.rotation * Vec3(0, 0, -1));
    const Designation eyes{head, gaze};
    const Nearest best = nearest(eyes, room, partner_head);
    if (best.id != head_target &&
        takes_over(best, current_angle(head_target, eyes, room, partner_head), config)) {
      head_target = best.id;
    }
  }
  const Hand hand = config.deictic_hand;
  if (head_tracked && (frame.valid & tracked::hand(hand)) != 0) {
    const Vec3& tip = frame.index_tip[static_cast<std::size_t>(index(hand))];
    const Vec3 ray = tip - head;
    // A hand nearer than the pointing reach designates only what it touches.
    const Designation finger{head, ray, ray.norm() >= config.pointing_reach_m, &tip,
                             config.touch_m};
    const Nearest best = nearest(finger, room, partner_head);
    const float current = current_angle(hand_target, finger, room, partner_head);
    bool switched = false;
    if (best.id != hand_target && takes_over(best, current, config)) {
      const bool at_once = best.id == head_target;  // the eyes are on it already
      pending_ticks = best.id == pending_hand_target ? pending_ticks + 1 : 1;
      pending_hand_target = best.id;
      switched = at_once || pending_ticks >= config.dwell_ticks;
    } else {
      pending_hand_target = kNoTarget;
    }
    if (switched) {
      hand_target = best.id;
      pending_hand_target = kNoTarget;
    } else if (current > config.acquire_deg) {
      // The hand designates nothing (yet): it will point where the eyes are.
      hand_target = head_target;
    }
  }
  frame.head_target = head_target;
  frame.hand_target = hand_target;
  frame.head_target_position = position_of(head_target, room, partner_head);
  frame.hand_target_position = position_of(hand_target, room, partner_head);
}

}  // namespace deixis
