// `deixis eval --live-rooms N` (docs/live-rooms.md): the translator measured end to end
// in rooms nobody designed. For each of N room pairs generated under stated rules
// (eval/room_pairs.h) this process starts itself as `deixis host` (room A) and `deixis join`
// (room B) on loopback, as a user would, waits for both, and reads the completion states each
// site's observer recorded of the other person (session.json, `remote_completions`). The pooled
// completions become live_rooms.md, live_rooms.json and live_rooms.png (eval/live_rooms.h).

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>

#include "app/child_process.h"
#include "app/commands.h"
#include "capture/subject.h"
#include "core/error.h"
#include "eval/live_rooms.h"
#include "eval/room_pairs.h"
#include "eval/room_rules_file.h"

namespace deixis::app {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr double kListenTimeout = 60.0;  // s for the host's setup (weights, avatar, script)

// Who performs in pair `k`: two different subjects of `names`, turning with k (and the seed), so
// that every subject performs in both rooms over enough pairs.
std::pair<eval::ScriptedPerson, eval::ScriptedPerson> performers(
    const std::vector<std::string>& names, std::uint64_t seed, int k) {
  const std::size_t n = names.size();
  const std::size_t first = (static_cast<std::size_t>(seed) + 2 * static_cast<std::size_t>(k)) % n;
  const std::size_t second =
      n > 1 ? (first + 1 + static_cast<std::size_t>(k) / n % (n - 1)) % n : first;
  const auto person = [](const std::string& name) {
    return eval::ScriptedPerson{name, capture::find_subject(name).handedness};
  };
  return {person(names[first]), person(names[second])};
}

std::vector<std::string> held_out_subjects() {
  std::vector<std::string> names;
  for (const capture::Subject& s : capture::test_subjects()) {
    names.push_back(s.name);
  }
  return names;
}

// A passphrase nobody else knows, so that the pairs' sessions are sealed as users' are.
std::string fresh_passphrase() {
  std::random_device device;
  char buffer[33];
  for (int i = 0; i < 4; ++i) {
    std::snprintf(buffer + 8 * i, 9, "%08x", device());
  }
  return buffer;
}

json read_session(const fs::path& path) {
  std::ifstream in(path);
  if (!in) {
    throw Error(path.string() + ": missing (the site wrote no report)");
  }
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw Error(path.string() + ": not JSON: " + e.what());
  }
}

double number_or_nan(const json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>()
                                          : std::numeric_limits<double>::quiet_NaN();
}

// The completions `observer` (room index) recorded of the other room's person.
void collect_completions(const eval::RoomPair& pair, std::size_t observer, const json& session,
                         std::vector<eval::LiveCompletion>& out) {
  const eval::GeneratedRoom& room = pair.rooms[observer];
  const eval::GeneratedRoom& performer = pair.rooms[1 - observer];
  for (const json& c : session.at("remote_completions")) {
    eval::LiveCompletion live;
    live.pair = pair.index;
    live.observer = room.site;
    live.subject = performer.user.subject;
    live.target = c.at("target").get<TargetId>();
    live.touch = c.at("kind").get<std::string>() == "touch";
    live.time_s = c.at("time_s").get<double>();
    const json& avatar = c.at("avatar");
    const json& copy = c.at("copy");
    const json none = json::object();  // a site too old to report the stages
    const json& network = c.contains("network") ? c.at("network") : none;
    const json& person = c.contains("person") ? c.at("person") : none;
    live.avatar_he = number_or_nan(avatar, "horizontal_deg");
    live.avatar_ve = number_or_nan(avatar, "vertical_deg");
    live.avatar_cm = number_or_nan(avatar, "touch_cm");
    live.copy_he = number_or_nan(copy, "horizontal_deg");
    live.copy_ve = number_or_nan(copy, "vertical_deg");
    live.copy_cm = number_or_nan(copy, "touch_cm");
    live.network_he = number_or_nan(network, "horizontal_deg");
    live.network_ve = number_or_nan(network, "vertical_deg");
    live.network_cm = number_or_nan(network, "touch_cm");
    live.person_he = number_or_nan(person, "horizontal_deg");
    live.person_ve = number_or_nan(person, "vertical_deg");
    live.person_cm = number_or_nan(person, "touch_cm");
    live.ik_fingertip_cm = number_or_nan(c, "ik_fingertip_cm");
    live.hold_s = number_or_nan(c, "hold_s");
    for (const eval::RoomObject& o : room.objects) {
      if (o.id == live.target) {
        live.geometry = eval::geometry_from_avatar(room, o.position);
      }
    }
    out.push_back(std::move(live));
  }
}

// Touches the performer's script completed against those the other site observed.
eval::TouchTally tally_touches(const eval::RoomPair& pair, std::size_t performer,
                               const json& own_session, const json& other_session) {
  const eval::GeneratedRoom& room = pair.rooms[performer];
  eval::TouchTally t{pair.index, room.site, room.user.subject, 0, 0};
  for (const json& step : own_session.at("own_steps")) {
    t.performed += step.at("action").get<std::string>() == "touch" ? 1 : 0;
  }
  for (const json& c : other_session.at("remote_completions")) {
    t.observed += c.at("kind").get<std::string>() == "touch" &&
                          c.at("target").get<TargetId>() == room.own_touch
                      ? 1
                      : 0;
  }
  return t;
}

void run_pair(const LiveRoomsOptions& o, const fs::path& self, const fs::path& dir) {
  const auto site_args = [&](const char* file, const char* out) {
    return std::vector<std::string>{
        "--site",        (dir / file).string(),  "--out",  (dir / out).string(),
        "--weights-dir", o.weights_dir.string(), "--wait", "60",
        "--no-video"};
  };
  run_host_and_join(self, site_args("a.json", "A"), site_args("b.json", "B"), kListenTimeout,
                    o.timeout);
}

}  // namespace

int run_eval_live_rooms(const LiveRoomsOptions& o) {
  const std::vector<std::string> names = o.subjects.empty() ? held_out_subjects() : o.subjects;
  try {
    for (const std::string& name : names) {
      capture::find_subject(name);  // an unknown subject is a bad flag, before anything runs
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "deixis eval: --subjects: %s\n", e.what());
    return 2;
  }
  eval::RoomRules rules;
  try {
    if (!o.rules.empty()) {
      rules = eval::read_room_rules(o.rules);
    }
    // Rules that leave no room are refused now, naming the rule, not after a pair has run.
    const auto [a, b] = performers(names, o.seed, 0);
    static_cast<void>(eval::generate_room_pair(rules, o.seed, 0, a, b));
  } catch (const Error& e) {
    std::fprintf(stderr, "deixis eval: --rules: %s\n", e.what());
    return 2;
  }
  try {
    const fs::path self = own_executable();
    pass_passphrase(fresh_passphrase());
    std::vector<eval::LiveCompletion> completions;
    std::vector<eval::TouchTally> touches;
    for (int k = 0; k < o.pairs; ++k) {
      const auto [a, b] = performers(names, o.seed, k);
      const eval::RoomPair pair = eval::generate_room_pair(rules, o.seed, k, a, b);
      char name[32];
      std::snprintf(name, sizeof name, "pair-%03d", k);
      const fs::path dir = o.out_dir / "live_rooms" / name;
      eval::write_room_pair(pair, o.avatar, dir);
      std::printf("pair %d/%d: A %s, B %s (%s)\n", k + 1, o.pairs, a.subject.c_str(),
                  b.subject.c_str(), dir.string().c_str());
      std::fflush(stdout);
      run_pair(o, self, dir);
      const json session_a = read_session(dir / "A" / "session.json");
      const json session_b = read_session(dir / "B" / "session.json");
      const std::size_t before = completions.size();
      collect_completions(pair, 0, session_a, completions);
      collect_completions(pair, 1, session_b, completions);
      touches.push_back(tally_touches(pair, 0, session_a, session_b));
      touches.push_back(tally_touches(pair, 1, session_b, session_a));
      std::printf("  %zu completions observed\n", completions.size() - before);
    }
    eval::LiveSummary summary = eval::summarize(completions, touches, o.pairs);
    summary.rules = eval::room_rules_json(rules);
    const fs::path md = o.out_dir / "live_rooms.md";
    std::ofstream(md) << eval::live_rooms_markdown(summary, o.command_line);
    eval::write_live_rooms_json(summary, completions, touches, o.out_dir / "live_rooms.json");
    eval::write_live_rooms_figure(completions, o.out_dir / "live_rooms.png");
    const eval::LiveGroup& all = summary.all;
    std::printf(
        "pointing: %zu completions, HE mean %.2f p90 %.2f worst %.2f deg, VE mean %.2f p90 %.2f "
        "worst %.2f deg (copy-paste HE %.2f, VE %.2f)\n",
        all.he.count, all.he.mean, all.he.p90, all.he.worst, all.ve.mean, all.ve.p90, all.ve.worst,
        all.copy_he.mean, all.copy_ve.mean);
    std::printf(
        "touching: %zu completions, mean %.2f cm, worst %.2f cm (copy-paste %.2f cm); "
        "%d of %d touches observed\n",
        all.touch_cm.count, all.touch_cm.mean, all.touch_cm.worst, all.copy_touch_cm.mean,
        summary.touches_observed, summary.touches_performed);
    std::printf("wrote %s, live_rooms.json, live_rooms.png\n", md.string().c_str());
    return 0;
  } catch (const Error& e) {
    std::fprintf(stderr, "deixis eval: %s\n", e.what());
    return 1;
  }
}

}  // namespace deixis::app
