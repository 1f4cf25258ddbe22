#include "eval/deictic_observer.h"

#include <limits>

#include "eval/metrics.h"
#include "gesture/features.h"

namespace deixis::eval {

namespace {

constexpr float kMovingSpeed = 0.3f;     // m/s: the hand is on its way
constexpr float kHoldingSpeed = 0.08f;   // m/s: the hand has settled
constexpr float kTouchDistance = 0.05f;  // m from the surface in the person's room: a touch

DeicticError error_of(const Vec3& head, const Vec3& tip, const Pose& T_world_root,
                      const TargetObject& object, bool touching) {
  DeicticError e;
  if (touching) {
    e.touch_cm = 100.0 * static_cast<double>((tip - closest_surface_point(object, tip)).norm());
    return e;
  }
  const Pose T_root_world = inverse(T_world_root);
  const eval::DeicticChain chain{transform_point(T_root_world, head),
                                 transform_point(T_root_world, tip)};
  const eval::PointingError p =
      eval::pointing_error(chain, transform_point(T_root_world, object.position));
  e.horizontal_deg = p.horizontal_deg;
  e.vertical_deg = p.vertical_deg;
  return e;
}

bool touches(const TrackingFrame& frame, Hand hand, const TargetMap* remote_room) {
  const TargetObject* object = remote_room ? remote_room->find(frame.hand_target) : nullptr;
  if (object == nullptr) {
    return false;
  }
  const Vec3& tip = frame.index_tip[index(hand)];
  return (tip - closest_surface_point(*object, tip)).norm() < kTouchDistance;
}

// A hand back in the upright posture holds nothing (the paper's own threshold for the distance
// feature d): a person who points and then rests keeps the object as their hand target.
bool away_from_rest(const TrackingFrame& frame, const presence::PoseCopy& copy) {
  const BodyCalibration& user = copy.user();
  const int hand = index(user.deictic_hand);
  const Vec3 rest = transform_point(user.T_world_root, user.rest_wrist_in_root[hand]);
  return (frame.T_world_wrist[hand].translation - rest).norm() > kNearRestDistance;
}

}  // namespace

AvatarChain chain_of(const presence::RemoteAvatar& avatar) {
  return {avatar.eye_midpoint(),
          avatar.index_fingertip(),
          avatar.T_world_root(),
          true,
          avatar.frame().deictic.T_world_head.translation,
          avatar.frame().deictic.index_tip};
}

DeicticError unmeasured() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  return {nan, nan, nan};
}

DeicticObserver::DeicticObserver(std::size_t capacity) {
  samples_.reserve(capacity);
}

void DeicticObserver::observe(const TrackingFrame& frame, std::uint32_t sequence, double time,
                              const AvatarChain& avatar, const presence::PoseCopy& copy,
                              const TargetMap& room, const TargetMap* remote_room) {
  const Hand hand = copy.user().deictic_hand;
  const Vec3& tip = frame.index_tip[index(hand)];
  // Speed on the sender's clock: frames that arrive late play in a burst at one local time, which
  // would read as a hand standing still.
  const float dt = static_cast<float>(frame.time - previous_sender_time_);
  const bool has_speed = has_previous_ && dt > 0.0f;
  const float speed = has_speed ? (tip - previous_tip_).norm() / dt : 0.0f;
  has_previous_ = true;
  previous_tip_ = tip;
  previous_sender_time_ = frame.time;

  if (frame.hand_target != target_) {
    end_hold();
    target_ = frame.hand_target;
  }
  const TargetObject* object = room.find(target_);
  if (target_ <= kPartnerTarget || object == nullptr) {
    return;  // the partner is looked at, not pointed at; an object this room lacks is skipped
  }
  if (!has_speed) {
    return;  // the first frame of a stream, or one not later than the last: no speed to judge
  }
  if (speed > kMovingSpeed) {
    if (phase_ == Phase::kHolding) {
      commit();  // the hand moves off: the hold ended on the last frame
    }
    phase_ = Phase::kMoving;
  } else if (speed < kHoldingSpeed && phase_ != Phase::kWaiting && away_from_rest(frame, copy)) {
    if (phase_ != Phase::kHolding) {
      hold_start_ = time;
    }
    phase_ = Phase::kHolding;
    candidate_ =
        measure(frame, sequence, time, avatar, copy, *object, touches(frame, hand, remote_room));
    // The person's own gesture against their copy of the target, in their room.
    const TargetObject* theirs = remote_room ? remote_room->find(target_) : nullptr;
    candidate_.person = theirs == nullptr
                            ? unmeasured()
                            : error_of(frame.T_world_head.translation, tip,
                                       copy.user().T_world_root, *theirs, candidate_.touching);
  }
}

void DeicticObserver::interrupt() {
  end_hold();
  has_previous_ = false;
}

void DeicticObserver::end_hold() {
  if (phase_ == Phase::kHolding) {
    commit();
  }
  phase_ = Phase::kWaiting;
}

void DeicticObserver::commit() {
  if (samples_.size() < samples_.capacity()) {
    samples_.push_back(candidate_);
  } else {
    ++dropped_;
  }
}

DeicticSample DeicticObserver::measure(const TrackingFrame& frame, std::uint32_t sequence,
                                       double time, const AvatarChain& avatar,
                                       const presence::PoseCopy& copy, const TargetObject& object,
                                       bool touching) const {
  const Hand hand = copy.user().deictic_hand;
  DeicticSample s;
  s.time = time;
  s.sequence = sequence;
  s.target = object.id;
  s.touching = touching;
  s.avatar = error_of(avatar.eye_midpoint, avatar.fingertip, avatar.T_world_root, object, touching);
  s.copy =
      error_of(copy.point(frame.T_world_head.translation), copy.point(frame.index_tip[index(hand)]),
               copy.T_world_origin(), object, touching);
  s.network = avatar.has_network ? error_of(avatar.network_head, avatar.network_fingertip,
                                            avatar.T_world_root, object, touching)
                                 : unmeasured();
  s.ik_fingertip_cm =
      avatar.has_network
          ? 100.0 * static_cast<double>((avatar.fingertip - avatar.network_fingertip).norm())
          : std::numeric_limits<double>::quiet_NaN();
  s.hold_s = time - hold_start_;
  return s;
}

}  // namespace deixis::eval
