#include "site/remote_people.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.h"
#include "core/math/angles.h"

namespace deixis::site {

namespace {

// A remote person's gaze, hold by hold: while their own gaze is on their head target in their
// room (within kSettledDeg), the eyes have settled there; the avatar's error at the last such
// frame of a hold (once settled for kSettledFrames) is the hold's sample, into storage reserved
// at meet().
struct GazeWatch {
  static constexpr float kSettledDeg = 4.0f;
  static constexpr std::uint32_t kSettledFrames = 15;  // 0.5 s at 30 Hz
  TargetId target = kNoTarget;
  std::uint32_t settled = 0;
  double error_deg = 0.0;
  double network_error_deg = 0.0;
  std::vector<GazeSample> samples;
  std::uint64_t dropped = 0;

  void observe(const presence::RemoteAvatar& avatar, const TrackingFrame& frame,
               const LocalTargets& room) {
    const Vec3* at = room.find_position(frame.head_target);
    if (at == nullptr || frame.head_target != target) {
      end_hold();
    }
    if (at == nullptr) {
      return;
    }
    target = frame.head_target;
    if (angle_deg(frame.gaze, frame.head_target_position - frame.T_world_head.translation) >
        kSettledDeg) {
      return;  // looking elsewhere, or on the way
    }
    ++settled;
    // The eyes as posed, from where they are after IK; the networks' gaze from their head H.
    error_deg =
        static_cast<double>(angle_deg(avatar.eye_line_of_sight(), *at - avatar.eye_midpoint()));
    const EndEffectorPoses& pose = avatar.frame().deictic;
    network_error_deg =
        static_cast<double>(angle_deg(pose.gaze, *at - pose.T_world_head.translation));
  }
  void end_hold() {
    if (settled >= kSettledFrames) {
      if (samples.size() < samples.capacity()) {
        samples.push_back({target, error_deg, network_error_deg});
      } else {
        ++dropped;
      }
    }
    target = kNoTarget;
    settled = 0;
  }
};

}  // namespace

struct RemotePeople::Slot {
  Pose T_world_origin;  // the spot's avatar root O
  bool taken = false;
  bool live = false;
  bool queued = false;   // in tick()'s current round
  float opacity = 0.0f;  // as drawn; an avatar kept after its person left fades out (a ghost)
  PersonStats stats;
  BodyCalibration body;                         // the person's, from their hello
  std::shared_ptr<const PersonAvatar> wearing;  // null: the site's default
  std::optional<presence::RemoteAvatar> avatar;
  std::optional<presence::PoseCopy> copy;         // the copy-paste baseline, when measuring
  std::optional<eval::DeicticObserver> observer;  // when measuring
  GazeWatch gaze;                                 // when measuring
};

RemotePeople::RemotePeople(const SiteConfig& site, const std::array<MoeNetworks, 2>& networks,
                           const ik::AvatarSolver& solver, const RemotePeopleOptions& options)
    : site_(site), networks_(networks), solver_(solver), options_(options) {
  slots_.reserve(site.spots.size());
  for (std::size_t i = 0; i < site.spots.size(); ++i) {
    slots_.push_back(std::make_unique<Slot>());
    slots_.back()->T_world_origin = presence::avatar_origin(solver, site.spots[i].T_world_floor());
    slots_.back()->stats.spot = i;
  }
  targets_.reserve(slots_.size() + 1);
  visible_.reserve(slots_.size());
  drawn_.reserve(slots_.size());
  round_.reserve(slots_.size());
  const MoeNetworks& right = networks[static_cast<std::size_t>(index(Hand::kRight))];
  buffers_.reserve(slots_.size(), right.mpnet, right.ugnet);
}

RemotePeople::~RemotePeople() = default;

RemotePeople::Slot* RemotePeople::find(PersonId id) {
  for (const auto& slot : slots_) {
    if (slot->taken && slot->stats.id == id) {
      return slot.get();
    }
  }
  return nullptr;
}

const RemotePeople::Slot* RemotePeople::find(PersonId id) const {
  return const_cast<RemotePeople*>(this)->find(id);
}

const presence::RemoteAvatar& RemotePeople::meet(PersonId id, const net::Hello& hello) {
  if (id == kNoPerson || id > kMaxPersonId) {
    throw Error(site_.source + ": person id " + std::to_string(id) + " is not a person (1-254)");
  }
  Slot* slot = find(id);
  if (slot != nullptr) {
    fold_into_record(*slot);  // the same id met again: a new stay on the same spot
  } else {
    const auto free =
        std::find_if(slots_.begin(), slots_.end(), [](const auto& s) { return !s->taken; });
    if (free == slots_.end()) {
      throw Error(site_.source + ": remote_avatar: " + std::to_string(slots_.size()) +
                  " spot(s), all taken: no place for site " + hello.site +
                  "'s person (add spots to remote_avatar.spots)");
    }
    slot = free->get();
    slot->opacity = 0.0f;  // a newcomer fades in, not from where a ghost on the spot was
    ++present_;
  }
  // A new hello naming the file they wear already (a reconnect, a new calibration) keeps it.
  const std::optional<net::AvatarHash> named = net::parse_avatar_hash(hello.avatar.model);
  if (options_.override_avatar) {
    slot->wearing = options_.override_avatar;
  } else if (!(slot->taken && slot->wearing && named && *named == slot->wearing->hash)) {
    slot->wearing = nullptr;
  }
  slot->body = hello.avatar.body;
  slot->taken = true;
  slot->live = true;
  slot->stats = PersonStats{id, hello.site, slot->stats.spot};
  dress(*slot);
  PersonRecord& record = record_of(hello.site);
  ++record.stays;
  record.height_m = static_cast<double>(hello.avatar.body.height);
  record.arm_length_m = static_cast<double>(hello.avatar.body.arm_length);
  list_visible();  // the fresh avatar is not posed yet: neither list may show it
  return *slot->avatar;
}

const ik::AvatarSolver& RemotePeople::solver_of(const Slot& slot) const {
  return slot.wearing ? slot.wearing->solver : solver_;
}

// A fresh avatar for the slot's person in what they wear: translation state, IK buffers, root
// and, when measuring, the copy-paste baseline for that rig.
void RemotePeople::dress(Slot& slot) {
  const ik::AvatarSolver& solver = solver_of(slot);
  // Left-handed people go through the right-hand weights on their mirror image (decision 68).
  const Hand weights = options_.left_hand_weights ? slot.body.deictic_hand
                                                  : translating_weights(slot.body.deictic_hand);
  const bool mirrored = weights != slot.body.deictic_hand;
  const MoeNetworks& n = networks_[static_cast<std::size_t>(index(weights))];
  const Pose& T_world_floor = site_.spots[slot.stats.spot].T_world_floor();
  slot.T_world_origin = presence::avatar_origin(solver, T_world_floor);
  slot.avatar.emplace(
      n.mpnet, n.ugnet, solver,
      presence::RemoteAvatarConfig{.user = slot.body,
                                   .T_world_floor = T_world_floor,
                                   .noise_seed = static_cast<std::uint32_t>(slot.stats.id),
                                   .touch_contact = options_.touch_contact,
                                   .mirrored = mirrored,
                                   .gaze_settle = options_.gaze_settle,
                                   .pointing_settle = options_.pointing_settle});
  if (options_.completions > 0) {
    slot.copy.emplace(slot.body, slot.T_world_origin, solver.rig.height);
    if (!slot.observer) {
      slot.observer.emplace(options_.completions);
      slot.gaze = GazeWatch{};
      slot.gaze.samples.reserve(options_.completions);
    }
  }
}

bool RemotePeople::wear(PersonId id, std::shared_ptr<const PersonAvatar> avatar) {
  Slot* slot = find(id);
  if (slot == nullptr || options_.override_avatar) {
    return false;
  }
  slot->wearing = std::move(avatar);
  if (slot->observer) {
    slot->observer->interrupt();  // a hold being measured ends with the avatar it was on
    slot->gaze.end_hold();
  }
  dress(*slot);
  list_visible();
  return true;
}

const PersonAvatar* RemotePeople::wearing(PersonId id) const {
  const Slot* slot = find(id);
  return slot != nullptr ? slot->wearing.get() : nullptr;
}

const PersonAvatar* RemotePeople::wearing(const presence::RemoteAvatar& avatar) const {
  for (const auto& slot : slots_) {
    if (slot->taken && &*slot->avatar == &avatar) {
      return slot->wearing.get();
    }
  }
  return nullptr;
}

PersonAvatarRecord RemotePeople::avatar_record(const Slot& slot) const {
  PersonAvatarRecord r;
  r.joints = solver_of(slot).joint_count();
  if (slot.wearing) {
    r.source = std::string(avatar_source_name(slot.wearing->source));
    r.hash = net::to_hex(slot.wearing->hash);
  }
  return r;
}

void RemotePeople::leave(PersonId id) {
  Slot* slot = find(id);
  if (slot == nullptr) {
    return;
  }
  fold_into_record(*slot);
  slot->taken = false;
  slot->live = false;
  slot->copy.reset();
  slot->observer.reset();
  --present_;
  list_visible();  // gone from the live ones at once; its avatar fades out (step_fades)
}

// A present person whose stream is live and whose avatar is posed: shown at full opacity.
bool RemotePeople::is_live(const Slot& slot) {
  return slot.taken && slot.live && slot.avatar->visible();
}

// Lists the live avatars and those drawn. Called whenever an avatar is replaced or let go, so
// neither list points at an avatar that is not posed.
void RemotePeople::list_visible() {
  visible_.clear();
  drawn_.clear();
  for (const auto& slot : slots_) {
    if (is_live(*slot)) {
      visible_.push_back(&*slot->avatar);
    }
    if (slot->avatar && slot->avatar->visible() && slot->opacity > 0.0f) {
      drawn_.push_back(
          {&*slot->avatar, slot->wearing ? &slot->wearing->avatar.mesh : nullptr, slot->opacity});
    }
  }
}

// One tick of every avatar's fade: up towards 1 while it is live, down towards 0 otherwise; the
// avatar of a person who left is let go once it has faded out.
void RemotePeople::step_fades() {
  constexpr float kIn = 1.0f / kFadeInTicks;
  constexpr float kOut = 1.0f / kFadeOutTicks;
  for (const auto& slot : slots_) {
    if (!slot->avatar) {
      continue;
    }
    // Snapped at the ends, so that rounding leaves no step of 1e-8 to draw.
    const float next = is_live(*slot) ? slot->opacity + kIn : slot->opacity - kOut;
    slot->opacity = next > 1.0f - 0.5f * kIn ? 1.0f : next < 0.5f * kOut ? 0.0f : next;
    if (!slot->taken && slot->opacity == 0.0f) {
      slot->avatar.reset();
      slot->wearing = nullptr;
    }
  }
}

PersonRecord& RemotePeople::record_of(const std::string& site) {
  for (PersonRecord& r : records_) {
    if (r.site == site) {
      return r;
    }
  }
  PersonRecord& r = records_.emplace_back();
  r.site = site;
  return r;
}

// A stay ends (the person left, or was met again): its counters and samples go into the site's
// record, and the slot's counters start over.
void RemotePeople::fold_into_record(Slot& slot) {
  PersonRecord& r = record_of(slot.stats.site);
  r.avatar = avatar_record(slot);
  r.frames_played += slot.stats.frames_played;
  r.frames_missed += slot.stats.frames_missed;
  r.visible_ticks += slot.stats.visible_ticks;
  slot.stats.frames_played = slot.stats.frames_missed = slot.stats.visible_ticks = 0;
  if (slot.observer) {
    slot.observer->interrupt();
    r.completions.insert(r.completions.end(), slot.observer->samples().begin(),
                         slot.observer->samples().end());
    r.completions_dropped += slot.observer->dropped();
    slot.observer.emplace(options_.completions);
    slot.gaze.end_hold();
    r.gazes.insert(r.gazes.end(), slot.gaze.samples.begin(), slot.gaze.samples.end());
    r.completions_dropped += slot.gaze.dropped;
    slot.gaze.samples.clear();
    slot.gaze.dropped = 0;
  }
}

std::span<const PersonTarget> RemotePeople::people_targets(PersonId self, const Vec3& own_head) {
  targets_.clear();
  if (self != kNoPerson) {
    targets_.push_back({self, own_head});
  }
  for (const auto& slot : slots_) {
    if (is_live(*slot) && slot->stats.id != self) {
      targets_.push_back({slot->stats.id, slot->avatar->eye_midpoint()});
    }
  }
  return targets_;
}

bool RemotePeople::play(const PersonFrame& f, const LocalTargets& room, double time) {
  Slot* slot = find(f.person);
  if (slot == nullptr) {
    return false;
  }
  slot->avatar->tick(f.frame, room);
  after_tick(*slot, f, room, time);
  return true;
}

// What follows a person's avatar tick: their counters and the observers.
void RemotePeople::after_tick(Slot& slot, const PersonFrame& f, const LocalTargets& room,
                              double time) {
  const presence::RemoteAvatar& avatar = *slot.avatar;
  slot.stats.frames_played += f.frame != nullptr ? 1 : 0;
  slot.stats.frames_missed += f.frame == nullptr ? 1 : 0;
  if (slot.observer && f.frame != nullptr && avatar.visible() && room.map != nullptr) {
    const eval::AvatarChain chain = eval::chain_of(avatar);
    slot.observer->observe(*f.frame, f.sequence, time, chain, *slot.copy, *room.map, f.remote_map);
    slot.gaze.observe(avatar, *f.frame, room);
  }
}

void RemotePeople::tick(std::span<const PersonFrame> frames, const LocalTargets& room,
                        double time) {
  std::size_t begin = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    Slot* slot = find(frames[i].person);
    if (slot == nullptr) {
      continue;
    }
    if (slot->queued) {  // their second frame: the round so far goes first
      run_round(frames.subspan(begin, i - begin), room, time);
      begin = i;
    }
    slot->queued = true;
    round_.push_back({&*slot->avatar, frames[i].frame});
  }
  run_round(frames.subspan(begin), room, time);
}

// One frame per person at most: the networks batched across them, then each one's counters.
void RemotePeople::run_round(std::span<const PersonFrame> frames, const LocalTargets& room,
                             double time) {
  if (round_.empty()) {
    return;
  }
  presence::tick_people(round_, room, buffers_);
  round_.clear();
  for (const PersonFrame& f : frames) {
    Slot* slot = find(f.person);
    if (slot != nullptr && slot->queued) {
      slot->queued = false;
      after_tick(*slot, f, room, time);
    }
  }
}

void RemotePeople::set_live(PersonId id, bool live) {
  if (Slot* slot = find(id)) {
    slot->live = live;
  }
}

void RemotePeople::interrupt(PersonId id) {
  if (Slot* slot = find(id); slot != nullptr && slot->observer) {
    slot->observer->interrupt();
    slot->gaze.end_hold();
  }
}

void RemotePeople::end_tick() {
  step_fades();
  list_visible();
  for (const auto& slot : slots_) {
    if (is_live(*slot)) {
      ++slot->stats.visible_ticks;
    }
  }
}

void RemotePeople::finish() {
  for (const auto& slot : slots_) {
    if (slot->taken && slot->observer) {
      slot->observer->interrupt();
      slot->gaze.end_hold();
    }
  }
}

const presence::RemoteAvatar* RemotePeople::avatar(PersonId id) const {
  const Slot* slot = find(id);
  return slot != nullptr ? &*slot->avatar : nullptr;
}

PersonId RemotePeople::find_site(std::string_view site) const {
  for (const auto& slot : slots_) {
    if (slot->taken && slot->stats.site == site) {
      return slot->stats.id;
    }
  }
  return kNoPerson;
}

const PersonStats* RemotePeople::stats(PersonId id) const {
  const Slot* slot = find(id);
  return slot != nullptr ? &slot->stats : nullptr;
}

std::vector<PersonStats> RemotePeople::present() const {
  std::vector<PersonStats> out;
  for (const auto& slot : slots_) {
    if (slot->taken) {
      out.push_back(slot->stats);
    }
  }
  return out;
}

std::vector<PersonRecord> RemotePeople::records() const {
  std::vector<PersonRecord> out = records_;
  for (const auto& slot : slots_) {
    if (!slot->taken) {
      continue;
    }
    auto r = std::find_if(out.begin(), out.end(),
                          [&](const PersonRecord& p) { return p.site == slot->stats.site; });
    r->avatar = avatar_record(*slot);
    r->frames_played += slot->stats.frames_played;
    r->frames_missed += slot->stats.frames_missed;
    r->visible_ticks += slot->stats.visible_ticks;
    if (slot->observer) {
      r->completions.insert(r->completions.end(), slot->observer->samples().begin(),
                            slot->observer->samples().end());
      r->completions_dropped += slot->observer->dropped();
      r->gazes.insert(r->gazes.end(), slot->gaze.samples.begin(), slot->gaze.samples.end());
      r->completions_dropped += slot->gaze.dropped;
    }
  }
  return out;
}

namespace {

// One target of a scripted frame; true when it named a person nobody here is.
bool resolve_target(TargetId& target, Vec3& position, std::span<const std::string> names,
                    const RemotePeople& people, bool direct) {
  if (!is_script_person_target(target)) {
    return false;
  }
  const std::size_t k = script_person_index(target);
  const PersonId id = k < names.size() ? people.find_site(names[k]) : kNoPerson;
  const presence::RemoteAvatar* avatar = people.avatar(id);
  if (avatar == nullptr) {
    target = kNoTarget;
    return true;
  }
  target = direct ? kPartnerTarget : person_target(id);
  if (avatar->visible()) {
    position = avatar->eye_midpoint();
  }
  return false;
}

}  // namespace

Vec3 expected_person_head(const SiteConfig& site, const ik::AvatarSolver& solver, std::size_t k) {
  return presence::avatar_origin(solver, site.spots.at(k).T_world_floor()).translation;
}

int resolve_script_people(TrackingFrame& frame, std::span<const std::string> names,
                          const RemotePeople& people, bool direct) {
  int unresolved = 0;
  unresolved +=
      resolve_target(frame.head_target, frame.head_target_position, names, people, direct) ? 1 : 0;
  unresolved +=
      resolve_target(frame.hand_target, frame.hand_target_position, names, people, direct) ? 1 : 0;
  return unresolved;
}

}  // namespace deixis::site
