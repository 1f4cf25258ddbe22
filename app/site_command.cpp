// `deixis host` / `deixis join`: one headless site whose user is the site's scripted person
// (docs/demo.md). This file performs the script (the capture's virtual user: a tool the site
// runtime never links), or plays the site's BVH recording (site/recorded_user.h), and hands
// the performance to the scripted site (site/scripted_site.h), which runs the 30 Hz loop through
// the one site runtime.

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "app/commands.h"
#include "capture/subject.h"
#include "capture/virtual_user.h"
#include "core/error.h"
#include "site/recorded_user.h"
#include "site/remote_people.h"
#include "site/scripted_site.h"

namespace deixis::app {

namespace {

namespace fs = std::filesystem;

// The site's virtual user performs its script in this room, with the remote person's avatar
// (target 0) where this room shows it; repeated to cover `seconds` (0: once). The site has one
// (run_site checks).
site::ScriptedUser perform_virtual_user(const site::SiteRunOptions& o, const site::SiteAssets& a) {
  const site::VirtualUser& user = *a.site.virtual_user;
  if (user.recording) {
    return site::play_recorded_user(a.site, o.seconds);
  }
  // The k-th person the script names is aimed at where the avatar on spot k stands; at run time
  // the target becomes whoever of that site is in the room (site/remote_people.h).
  std::vector<capture::ScenePerson> people;
  for (std::size_t k = 0; k < user.people.size(); ++k) {
    people.push_back(
        {user.people[k], script_person_target(k), site::expected_person_head(a.site, a.solver, k)});
  }
  const capture::VirtualUserScene scene{a.site.user.T_world_floor(), a.site.target_map.objects,
                                        a.T_world_remote_origin.translation, people};
  capture::ScriptPerformance performance;
  try {
    performance = capture::perform_script(capture::find_subject(user.subject), user.script, scene,
                                          user.seed, o.seconds);
  } catch (const Error& e) {
    throw Error(o.site.string() + ": " + e.what());
  }
  site::ScriptedUser scripted;
  scripted.body = performance.sequence.calibration;
  scripted.frames = std::move(performance.sequence.frames);
  scripted.deictic.reserve(performance.sequence.labels.size());
  for (const capture::Labels& labels : performance.sequence.labels) {
    scripted.deictic.push_back(labels[1]);
  }
  scripted.steps = std::move(performance.steps);
  return scripted;
}

void use_site_logger(const site::SiteRunOptions& o, const std::string& site) {
  auto logger = spdlog::stderr_color_mt("deixis");
  spdlog::set_default_logger(logger);
  spdlog::set_pattern(std::string("[%H:%M:%S.%e] [") + (o.host ? "host " : "join ") + site +
                      "] %v");
}

}  // namespace

int run_site(const site::SiteRunOptions& options) {
  std::optional<site::SiteAssets> assets;
  site::ScriptedUser user;
  try {
    site::SiteConfig site = site::read_site_config(options.site);
    if (!site.virtual_user) {
      throw Error(options.site.string() +
                  ": virtual_user: missing (host and join need a scripted user; a headset front "
                  "end is not part of this build)");
    }
    assets.emplace(site::load_site_assets(std::move(site), options.weights_dir));
    site::load_run_avatars(*assets, options);
    user = perform_virtual_user(options, *assets);
    use_site_logger(options, assets->site.site);
    if (assets->site.virtual_user->recording) {
      spdlog::info("{}", site::describe_recorded_user(assets->site, user));
    }
    for (const site::BehindSpot& b : site::behind_spots(assets->site)) {
      spdlog::warn("{}", site::describe(assets->site, b));
    }
    std::error_code ec;
    fs::create_directories(options.out_dir, ec);
    if (ec || !fs::is_directory(options.out_dir)) {
      throw Error(options.out_dir.string() + ": cannot create the output directory");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "deixis %s: %s\n", options.host ? "host" : "join", e.what());
    return 2;
  }
  try {
    site::run_scripted_site(options, *assets, user);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "deixis %s: %s\n", options.host ? "host" : "join", e.what());
    return 1;
  }
}

}  // namespace deixis::app
