// The translator of one remote person through the C API: presence::RemoteAvatar (translator,
// touch contact, gaze settling, whole-avatar IK) on an avatar this library loaded.
#include <cmath>

#include "api/boundary.h"
#include "api/conversions.h"
#include "api/handles.h"

using namespace deixis;
using namespace deixis::api;

namespace {

bool finite(const Pose& p) {
  return p.rotation.allFinite() && p.translation.allFinite();
}

// The config is the caller's data: check it as untrusted input before the C++ side, which
// assumes a validated calibration, sees it.
presence::RemoteAvatarConfig config_from_c(const deixis_translator_config& c) {
  presence::RemoteAvatarConfig config;
  config.user = from_c(c.person);
  const BodyCalibration& user = config.user;
  require(std::isfinite(user.height) && user.height >= 0.5f && user.height <= 2.5f,
          "deixis_translator_config: person.height must be 0.5–2.5 m");
  require(std::isfinite(user.arm_length) && user.arm_length >= 0.2f && user.arm_length <= 1.5f,
          "deixis_translator_config: person.arm_length must be 0.2–1.5 m");
  require(finite(user.T_world_root) && user.rest_wrist_in_root[0].allFinite() &&
              user.rest_wrist_in_root[1].allFinite(),
          "deixis_translator_config: person.root or rest wrists not finite (or a zero quaternion)");
  config.T_world_floor = from_c(c.avatar_floor);
  require(finite(config.T_world_floor),
          "deixis_translator_config: avatar_floor not finite (or a zero quaternion)");
  require(c.mirror == DEIXIS_MIRROR_AUTO || c.mirror == DEIXIS_MIRROR_OFF ||
              c.mirror == DEIXIS_MIRROR_ON,
          "deixis_translator_config: mirror is not DEIXIS_MIRROR_AUTO, _OFF or _ON");
  config.mirrored = c.mirror == DEIXIS_MIRROR_ON ||
                    (c.mirror == DEIXIS_MIRROR_AUTO && user.deictic_hand == Hand::kLeft);
  config.noise_seed = c.noise_seed;
  config.touch_contact = c.touch_contact != 0;
  config.gaze_settle = c.gaze_settle != 0;
  config.pointing_settle = c.pointing_settle != 0;
  return config;
}

void fill(const presence::RemoteAvatar& remote, deixis_avatar_frame& out) {
  const AvatarFrame& f = remote.frame();
  out.visible = f.ready ? 1 : 0;
  out.held = f.held ? 1 : 0;
  out.deictic_hand = index(f.deictic_hand);
  out.head = to_c(f.deictic.T_world_head);
  out.gaze = to_c(remote.gaze());
  out.wrist = to_c(f.deictic.T_world_wrist);
  out.index_tip = to_c(f.deictic.index_tip);
  out.eye_midpoint = to_c(remote.eye_midpoint());
  out.fingertip = to_c(remote.index_fingertip());
  for (int k = 0; k < 3; ++k) {
    out.progression[k] = f.progression[static_cast<std::size_t>(k)];
  }
  out.head_weight = f.head_weight;
  out.hand_weight = f.hand_weight;
  out.head_target = f.head_target;
  out.hand_target = f.hand_target;
}

}  // namespace

extern "C" {

void deixis_translator_config_init(deixis_translator_config* config) {
  if (config == nullptr) {
    return;
  }
  *config = {};
  deixis_body_calibration_init(&config->person);
  config->avatar_floor = to_c(Pose{});
  config->noise_seed = 1;
  config->mirror = DEIXIS_MIRROR_AUTO;
  config->touch_contact = 1;
  config->gaze_settle = 1;
  config->pointing_settle = 1;
}

deixis_status deixis_translator_create(uint32_t abi_version, const deixis_mpnet* mpnet,
                                       const deixis_ugnet* ugnet, const deixis_avatar* avatar,
                                       const deixis_translator_config* config,
                                       deixis_translator** out, deixis_error* error) {
  return create_guarded(error, DEIXIS_ERROR_INVALID_ARGUMENT, [&] {
    check_abi(abi_version);
    require(out != nullptr, "deixis_translator_create: out is null");
    *out = nullptr;
    require(mpnet != nullptr && ugnet != nullptr && avatar != nullptr && config != nullptr,
            "deixis_translator_create: mpnet, ugnet, avatar and config must not be null");
    auto handle = std::make_unique<deixis_translator>();
    handle->avatar = avatar;
    handle->remote = std::make_unique<presence::RemoteAvatar>(
        mpnet->network, ugnet->network, avatar->solver, config_from_c(*config));
    *out = handle.release();
  });
}

void deixis_translator_destroy(deixis_translator* translator) {
  delete translator;
}

const char* deixis_translator_last_error(const deixis_translator* translator) {
  return translator == nullptr ? "null translator" : translator->last_error.c_str();
}

deixis_status deixis_translator_tick(deixis_translator* translator,
                                     const deixis_tracking_frame* frame, const deixis_room* room,
                                     deixis_avatar_frame* out) {
  if (translator == nullptr) {
    return DEIXIS_ERROR_INVALID_ARGUMENT;
  }
  return handle_guarded(&translator->last_error, [&] {
    require(room != nullptr && out != nullptr,
            "deixis_translator_tick: room and out must not be null");
    const LocalTargets targets = room->local_targets();
    if (frame != nullptr) {
      const TrackingFrame tracking = from_c(*frame);
      translator->remote->tick(&tracking, targets);
    } else {
      translator->remote->tick(nullptr, targets);
    }
    fill(*translator->remote, *out);
  });
}

deixis_status deixis_translator_joint_poses(const deixis_translator* translator, int32_t space,
                                            deixis_pose* out, size_t capacity) {
  if (translator == nullptr || out == nullptr) {
    return DEIXIS_ERROR_INVALID_ARGUMENT;
  }
  const presence::RemoteAvatar& remote = *translator->remote;
  const std::span<const Pose> model = remote.model_pose();
  if (capacity < model.size() ||
      (space != DEIXIS_SPACE_WORLD && space != DEIXIS_SPACE_MODEL && space != DEIXIS_SPACE_LOCAL)) {
    return DEIXIS_ERROR_INVALID_ARGUMENT;
  }
  for (std::size_t j = 0; j < model.size(); ++j) {
    switch (space) {
      case DEIXIS_SPACE_WORLD:
        out[j] = to_c(compose(remote.T_world_model(), model[j]));
        break;
      case DEIXIS_SPACE_MODEL:
        out[j] = to_c(model[j]);
        break;
      default:
        out[j] = to_c(remote.local_pose()[j]);
        break;
    }
  }
  return DEIXIS_OK;
}

deixis_status deixis_translator_model_pose(const deixis_translator* translator, deixis_pose* out) {
  if (translator == nullptr || out == nullptr) {
    return DEIXIS_ERROR_INVALID_ARGUMENT;
  }
  *out = to_c(translator->remote->T_world_model());
  return DEIXIS_OK;
}

deixis_status deixis_translator_stats_get(const deixis_translator* translator,
                                          deixis_translator_stats* out) {
  if (translator == nullptr || out == nullptr) {
    return DEIXIS_ERROR_INVALID_ARGUMENT;
  }
  const TranslatorStats& s = translator->remote->stats();
  *out = {s.ticks, s.held, s.rejected_frames, s.unknown_targets, s.restarts};
  return DEIXIS_OK;
}

}  // extern "C"
