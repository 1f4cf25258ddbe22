#pragma once
// A site's virtual user performed in its own room at 30 Hz, as `deixis host --site` performs
// it: the scripted person the process tests put in a headset (the test runtime's script in
// xr_site_test, Monado's remote driver in monado_test).

#include <filesystem>
#include <vector>

#include "avatar/avatar_loader.h"
#include "capture/subject.h"
#include "capture/virtual_user.h"
#include "core/tracking.h"
#include "presence/remote_avatar.h"
#include "site/site_config.h"

namespace deixis::app {

inline std::vector<TrackingFrame> performed_virtual_user(const std::filesystem::path& site_file) {
  const site::SiteConfig a = site::read_site_config(site_file);
  const ik::AvatarSolver solver = ik::AvatarSolver::build(avatar::load_avatar(a.avatar_path).rig);
  const Pose partner = presence::avatar_origin(solver, a.remote_avatar.T_world_floor());
  const capture::VirtualUserScene scene{a.user.T_world_floor(), a.target_map.objects,
                                        partner.translation};
  const site::VirtualUser& user = *a.virtual_user;
  return capture::perform_script(capture::find_subject(user.subject), user.script, scene, user.seed)
      .sequence.frames;
}

}  // namespace deixis::app
