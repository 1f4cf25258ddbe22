#include "eval/live_rooms.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "dataset/raster.h"

namespace deixis::eval {

namespace {

using json = nlohmann::ordered_json;
using dataset::Canvas;
using dataset::Rgb;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// One group's six distributions over `members`.
LiveGroup group(std::string label, const std::vector<const LiveCompletion*>& members) {
  std::vector<double> he, ve, cm, copy_he, copy_ve, copy_cm;
  for (const LiveCompletion* c : members) {
    if (c->touch) {
      cm.push_back(c->avatar_cm);
      copy_cm.push_back(c->copy_cm);
    } else {
      he.push_back(c->avatar_he);
      ve.push_back(c->avatar_ve);
      copy_he.push_back(c->copy_he);
      copy_ve.push_back(c->copy_ve);
    }
  }
  return {std::move(label),      distribution(he),      distribution(ve),     distribution(cm),
          distribution(copy_he), distribution(copy_ve), distribution(copy_cm)};
}

// Groups of `completions` (pointing only when `pointing_only`) by `key`, in the order of
// `labels`; a label nobody falls in is left out.
std::vector<LiveGroup> grouped(const std::vector<LiveCompletion>& completions,
                               const std::vector<std::string>& labels,
                               const std::function<std::string(const LiveCompletion&)>& key,
                               bool pointing_only) {
  std::vector<LiveGroup> out;
  for (const std::string& label : labels) {
    std::vector<const LiveCompletion*> members;
    for (const LiveCompletion& c : completions) {
      if ((!pointing_only || !c.touch) && key(c) == label) {
        members.push_back(&c);
      }
    }
    if (!members.empty()) {
      out.push_back(group(label, members));
    }
  }
  return out;
}

constexpr std::size_t kWorstListed = 10;

double worse_angle(const LiveCompletion& c) {
  return std::max(c.avatar_he, c.avatar_ve);
}

LiveStages stages_of(const std::vector<LiveCompletion>& completions) {
  std::vector<double> v[8];
  for (const LiveCompletion& c : completions) {
    if (c.touch) {
      continue;
    }
    const double values[8] = {c.person_he, c.person_ve, c.network_he,      c.network_ve,
                              c.avatar_he, c.avatar_ve, c.ik_fingertip_cm, c.hold_s};
    for (int k = 0; k < 8; ++k) {
      v[k].push_back(values[k]);
    }
  }
  return {distribution(v[0]), distribution(v[1]), distribution(v[2]), distribution(v[3]),
          distribution(v[4]), distribution(v[5]), distribution(v[6]), distribution(v[7])};
}

std::string distance_bin(const LiveCompletion& c) {
  const float d = c.geometry.distance;
  return d < 1.5f ? "< 1.5 m" : d < 2.5f ? "1.5–2.5 m" : d < 3.5f ? "2.5–3.5 m" : "≥ 3.5 m";
}
std::string elevation_bin(const LiveCompletion& c) {
  const float e = c.geometry.elevation_deg;
  return e < -15.0f ? "below −15°" : e < 0.0f ? "−15–0°" : e < 15.0f ? "0–15°" : "above 15°";
}
std::string azimuth_bin(const LiveCompletion& c) {
  const float a = std::abs(c.geometry.azimuth_deg);
  return a < 30.0f ? "0–30°" : a < 60.0f ? "30–60°" : a < 90.0f ? "60–90°" : "≥ 90° (behind)";
}

json number(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}

// One stage's error at a completion: angles for a point, the distance for a touch.
json error_json(bool touch, double he, double ve, double cm) {
  return touch ? json{{"touch_cm", number(cm)}}
               : json{{"he_deg", number(he)}, {"ve_deg", number(ve)}};
}

json distribution_json(const Distribution& d) {
  return {{"count", d.count},
          {"mean", number(d.mean)},
          {"median", number(d.median)},
          {"p90", number(d.p90)},
          {"worst", number(d.worst)}};
}

json group_json(const LiveGroup& g) {
  return {{"label", g.label},
          {"deixis",
           {{"he_deg", distribution_json(g.he)},
            {"ve_deg", distribution_json(g.ve)},
            {"touch_cm", distribution_json(g.touch_cm)}}},
          {"copy_paste",
           {{"he_deg", distribution_json(g.copy_he)},
            {"ve_deg", distribution_json(g.copy_ve)},
            {"touch_cm", distribution_json(g.copy_touch_cm)}}}};
}

json groups_json(const std::vector<LiveGroup>& groups) {
  json out = json::array();
  for (const LiveGroup& g : groups) {
    out.push_back(group_json(g));
  }
  return out;
}

std::string cell(double v) {
  if (!std::isfinite(v)) {
    return "–";
  }
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2f", v);
  return buffer;
}

std::string quartet(const Distribution& d) {
  return cell(d.mean) + " | " + cell(d.median) + " | " + cell(d.p90) + " | " + cell(d.worst);
}

void pointing_table(std::ostringstream& md, const std::vector<LiveGroup>& groups,
                    const char* heading) {
  md << "| " << heading
     << " | n | HE mean | median | p90 | worst | VE mean | median | p90 | worst | copy HE mean | "
        "copy VE mean |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const LiveGroup& g : groups) {
    if (g.he.count == 0) {
      continue;
    }
    md << "| " << g.label << " | " << g.he.count << " | " << quartet(g.he) << " | " << quartet(g.ve)
       << " | " << cell(g.copy_he.mean) << " | " << cell(g.copy_ve.mean) << " |\n";
  }
  md << '\n';
}

// A scatter panel: pointing errors (HE and VE of Deixis, HE of copy-paste) against `x`.
void scatter(Canvas& canvas, int x0, const char* title, float x_lo, float x_hi,
             const std::vector<LiveCompletion>& completions,
             const std::function<float(const LiveCompletion&)>& x) {
  constexpr int kWidth = 420, kHeight = 300, kMargin = 44;
  const Rgb axis{60, 60, 60};
  const int left = x0 + kMargin, right = x0 + kWidth - 12, top = 34, bottom = kHeight - 34;
  double top_value = 6.0;  // the goal's worst case, always in view
  for (const LiveCompletion& c : completions) {
    if (!c.touch) {
      top_value = std::max({top_value, c.avatar_he, c.avatar_ve});
    }
  }
  top_value = std::min(top_value * 1.05, 60.0);
  const auto px = [&](float v) {
    return static_cast<float>(left) + (v - x_lo) / (x_hi - x_lo) * static_cast<float>(right - left);
  };
  const auto py = [&](double v) {
    return static_cast<float>(bottom - std::min(v, top_value) / top_value * (bottom - top));
  };
  canvas.text(static_cast<float>(left), 8.0f, title, axis, 1.5f);
  canvas.line(static_cast<float>(left), static_cast<float>(bottom), static_cast<float>(right),
              static_cast<float>(bottom), axis);
  canvas.line(static_cast<float>(left), static_cast<float>(top), static_cast<float>(left),
              static_cast<float>(bottom), axis);
  canvas.text(static_cast<float>(x0 + 4), static_cast<float>(top), cell(top_value), axis);
  canvas.text(static_cast<float>(x0 + 4), static_cast<float>(bottom - 8), "0", axis);
  canvas.line(static_cast<float>(left), py(6.0), static_cast<float>(right), py(6.0),
              Rgb{200, 200, 200});  // the worst-case goal
  for (int k = 0; k <= 4; ++k) {
    const float v = x_lo + (x_hi - x_lo) * static_cast<float>(k) / 4.0f;
    char buffer[16];
    std::snprintf(buffer, sizeof buffer, "%.0f", static_cast<double>(v));
    canvas.text(px(v) - 8.0f, static_cast<float>(bottom + 8), buffer, axis);
  }
  for (const LiveCompletion& c : completions) {
    if (c.touch) {
      continue;
    }
    const float at = std::clamp(x(c), x_lo, x_hi);
    canvas.disc(px(at), py(c.copy_he), 2.0f, Rgb{190, 190, 190});
    canvas.disc(px(at), py(c.avatar_he), 3.0f, Rgb{31, 119, 180});
    canvas.disc(px(at), py(c.avatar_ve), 3.0f, Rgb{214, 39, 40});
  }
}

}  // namespace

Distribution distribution(const std::vector<double>& values) {
  std::vector<double> v;
  for (const double x : values) {
    if (std::isfinite(x)) {
      v.push_back(x);
    }
  }
  Distribution d;
  d.count = v.size();
  if (v.empty()) {
    d.mean = d.median = d.p90 = d.worst = kNan;
    return d;
  }
  std::sort(v.begin(), v.end());
  double sum = 0.0;
  for (const double x : v) {
    sum += x;
  }
  d.mean = sum / static_cast<double>(v.size());
  const auto quantile = [&](double q) {
    const double at = q * static_cast<double>(v.size() - 1);
    const std::size_t below = static_cast<std::size_t>(std::floor(at));
    const std::size_t above = std::min(below + 1, v.size() - 1);
    return v[below] + (at - static_cast<double>(below)) * (v[above] - v[below]);
  };
  d.median = quantile(0.5);
  d.p90 = quantile(0.9);
  d.worst = v.back();
  return d;
}

LiveSummary summarize(const std::vector<LiveCompletion>& completions,
                      const std::vector<TouchTally>& touches, int pairs) {
  LiveSummary s;
  s.pairs = pairs;
  std::vector<const LiveCompletion*> everyone;
  std::vector<std::string> subjects;
  for (const LiveCompletion& c : completions) {
    everyone.push_back(&c);
    if (std::find(subjects.begin(), subjects.end(), c.subject) == subjects.end()) {
      subjects.push_back(c.subject);
    }
  }
  std::sort(subjects.begin(), subjects.end());
  s.all = group("all", everyone);
  s.by_subject = grouped(
      completions, subjects, [](const LiveCompletion& c) { return c.subject; }, false);
  s.by_distance =
      grouped(completions, {"< 1.5 m", "1.5–2.5 m", "2.5–3.5 m", "≥ 3.5 m"}, distance_bin, true);
  s.by_elevation =
      grouped(completions, {"below −15°", "−15–0°", "0–15°", "above 15°"}, elevation_bin, true);
  s.by_azimuth =
      grouped(completions, {"0–30°", "30–60°", "60–90°", "≥ 90° (behind)"}, azimuth_bin, true);
  s.stages = stages_of(completions);
  for (const LiveCompletion& c : completions) {
    if (!c.touch && std::isfinite(worse_angle(c))) {
      s.worst.push_back(&c);
    }
  }
  std::sort(s.worst.begin(), s.worst.end(), [](const LiveCompletion* a, const LiveCompletion* b) {
    return worse_angle(*a) > worse_angle(*b);
  });
  s.worst.resize(std::min(s.worst.size(), kWorstListed));
  for (const TouchTally& t : touches) {
    s.touches_performed += t.performed;
    s.touches_observed += std::min(t.observed, t.performed);
  }
  return s;
}

std::string live_rooms_markdown(const LiveSummary& s, const std::string& command_line) {
  std::ostringstream md;
  md << "## Live rooms: host and join in generated room pairs\n\n"
     << "`" << command_line << "` — " << s.pairs
     << " room pairs (docs/live-rooms.md), every completion state each site's observer "
        "recorded of the other person. Angles in degrees, touch in cm; copy-paste is the "
        "person's pose copied onto the avatar's spot unchanged.\n\n";
  if (!s.rules.empty()) {
    md << "Room rules: `" << s.rules << "`\n\n";
  }
  md << "### Pointing\n\n";
  pointing_table(md, {s.all}, "completions");
  md << "### Touching\n\n| | n | mean | median | p90 | worst | copy mean |\n"
        "|---|---:|---:|---:|---:|---:|---:|\n"
     << "| Deixis | " << s.all.touch_cm.count << " | " << quartet(s.all.touch_cm) << " | "
     << cell(s.all.copy_touch_cm.mean) << " |\n\n"
     << "Touches completed by the users: " << s.touches_performed << "; observed as completed at "
     << "the other site: " << s.touches_observed << ".\n\n";
  md << "### Pointing per subject\n\n";
  pointing_table(md, s.by_subject, "subject");
  md << "### Pointing per target geometry, seen from the avatar\n\n";
  pointing_table(md, s.by_distance, "horizontal distance");
  pointing_table(md, s.by_elevation, "elevation from its shoulder (1.4 m)");
  pointing_table(md, s.by_azimuth, "azimuth from its facing");
  const LiveStages& st = s.stages;
  md << "### Where the error comes from\n\n"
     << "Each pointing completion measured at each stage of the chain, the same way: the "
        "person's own gesture in their room against their copy of the target; the networks' "
        "end-effectors (H and the fingertip the translator gave IK) in this room; the avatar "
        "after pointing settling, touch contact and IK, as the watcher sees it. The fingertip "
        "shift is how far those moved the fingertip off the networks' (cm); the hold is how long "
        "the person's hand had been still at the completion (s).\n\n"
     << "| stage | HE mean | p90 | worst | VE mean | p90 | worst |\n"
        "|---|---:|---:|---:|---:|---:|---:|\n";
  const auto stage = [&](const char* name, const Distribution& he, const Distribution& ve) {
    md << "| " << name << " | " << cell(he.mean) << " | " << cell(he.p90) << " | " << cell(he.worst)
       << " | " << cell(ve.mean) << " | " << cell(ve.p90) << " | " << cell(ve.worst) << " |\n";
  };
  stage("the person, in their room", st.person_he, st.person_ve);
  stage("the networks, before IK", st.network_he, st.network_ve);
  stage("the avatar, after settling and IK", st.avatar_he, st.avatar_ve);
  md << "\nFingertip shift: mean " << cell(st.ik_fingertip_cm.mean) << " cm, worst "
     << cell(st.ik_fingertip_cm.worst) << " cm. Hold at completion: median "
     << cell(st.hold_s.median) << " s.\n\n"
     << "The worst pointing completions (by the larger of HE and VE):\n\n"
     << "| pair | seen in | subject | target | distance m | elevation ° | azimuth ° | person "
        "HE/VE | networks HE/VE | avatar HE/VE | fingertip shift cm | hold s |\n"
        "|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const LiveCompletion* c : s.worst) {
    char row[320];
    std::snprintf(row, sizeof row, "| %d | %s | %s | %d | %.2f | %.0f | %.0f | ", c->pair,
                  c->observer.c_str(), c->subject.c_str(), c->target,
                  static_cast<double>(c->geometry.distance),
                  static_cast<double>(c->geometry.elevation_deg),
                  static_cast<double>(c->geometry.azimuth_deg));
    md << row << cell(c->person_he) << " / " << cell(c->person_ve) << " | " << cell(c->network_he)
       << " / " << cell(c->network_ve) << " | " << cell(c->avatar_he) << " / " << cell(c->avatar_ve)
       << " | " << cell(c->ik_fingertip_cm) << " | " << cell(c->hold_s) << " |\n";
  }
  md << '\n';
  return md.str();
}

void write_live_rooms_json(const LiveSummary& s, const std::vector<LiveCompletion>& completions,
                           const std::vector<TouchTally>& touches,
                           const std::filesystem::path& path) {
  json list = json::array();
  for (const LiveCompletion& c : completions) {
    list.push_back({{"pair", c.pair},
                    {"observer", c.observer},
                    {"subject", c.subject},
                    {"target", c.target},
                    {"kind", c.touch ? "touch" : "point"},
                    {"time_s", c.time_s},
                    {"avatar", error_json(c.touch, c.avatar_he, c.avatar_ve, c.avatar_cm)},
                    {"copy", error_json(c.touch, c.copy_he, c.copy_ve, c.copy_cm)},
                    {"network", error_json(c.touch, c.network_he, c.network_ve, c.network_cm)},
                    {"ik_fingertip_cm", number(c.ik_fingertip_cm)},
                    {"person", error_json(c.touch, c.person_he, c.person_ve, c.person_cm)},
                    {"hold_s", number(c.hold_s)},
                    {"distance_m", c.geometry.distance},
                    {"elevation_deg", c.geometry.elevation_deg},
                    {"azimuth_deg", c.geometry.azimuth_deg}});
  }
  json tallies = json::array();
  for (const TouchTally& t : touches) {
    tallies.push_back({{"pair", t.pair},
                       {"site", t.site},
                       {"subject", t.subject},
                       {"performed", t.performed},
                       {"observed", t.observed}});
  }
  const json out = {{"pairs", s.pairs},
                    {"rules", s.rules.empty() ? json(nullptr) : json::parse(s.rules)},
                    {"all", group_json(s.all)},
                    {"stages",
                     {{"person_he_deg", distribution_json(s.stages.person_he)},
                      {"person_ve_deg", distribution_json(s.stages.person_ve)},
                      {"network_he_deg", distribution_json(s.stages.network_he)},
                      {"network_ve_deg", distribution_json(s.stages.network_ve)},
                      {"avatar_he_deg", distribution_json(s.stages.avatar_he)},
                      {"avatar_ve_deg", distribution_json(s.stages.avatar_ve)},
                      {"ik_fingertip_cm", distribution_json(s.stages.ik_fingertip_cm)},
                      {"hold_s", distribution_json(s.stages.hold_s)}}},
                    {"by_subject", groups_json(s.by_subject)},
                    {"by_distance", groups_json(s.by_distance)},
                    {"by_elevation", groups_json(s.by_elevation)},
                    {"by_azimuth", groups_json(s.by_azimuth)},
                    {"touches_performed", s.touches_performed},
                    {"touches_observed", s.touches_observed},
                    {"touches", tallies},
                    {"completions", list}};
  std::ofstream file(path);
  file << out.dump(2) << '\n';
  if (!file) {
    throw Error(path.string() + ": cannot write");
  }
}

void write_live_rooms_figure(const std::vector<LiveCompletion>& completions,
                             const std::filesystem::path& path) {
  Canvas canvas(840, 330, Rgb{255, 255, 255});
  scatter(canvas, 0, "error [deg] vs target elevation [deg]", -45.0f, 45.0f, completions,
          [](const LiveCompletion& c) { return c.geometry.elevation_deg; });
  scatter(canvas, 420, "error [deg] vs |azimuth| from the avatar [deg]", 0.0f, 180.0f, completions,
          [](const LiveCompletion& c) { return std::abs(c.geometry.azimuth_deg); });
  const Rgb axis{60, 60, 60};
  canvas.disc(20.0f, 318.0f, 3.0f, Rgb{31, 119, 180});
  canvas.text(28.0f, 314.0f, "Deixis HE", axis);
  canvas.disc(120.0f, 318.0f, 3.0f, Rgb{214, 39, 40});
  canvas.text(128.0f, 314.0f, "Deixis VE", axis);
  canvas.disc(220.0f, 318.0f, 2.0f, Rgb{190, 190, 190});
  canvas.text(228.0f, 314.0f, "copy-paste HE   (line: 6 deg)", axis);
  canvas.write_png(path);
}

}  // namespace deixis::eval
