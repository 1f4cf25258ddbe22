#pragma once
// What the C API's opaque handles are (include/deixis/deixis.h): each wraps the C++ object it
// stands for, plus what the boundary needs (a handle's last error, the avatar's solver).
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "avatar/avatar_loader.h"
#include "core/target_map.h"
#include "deixis/deixis.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "gesture/target_selection.h"
#include "ik/avatar_solver.h"
#include "presence/remote_avatar.h"

struct deixis_mpnet {
  deixis::nn::Mpnet network;
};

struct deixis_ugnet {
  deixis::nn::Ugnet network;
};

// One solver serves every translator that wears this avatar (presence::RemoteAvatar keeps a
// pointer to it), so the avatar owns it.
struct deixis_avatar {
  deixis::avatar::Avatar avatar;
  deixis::ik::AvatarSolver solver;
};

// A target map that only grows when an object is added, and the heads of up to 254 people in a
// fixed array, so that moving objects and people between ticks allocates nothing.
struct deixis_room {
  deixis::TargetMap map;
  deixis::Vec3 partner_head = deixis::Vec3::Zero();
  std::array<deixis::PersonTarget, deixis::kMaxPersonId> people{};
  std::size_t people_count = 0;
  std::string last_error;

  deixis::LocalTargets local_targets() const {
    return {&map, partner_head, std::span<const deixis::PersonTarget>(people.data(), people_count)};
  }
};

struct deixis_translator {
  const deixis_avatar* avatar = nullptr;
  std::unique_ptr<deixis::presence::RemoteAvatar> remote;
  std::string last_error;
};

struct deixis_target_selector {
  deixis::TargetSelector selector;
  deixis::PersonId self = deixis::kNoPerson;
  std::string last_error;
};
