#include "gesture/target_selection.h"

#include <cmath>
#include <limits>

#include "core/math/angles.h"

namespace deixis {

namespace {

// A candidate's position, or null when it is not one (gone from the room, never there).
const Vec3* candidate_position(TargetId id, const SelectionCandidates& c) {
  if (id == kPartnerTarget) {
    return c.partner_head;
  }
  if (is_person_target(id)) {
    const PersonId person = target_person(id);
    const PersonTarget* p = person != c.self ? find_person(c.people, person) : nullptr;
    return p != nullptr ? &p->head : nullptr;
  }
  const TargetObject* object = c.map != nullptr ? c.map->find(id) : nullptr;
  return object != nullptr ? &object->position : nullptr;
}

// Where a target is for the frame: the candidate's position, else the other person's head (a
// direct session's target stays "the other person" until one is designated), else nothing's
// point ahead of the user's head.
Vec3 position_of(TargetId id, const SelectionCandidates& c, const Pose& T_world_head) {
  if (const Vec3* p = candidate_position(id, c)) {
    return *p;
  }
  if (c.partner_head != nullptr) {
    return *c.partner_head;
  }
  return nothing_designated_point(T_world_head);
}

// In a room nobody is "the other person": a target that is not (or no longer) a candidate there,
// the initial kPartnerTarget included, is nothing designated. A direct session keeps it.
TargetId in_this_room(TargetId id, const SelectionCandidates& c) {
  if (c.partner_head != nullptr || candidate_position(id, c) != nullptr) {
    return id;
  }
  return kNoTarget;
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
// else its angle off the ray, ∞ without a ray. `object` is null for a person.
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

// The candidate nearest to being designated (the first of equals: the other person, the
// objects, then the people), and its angle.
Nearest nearest(const Designation& d, const SelectionCandidates& c) {
  Nearest best;
  const auto consider = [&](TargetId id, const TargetObject* object, const Vec3& centre) {
    const float a = angle_to(d, object, centre);
    if (best.id == kNoTarget || a < best.angle_deg) {
      best = {id, a};
    }
  };
  if (c.partner_head != nullptr) {
    consider(kPartnerTarget, nullptr, *c.partner_head);
  }
  if (c.map != nullptr) {
    for (const TargetObject& object : c.map->objects) {
      consider(object.id, &object, object.position);
    }
  }
  for (const PersonTarget& person : c.people) {
    if (person.id != c.self && person.id != kNoPerson) {
      consider(person_target(person.id), nullptr, person.head);
    }
  }
  return best;
}

// The current target's angle (∞ when it is not a candidate in this room).
float current_angle(TargetId current, const Designation& d, const SelectionCandidates& c) {
  const Vec3* position = candidate_position(current, c);
  if (position == nullptr) {
    return std::numeric_limits<float>::infinity();
  }
  const TargetObject* object =
      current != kPartnerTarget && !is_person_target(current) && c.map != nullptr
          ? c.map->find(current)
          : nullptr;
  return angle_to(d, object, *position);
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

void TargetSelector::select(TrackingFrame& frame, const SelectionCandidates& candidates) {
  head_target = in_this_room(head_target, candidates);
  hand_target = in_this_room(hand_target, candidates);
  const Vec3 head = frame.T_world_head.translation;
  const bool head_tracked = (frame.valid & tracked::kHead) != 0;
  if (head_tracked) {
    const Vec3 gaze = (frame.valid & tracked::kGaze) != 0
                          ? frame.gaze
                          : Vec3(frame.T_world_head.rotation * Vec3(0, 0, -1));
    const Designation eyes{head, gaze};
    const Nearest best = nearest(eyes, candidates);
    if (best.id != head_target &&
        takes_over(best, current_angle(head_target, eyes, candidates), config)) {
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
    const Nearest best = nearest(finger, candidates);
    const float current = current_angle(hand_target, finger, candidates);
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
  frame.head_target_position = position_of(head_target, candidates, frame.T_world_head);
  frame.hand_target_position = position_of(hand_target, candidates, frame.T_world_head);
}

}  // namespace deixis
