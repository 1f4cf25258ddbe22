#pragma once
// The relay (docs/relay.md): rooms of up to max_people members, keyed by a RoomToken (a hash of
// the room's name; the relay never learns the name). It tells each member who is in its room,
// who joined and who left, and forwards opaque payloads between the members of one room on the
// channel they came on. It never parses a payload: with a passphrase, members seal everything
// end to end (docs/rooms-protocol.md) and the relay sees sizes and timing only.
//
// Non-blocking, over any Link (EnetLink in the `deixis relay` command), on the caller's clock:
// service(now) handles at most max_events_per_service link events, then the timers. The defences
// are the direct session's (docs/protocol.md §6, docs/security.md), per connection:
//   - a connection that has not entered a room within pending_timeout is let go (with the
//     direct protocol's "version mismatch" code, so a direct-session joiner that reached a relay
//     stops with a clear reason); at most max_pending_per_address such connections per network
//     address, at most max_pending in all (the oldest let go when full), so silent connections
//     never keep a member out;
//   - every member has a packet and byte budget per second (PeerBudget); one that floods is cut
//     off with a logged reason and told so (kFlooding);
//   - rooms are capped in size (max_people: kRoomFull, final for the client) and in number
//     (max_rooms: kRelayFull); a room is forgotten when its last member leaves;
//   - a member whose link refuses a reliable copy (its queue is full: it cannot keep up) is let go,
//     so that it comes back with a fresh view of the room rather than miss a message;
//   - a keepalive goes to each member that has heard nothing for keepalive_interval, so clients
//     notice a dead relay quickly; a member silent for member_timeout is let go.
// Drops are counted per reason and logged at a limited rate (drop_log.h); so are joins and leaves.
// Forwarding allocates nothing in the relay itself once rooms are stable (ENet allocates its own
// packets, as enet_link.h says).

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

#include "net/drop_log.h"
#include "net/link.h"
#include "net/relay_client.h"
#include "net/relay_wire.h"
#include "net/session.h"

namespace spdlog {
class logger;
}

namespace deixis::net {

struct RelayServerConfig {
  std::size_t max_people = 8;  // per room, 2 … kMaxRoomPeople (--max-people)
  std::size_t max_rooms = 128;
  std::size_t max_connections = 512;  // members and pending together (the link holds as many)
  double pending_timeout = 3.0;       // s from connecting to entering a room
  std::size_t max_pending = 64;
  std::size_t max_pending_per_address = 4;
  std::size_t max_pending_packets = 4;  // a stranger needs one (enter) and a keepalive or two
  std::size_t max_events_per_service = 256;
  double keepalive_interval = kRelayKeepaliveInterval;
  double member_timeout = 3.0;  // s of silence before a member is let go
  // Per member: tracking to everyone at 30 Hz, heartbeats, key messages to each of seven others,
  // target maps and an avatar file in 30 kB pieces, with room to spare (docs/relay.md).
  PeerBudget budget{400.0, 1024.0 * 1024.0, 2.0};
  std::shared_ptr<spdlog::logger> logger;  // null: spdlog's default logger
};

struct RelayServerStats {
  std::uint64_t connections = 0;  // connections accepted as pending
  std::uint64_t entered = 0;      // members that entered a room
  std::uint64_t left = 0;         // members that left (or were let go)
  std::uint64_t rooms_created = 0;
  std::uint64_t rooms_forgotten = 0;
  std::uint64_t refused_room_full = 0;
  std::uint64_t refused_relay_full = 0;
  std::uint64_t refused_version = 0;
  std::uint64_t pending_timed_out = 0;    // did not enter within pending_timeout
  std::uint64_t pending_over_budget = 0;  // turned away: their address had too many pending
  std::uint64_t connections_full = 0;     // turned away: max_connections reached
  std::uint64_t pending_evicted = 0;      // let go to make room (the pending table was full)
  std::uint64_t pending_chatty = 0;       // sent more packets than entering needs
  std::uint64_t members_timed_out = 0;
  std::uint64_t floods_cut = 0;
  std::uint64_t forwards_in = 0;   // forwards accepted
  std::uint64_t forwards_out = 0;  // forwarded packets handed to the link
  std::uint64_t bytes_in = 0;      // payload bytes
  std::uint64_t bytes_out = 0;
  std::uint64_t to_absent = 0;       // forwards to an id not in the room (it may just have left)
  std::uint64_t send_failures = 0;   // the link refused a packet
  std::uint64_t members_behind = 0;  // let go: a reliable copy could not be queued for them
  std::uint64_t keepalives_sent = 0;
  std::uint64_t service_bounded = 0;  // service() calls that left events for the next one
};

class RelayServer {
 public:
  // Throws deixis::Error for a configuration out of range (max_people outside 2 … kMaxRoomPeople).
  RelayServer(Link& link, RelayServerConfig config);
  ~RelayServer();
  RelayServer(const RelayServer&) = delete;
  RelayServer& operator=(const RelayServer&) = delete;

  // Handles at most max_events_per_service link events (waiting at most `wait_ms` for the first)
  // and the timers.
  void service(double now, std::uint32_t wait_ms = 0);

  std::size_t rooms() const { return room_count_; }
  std::size_t members() const;  // in all rooms
  std::size_t pending() const;  // connected, not (yet) in a room
  // Members of the room with this token (0 when there is no such room).
  std::size_t members_in(const RoomToken& room) const;
  const RelayServerStats& stats() const { return stats_; }
  const DropCounters& drops() const { return drop_log_.counters(); }
  const RelayServerConfig& config() const { return config_; }

 private:
  enum class ConnState : std::uint8_t { kFree, kPending, kMember };
  struct Bucket {
    double packets = 0.0;
    double bytes = 0.0;
    double last = 0.0;
  };
  struct Conn {
    ConnState state = ConnState::kFree;
    PeerId peer = kNoPeer;
    std::uint32_t address = 0;
    double since = 0.0;
    double last_heard = 0.0;
    double last_sent = 0.0;
    std::size_t packets = 0;  // while pending
    std::size_t room = 0;     // kMember: index into rooms_
    MemberId id = kNoMember;
    Bucket budget;
  };
  struct Member {
    MemberId id = kNoMember;
    std::size_t conn = 0;
    std::uint8_t announce_size = 0;
    std::array<std::uint8_t, kAnnounceMax> announce{};
    std::span<const std::uint8_t> announce_view() const { return {announce.data(), announce_size}; }
  };
  struct Room {
    bool used = false;
    RoomToken token{};
    std::uint8_t params_size = 0;
    std::array<std::uint8_t, kRoomParamsMax> params{};
    std::size_t count = 0;
    std::array<Member, kMaxRoomPeople> members{};
    MemberId next_id = kFirstMember;
  };

  spdlog::logger& log() const;
  void on_event(const LinkEvent& e, double now);
  void on_connected(PeerId peer, double now);
  void on_disconnected(PeerId peer, double now);
  void on_packet(PeerId peer, Channel channel, std::span<const std::byte> bytes, double now);
  void on_pending_packet(std::size_t c, Channel channel, std::span<const std::byte> bytes,
                         double now);
  void on_member_packet(std::size_t c, Channel channel, std::span<const std::byte> bytes,
                        double now);
  void on_enter(std::size_t c, const RelayEnter& m, double now);
  void forward(std::size_t c, Channel channel, const RelayForward& m, double now);
  bool within_budget(Conn& conn, std::size_t bytes, double now);
  void timers(double now);

  std::size_t find_conn(PeerId peer) const;  // conns_.size(): none
  std::size_t find_or_make_room(const RoomToken& token, std::span<const std::uint8_t> params);
  std::size_t find_room(const RoomToken& token) const;  // rooms_.size(): none
  MemberId next_member_id(Room& room);
  void remove_member(std::size_t c, double now, const char* why);
  // Ends a connection: a member leaves its room first; the conn slot is freed.
  void release(std::size_t c, std::uint32_t code, double now, const char* why);
  void refuse(std::size_t c, RelayRefusal why, double now);
  void evict_oldest_pending(double now);
  std::size_t pending_from(std::uint32_t address) const;
  bool send(std::size_t c, Channel channel, std::span<const std::byte> packet);
  void note(double now, const char* what, std::size_t c, std::size_t room_size);

  Link& link_;
  RelayServerConfig config_;
  DropLog drop_log_;
  LineBudget join_log_budget_{10.0, 5.0};
  LineBudget warn_budget_;
  RelayServerStats stats_;
  std::vector<Conn> conns_;  // fixed capacity: slots reused
  std::unordered_map<PeerId, std::size_t> conn_of_;
  std::vector<std::size_t> free_conns_;
  std::vector<Room> rooms_;
  std::size_t room_count_ = 0;
  std::size_t pending_count_ = 0;
  double next_timers_ = 0.0;
  std::vector<std::byte> tx_;  // one outgoing packet, preallocated (kMaxPacketBytes)
};

}  // namespace deixis::net
