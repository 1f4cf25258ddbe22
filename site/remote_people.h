#pragma once
// The remote people a site shows (docs/site-config.md, "Many people at a site"): each one a
// presence::RemoteAvatar with its own translation state, standing on one of the site's avatar
// spots. People take spots in order of arrival (the first free one); a person who leaves frees
// theirs; one more person than spots is a deixis::Error naming the site file. One person's loss,
// jitter or departure touches only their own avatar.
//
// People are targets (core/target_map.h, person_target): people_targets() lists where every
// visible avatar's head is in this room, and the own user's head under their own id, for this
// room's LocalTargets, so when X looks or points at Y, X's avatar here turns to Y's avatar here.
//
// Driving it, once per 30 Hz tick (a room session, or the direct SitePeer with one person):
//   meet(id, hello) / leave(id) as people come and go;
//   room.people = people_targets(self, own_head);
//   tick() a batch of due frames, one per person (null: missed), the networks batched across
//   people — or play() one person's;
//   end_tick() counts visible ticks and steps the fades; visible() lists the live avatars,
//   drawn() what to draw with each one's opacity.
// Avatars fade rather than pop (decision 84): one whose stream stops, or whose person leaves,
// fades out in kFadeOutTicks holding its last pose; one that comes (back) fades in over
// kFadeInTicks. Once everyone has met, nothing here allocates per tick.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "eval/deictic_observer.h"
#include "net/messages.h"
#include "presence/people_tick.h"
#include "presence/pose_copy.h"
#include "presence/remote_avatar.h"
#include "site/avatar_cache.h"
#include "site/moe_weights.h"
#include "site/site_config.h"
#include "site/site_report.h"

namespace deixis::site {

struct RemotePeopleOptions {
  // Per person, how many completion states (eval/deictic_observer.h: pointing, he_deg/ve_deg)
  // and gaze holds (PersonRecord::gazes) are kept; 0 measures nothing (a driver that measures on
  // its own).
  std::size_t completions = 0;
  bool touch_contact = true;
  bool gaze_settle = true;  // false: the networks' own gaze, unsettled (presence/gaze_settle.h)
  // false: the networks' own pointing, unsettled (presence/pointing_settle.h)
  bool pointing_settle = true;
  // Every remote person wears this avatar here, whatever they chose (a site's local override,
  // `--remote-avatar`); null: the site's own until wear() gives them theirs.
  std::shared_ptr<const PersonAvatar> override_avatar{};
  // A left-handed person is translated with the right-hand weights on their mirror image
  // (docs/decisions.md §68: the left-hand weights turn the avatar's gaze 28° short of a person
  // on its left); true puts them through the left-hand weights as they are (decision 17), to
  // measure the difference.
  bool left_hand_weights = false;
};

// One remote person, as seen from this site.
struct PersonStats {
  PersonId id = kNoPerson;
  std::string site;  // their site's name, from their hello
  std::size_t spot = 0;
  std::uint64_t frames_played = 0;  // frames translated into the avatar
  std::uint64_t frames_missed = 0;  // ticks their frame did not come (the avatar held)
  std::uint64_t visible_ticks = 0;  // ticks their avatar was shown
};

// An avatar to draw this tick: live, fading in, or fading out (a stream that stopped, a person
// who left) in its last pose. `mesh`: what it wears, null for the site's default.
struct DrawnAvatar {
  const presence::RemoteAvatar* avatar = nullptr;
  const avatar::SkinnedMesh* mesh = nullptr;
  float opacity = 1.0f;  // (0, 1]
};

// One person's frame for a tick. `frame` null: their frame was due and did not come (missed).
struct PersonFrame {
  PersonId person = kNoPerson;
  const TrackingFrame* frame = nullptr;
  std::uint32_t sequence = 0;             // the frame's sequence number (for the observer)
  const TargetMap* remote_map = nullptr;  // the person's room (null until it arrived)
};

class RemotePeople {
 public:
  // `site`, `networks` and `solver` must outlive it. `solver` is the site's default avatar's,
  // which everyone wears until they wear another (wear(), the override).
  RemotePeople(const SiteConfig& site, const std::array<MoeNetworks, 2>& networks,
               const ik::AvatarSolver& solver, const RemotePeopleOptions& options = {});
  ~RemotePeople();
  RemotePeople(const RemotePeople&) = delete;
  RemotePeople& operator=(const RemotePeople&) = delete;

  // Person `id` arrived (their hello): a fresh avatar on the first free spot. Someone already
  // there under `id` (a new hello: they reconnected, or changed) keeps their spot and gets a fresh
  // avatar. Throws deixis::Error naming the site file when every spot is taken, or for id 0/255.
  const presence::RemoteAvatar& meet(PersonId id, const net::Hello& hello);
  // Person `id` left: their spot is free, their avatar fades out where it stood (until someone
  // else takes the spot). Unknown ids are ignored.
  void leave(PersonId id);
  // Person `id` wears `avatar` from now on (null: the site's default again): their avatar starts
  // over with its rig and solver on the same spot (hidden until their next frame); nobody else's
  // changes. Ignored (false) for unknown ids and while an override is set. `avatar` is kept
  // alive as long as anyone wears it (SiteView keeps its mesh by address meanwhile).
  bool wear(PersonId id, std::shared_ptr<const PersonAvatar> avatar);
  // What person `id` wears here: null for the site's default (or not present).
  const PersonAvatar* wearing(PersonId id) const;
  // What the person whose avatar is `avatar` wears (null: the default, or not one of ours).
  const PersonAvatar* wearing(const presence::RemoteAvatar& avatar) const;

  // Where this room's people are for this room's LocalTargets: every visible avatar's head (its
  // eye midpoint after IK, as of the last tick) and, unless `self` is kNoPerson, the own user's
  // head under their own id. Valid until the next call.
  std::span<const PersonTarget> people_targets(PersonId self, const Vec3& own_head);

  // Plays one frame of person `id` into their avatar with this room's targets (`frame` null: a
  // missed frame, the avatar holds). `time`: s since the run began (for the observer). Unknown
  // ids are ignored (false).
  bool play(const PersonFrame& frame, const LocalTargets& room, double time = 0.0);
  // Plays a tick's frames with the networks batched across people (presence::tick_people; equal
  // to play() one by one within 1e-5). A person given twice plays both frames, in order, in
  // rounds of one frame per person. Unknown ids are ignored.
  void tick(std::span<const PersonFrame> frames, const LocalTargets& room, double time = 0.0);
  // Whether a present person's stream is live (the direct session hides the avatar while its
  // stream is down, keeping it for a reconnect). On by meet().
  void set_live(PersonId id, bool live);
  // The stream of `id` stopped: a hold the observer was following ends.
  void interrupt(PersonId id);
  // The tick is over: counts visible ticks, steps the fades, lists the visible and the drawn.
  void end_tick();
  // The run is over: holds in progress end (before records()).
  void finish();

  std::size_t size() const { return present_; }
  std::size_t capacity() const { return slots_.size(); }
  // The avatar of person `id` (null when not present), visible or not.
  const presence::RemoteAvatar* avatar(PersonId id) const;
  // Visible avatars, in spot order, as of the last end_tick() (what the view draws).
  std::span<const presence::RemoteAvatar* const> visible() const { return visible_; }
  // What to draw, in spot order, as of the last end_tick(): the visible avatars and those fading
  // in or out, each with its opacity and mesh.
  std::span<const DrawnAvatar> drawn() const { return drawn_; }
  static constexpr int kFadeInTicks = 8;    // 0.27 s at 30 Hz
  static constexpr int kFadeOutTicks = 15;  // 0.5 s
  // The person of a site name present now (kNoPerson: nobody of that name).
  PersonId find_site(std::string_view site) const;
  const PersonStats* stats(PersonId id) const;
  // Every present person's stats, in spot order.
  std::vector<PersonStats> present() const;
  // One record per remote site met during the run (in order of first arrival).
  std::vector<PersonRecord> records() const;

 private:
  struct Slot;
  Slot* find(PersonId id);
  const Slot* find(PersonId id) const;
  PersonRecord& record_of(const std::string& site);
  PersonAvatarRecord avatar_record(const Slot& slot) const;
  const ik::AvatarSolver& solver_of(const Slot& slot) const;
  void dress(Slot& slot);
  void fold_into_record(Slot& slot);
  static bool is_live(const Slot& slot);
  void list_visible();
  void step_fades();
  void after_tick(Slot& slot, const PersonFrame& frame, const LocalTargets& room, double time);
  void run_round(std::span<const PersonFrame> frames, const LocalTargets& room, double time);

  const SiteConfig& site_;
  const std::array<MoeNetworks, 2>& networks_;
  const ik::AvatarSolver& solver_;
  RemotePeopleOptions options_;
  std::vector<std::unique_ptr<Slot>> slots_;  // one per spot
  std::size_t present_ = 0;
  std::vector<PersonTarget> targets_;
  std::vector<presence::PersonTick> round_;  // tick(): this round's avatars and frames
  presence::PeopleTickBuffers buffers_;
  std::vector<const presence::RemoteAvatar*> visible_;
  std::vector<DrawnAvatar> drawn_;
  std::vector<PersonRecord> records_;  // of people who left (present people are added on read)
};

// Where the k-th person a site's script names (VirtualUser::people[k]) is expected while the
// script is performed, before anyone arrives: the eyes of an avatar on spot k (k < spots, which
// the site file's validation guarantees). What capture::ScenePerson::head is given.
Vec3 expected_person_head(const SiteConfig& site, const ik::AvatarSolver& solver, std::size_t k);

// A scripted user's frame (core/script_step.h): its head and hand targets that are people the
// script named by site (script_person_target(k), `names[k]`) become person_target of whoever of
// that site is in the room now, at their avatar's eyes; in a direct two-site session
// (`direct`), the other site's person is "the other person" (kPartnerTarget). Nobody of that
// name here: the target becomes kNoTarget (the step designates nothing; receivers hold the last
// frame) and is counted in the return value (0–2 for the frame).
int resolve_script_people(TrackingFrame& frame, std::span<const std::string> names,
                          const RemotePeople& people, bool direct = false);

}  // namespace deixis::site
