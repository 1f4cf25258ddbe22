#include "sim/sim_user.h"

#include <algorithm>
#include <cmath>

#include "capture/body.h"
#include "capture/posture.h"
#include "capture/recorder.h"

namespace deixis::sim {

namespace {

constexpr float kPartnerSize = 0.2f;      // m: the partner's head as a target object
constexpr float kLookDistance = 2.5f;     // m: where a free look's fixation point lies
constexpr float kMinLookChange = 0.026f;  // rad (1.5°): smaller mouse moves are not a shift
constexpr float kMaxYaw = 1.75f;          // rad: about 100° to either side
constexpr float kMaxPitch = 1.05f;        // rad: about 60° up or down

float angle_between(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0f, 1.0f));
}

}  // namespace

SimUser::SimUser(const capture::Subject& subject, const SimUserScene& scene, std::uint64_t seed)
    : body_(capture::make_body(subject)),
      rng_(seed),
      motion_rng_(rng_.fork(1)),
      motion_(body_, scene.T_world_floor, motion_rng_),
      actor_(motion_, labels_, rng_),
      targets_(scene.objects),
      calibration_(capture::calibrate(motion_)) {
  targets_.push_back({kPartnerTarget, "partner", TargetKind::kSphere, scene.partner_head,
                      Vec3::Constant(kPartnerSize)});
  // Upright, facing the other person, as the scripted users start (virtual_user.h): the
  // translator needs a head and a hand target in every frame.
  labels_.head_target.set(0.0, kPartnerTarget);
  labels_.hand_target.set(0.0, kPartnerTarget);
  wanted_ = planned_ = angles_toward(scene.partner_head);
}

const TargetObject* SimUser::find(TargetId id) const {
  for (const TargetObject& t : targets_) {
    if (t.id == id) {
      return &t;
    }
  }
  return nullptr;
}

Vec3 SimUser::look_direction(LookAngles look) const {
  const Vec3 local(-std::sin(look.yaw) * std::cos(look.pitch), std::sin(look.pitch),
                   -std::cos(look.yaw) * std::cos(look.pitch));
  return motion_.stance().rotation * local;
}

LookAngles SimUser::angles_toward(const Vec3& p_world) const {
  const Vec3 d = motion_.stance().rotation.transpose() *
                 (p_world - calibration_.T_world_root.translation).normalized();
  return {std::atan2(-d.x(), -d.z()), std::asin(std::clamp(d.y(), -1.0f, 1.0f))};
}

void SimUser::look(LookAngles look) {
  wanted_ = {std::clamp(look.yaw, -kMaxYaw, kMaxYaw),
             std::clamp(look.pitch, -kMaxPitch, kMaxPitch)};
}

void SimUser::update(double t) {
  const Vec3 wanted = look_direction(wanted_);
  if (angle_between(wanted, look_direction(planned_)) < kMinLookChange ||
      motion_.gaze.end_time() > t || motion_.head.end_time() > t) {
    return;
  }
  // One gaze shift as people make them (actor.h): the eyes lead with a saccade, the head follows
  // a few tens of ms later and takes most of what exceeds the eyes' comfortable range.
  const capture::Posture now = motion_.posture_at(t);
  const Vec3 ahead = now.R_world_head * Vec3(0, 0, -1);
  const float amplitude = angle_between(ahead, wanted);
  const capture::Style& style = body_.subject.style;
  const float head_amplitude =
      std::clamp(style.head_share * std::max(0.0f, amplitude - style.eye_only_range),
                 std::max(0.0f, amplitude - 0.45f), amplitude);
  const Vec3 eyes = calibration_.T_world_root.translation;
  motion_.gaze.move(t, std::min(0.025 + 0.13 * static_cast<double>(amplitude), 0.20),
                    capture::GazeKey{eyes + kLookDistance * wanted, false});
  if (head_amplitude > 0.02f) {
    const float share = head_amplitude / amplitude;
    motion_.head.move(
        t + 0.03, 0.22 + 0.28 * static_cast<double>(head_amplitude),
        capture::HeadKey{
            Quat(capture::look_rotation(capture::slerp_direction(ahead, wanted, share))), false});
  }
  planned_ = wanted_;
}

void SimUser::look_at_partner(double t) {
  const TargetObject& partner = *find(kPartnerTarget);
  actor_.look_at(t, partner);
  wanted_ = planned_ = angles_toward(partner.position);
}

std::string SimUser::point(double t, TargetId id) {
  const TargetObject* target = find(id);
  if (target == nullptr) {
    return "no object " + std::to_string(id);
  }
  actor_.point(t, *target, true);
  wanted_ = planned_ = angles_toward(target->position);
  return {};
}

std::string SimUser::touch(double t, TargetId id) {
  const TargetObject* target = find(id);
  if (target == nullptr) {
    return "no object " + std::to_string(id);
  }
  // Checked first: the actor would refuse only after it had begun labelling the reach.
  if (!capture::touch_torso(motion_, *target)) {
    return target->name + " is out of reach";
  }
  actor_.touch(t, *target, true);
  wanted_ = planned_ = angles_toward(target->position);
  return {};
}

void SimUser::explain(double t, double seconds) {
  // As a scripted user explains (virtual_user.cpp): to the other person, the hand leaving what it
  // designated, with small nods.
  const TargetObject& listener = *find(kPartnerTarget);
  if (labels_.head_target.last() != kPartnerTarget) {
    look_at_partner(t);
  }
  const TargetId current = labels_.hand_target.last();
  const TargetObject* leaving = find(current);
  const double hands_end =
      actor_.gesticulate(t + 0.1, seconds, rng_.chance(0.4),
                         leaving != nullptr ? leaving->position : listener.position,
                         current != kPartnerTarget ? kPartnerTarget : kNoTarget);
  actor_.nod(t + 0.2, hands_end - t - 0.2);
}

void SimUser::rest(double t) {
  actor_.rest(t);
}

TrackingFrame SimUser::sample(double t) const {
  const capture::Posture posture = motion_.posture_at(t);
  TrackingFrame f = capture::track(posture, capture::solve_joints(body_, posture));
  f.time = t;
  f.head_target = labels_.head_target.at(t);
  f.hand_target = labels_.hand_target.at(t);
  const TargetObject* head = find(f.head_target);
  const TargetObject* hand = find(f.hand_target);
  f.head_target_position = head != nullptr ? head->position : Vec3::Zero();
  f.hand_target_position = hand != nullptr ? hand->position : Vec3::Zero();
  return f;
}

}  // namespace deixis::sim
