// net_peer: one Deixis site in its own process, over real ENet sockets, for the tests in
// processes_test.cpp. It connects (as host or joiner), streams moving tracking frames at 30 Hz,
// checks everything it receives against what the other side must have sent (the same fixtures,
// net_fixtures.h), and prints one line "result key=value ..." to stdout. A host listening on port
// 0 first prints "port N" with the port the system chose, so tests never guess free ports.
//
//   net_peer --role host|join|rogue|storm|hammer|garbage --site A --peer-site B [--port N]
//            [--passphrase P] [--kdf cheap|interactive|weak] [--frames N] [--rate HZ]
//            [--until streamed|refused|streams2|stream-with:SITE|cut|deadline] [--map-every S]
//            [--deadline S] [--local ADDRESS] [--count N] [--drop-with CODE]
//
// --role rogue: a joiner that ignores the protocol: it sends tracking and a hello before any
// handshake, answers the welcome with a proof from its own (wrong) passphrase, and keeps sending
// tracking; it reports every message type it received.
// The hostile roles of hostile_test.cpp, each from --local (another loopback address: a stranger
// on another machine) and until --deadline:
//   storm    --count N connections that never say anything, each reconnecting when let go;
//   hammer   joins with a wrong passphrase, one after the other, as fast as the host allows;
//   garbage  --count datagrams of random bytes a second at the host's port.
// --rate HZ (join): send tracking at HZ instead of 30 (a peer that floods). --drop-with CODE
// (host): halfway through the frames, drop the connection with ENet disconnect data CODE and no
// bye (what a spoofed disconnect looks like to the joiner), then listen again.

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <string>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <random>
#include <thread>

#include "net/enet_link.h"
#include "net/passphrase.h"
#include "net/session.h"
#include "net/tracking_codec.h"
#include "net_fixtures.h"

#if defined(DEIXIS_SANITIZED)
extern "C" std::size_t __sanitizer_get_current_allocated_bytes();
#else
#include <malloc.h>
#endif

namespace {

using namespace deixis;
using namespace deixis::net;

// Bytes the program holds on the heap now (ASan's count under ASan, glibc's otherwise).
std::size_t heap_in_use() {
#if defined(DEIXIS_SANITIZED)
  return __sanitizer_get_current_allocated_bytes();
#else
  return mallinfo2().uordblks;
#endif
}

struct Options {
  std::string role = "host";
  std::string site = "A";
  std::string peer_site = "B";
  std::uint16_t port = 0;
  std::string passphrase;
  std::string kdf = "cheap";
  std::uint32_t frames = 45;
  double rate = 30.0;
  std::string until = "streamed";
  std::string until_site;
  double map_every = 0.0;
  double deadline = 20.0;
  std::string local;
  int count = 32;
  std::uint32_t drop_with = 0;
};

Options parse(int argc, char** argv) {
  Options o;
  using Set = std::function<void(const std::string&)>;
  const std::map<std::string, Set> options = {
      {"--role", [&](const std::string& v) { o.role = v; }},
      {"--site", [&](const std::string& v) { o.site = v; }},
      {"--peer-site", [&](const std::string& v) { o.peer_site = v; }},
      {"--port", [&](const std::string& v) { o.port = static_cast<std::uint16_t>(std::stoi(v)); }},
      {"--passphrase", [&](const std::string& v) { o.passphrase = v; }},
      {"--kdf", [&](const std::string& v) { o.kdf = v; }},
      {"--rate", [&](const std::string& v) { o.rate = std::stod(v); }},
      {"--local", [&](const std::string& v) { o.local = v; }},
      {"--count", [&](const std::string& v) { o.count = std::stoi(v); }},
      {"--drop-with",
       [&](const std::string& v) { o.drop_with = static_cast<std::uint32_t>(std::stoul(v)); }},
      {"--frames",
       [&](const std::string& v) { o.frames = static_cast<std::uint32_t>(std::stoul(v)); }},
      {"--until",
       [&](const std::string& v) {
         o.until = v;
         if (v.rfind("stream-with:", 0) == 0) {
           o.until = "stream-with";
           o.until_site = v.substr(12);
         }
       }},
      {"--map-every", [&](const std::string& v) { o.map_every = std::stod(v); }},
      {"--deadline", [&](const std::string& v) { o.deadline = std::stod(v); }},
  };
  for (int i = 1; i + 1 < argc; i += 2) {
    const auto it = options.find(argv[i]);
    if (it == options.end()) {
      std::fprintf(stderr, "net_peer: unknown option %s\n", argv[i]);
      std::exit(2);
    }
    it->second(argv[i + 1]);
  }
  return o;
}

class Clock {
 public:
  double now() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

Role role_of(const std::string& role) {
  return role == "host" ? Role::kHost : Role::kJoiner;
}
Role other(Role r) {
  return r == Role::kHost ? Role::kJoiner : Role::kHost;
}

SessionConfig config_for(Role role, const std::string& site, const Options& o) {
  SessionConfig c = testing::session_config(role, site, o.passphrase);
  c.derive_on_this_thread = false;  // as a site does: Argon2id off the loop
  if (o.kdf == "interactive") {
    c.kdf = c.min_kdf = kInteractiveKdf;  // Argon2id INTERACTIVE: 64 MiB, the joiner's floor
  } else if (o.kdf == "weak") {
    c.kdf = KdfCost{1, 8};  // what a fake host might announce
  }
  return c;
}

bool hello_matches(const Hello& got, const Hello& expected) {
  const BodyCalibration& a = got.avatar.body;
  const BodyCalibration& b = expected.avatar.body;
  return got.site == expected.site && got.avatar.model == expected.avatar.model &&
         a.height == b.height && a.arm_length == b.arm_length && a.deictic_hand == b.deictic_hand &&
         a.T_world_root.translation == b.T_world_root.translation &&
         (a.T_world_root.rotation - b.T_world_root.rotation).norm() < 1e-6f &&
         a.rest_wrist_in_root == b.rest_wrist_in_root;
}

bool map_matches(const TargetMap& got, const TargetMap& expected) {
  if (got.site != expected.site || got.objects.size() != expected.objects.size()) {
    return false;
  }
  for (std::size_t i = 0; i < got.objects.size(); ++i) {
    const TargetObject& a = got.objects[i];
    const TargetObject& b = expected.objects[i];
    if (a.id != b.id || a.name != b.name || a.kind != b.kind || a.position != b.position ||
        a.size != b.size) {
      return false;
    }
  }
  return true;
}

struct Received {
  std::uint64_t played = 0, missed = 0, bad = 0, out_of_order = 0, duplicates = 0;
  std::int64_t last = -1;
};

void check_frame(const Playout& p, const Vec3& remote_root, Received& r) {
  if (static_cast<std::int64_t>(p.sequence) <= r.last) {
    ++r.duplicates;
  } else if (r.last >= 0 && static_cast<std::int64_t>(p.sequence) != r.last + 1) {
    ++r.out_of_order;
  }
  r.last = std::max<std::int64_t>(r.last, p.sequence);
  if (p.kind == PlayoutKind::kMissed) {
    ++r.missed;
    return;
  }
  ++r.played;
  const TrackingFrame expected = testing::moving_frame(p.sequence, remote_root);
  const TrackingFrame& got = *p.frame;
  const bool close =
      (got.T_world_head.translation - expected.T_world_head.translation).norm() < 0.001f &&
      (got.index_tip[1] - expected.index_tip[1]).norm() < 0.001f &&
      (got.T_world_wrist[1].rotation - expected.T_world_wrist[1].rotation).norm() < 0.005f &&
      got.head_target == expected.head_target && got.hand_target == expected.hand_target &&
      got.valid == expected.valid;
  r.bad += close ? 0 : 1;
}

int run_session(const Options& o) {
  const Role role = role_of(o.role);
  std::unique_ptr<EnetLink> link = role == Role::kHost
                                       ? EnetLink::host("127.0.0.1", o.port)
                                       : EnetLink::join("127.0.0.1", o.port, o.local);
  if (role == Role::kHost) {
    std::printf("port %u\n", static_cast<unsigned>(link->port()));
    std::fflush(stdout);
  }
  SessionConfig config = config_for(role, o.site, o);
  link->set_timeout_ms(static_cast<std::uint32_t>(config.heartbeat_timeout * 1000.0) + 2000);
  const Vec3 own_root = config.hello.avatar.body.T_world_root.translation;
  const SessionConfig peer = config_for(other(role), o.peer_site, o);
  const Vec3 remote_root = peer.hello.avatar.body.T_world_root.translation;
  TargetMap expected_map = peer.target_map;
  if (o.map_every > 0.0) {
    expected_map.objects[0].position.x() += 0.01f;  // what the peer's updates send
  }
  Session session(*link, config);

  const Clock clock;
  session.start(clock.now());
  Received r;
  std::uint32_t sent = 0;
  double next_tick = 0.0;
  double next_map = o.map_every;
  double streaming_since = -1.0;
  std::size_t heap_warm = 0;
  bool timed_out = false;
  double refused_at = -1.0;
  std::uint64_t streams_seen = 0;
  std::uint64_t played_in_second_stream = 0;
  bool sealed_seen = false;
  double done_at = -1.0;
  double first_stream = -1.0;
  bool dropped = false;
  bool saw_site = false;
  while (true) {
    const double now = clock.now();
    if (now > o.deadline) {
      timed_out = true;
      break;
    }
    const double until_tick = std::max(0.0, next_tick - now);
    session.service(now, static_cast<std::uint32_t>(std::min(5.0, 1000.0 * until_tick)));
    if (session.status().streams > streams_seen) {
      streams_seen = session.status().streams;
      r.last = -1;  // a new connection numbers its frames from 0
      sent = 0;     // and this side sends its frames afresh
    }
    if (session.state() == SessionState::kStreaming) {
      if (streaming_since < 0.0) {
        streaming_since = now;
      }
      if (first_stream < 0.0) {
        first_stream = now;
      }
      const Hello* remote = session.remote_hello();
      saw_site = saw_site || (remote != nullptr && remote->site == o.until_site);
      if (o.drop_with != 0 && !dropped && sent >= o.frames / 2) {
        // No bye: only ENet's disconnect data, as a third party spoofing it would send.
        link->disconnect(session.peer(), o.drop_with);
        session.close(now);
        session.start(now);
        dropped = true;
      }
      if (now >= next_tick && sent < o.frames) {
        TrackingFrame f = testing::moving_frame(sent, own_root);
        f.time = now;  // the sender's clock
        if (session.send_tracking(f)) {
          ++sent;
        }
        next_tick = now + 1.0 / o.rate;
      }
      if (o.map_every > 0.0 && now >= next_map) {
        TargetMap map = config.target_map;
        map.objects[0].position.x() += 0.01f;  // the room changed a little
        session.set_target_map(map);
        next_map = now + o.map_every;
      }
      if (heap_warm == 0 && now - streaming_since > 1.0) {
        heap_warm = heap_in_use();
      }
    } else {
      streaming_since = -1.0;
    }
    for (Playout p = session.next_frame(now);
         p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed;
         p = session.next_frame(now)) {
      check_frame(p, remote_root, r);
      played_in_second_stream += streams_seen >= 2 && p.kind == PlayoutKind::kFrame ? 1 : 0;
    }
    // When to stop.
    sealed_seen = sealed_seen || (session.state() == SessionState::kStreaming && session.sealed());
    // Every frame the peer sent came out here, as a frame or as missed tracking: so the peer has
    // sent them all.
    const bool all_played = sent >= o.frames && r.last + 1 >= static_cast<std::int64_t>(o.frames);
    if (o.until == "streamed") {
      if (role == Role::kJoiner && all_played && done_at < 0.0) {
        done_at = now;
      }
      if (done_at >= 0.0 && now - done_at > 0.3) {
        break;  // the joiner ends the session, after the host has had time to play its tail
      }
      if (role == Role::kHost && session.status().streams > 0 &&
          session.state() != SessionState::kStreaming) {
        break;  // the joiner said bye
      }
    } else if (o.until == "refused") {
      if (session.state() == SessionState::kRefused) {
        break;
      }
      if ((session.status().auth_failures > 0 || session.strangers().chatty > 0) &&
          refused_at < 0.0) {
        refused_at = now;
      }
      if (refused_at >= 0.0 && now - refused_at > 0.5) {
        break;  // watched what the refused peer sends afterwards
      }
    } else if (o.until == "streams2") {
      if (played_in_second_stream >= 15 && !(role == Role::kHost && o.drop_with != 0)) {
        break;
      }
      if (role == Role::kHost && o.drop_with == 0 && sent >= o.frames) {
        break;  // this host leaves after its frames; another takes its place
      }
      if (role == Role::kHost && o.drop_with != 0 && session.status().streams >= 2 &&
          session.state() != SessionState::kStreaming) {
        break;  // the joiner came back after the dropped connection, and left
      }
    } else if (o.until == "stream-with") {
      if (saw_site && session.state() != SessionState::kStreaming) {
        break;  // the peer we waited for streamed with us and left
      }
    } else if (o.until == "cut") {
      if (session.status().last_bye == ByeReason::kFlooding) {
        break;  // the peer cut us off for sending too much
      }
    } else if (o.until == "deadline") {
      if (now > o.deadline - 0.1) {
        break;
      }
    }
  }
  const std::size_t heap_end = heap_in_use();
  const double end = clock.now();
  const SessionState final_state = session.state();
  session.close(end);
  link->drain(500);

  const DropCounters& d = session.drops();
  const Hello* hello = session.remote_hello();
  const TargetMap* map = session.remote_target_map();
  std::printf(
      "result site=%s state=%s streams=%llu attempts=%llu hello_ok=%d map_ok=%d sealed=%d sent=%u "
      "played=%llu missed=%llu bad=%llu out_of_order=%llu duplicates_played=%llu "
      "tracking_received=%llu drops=%llu unauthenticated=%llu decrypt_failed=%llu "
      "replayed=%llu auth_failures=%llu last_bye=%d timeouts=%llu ignored=%llu heap_warm=%zu "
      "heap_end=%zu timed_out=%d second_stream_played=%llu maps_received=%llu first_stream=%.3f "
      "end_cause=%d floods_cut=%llu strangers=%llu over_budget=%llu evicted=%llu "
      "stranger_timeouts=%llu held_back=%llu busy=%llu salts_rotated=%llu chatty=%llu\n",
      o.site.c_str(), std::string(state_name(final_state)).c_str(),
      static_cast<unsigned long long>(session.status().streams),
      static_cast<unsigned long long>(session.status().attempts),
      hello != nullptr && hello_matches(*hello, peer.hello) ? 1 : 0,
      map != nullptr && map_matches(*map, expected_map) ? 1 : 0, sealed_seen ? 1 : 0, sent,
      static_cast<unsigned long long>(r.played), static_cast<unsigned long long>(r.missed),
      static_cast<unsigned long long>(r.bad), static_cast<unsigned long long>(r.out_of_order),
      static_cast<unsigned long long>(r.duplicates),
      static_cast<unsigned long long>(session.stats().tracking_received),
      static_cast<unsigned long long>(d.total),
      static_cast<unsigned long long>(d[DropReason::kUnauthenticated]),
      static_cast<unsigned long long>(d[DropReason::kDecryptFailed]),
      static_cast<unsigned long long>(d[DropReason::kReplayed]),
      static_cast<unsigned long long>(session.status().auth_failures),
      static_cast<int>(session.status().last_bye),
      static_cast<unsigned long long>(session.status().timeouts),
      static_cast<unsigned long long>(link->ignored_packets()), heap_warm, heap_end,
      timed_out ? 1 : 0, static_cast<unsigned long long>(played_in_second_stream),
      static_cast<unsigned long long>(session.stats().target_maps_received), first_stream,
      static_cast<int>(session.status().last_end),
      static_cast<unsigned long long>(session.stats().floods_cut),
      static_cast<unsigned long long>(session.strangers().connected),
      static_cast<unsigned long long>(session.strangers().over_budget),
      static_cast<unsigned long long>(session.strangers().evicted),
      static_cast<unsigned long long>(session.strangers().timed_out),
      static_cast<unsigned long long>(session.strangers().held_back),
      static_cast<unsigned long long>(session.strangers().busy),
      static_cast<unsigned long long>(session.strangers().salts_rotated),
      static_cast<unsigned long long>(session.strangers().chatty));
  return 0;
}

// The join a joiner with the key `key` (of another passphrase) makes for `welcome`.
Join wrong_join(const Welcome& welcome, const std::optional<Key>& key, const std::string& site) {
  Join join;
  join.auth = welcome.auth;
  random_bytes(join.joiner_challenge);
  if (key) {
    const ExchangeKeyPair ours = make_exchange_keys();
    join.joiner_key = ours.public_key;
    const Key transcript = transcript_of(welcome, join);
    if (const auto prk = handshake_secret(*key, transcript, ours, welcome.host_key, false)) {
      join.proof = seal_join_proof(*prk, transcript, site);
    }
  }
  return join;
}

// A joiner without the passphrase that does not follow the protocol.
int run_rogue(const Options& o) {
  std::unique_ptr<EnetLink> link = EnetLink::join("127.0.0.1", o.port, o.local);
  const SessionConfig config = config_for(Role::kJoiner, o.site, o);
  PeerId peer = kNoPeer;
  const Vec3 root = config.hello.avatar.body.T_world_root.translation;
  std::vector<std::byte> tracking(kTrackingBytes);
  std::vector<std::byte> hello;
  encode(config.hello, hello);
  std::vector<std::byte> forged(kTrackingBytes + kSealOverheadBytes, std::byte{0x5A});
  forged[0] = std::byte{0x20};
  std::uint32_t seq = 0;
  const auto spray = [&] {
    for (int i = 0; i < 5; ++i) {
      encode_tracking({seq, testing::moving_frame(seq, root)}, root, tracking);
      ++seq;
      link->send(peer, Channel::kTracking, tracking);
      link->send(peer, Channel::kTracking, forged);
    }
  };
  std::map<int, int> received;
  int bye_reason = -1;
  bool disconnected = false;
  const Clock clock;
  peer = link->connect();
  while (!disconnected && clock.now() < o.deadline) {
    for (LinkEvent e = link->next_event(5); e.kind != LinkEvent::Kind::kNone;
         e = link->next_event(0)) {
      if (e.kind == LinkEvent::Kind::kConnected) {
        spray();
        link->send(peer, Channel::kReliable, hello);
      } else if (e.kind == LinkEvent::Kind::kDisconnected) {
        disconnected = true;
      } else if (e.kind == LinkEvent::Kind::kReceived && !e.bytes.empty()) {
        ++received[std::to_integer<int>(e.bytes[0])];
        Welcome welcome;
        Bye bye;
        if (decode(e.bytes, welcome).ok()) {
          // A proof from the wrong passphrase, made exactly as a joiner would.
          const auto key = derive_master_key(o.passphrase, welcome.salt, welcome.kdf);
          std::vector<std::byte> bytes;
          encode(wrong_join(welcome, key, o.site), bytes);
          link->send(peer, Channel::kReliable, bytes);
          spray();
        } else if (decode(e.bytes, bye).ok()) {
          bye_reason = static_cast<int>(bye.reason);
          spray();  // and more, as the connection closes
        }
      }
    }
  }
  int others = 0;
  for (const auto& [type, count] : received) {
    others += type == 0x01 || type == 0x07 ? 0 : count;
  }
  std::printf(
      "result site=%s got_welcome=%d got_bye=%d bye_reason=%d other_messages=%d "
      "disconnected=%d\n",
      o.site.c_str(), received[0x01], received[0x07], bye_reason, others, disconnected ? 1 : 0);
  return 0;
}

// --count connections that never send anything above ENet; each one let go connects again.
int run_storm(const Options& o) {
  std::vector<std::unique_ptr<EnetLink>> links;
  for (int i = 0; i < o.count; ++i) {
    links.push_back(EnetLink::join("127.0.0.1", o.port, o.local));
    links.back()->connect();
  }
  std::printf("storm started\n");
  std::fflush(stdout);
  std::uint64_t connects = static_cast<std::uint64_t>(o.count), let_go = 0, connected = 0;
  const Clock clock;
  while (clock.now() < o.deadline) {
    for (auto& link : links) {
      for (LinkEvent e = link->next_event(0); e.kind != LinkEvent::Kind::kNone;
           e = link->next_event(0)) {
        if (e.kind == LinkEvent::Kind::kConnected) {
          ++connected;
        } else if (e.kind == LinkEvent::Kind::kDisconnected) {
          ++let_go;
          ++connects;
          link->connect();
        }
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  std::printf("result connects=%llu connected=%llu let_go=%llu\n",
              static_cast<unsigned long long>(connects), static_cast<unsigned long long>(connected),
              static_cast<unsigned long long>(let_go));
  return 0;
}

// Joins with a wrong passphrase, one connection after the other, until the deadline.
int run_hammer(const Options& o) {
  std::unique_ptr<EnetLink> link = EnetLink::join("127.0.0.1", o.port, o.local);
  std::optional<Key> key;
  Salt salt{};
  KdfCost cost{0, 0};
  std::uint64_t guesses = 0, refused = 0, held_back = 0, other_byes = 0;
  const Clock clock;
  PeerId peer = link->connect();
  std::printf("hammer started\n");
  std::fflush(stdout);
  while (clock.now() < o.deadline) {
    for (LinkEvent e = link->next_event(5); e.kind != LinkEvent::Kind::kNone;
         e = link->next_event(0)) {
      Welcome welcome;
      Bye bye;
      if (e.kind == LinkEvent::Kind::kDisconnected) {
        // Turned away at once while the address backs off: ENet's disconnect data says so.
        held_back += e.data == static_cast<std::uint32_t>(ByeReason::kTryLater) ? 1 : 0;
        peer = link->connect();
      } else if (e.kind == LinkEvent::Kind::kReceived && decode(e.bytes, welcome).ok()) {
        if (!key || salt != welcome.salt || !(cost == welcome.kdf)) {
          salt = welcome.salt;  // an attacker derives once per salt, and guesses fast
          cost = welcome.kdf;
          key = derive_master_key(o.passphrase, salt, cost);
        }
        std::vector<std::byte> bytes;
        encode(wrong_join(welcome, key, o.site), bytes);
        link->send(peer, Channel::kReliable, bytes);
        ++guesses;
      } else if (e.kind == LinkEvent::Kind::kReceived && decode(e.bytes, bye).ok()) {
        refused += bye.reason == ByeReason::kAuthenticationFailed ? 1 : 0;
        held_back += bye.reason == ByeReason::kTryLater ? 1 : 0;
        other_byes +=
            bye.reason != ByeReason::kAuthenticationFailed && bye.reason != ByeReason::kTryLater
                ? 1
                : 0;
        link->disconnect(peer, 0);
        peer = link->connect();
      }
    }
  }
  std::printf("result guesses=%llu refused=%llu held_back=%llu other_byes=%llu seconds=%.2f\n",
              static_cast<unsigned long long>(guesses), static_cast<unsigned long long>(refused),
              static_cast<unsigned long long>(held_back),
              static_cast<unsigned long long>(other_byes), clock.now());
  return 0;
}

// --count datagrams of random bytes a second at the host's port, in 1-ms bursts.
int run_garbage(const Options& o) {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) {
    std::fprintf(stderr, "net_peer: no UDP socket\n");
    return 1;
  }
  sockaddr_in local{};
  local.sin_family = AF_INET;
  inet_pton(AF_INET, o.local.empty() ? "127.0.0.1" : o.local.c_str(), &local.sin_addr);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(o.port);
  inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
  if (bind(fd, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
    std::fprintf(stderr, "net_peer: cannot bind %s\n", o.local.c_str());
    close(fd);
    return 1;
  }
  std::mt19937 rng(7);
  std::array<unsigned char, 1400> datagram{};
  std::uint64_t sent = 0;
  const int per_ms = std::max(1, o.count / 1000);
  std::printf("garbage started\n");
  std::fflush(stdout);
  const Clock clock;
  while (clock.now() < o.deadline) {
    for (int i = 0; i < per_ms; ++i) {
      const std::size_t size = 1 + rng() % datagram.size();
      for (std::size_t k = 0; k < size; ++k) {
        datagram[k] = static_cast<unsigned char>(rng());
      }
      if (sendto(fd, datagram.data(), size, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to) >
          0) {
        ++sent;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  close(fd);
  std::printf("result sent=%llu per_second=%.0f\n", static_cast<unsigned long long>(sent),
              static_cast<double>(sent) / clock.now());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_default_logger(spdlog::stderr_color_mt("net_peer"));
  try {
    const Options o = parse(argc, argv);
    spdlog::set_pattern("[%H:%M:%S.%e] [" + o.role + " " + o.site + "] %v");
    if (o.role == "rogue") {
      return run_rogue(o);
    }
    if (o.role == "storm") {
      return run_storm(o);
    }
    if (o.role == "hammer") {
      return run_hammer(o);
    }
    if (o.role == "garbage") {
      return run_garbage(o);
    }
    return run_session(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "net_peer: %s\n", e.what());
    return 1;
  }
}
