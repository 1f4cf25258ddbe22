#pragma once
// What `deixis eval --live-rooms` reports (docs/live-rooms.md): the completions each site's
// observer recorded of the other person (site/site_report.h, `remote_completions`), pooled over
// generated room pairs (eval/room_pairs.h), as distributions — mean, median, 90th percentile and
// worst — for Deixis' avatar and for copying the pose, overall, per subject and per target
// geometry seen from the avatar; and whether every touch a user completed was observed.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "eval/room_pairs.h"

namespace deixis::eval {

// One completion state of a person's pointing or touching, as the other site observed it.
struct LiveCompletion {
  int pair = 0;
  std::string observer;  // the site where the avatar stood
  std::string subject;   // the person who pointed or touched
  TargetId target = kNoTarget;
  bool touch = false;
  double time_s = 0.0;  // the observer's clock
  // Pointing: horizontal and vertical angle errors (deg); touching: the distance (cm). The
  // other kind's fields are NaN.
  double avatar_he = 0.0, avatar_ve = 0.0, avatar_cm = 0.0;
  double copy_he = 0.0, copy_ve = 0.0, copy_cm = 0.0;
  TargetGeometry geometry;  // the target in the observer's room, from the avatar's spot
  // Where the error comes from (eval/deictic_observer.h, DeicticSample): the networks' own
  // end-effectors before IK, how far settling, contact and IK moved the fingertip (cm), the
  // person's own gesture in their room, and how long the hold had lasted (s). NaN where the site
  // did not report them.
  double network_he = 0.0, network_ve = 0.0, network_cm = 0.0;
  double ik_fingertip_cm = 0.0;
  double person_he = 0.0, person_ve = 0.0, person_cm = 0.0;
  double hold_s = 0.0;
};

// Touches one person's script completed, and how many of them the other site observed.
struct TouchTally {
  int pair = 0;
  std::string site;
  std::string subject;
  int performed = 0;
  int observed = 0;
};

struct Distribution {
  std::size_t count = 0;
  double mean = 0.0, median = 0.0, p90 = 0.0, worst = 0.0;  // NaN when count is 0
};
// Of the finite values (NaN and ±inf are left out); the 90th percentile interpolates linearly
// between order statistics (numpy's default).
Distribution distribution(const std::vector<double>& values);

// Deixis' and copy-paste's distributions over one group of completions.
struct LiveGroup {
  std::string label;
  Distribution he, ve, touch_cm;
  Distribution copy_he, copy_ve, copy_touch_cm;
};

// The stages of the pointing chain over a group of completions: the person's own gesture, the
// networks' end-effectors, the avatar after settling and IK (means of HE and VE), and the
// fingertip shift between the last two.
struct LiveStages {
  Distribution person_he, person_ve, network_he, network_ve, avatar_he, avatar_ve;
  Distribution ik_fingertip_cm, hold_s;
};

struct LiveSummary {
  int pairs = 0;
  LiveGroup all;
  LiveStages stages;                         // every pointing completion
  std::vector<const LiveCompletion*> worst;  // the worst pointing completions, worst first
  std::vector<LiveGroup> by_subject;
  std::vector<LiveGroup> by_distance;   // pointing targets' horizontal distance from the avatar
  std::vector<LiveGroup> by_elevation;  // above or below the avatar's shoulder
  std::vector<LiveGroup> by_azimuth;    // |azimuth| from where the avatar faces
  int touches_performed = 0;
  int touches_observed = 0;
  std::string rules;  // the room rules the pairs were laid out by, as JSON (room_rules_file.h)
};

// `worst` points into `completions`, which must outlive the summary.
LiveSummary summarize(const std::vector<LiveCompletion>& completions,
                      const std::vector<TouchTally>& touches, int pairs);

// The report's three files: a Markdown section, JSON (the summary and every completion) and a
// figure (pointing errors against the target's elevation and azimuth, Deixis and copy-paste).
// Each throws deixis::Error naming the path it cannot write.
std::string live_rooms_markdown(const LiveSummary& summary, const std::string& command_line);
void write_live_rooms_json(const LiveSummary& summary,
                           const std::vector<LiveCompletion>& completions,
                           const std::vector<TouchTally>& touches,
                           const std::filesystem::path& path);
void write_live_rooms_figure(const std::vector<LiveCompletion>& completions,
                             const std::filesystem::path& path);

}  // namespace deixis::eval
