#pragma once
// A site's virtual user played from a BVH recording (`virtual_user.bvh`, docs/bvh.md#driving-a-
// site) as the scripted site's user: the recorded person stands on the site's `user` spot and
// faces where it faces (mocap/recorded_person.h), sampled at 30 Hz, the rate the networks and the
// wire use. The body is what the site's hello sends (site_hello). A recording designates nothing:
// its frames carry no targets, its deictic progression is 0 (no rays drawn) and it has no steps.

#include <string>

#include "site/scripted_site.h"
#include "site/site_config.h"

namespace deixis::site {

// `site.virtual_user` must hold a recording. `seconds` > 0: that long (looping, or once and then
// held at the last frame); 0: the recording once. Throws deixis::Error naming the site file.
ScriptedUser play_recorded_user(const SiteConfig& site, double seconds);

// One line for the log: the file, its frames, unit, playback and the body sent.
std::string describe_recorded_user(const SiteConfig& site, const ScriptedUser& user);

}  // namespace deixis::site
