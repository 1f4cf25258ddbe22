#pragma once
// A site in a room of several people (docs/rooms-protocol.md, docs/relay.md): the user's tracking
// goes through a relay to every other member of the room each 30 Hz tick, and every remote person
// comes back as their own translated avatar in this room (site::RemotePeople), on the site's
// avatar spots in order of arrival. The room counterpart of SitePeer (site/site_peer.h): the same
// non-blocking shape (poll, tick, wait), so a frame loop never stalls on the network.
//
// People are targets: the LocalTargets a tick translates with list every visible avatar's head
// and this site's own user (under the relay's id for them), so when X looks at Y, X's avatar here
// looks at Y's avatar here.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "net/relay_client.h"
#include "net/room_session.h"
#include "site/moe_weights.h"
#include "site/remote_people.h"
#include "site/site_config.h"
#include "site/site_session.h"

namespace deixis::site {

struct RoomPeerOptions {
  std::string relay_host = "127.0.0.1";
  std::uint16_t relay_port = 7351;
  std::string room;  // the room's name (the relay sees only its hash)
  std::string passphrase;
  double wait = 30.0;  // s to reach the relay and enter the room
  // Rehearsing a bad link: this share of the user's outgoing tracking packets is lost on the
  // way out, after the session numbered them, as a lossy network would (0 in use).
  double drop_tracking = 0.0;
  std::uint32_t drop_seed = 1;
  RemotePeopleOptions people;
  // The avatar file the user chose, offered to everyone by its hash (docs/avatars.md).
  std::shared_ptr<const std::vector<std::byte>> avatar_file{};
  // Whether people's chosen avatars are fetched and worn (as SitePeerOptions::chosen_avatars),
  // kept on disk in `avatar_cache` (empty: in memory only).
  bool chosen_avatars = false;
  std::filesystem::path avatar_cache{};
};

struct RoomPeerStats {
  std::uint64_t ticks = 0, sent = 0, dropped_on_purpose = 0, played = 0, missed = 0;
  std::uint64_t people_refused = 0;  // more people than spots: not shown
  // The last tick's translation of everyone it played (networks batched across people, contact,
  // IK), in ms; negative when it played no one.
  double tick_translation_ms = -1.0;
};

class RoomPeer {
 public:
  // Resolves the relay's address at once; throws deixis::Error when it cannot, or when the
  // site's hello or target map break a wire rule. `user`: the user's calibration, in the hello.
  RoomPeer(const RoomPeerOptions& options, const SiteConfig& site, const BodyCalibration& user,
           const std::array<MoeNetworks, 2>& networks, const ik::AvatarSolver& solver, double now);
  ~RoomPeer();
  RoomPeer(const RoomPeer&) = delete;
  RoomPeer& operator=(const RoomPeer&) = delete;

  // One tick: services the relay, meets and lets go of people, sends the user's frame (stamped
  // `sampled`) to everyone verified, and plays each person's due frames into their avatar with
  // `room`'s targets plus the room's people. Throws deixis::Error when the relay or the room
  // refuses this site for good, or when it is not in the room within `wait` s of starting.
  void tick(const TrackingFrame& user, double sampled, double now, const LocalTargets& room);
  // Services the relay without sending or playing; throws as tick() does.
  void poll(double now);
  // Waits on the relay until `until`, servicing it meanwhile.
  void wait(const SiteClock& clock, double until);

  bool in_room() const { return session_->state() == net::RoomState::kInRoom; }
  net::MemberId self() const { return session_->self(); }
  const RemotePeople& people() const { return people_; }
  RemotePeople& people() { return people_; }
  const net::RoomSession& session() const { return *session_; }
  const net::RelayClient& relay() const { return *client_; }
  const RoomPeerStats& stats() const { return stats_; }
  // The user recalibrated: a new hello to everyone verified (and to those who come later).
  // Throws deixis::Error if it breaks a wire rule.
  void set_user(const SiteConfig& site, const BodyCalibration& user);
  // Says bye to the room and leaves the relay (at most 0.5 s).
  void close(double now);

 private:
  void service(double now, std::uint32_t wait_ms);
  void check(double now) const;
  void take_events();
  void play_due_frames(double now, const LocalTargets& room);
  void take_chosen_avatars();
  void avatar_download_ended(net::MemberId person);

  RoomPeerOptions options_;
  std::unique_ptr<net::RelayClient> client_;
  class LossyTransport;  // RelayTransport losing a share of tracking packets (drop_tracking)
  std::unique_ptr<net::RelayTransport> relay_transport_;
  std::unique_ptr<LossyTransport> transport_;
  std::unique_ptr<net::RoomSession> session_;
  RemotePeople people_;
  std::unique_ptr<ChosenAvatars> chosen_;  // null: everyone wears the site's avatar
  std::vector<PersonFrame> batch_;         // one round of due frames, at most one per person
  double started_ = 0.0;
  bool entered_once_ = false;
  bool closed_ = false;
  RoomPeerStats stats_;
};

}  // namespace deixis::site
