#include "site/recorded_user.h"

#include <cstdio>

#include "core/error.h"
#include "mocap/recorded_person.h"

namespace deixis::site {

namespace {

constexpr double kRate = 30.0;  // Hz (docs/conventions.md#rates-and-windows)

}  // namespace

ScriptedUser play_recorded_user(const SiteConfig& site, double seconds) {
  const RecordedUser& recording = *site.virtual_user->recording;
  mocap::RecordedPerson person;
  try {
    person = mocap::perform_recording(*recording.bvh, recording.play, site.user.T_world_floor(),
                                      seconds, kRate);
  } catch (const Error& e) {
    throw Error(site.source + ": virtual_user.bvh: " + e.what());
  }
  ScriptedUser user;
  user.body = person.body;
  user.deictic.assign(person.frames.size(), 0.0f);
  user.frames = std::move(person.frames);
  return user;
}

std::string describe_recorded_user(const SiteConfig& site, const ScriptedUser& user) {
  const RecordedUser& r = *site.virtual_user->recording;
  char line[512];
  std::snprintf(
      line, sizeof line,
      "virtual user: %s, %zu frames at %.1f Hz (unit %s), %s, %zu samples at 30 Hz; body height "
      "%.3f m, arm %.3f m, %s hand",
      r.path.string().c_str(), r.bvh->frames(), 1.0 / r.bvh->frame_time,
      std::string(mocap::unit_name(r.unit)).c_str(),
      r.play.playback == mocap::Playback::kLoop ? "looping" : "once", user.frames.size(),
      static_cast<double>(user.body.height), static_cast<double>(user.body.arm_length),
      user.body.deictic_hand == Hand::kLeft ? "left" : "right");
  return line;
}

}  // namespace deixis::site
