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

// The candidate nearest to a ray from `origin` along `direction` in angle, and that angle.
// `fingertip` (may be null): a candidate whose surface it nearly touches counts as 0°.
struct Nearest {
  TargetId id = kNoTarget;
  float angle_deg = std::numeric_limits<float>::infinity();
};

float candidate_angle(const Vec3& origin, const Vec3& direction, const Vec3* fingertip,
                      float touch_m, const TargetObject* object, const Vec3& centre) {
  if (fingertip != nullptr && object != nullptr &&
      (*fingertip - closest_surface_point(*object, *fingertip)).norm() <= touch_m) {
    return 0.0f;
  }
  return angle_deg(direction, centre - origin);
}

Nearest nearest(const Vec3& origin, const Vec3& direction, const Vec3* fingertip, float touch_m,
                const TargetMap& room, const Vec3& partner_head) {
  Nearest best;
  best.id = kPartnerTarget;
  best.angle_deg = angle_deg(direction, partner_head - origin);
  for (const TargetObject& object : room.objects) {
    const float a =
        candidate_angle(origin, direction, fingertip, touch_m, &object, object.position);
    if (a < best.angle_deg) {
      best = {object.id, a};
    }
  }
  return best;
}

// The current target's angle to the ray (∞ when it no longer exists in this room).
float current_angle(TargetId current, const Vec3& origin, const Vec3& direction,
                    const Vec3* fingertip, float touch_m, const TargetMap& room,
                    const Vec3& partner_head) {
  if (current == kPartnerTarget) {
    return angle_deg(direction, partner_head - origin);
  }
  const TargetObject* object = room.find(current);
  if (object == nullptr) {
    return std::numeric_limits<float>::infinity();
  }
  return candidate_angle(origin, direction, fingertip, touch_m, object, object->position);
}

// Without a pointing ray: the object the fingertip touches (0°), if any.
Nearest touched(const Vec3& tip, float touch_m, const TargetMap& room) {
  for (const TargetObject& object : room.objects) {
    if ((tip - closest_surface_point(object, tip)).norm() <= touch_m) {
      return {object.id, 0.0f};
    }
  }
  return {};
}

float touch_angle(TargetId current, const Vec3& tip, float touch_m, const TargetMap& room) {
  const TargetObject* object = room.find(current);
  return object != nullptr && (tip - closest_surface_point(*object, tip)).norm() <= touch_m
             ? 0.0f
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
    const Nearest best = nearest(head, gaze, nullptr, 0.0f, room, partner_head);
    if (best.id != head_target &&
        takes_over(best, current_angle(head_target, head, gaze, nullptr, 0.0f, room, partner_head),
                   config)) {
      head_target = best.id;
    }
  }
  const Hand hand = config.deictic_hand;
  if (head_tracked && (frame.valid & tracked::hand(hand)) != 0) {
    const Vec3& tip = frame.index_tip[static_cast<std::size_t>(index(hand))];
    const Vec3 ray = tip - head;
    // A hand nearer than the pointing reach designates only what it touches.
    const bool extended = ray.norm() >= config.pointing_reach_m;
    const Nearest best = extended ? nearest(head, ray, &tip, config.touch_m, room, partner_head)
                                  : touched(tip, config.touch_m, room);
    const float current =
        extended ? current_angle(hand_target, head, ray, &tip, config.touch_m, room, partner_head)
                 : touch_angle(hand_target, tip, config.touch_m, room);
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
