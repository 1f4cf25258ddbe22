#include "eval/real_motion.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/math/angles.h"
#include "eval/real_motion_room.h"
#include "gesture/target_selection.h"
#include "gesture/translator.h"
#include "mocap/player.h"
#include "presence/pose_copy.h"

namespace deixis::eval {

namespace {

namespace fs = std::filesystem;

constexpr float kAvatarHeightM = 1.70f;  // the training subject's size, as docs/eval.md's avatar
constexpr double kAbove = 0.5;
constexpr std::size_t kFramesPerSecond = 30;  // kRealMotionRateHz

double rotation_deg(const Mat3& a, const Mat3& b) {
  const double c = (static_cast<double>((a.transpose() * b).trace()) - 1.0) / 2.0;
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
}

FollowingError following_error(const EndEffectorPoses& avatar, const EndEffectorPoses& copy) {
  const auto cm = [](const Vec3& a, const Vec3& b) {
    return 100.0 * static_cast<double>((a - b).norm());
  };
  return {cm(avatar.T_world_head.translation, copy.T_world_head.translation),
          rotation_deg(avatar.T_world_head.rotation, copy.T_world_head.rotation),
          cm(avatar.T_world_wrist.translation, copy.T_world_wrist.translation),
          rotation_deg(avatar.T_world_wrist.rotation, copy.T_world_wrist.rotation)};
}

void add(FollowingError& sum, const FollowingError& e) {
  sum.head_cm += e.head_cm;
  sum.head_deg += e.head_deg;
  sum.hand_cm += e.hand_cm;
  sum.hand_deg += e.hand_deg;
}

FollowingError divided(const FollowingError& sum, std::size_t n) {
  const double d = static_cast<double>(n);
  return {sum.head_cm / d, sum.head_deg / d, sum.hand_cm / d, sum.hand_deg / d};
}

void keep_larger(FollowingError& worst, const FollowingError& e) {
  worst.head_cm = std::max(worst.head_cm, e.head_cm);
  worst.head_deg = std::max(worst.head_deg, e.head_deg);
  worst.hand_cm = std::max(worst.hand_cm, e.hand_cm);
  worst.hand_deg = std::max(worst.hand_deg, e.hand_deg);
}

// One weight set's running sums over the recording.
struct SetSums {
  FollowingError following{};
  std::size_t following_frames = 0;
  std::vector<FollowingError> second_sums;
  std::vector<std::size_t> second_frames;
  ChannelValues above{};
  ChannelValues onsets{};
  std::array<bool, 3> was_above = {false, false, true};  // the loop starts idle (0, 0, 1)
  ChannelValues difference{};
};

void count_progression(SetSums& s, const nn::Progression& p) {
  for (std::size_t c = 0; c < p.size(); ++c) {
    const bool above = static_cast<double>(p[c]) > kAbove;
    s.above[c] += above ? 1.0 : 0.0;
    s.onsets[c] += above && !s.was_above[c] ? 1.0 : 0.0;
    s.was_above[c] = above;
  }
}

// One frame of one set's translator: its progression, and on a free frame its following error.
void take_frame(SetSums& s, const AvatarFrame& out, const EndEffectorPoses& copied, bool free,
                std::size_t second) {
  count_progression(s, out.progression);
  if (!free || !out.ready) {
    return;
  }
  const FollowingError e = following_error(out.deictic, copied);
  add(s.following, e);
  ++s.following_frames;
  add(s.second_sums[second], e);
  ++s.second_frames[second];
}

RealMotionFigures figures(const SetSums& s, const std::string& label, std::size_t frames,
                          bool compared) {
  RealMotionFigures f;
  f.weights = label;
  if (s.following_frames > 0) {
    f.mean = divided(s.following, s.following_frames);
  } else {
    const double nan = std::nan("");
    f.mean = f.worst_second = {nan, nan, nan, nan};
  }
  for (std::size_t second = 0; second < s.second_sums.size(); ++second) {
    if (s.second_frames[second] == 0) {
      f.per_second.emplace_back();
      continue;
    }
    f.per_second.emplace_back(divided(s.second_sums[second], s.second_frames[second]));
    keep_larger(f.worst_second, *f.per_second.back());
  }
  const double n = static_cast<double>(std::max<std::size_t>(frames, 1));
  const double minutes = n / kRealMotionRateHz / 60.0;
  for (std::size_t c = 0; c < 3; ++c) {
    f.share_above_half[c] = s.above[c] / n;
    f.onsets_per_minute[c] = s.onsets[c] / minutes;
  }
  if (compared) {
    f.mpnet_difference =
        ChannelValues{s.difference[0] / n, s.difference[1] / n, s.difference[2] / n};
  }
  return f;
}

// What the person's own rays designate this frame, whatever the selection holds on to (it keeps
// the last target looked at, decision 44): a target within the acquisition angle of the gaze,
// or of the eye → fingertip ray with the arm extended, or touched.
struct Designating {
  bool gaze = false;
  bool hand = false;
};

Designating designating(const TrackingFrame& f, const TargetMap& room,
                        const TargetSelectionConfig& c) {
  const Vec3& H = f.T_world_head.translation;
  const Vec3& tip = f.index_tip[static_cast<std::size_t>(index(c.deictic_hand))];
  const Vec3 ray = tip - H;
  const bool extended = ray.norm() >= c.pointing_reach_m;
  Designating d;
  for (const TargetObject& o : room.objects) {
    d.gaze = d.gaze || angle_deg(f.gaze, o.position - H) <= c.acquire_deg;
    d.hand = d.hand || (extended && angle_deg(ray, o.position - H) <= c.acquire_deg) ||
             (tip - closest_surface_point(o, tip)).norm() <= c.touch_m;
  }
  return d;
}

// A reader or tracker error that does not name the file yet gets its name in front.
[[noreturn]] void rethrow_naming(const fs::path& file, const std::exception& e) {
  const std::string what = e.what();
  if (what.starts_with(file.string())) {
    throw Error(what);
  }
  throw Error(file.string() + ": " + what);
}

}  // namespace

Recording sample_recording(const mocap::Bvh& bvh, double metres_per_unit, std::string name) {
  Recording r;
  r.name = std::move(name);
  r.source_frames = bvh.frames();
  r.source_rate_hz = 1.0 / bvh.frame_time;
  mocap::BvhPlayer player(bvh, metres_per_unit, mocap::Playback::kOnce);
  r.body = player.tracking().calibrate(Hand::kRight);
  // The samples a site playing the recording sends (mocap/player.h).
  const std::size_t count = mocap::sample_count(player.duration(), kRealMotionRateHz);
  r.frames.resize(count);
  for (std::size_t k = 0; k < count; ++k) {
    player.at(static_cast<double>(k) / kRealMotionRateHz, r.frames[k]);
  }
  return r;
}

Recording load_recording(const fs::path& file) {
  const mocap::Bvh bvh = mocap::read_bvh(file);  // errors name file:line
  try {
    const mocap::LengthUnit unit = mocap::infer_unit(bvh);
    Recording r = sample_recording(bvh, mocap::metres_per_unit(unit), file.filename().string());
    r.unit = std::string(mocap::unit_name(unit));
    return r;
  } catch (const std::exception& e) {
    rethrow_naming(file, e);
  }
}

MotionNetworks load_motion_networks(const std::string& label, const fs::path& dir) {
  const fs::path right = dir / "right";
  return {label, nn::Mpnet::load(right / "MPNet(MoE)(AC)80.safetensors"),
          nn::Ugnet::load(right / "UGNet(MoE)(AC)120.safetensors")};
}

RealMotionResult measure_real_motion(const Recording& recording,
                                     std::span<const MotionNetworks> networks,
                                     std::optional<std::size_t> reference) {
  const RealMotionRooms rooms = real_motion_rooms(recording.body);
  TargetSelector selector{target_selection_for(recording.body)};
  const SelectionCandidates candidates{&rooms.person_room, nullptr, {}, kNoPerson};
  const LocalTargets avatar_room{&rooms.avatar_room};
  const presence::PoseCopy copy(recording.body, rooms.T_world_avatar_root, kAvatarHeightM);
  std::vector<Translator> translators;
  for (const MotionNetworks& n : networks) {
    translators.emplace_back(
        n.mpnet, n.ugnet,
        TranslatorConfig{recording.body, rooms.T_world_avatar_root, kAvatarHeightM, 1, false});
  }
  const std::size_t seconds = (recording.frames.size() + kFramesPerSecond - 1) / kFramesPerSecond;
  std::vector<SetSums> sums(networks.size());
  for (SetSums& s : sums) {
    s.second_sums.assign(seconds, FollowingError{});
    s.second_frames.assign(seconds, 0);
  }
  RealMotionResult result;
  result.recording = recording.name;
  result.frames = recording.frames.size();
  result.seconds = recording.seconds();
  std::vector<nn::Progression> progression(networks.size());
  double head_designated = 0;
  double hand_designated = 0;
  for (std::size_t k = 0; k < recording.frames.size(); ++k) {
    TrackingFrame frame = recording.frames[k];
    selector.select(frame, candidates);
    const Designating d = designating(frame, rooms.person_room, selector.config);
    head_designated += d.gaze ? 1.0 : 0.0;
    hand_designated += d.hand ? 1.0 : 0.0;
    const bool free = !d.gaze && !d.hand;
    result.free_frames += free ? 1 : 0;
    const EndEffectorPoses copied = copy.targets(frame).deictic;
    for (std::size_t s = 0; s < networks.size(); ++s) {
      const AvatarFrame out = translators[s].tick(&frame, avatar_room);
      progression[s] = out.progression;
      take_frame(sums[s], out, copied, free, k / kFramesPerSecond);
    }
    for (std::size_t s = 0; reference && s < networks.size(); ++s) {
      for (std::size_t c = 0; c < 3; ++c) {
        sums[s].difference[c] +=
            static_cast<double>(std::abs(progression[s][c] - progression[*reference][c]));
      }
    }
  }
  const double n = static_cast<double>(std::max<std::size_t>(result.frames, 1));
  result.head_designated = head_designated / n;
  result.hand_designated = hand_designated / n;
  for (std::size_t s = 0; s < networks.size(); ++s) {
    result.sets.push_back(
        figures(sums[s], networks[s].label, result.frames, reference && s != *reference));
  }
  return result;
}

}  // namespace deixis::eval
