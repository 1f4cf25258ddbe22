#include "gesture/translator.h"

#include <algorithm>
#include <cmath>

#include "core/math/angles.h"

namespace deixis {

namespace {

bool finite(const Vec3& v) {
  return v.allFinite();
}

bool finite(const TrackingFrame& f) {
  return std::isfinite(f.time) && is_finite(f.T_world_head) && finite(f.gaze) &&
         is_finite(f.T_world_wrist[0]) && is_finite(f.T_world_wrist[1]) && finite(f.index_tip[0]) &&
         finite(f.index_tip[1]) && finite(f.head_target_position) && finite(f.hand_target_position);
}

// The avatar starts where the user is, scaled to its size.
EndEffectors initial_avatar(const EndEffectors& user, float scale) {
  EndEffectors x = user;
  for (const int at : {ee::kHandPosition, ee::kFingertip}) {
    set_vec3(x, at, get_vec3(x, at) / scale);
  }
  return x;
}

}  // namespace

Translator::Translator(nn::Mpnet mpnet, nn::Ugnet ugnet, const TranslatorConfig& config)
    : config_(config),
      loop_(mpnet, ugnet, config.user.height / config.avatar_height),
      rng_(config.noise_seed),
      needs_noise_(ugnet.needs_noise()) {}

const Vec3* LocalTargets::find_position(TargetId id) const {
  if (id == kPartnerTarget) {
    return &partner_head;
  }
  if (is_person_target(id)) {
    const PersonTarget* person = find_person(target_person(id));
    return person != nullptr ? &person->head : nullptr;
  }
  const TargetObject* object = map != nullptr ? map->find(id) : nullptr;
  return object != nullptr ? &object->position : nullptr;
}

bool Translator::usable(const TrackingFrame& frame) const {
  const std::uint8_t needed =
      tracked::kHead | tracked::kGaze | tracked::hand(config_.user.deictic_hand);
  return (frame.valid & needed) == needed && finite(frame) && frame.gaze.norm() > 1e-6f;
}

Vec3 Translator::avatar_target_position(TargetId id, const Vec3& user_position,
                                        const LocalTargets& room) {
  // Another person of the room is wherever their head is in this room (docs/target-map.md).
  if (const Vec3* here = room.find_position(id)) {
    return *here;
  }
  // Nothing designated, or this room has no copy of the object: keep the user's target where it
  // is relative to the user's root, seen from the avatar's root (what copying the pose would do).
  if (id != kNoTarget) {
    ++stats_.unknown_targets;
  }
  const Vec3 in_user_root = transform_point(inverse(config_.user.T_world_root), user_position);
  return transform_point(config_.T_world_avatar_root, in_user_root);
}

TranslationInput Translator::input_for(const TrackingFrame& frame, const LocalTargets& room) {
  TranslationInput in;
  in.user_features = mpnet_features(frame, config_.user);
  in.user_x = end_effectors(frame, config_.user);
  // UGNet's hand positions are in the user's size and scaled to the avatar's afterwards (k =
  // 1/scale in the blend), so the avatar's targets go in at the user's size too: their offsets
  // from O times scale. Angles do not change; the touch distance r does, and with it where a
  // touch lands on an avatar of another size (docs/decisions.md §32).
  const Pose& O = config_.T_world_avatar_root;
  const auto at_user_size = [&](const Vec3& p) {
    return Vec3(O.translation + loop_.scale() * (p - O.translation));
  };
  in.avatar_target = target_feature_from_root(
      O, at_user_size(avatar_target_position(frame.head_target, frame.head_target_position, room)),
      at_user_size(avatar_target_position(frame.hand_target, frame.hand_target_position, room)));
  if (config_.mirrored) {
    // The networks see the person's mirror image; finish_tick() mirrors the avatar back. The
    // MPNet angles are mirror invariant, its target feature is not.
    mirror_end_effectors(in.user_x);
    mirror_target_feature(std::span<float, kTargetFeatureSize>(
        in.user_features.data() + mf::kTarget, kTargetFeatureSize));
    mirror_target_feature(in.avatar_target);
  }
  return in;
}

std::span<const float> Translator::draw_noise() {
  if (!needs_noise_) {
    return {};
  }
  std::normal_distribution<float> normal(0.0f, 1.0f);
  for (float& v : noise_) {
    v = normal(rng_);
  }
  return noise_;
}

AvatarFrame Translator::tick(const TrackingFrame* frame, const LocalTargets& room) {
  if (begin_tick(frame, room)) {
    run_networks();
  }
  return result_;
}

void Translator::run_networks() {
  take_progression(mpnet().run(mpnet_window()).progression);
  end_tick(ugnet().run(ugnet_window(), ugnet_noise()));
}

bool Translator::begin_tick(const TrackingFrame* frame, const LocalTargets& room) {
  ++stats_.ticks;
  // A fresh result (its poses keep last tick's values until finish_tick() writes them).
  result_.ready = false;
  result_.held = false;
  result_.deictic_hand = config_.user.deictic_hand;
  result_.head_target = result_.hand_target = kNoTarget;
  result_.person_gaze_off_deg = 180.0f;
  result_.person_point_off_deg = 180.0f;
  result_.progression = {};
  result_.head_weight = result_.hand_weight = 0.0f;
  if (frame != nullptr && usable(*frame)) {
    last_valid_ = *frame;
    // Nothing designated is a point ahead of the person's head, computed here from their
    // tracking as their own site did (it does not travel on the wire; core/target_map.h).
    if (last_valid_.head_target == kNoTarget) {
      last_valid_.head_target_position = nothing_designated_point(last_valid_.T_world_head);
    }
    if (last_valid_.hand_target == kNoTarget) {
      last_valid_.hand_target_position = nothing_designated_point(last_valid_.T_world_head);
    }
    const Hand other_hand = other(config_.user.deictic_hand);
    if ((frame->valid & tracked::hand(other_hand)) != 0) {
      const Mat3& R_world_root = config_.user.T_world_root.rotation;
      const Pose& wrist = frame->T_world_wrist[index(other_hand)];
      last_other_wrist_from_head_ = {
          R_world_root.transpose() * wrist.rotation,
          R_world_root.transpose() * (wrist.translation - frame->T_world_head.translation)};
    }
  } else {
    if (frame != nullptr) {
      ++stats_.rejected_frames;
    }
    if (!started_) {
      return false;  // nothing valid yet: the avatar stays hidden
    }
    ++stats_.held;
    result_.held = true;
  }

  input_ = input_for(last_valid_, room);
  if (!started_) {
    loop_.reset(input_, initial_avatar(input_.user_x, loop_.scale()), draw_noise());
    started_ = true;
  }
  draw_noise();  // this step's draws (ugnet_noise())
  step_ = loop_.open_step(input_);
  if (std::all_of(step_.avatar_x.begin(), step_.avatar_x.end(),
                  [](float v) { return std::isfinite(v); })) {
    return true;
  }
  // Finite inputs never produced this in any test, but a pose must never carry NaN: start over
  // from the user's current pose (one by one: this tick leaves the batch).
  ++stats_.restarts;
  loop_.reset(input_, initial_avatar(input_.user_x, loop_.scale()), draw_noise());
  step_ = loop_.step(input_, draw_noise());
  if (!std::all_of(step_.avatar_x.begin(), step_.avatar_x.end(),
                   [](float v) { return std::isfinite(v); })) {
    step_.avatar_x = initial_avatar(input_.user_x, loop_.scale());
  }
  finish_tick();
  return false;
}

void Translator::take_progression(const nn::Progression& progression) {
  loop_.take_mpnet(progression, step_);
}

std::span<const float> Translator::ugnet_noise() const {
  return needs_noise_ ? std::span<const float>(noise_) : std::span<const float>{};
}

void Translator::end_tick(const nn::PoseVector& prediction) {
  loop_.end_step(prediction, step_);
  finish_tick();
}

void Translator::finish_tick() {
  result_.ready = true;
  EndEffectors avatar_x = step_.avatar_x;
  if (config_.mirrored) {
    mirror_end_effectors(avatar_x);  // back from the networks' mirror image
  }
  result_.deictic = decode_end_effectors(avatar_x, config_.T_world_avatar_root);
  result_.other_wrist_from_head = last_other_wrist_from_head_;
  result_.other_wrist_from_head.translation /= loop_.scale();
  result_.head_target = last_valid_.head_target;
  // MPNet's ET^H feature of the same frame (mirror invariant): the angle between the person's
  // gaze and their head target, in radians.
  result_.person_gaze_off_deg = input_.user_features[mf::kEyeToHeadTarget] * kDegPerRad;
  result_.hand_target = last_valid_.hand_target;
  // IT^R of the same frame: the person's eye → fingertip ray against the ray to their hand target.
  result_.person_point_off_deg = input_.user_features[mf::kFingerToHandTarget] * kDegPerRad;
  result_.progression = step_.progression;
  result_.head_weight = step_.head_weight;
  result_.hand_weight = step_.hand_weight;
}

}  // namespace deixis
