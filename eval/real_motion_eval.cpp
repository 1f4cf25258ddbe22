#include "eval/real_motion_eval.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "eval/real_motion_room.h"

namespace deixis::eval {

namespace {

std::optional<double> finite(double v) {
  return std::isfinite(v) ? std::optional<double>(v) : std::nullopt;
}

std::string fixed(double v, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

Table recordings_table() {
  Table t{"R0", "The recordings as measured", {}, {}, {}};
  t.columns = {{"length", "s", 1, false},
               {"height", "m", 3, false},
               {"arm", "m", 3, false},
               {"nothing designated", "%", 1, false},
               {"gaze on a target", "%", 1, false},
               {"hand on a target", "%", 1, false}};
  t.notes = {
      "30 Hz samples of each recording (mocap's player); height and arm from its first "
      "upright frame (docs/bvh.md). A target is designated when it is within 12° of the "
      "gaze ray (the head's forward: recordings have no eyes) or of the eye → fingertip ray "
      "with the arm extended, or touched: gesture/target_selection.h's rules on this frame "
      "alone (the selection the translator is sent keeps the last target looked at)."};
  t.rows.push_back({"recording", "", {}, {}, ""});
  return t;
}

Table following_table() {
  Table t{
      "R1", "(a) How closely the avatar follows the person when nothing is designated", {}, {}, {}};
  t.columns = {{"head", "cm", 2},           {"head", "°", 2},
               {"hand", "cm", 2},           {"hand", "°", 2},
               {"worst 1 s hand", "cm", 2}, {"worst 1 s hand", "°", 2}};
  t.notes = {
      "The translator's head H and deictic wrist (networks' output, before IK) against the "
      "pose copied onto the avatar's root at the avatar's size, on the frames where the "
      "person designates nothing; mean over those frames, and the largest mean of one "
      "second of them (results.json has every second)."};
  return t;
}

Table belief_table() {
  Table t{
      "R2", "(b) How often the translator believes a gaze shift or deictic gesture", {}, {}, {}};
  t.columns = {{"gaze > 0.5", "%", 1, false},
               {"deictic > 0.5", "%", 1, false},
               {"idle > 0.5", "%", 1, false},
               {"gaze onsets", "/min", 1, false},
               {"deictic onsets", "/min", 1, false}};
  t.notes = {
      "MPNet's progression on every frame (30 Hz) of the recording: the share of frames "
      "above 0.5 per channel, and onsets (a frame above 0.5 after one at or below) per "
      "minute of recording."};
  return t;
}

Table agreement_table() {
  Table t{"R3", "(c) Our MPNet against the authors' MPNet on the same frames", {}, {}, {}};
  t.columns = {{"|Δ gaze|", "", 3}, {"|Δ deictic|", "", 3}, {"|Δ idle|", "", 3}};
  t.notes = {
      "Mean absolute difference of the progression per channel, frame by frame: both "
      "MPNets read the same windows of the person's features. The authors' MPNet was "
      "trained on real people, ours on the synthetic capture."};
  return t;
}

TableRow& row_for(Table& t, const std::string& weights) {
  for (TableRow& r : t.rows) {
    if (r.weights == weights) {
      return r;
    }
  }
  t.rows.push_back({"translator", weights, {}, {}, ""});
  return t.rows.back();
}

std::array<std::vector<std::optional<double>>, 4> series(const RealMotionFigures& f) {
  std::array<std::vector<std::optional<double>>, 4> out;
  for (const std::optional<FollowingError>& e : f.per_second) {
    out[0].push_back(e ? finite(e->head_cm) : std::nullopt);
    out[1].push_back(e ? finite(e->head_deg) : std::nullopt);
    out[2].push_back(e ? finite(e->hand_cm) : std::nullopt);
    out[3].push_back(e ? finite(e->hand_deg) : std::nullopt);
  }
  return out;
}

std::string room_note() {
  std::ostringstream note;
  note << "The room: spheres 0.2 m across around the person's calibrated root O (azimuth + to the "
          "right, elevation, distance):";
  for (const TargetPlacement& p : kRealMotionTargets) {
    const TargetPlacement c = moved_copy(p);
    note << ' ' << p.id << " at (" << fixed(p.azimuth_deg, 0) << "°, " << fixed(p.elevation_deg, 0)
         << "°, " << fixed(p.distance_m, 1) << " m) → (" << fixed(c.azimuth_deg, 0) << "°, "
         << fixed(c.elevation_deg, 0) << "°, " << fixed(c.distance_m, 1) << " m);";
  }
  note << " the second of each pair is where the avatar's room has it. Networks: MPNet GRU-MoE "
          "and UGNet MoE (AC), right hand, the sites' pair.";
  return note.str();
}

}  // namespace

RealMotionSection real_motion_section(const std::vector<Recording>& recordings,
                                      const std::vector<RealMotionResult>& results) {
  RealMotionSection section;
  section.notes.push_back(room_note());
  Table r0 = recordings_table();
  Table r1 = following_table();
  Table r2 = belief_table();
  Table r3 = agreement_table();
  for (std::size_t i = 0; i < results.size(); ++i) {
    const RealMotionResult& m = results[i];
    const Recording& rec = recordings[i];
    section.recordings.push_back(m.recording);
    const double n = static_cast<double>(std::max<std::size_t>(m.frames, 1));
    r0.rows[0].per_subject[m.recording] = {m.seconds,
                                           rec.body.height,
                                           rec.body.arm_length,
                                           100.0 * static_cast<double>(m.free_frames) / n,
                                           100.0 * m.head_designated,
                                           100.0 * m.hand_designated};
    for (const RealMotionFigures& f : m.sets) {
      row_for(r1, f.weights).per_subject[m.recording] = {
          finite(f.mean.head_cm),  finite(f.mean.head_deg),        finite(f.mean.hand_cm),
          finite(f.mean.hand_deg), finite(f.worst_second.hand_cm), finite(f.worst_second.hand_deg)};
      row_for(r2, f.weights).per_subject[m.recording] = {
          100.0 * f.share_above_half[0], 100.0 * f.share_above_half[1],
          100.0 * f.share_above_half[2], f.onsets_per_minute[0], f.onsets_per_minute[1]};
      if (f.mpnet_difference) {
        const ChannelValues& d = *f.mpnet_difference;
        row_for(r3, f.weights).per_subject[m.recording] = {d[0], d[1], d[2]};
      }
      section.per_second.push_back({m.recording, f.weights, series(f)});
    }
  }
  if (r3.rows.empty()) {
    r3.notes.push_back("n/a: no weight set labelled \"authors\" besides another set to compare.");
  }
  section.tables = {r0, r1, r2, r3};
  return section;
}

RealMotionSection evaluate_real_motion(const RealMotionOptions& options) {
  const auto say = [&](const std::string& line) {
    if (options.progress) {
      options.progress(line);
    }
  };
  std::vector<Recording> recordings;
  for (const std::filesystem::path& file : options.files) {
    recordings.push_back(load_recording(file));
    const Recording& r = recordings.back();
    say("bvh " + file.string() + ": " + std::to_string(r.source_frames) + " frames at " +
        fixed(r.source_rate_hz, 1) + " Hz (unit " + r.unit + "), " +
        std::to_string(r.frames.size()) + " samples at 30 Hz; height " + fixed(r.body.height, 3) +
        " m, arm " + fixed(r.body.arm_length, 3) + " m");
  }
  std::vector<MotionNetworks> networks;
  std::optional<std::size_t> reference;
  for (const WeightSet& w : options.weights) {
    if (w.label == "authors" && !reference) {
      reference = networks.size();
    }
    networks.push_back(load_motion_networks(w.label, w.dir));
  }
  if (networks.size() < 2) {
    reference.reset();  // nothing to compare with
  }
  std::vector<RealMotionResult> results;
  for (const Recording& r : recordings) {
    results.push_back(measure_real_motion(r, networks, reference));
    say("bvh " + r.name + ": measured " + fixed(r.seconds(), 1) + " s for " +
        std::to_string(networks.size()) + " weight set(s)");
  }
  return real_motion_section(recordings, results);
}

}  // namespace deixis::eval
