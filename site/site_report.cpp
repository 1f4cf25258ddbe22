#include "site/site_report.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "net/protocol.h"

namespace deixis::site {

namespace {

using json = nlohmann::json;

// JSON has no NaN: a missing figure is null.
json number(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}

json timing(const std::vector<double>& ms) {
  return {{"count", ms.size()},
          {"p50", number(percentile(ms, 50))},
          {"p99", number(percentile(ms, 99))}};
}

json error_json(const eval::DeicticError& e, bool touching) {
  if (touching) {
    return {{"touch_cm", number(e.touch_cm)}};
  }
  return {{"horizontal_deg", number(e.horizontal_deg)}, {"vertical_deg", number(e.vertical_deg)}};
}

struct Means {
  std::size_t count = 0;
  double avatar_h = 0, avatar_v = 0, avatar_cm = 0, copy_h = 0, copy_v = 0, copy_cm = 0;
};

Means means(const std::vector<eval::DeicticSample>& samples, bool touching) {
  Means m;
  for (const eval::DeicticSample& s : samples) {
    if (s.touching != touching) {
      continue;
    }
    ++m.count;
    m.avatar_h += s.avatar.horizontal_deg;
    m.avatar_v += s.avatar.vertical_deg;
    m.avatar_cm += s.avatar.touch_cm;
    m.copy_h += s.copy.horizontal_deg;
    m.copy_v += s.copy.vertical_deg;
    m.copy_cm += s.copy.touch_cm;
  }
  const double n =
      m.count > 0 ? static_cast<double>(m.count) : std::numeric_limits<double>::quiet_NaN();
  for (double* v : {&m.avatar_h, &m.avatar_v, &m.avatar_cm, &m.copy_h, &m.copy_v, &m.copy_cm}) {
    *v /= n;
  }
  return m;
}

json means_json(const Means& m, bool touching) {
  if (touching) {
    return {{"count", m.count},
            {"avatar_touch_cm", number(m.avatar_cm)},
            {"copy_touch_cm", number(m.copy_cm)}};
  }
  return {{"count", m.count},
          {"avatar_horizontal_deg", number(m.avatar_h)},
          {"avatar_vertical_deg", number(m.avatar_v)},
          {"copy_horizontal_deg", number(m.copy_h)},
          {"copy_vertical_deg", number(m.copy_v)}};
}

// Connections a host did not serve (docs/security.md): how many, and what became of them.
json strangers_json(const net::StrangerStats& s) {
  return {{"connected", s.connected}, {"turned_away", s.over_budget},    {"evicted", s.evicted},
          {"timed_out", s.timed_out}, {"held_back", s.held_back},        {"told_busy", s.busy},
          {"chatty", s.chatty},       {"salts_rotated", s.salts_rotated}};
}

json network_json(const SiteRecord& r) {
  const std::size_t frame_bytes = net::kTrackingBytes + (r.sealed ? net::kSealOverheadBytes : 0);
  const double datagram = r.traffic.sent_datagrams > 0
                              ? static_cast<double>(r.traffic.sent_bytes) /
                                    static_cast<double>(r.traffic.sent_datagrams)
                              : std::numeric_limits<double>::quiet_NaN();
  return {{"packets_sent", r.net.packets_sent},
          {"packets_received", r.net.packets_received},
          {"tracking_sent", r.net.tracking_sent},
          {"tracking_received", r.net.tracking_received},
          {"frames_played", r.jitter.played},
          {"frames_lost", r.jitter.missed},
          {"late", r.jitter.late},
          {"duplicates", r.jitter.duplicates},
          {"rejected", r.rejected},
          {"sealed", r.sealed},
          {"bytes_per_frame", frame_bytes},
          {"udp_payload_bytes_per_datagram", number(datagram)},
          {"bytes_sent", r.net.bytes_sent},
          {"bytes_received", r.net.bytes_received},
          {"floods_cut", r.net.floods_cut},
          {"auth_failures", r.auth_failures},
          {"strangers", strangers_json(r.strangers)}};
}

json steps_json(const std::vector<StepTiming>& steps) {
  json out = json::array();
  for (const StepTiming& s : steps) {
    out.push_back({{"step", s.step},
                   {"cycle", s.cycle},
                   {"action", std::string(action_name(s.action))},
                   {"target", s.target},
                   {"complete_s", s.complete}});
  }
  return out;
}

json completions_json(const std::vector<eval::DeicticSample>& samples) {
  json out = json::array();
  for (const eval::DeicticSample& s : samples) {
    out.push_back({{"time_s", s.time},
                   {"sequence", s.sequence},
                   {"target", s.target},
                   {"kind", s.touching ? "touch" : "point"},
                   {"avatar", error_json(s.avatar, s.touching)},
                   {"copy", error_json(s.copy, s.touching)},
                   {"network", error_json(s.network, s.touching)},
                   {"ik_fingertip_cm", number(s.ik_fingertip_cm)},
                   {"person", error_json(s.person, s.touching)},
                   {"hold_s", number(s.hold_s)}});
  }
  return out;
}

// One remote site's person: counters and the mean pointing errors of their avatar at the
// completion states observed (null when none was).
// The mean gaze error over the holds, over those on people (person targets), as JSON numbers
// (null for none) and the holds themselves.
json gazes_json(const std::vector<GazeSample>& gazes, json& entry) {
  double all = 0.0, at_people = 0.0, network = 0.0;
  std::size_t people = 0;
  json list = json::array();
  for (const GazeSample& g : gazes) {
    all += g.error_deg;
    network += g.network_error_deg;
    if (is_person_target(g.target)) {
      at_people += g.error_deg;
      ++people;
    }
    list.push_back({{"target", g.target},
                    {"error_deg", number(g.error_deg)},
                    {"network_error_deg", number(g.network_error_deg)}});
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  entry["gaze_count"] = gazes.size();
  entry["gaze_deg"] = number(gazes.empty() ? nan : all / static_cast<double>(gazes.size()));
  entry["gaze_at_people_deg"] = number(people == 0 ? nan : at_people / static_cast<double>(people));
  entry["gaze_network_deg"] =
      number(gazes.empty() ? nan : network / static_cast<double>(gazes.size()));
  return list;
}

json people_json(const std::vector<PersonRecord>& people) {
  json out = json::array();
  for (const PersonRecord& p : people) {
    const Means m = means(p.completions, false);
    const Means t = means(p.completions, true);
    out.push_back({{"site", p.site},
                   {"frames_played", p.frames_played},
                   {"frames_missed", p.frames_missed},
                   {"visible_ticks", p.visible_ticks},
                   {"stays", p.stays},
                   {"height_m", p.height_m},
                   {"arm_length_m", p.arm_length_m},
                   {"pointing_count", m.count},
                   {"he_deg", number(m.avatar_h)},
                   {"ve_deg", number(m.avatar_v)},
                   {"copy_he_deg", number(m.copy_h)},
                   {"copy_ve_deg", number(m.copy_v)},
                   {"touching_count", t.count},
                   {"touch_cm", number(t.avatar_cm)},
                   {"completions_dropped", p.completions_dropped}});
    out.back()["gazes"] = gazes_json(p.gazes, out.back());
    out.back()["avatar"] = {{"source", p.avatar.source},
                            {"hash", p.avatar.hash.empty() ? json(nullptr) : json(p.avatar.hash)},
                            {"joints", p.avatar.joints}};
  }
  return out;
}

}  // namespace

double percentile(std::vector<double> values, double p) {
  if (values.empty()) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  std::sort(values.begin(), values.end());
  const double rank = std::ceil(p / 100.0 * static_cast<double>(values.size()));
  const auto i =
      static_cast<std::size_t>(std::clamp(rank, 1.0, static_cast<double>(values.size())));
  return values[i - 1];
}

void write_site_report(const SiteRecord& r, const std::filesystem::path& path) {
  const json j = {{"format", "deixis-site-run"},
                  {"version", 1},
                  {"site", r.site},
                  {"role", r.role},
                  {"peer_site", r.peer_site},
                  {"seconds", r.seconds},
                  {"ticks", r.ticks},
                  {"late_ticks", r.late_ticks},
                  {"avatar_visible_ticks", r.visible_ticks},
                  {"network", network_json(r)},
                  {"translation_ms", timing(r.translation_ms)},
                  {"render_ms", timing(r.render_ms)},
                  {"own_steps", steps_json(r.own_steps)},
                  {"remote_completions", completions_json(r.remote_completions)},
                  {"remote_completions_dropped", r.completions_dropped},
                  {"pointing", means_json(means(r.remote_completions, false), false)},
                  {"touching", means_json(means(r.remote_completions, true), true)},
                  {"video", r.video.empty() ? json(nullptr) : json(r.video)},
                  {"people", people_json(r.people)}};
  std::ofstream out(path);
  out << j.dump(2) << '\n';
  if (!out) {
    throw Error(path.string() + ": cannot write the run's report");
  }
}

namespace {

// "HE 1.2° VE 3.4°", or "none observed" when nothing completed (means of nothing are NaN).
void print_completions(std::FILE* out, const std::string& site, const Means& p, const Means& t) {
  std::fprintf(out, "  %s's pointing (%zu)", site.c_str(), p.count);
  if (p.count > 0) {
    std::fprintf(out, ": avatar HE %.1f° VE %.1f°, copy HE %.1f° VE %.1f°", p.avatar_h, p.avatar_v,
                 p.copy_h, p.copy_v);
  }
  std::fprintf(out, "; touching (%zu)", t.count);
  if (t.count > 0) {
    std::fprintf(out, ": avatar %.1f cm, copy %.1f cm", t.avatar_cm, t.copy_cm);
  }
  std::fprintf(out, "\n");
}

}  // namespace

void print_site_summary(const SiteRecord& r, std::FILE* out) {
  const Means p = means(r.remote_completions, false);
  const Means t = means(r.remote_completions, true);
  std::fprintf(out,
               "site %s (%s): %llu ticks in %.1f s, %llu late; tracking sent %llu, received "
               "%llu, lost %llu, rejected %llu; avatar visible %llu ticks\n",
               r.site.c_str(), r.role.c_str(), static_cast<unsigned long long>(r.ticks), r.seconds,
               static_cast<unsigned long long>(r.late_ticks),
               static_cast<unsigned long long>(r.net.tracking_sent),
               static_cast<unsigned long long>(r.net.tracking_received),
               static_cast<unsigned long long>(r.jitter.missed),
               static_cast<unsigned long long>(r.rejected),
               static_cast<unsigned long long>(r.visible_ticks));
  std::fprintf(out, "  translation p50 %.2f ms p99 %.2f ms", percentile(r.translation_ms, 50),
               percentile(r.translation_ms, 99));
  if (r.render_ms.empty()) {
    std::fprintf(out, "; not rendered\n");
  } else {
    std::fprintf(out, "; render p50 %.1f ms p99 %.1f ms\n", percentile(r.render_ms, 50),
                 percentile(r.render_ms, 99));
  }
  if (r.room) {
    // A room: one line per person (their completions are kept per person).
    for (const PersonRecord& person : r.people) {
      print_completions(out, person.site, means(person.completions, false),
                        means(person.completions, true));
    }
  } else {
    print_completions(out, r.peer_site, p, t);
  }
}

}  // namespace deixis::site
