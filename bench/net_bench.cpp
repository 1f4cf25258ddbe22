// The network layer's figures: bytes and time per tracking frame, sealing, the jitter
// buffer, a streaming tick of two sessions, one frame through real ENet on loopback, the
// jitter-buffer delay against network jitter (the figure behind the 50 ms default), and the
// relay's forwarding rate and added latency (docs/relay.md).
//
//   build/release/bench/net_bench
//   build/release/bench/net_bench --benchmark_filter=JitterDelay --benchmark_repetitions=1

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <random>
#include <vector>

#include <spdlog/spdlog.h>

#include "net/enet_link.h"
#include "net/jitter_buffer.h"
#include "net/relay_client.h"
#include "net/relay_server.h"
#include "net/sealing.h"
#include "net/session.h"
#include "net/simulated_link.h"
#include "net/tracking_codec.h"

namespace {

using namespace deixis;
using namespace deixis::net;

constexpr double kTick = 1.0 / 30.0;
// ENet around one tracking packet in its own datagram: protocol header 2 bytes (peer id; the
// sent time only rides along when a command needs an acknowledgement), an unsequenced send
// command 8 bytes (BM_EnetLoopbackFrame measures the sum); then UDP 8 and IPv4 20.
constexpr double kEnetBytes = 10.0;
constexpr double kUdpIpBytes = 28.0;

TrackingFrame frame_at(std::uint32_t i, const Vec3& root) {
  const float t = static_cast<float>(i) * static_cast<float>(kTick);
  TrackingFrame f;
  f.time = i * kTick;
  const Mat3 head = Eigen::AngleAxisf(0.3f * std::sin(t), Vec3::UnitY()).toRotationMatrix();
  f.T_world_head = Pose{head, root + Vec3(0.01f * std::sin(t), 0, 0)};
  f.gaze = (head * Vec3(0.1f, -0.05f, -1.0f)).normalized();
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    const float side = h == Hand::kRight ? 1.0f : -1.0f;
    const Mat3 wrist =
        Eigen::AngleAxisf(side * (0.2f + 0.3f * std::sin(t)), Vec3::UnitZ()).toRotationMatrix();
    f.T_world_wrist[index(h)] = Pose{wrist, root + Vec3(0.2f * side, -0.6f, -0.2f)};
    f.index_tip[index(h)] = f.T_world_wrist[index(h)].translation + wrist * Vec3(0.15f, 0, 0);
  }
  f.valid = tracked::kAll;
  f.head_target = 3;
  f.hand_target = 7;
  f.head_target_position = root + Vec3(-1, 0, -2);
  f.hand_target_position = root + Vec3(0.5f, -0.4f, -1.2f);
  return f;
}

std::vector<TrackingFrame> frames(const Vec3& root) {
  std::vector<TrackingFrame> v;
  for (std::uint32_t i = 0; i < 1024; ++i) {
    v.push_back(frame_at(i, root));
  }
  return v;
}

SessionConfig session_config(Role role, std::string site, std::string passphrase) {
  SessionConfig c;
  c.role = role;
  c.hello.site = std::move(site);
  c.passphrase = std::move(passphrase);
  c.kdf = c.min_kdf = {1, 8};  // the handshake is not what these benchmarks time
  // Frames back to back, as fast as the loop goes: far beyond a real peer's budget, on purpose.
  c.budget.packets_per_second = 1e9;
  c.budget.bytes_per_second = 1e12;
  c.logger = std::make_shared<spdlog::logger>("bench");  // no sinks: quiet
  return c;
}

void bytes_counters(benchmark::State& state, double payload) {
  state.counters["payload_B"] = payload;
  state.counters["udp_payload_B"] = payload + kEnetBytes;
  state.counters["on_wire_B"] = payload + kEnetBytes + kUdpIpBytes;
  state.counters["kB_per_s_at_30Hz"] = 30.0 * (payload + kEnetBytes + kUdpIpBytes) / 1000.0;
}

void BM_EncodeTracking(benchmark::State& state) {
  const Vec3 root(0, 1.6f, 0);
  const std::vector<TrackingFrame> f = frames(root);
  std::array<std::byte, kTrackingBytes> out{};
  std::uint32_t i = 0;
  for (auto _ : state) {
    const TrackingEncoding e = encode_tracking({i, f[i & 1023]}, root, out);
    benchmark::DoNotOptimize(e);
    benchmark::ClobberMemory();
    ++i;
  }
  bytes_counters(state, kTrackingBytes);
}
BENCHMARK(BM_EncodeTracking);

void BM_DecodeTracking(benchmark::State& state) {
  const Vec3 root(0, 1.6f, 0);
  const std::vector<TrackingFrame> f = frames(root);
  std::vector<std::array<std::byte, kTrackingBytes>> packets(1024);
  for (std::uint32_t i = 0; i < 1024; ++i) {
    encode_tracking({i, f[i]}, root, packets[i]);
  }
  TrackingMessage m;
  std::uint32_t i = 0;
  for (auto _ : state) {
    const WireResult r = decode_tracking(packets[i++ & 1023], root, m);
    benchmark::DoNotOptimize(r);
    benchmark::DoNotOptimize(m);
  }
  bytes_counters(state, kTrackingBytes);
}
BENCHMARK(BM_DecodeTracking);

void BM_SealAndOpenTracking(benchmark::State& state) {
  Key key{};
  key.fill(std::byte{1});
  PacketSealer sealer(key);
  PacketOpener opener(key);
  std::array<std::byte, kTrackingBytes> plain{};
  encode_tracking({0, frame_at(0, Vec3::Zero())}, Vec3::Zero(), plain);
  std::array<std::byte, kTrackingBytes + kSealOverheadBytes> sealed{};
  std::array<std::byte, kTrackingBytes> scratch{};
  for (auto _ : state) {
    const std::size_t n = sealer.seal(Channel::kTracking, plain, sealed);
    std::span<const std::byte> opened;
    const WireResult r =
        opener.open(Channel::kTracking, std::span(sealed).first(n), scratch, opened);
    benchmark::DoNotOptimize(r);
  }
  bytes_counters(state, kTrackingBytes + kSealOverheadBytes);
}
BENCHMARK(BM_SealAndOpenTracking);

void BM_JitterBufferPushPop(benchmark::State& state) {
  JitterBuffer buffer;
  const TrackingFrame f = frame_at(0, Vec3::Zero());
  std::uint32_t i = 0;
  for (auto _ : state) {
    TrackingFrame g = f;
    g.time = i * kTick;
    buffer.push(i, g, g.time + 0.02);
    const Playout p = buffer.pop(g.time + 0.02);
    benchmark::DoNotOptimize(p);
    ++i;
  }
}
BENCHMARK(BM_JitterBufferPushPop);

// Two sessions streaming to each other (sealed) over the simulated network: one tracking tick of
// both sides, everything included but a real socket.
void BM_SessionTickSealed(benchmark::State& state) {
  SimulatedNetwork network({}, 1);
  Session host(network.host(), session_config(Role::kHost, "A", "bench"));
  Session joiner(network.joiner(), session_config(Role::kJoiner, "B", "bench"));
  double now = 0.0;
  host.start(now);
  joiner.start(now);
  while (host.state() != SessionState::kStreaming || joiner.state() != SessionState::kStreaming) {
    now += 0.005;
    network.set_time(now);
    host.service(now);
    joiner.service(now);
  }
  const std::vector<TrackingFrame> f = frames(Vec3::Zero());
  std::uint32_t i = 0;
  for (auto _ : state) {
    TrackingFrame g = f[i & 1023];
    g.time = now;
    host.send_tracking(g);
    joiner.send_tracking(g);
    now += kTick;
    network.set_time(now);
    host.service(now);
    joiner.service(now);
    for (Session* s : {&host, &joiner}) {
      for (Playout p = s->next_frame(now);
           p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed;
           p = s->next_frame(now)) {
        benchmark::DoNotOptimize(p);
      }
    }
    ++i;
  }
  state.counters["played"] = static_cast<double>(host.jitter().played);
}
BENCHMARK(BM_SessionTickSealed);

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// One tracking frame from a joiner to a host through real ENet sockets on 127.0.0.1, until the
// host has decoded it: send, flush, the kernel's loopback, receive, open, decode, jitter push.
void BM_EnetLoopbackFrame(benchmark::State& state) {
  const bool sealed = state.range(0) != 0;
  auto host_link = EnetLink::host("127.0.0.1", 0);
  auto joiner_link = EnetLink::join("127.0.0.1", host_link->port());
  Session host(*host_link, session_config(Role::kHost, "A", sealed ? "bench" : ""));
  Session joiner(*joiner_link, session_config(Role::kJoiner, "B", sealed ? "bench" : ""));
  const auto start = std::chrono::steady_clock::now();
  host.start(0.0);
  joiner.start(0.0);
  while ((host.state() != SessionState::kStreaming || joiner.state() != SessionState::kStreaming) &&
         seconds_since(start) < 10.0) {
    host.service(seconds_since(start), 1);
    joiner.service(seconds_since(start), 1);
  }
  if (host.state() != SessionState::kStreaming) {
    state.SkipWithError("could not connect over loopback");
    return;
  }
  const std::vector<TrackingFrame> f = frames(Vec3::Zero());
  const EnetLink::Traffic before = joiner_link->traffic();
  std::uint32_t i = 0;
  for (auto _ : state) {
    const std::uint64_t received = host.stats().tracking_received;
    TrackingFrame g = f[i++ & 1023];
    g.time = seconds_since(start);
    joiner.send_tracking(g);
    while (host.stats().tracking_received == received && seconds_since(start) < 60.0) {
      host.service(seconds_since(start), 1);
    }
    joiner.service(seconds_since(start));  // acknowledgements, heartbeats
  }
  const EnetLink::Traffic after = joiner_link->traffic();
  const double datagrams = static_cast<double>(after.sent_datagrams - before.sent_datagrams);
  state.counters["udp_payload_B_per_datagram"] =
      static_cast<double>(after.sent_bytes - before.sent_bytes) / std::max(1.0, datagrams);
  state.counters["datagrams_per_frame"] = datagrams / static_cast<double>(state.iterations());
}
BENCHMARK(BM_EnetLoopbackFrame)->Arg(0)->Arg(1)->ArgNames({"sealed"})->UseRealTime();

// What the passphrase costs a joiner: from its start to both sides streaming, over real sockets
// on 127.0.0.1, with the host's key already derived and the joiner's Argon2id at the cost the
// host asks (range 0: libsodium's INTERACTIVE, the joiner's floor; 1: MODERATE, the ceiling).
// Everything else in the handshake (X25519, proofs, hellos) is included; Argon2id dominates.
void BM_Handshake(benchmark::State& state) {
  const KdfCost cost = state.range(0) == 0 ? kInteractiveKdf : KdfCost{3, 256 * 1024};
  for (auto _ : state) {
    auto host_link = EnetLink::host("127.0.0.1", 0);
    auto joiner_link = EnetLink::join("127.0.0.1", host_link->port());
    SessionConfig host_config = session_config(Role::kHost, "A", "bench");
    SessionConfig joiner_config = session_config(Role::kJoiner, "B", "bench");
    host_config.kdf = cost;
    joiner_config.min_kdf = kInteractiveKdf;
    Session host(*host_link, host_config);
    Session joiner(*joiner_link, joiner_config);
    const auto created = std::chrono::steady_clock::now();
    while (host.deriving_key() && seconds_since(created) < 30.0) {
      host.service(seconds_since(created), 1);  // the host's own key, derived before anyone comes
    }
    const auto start = std::chrono::steady_clock::now();
    host.start(0.0);
    joiner.start(0.0);
    while (
        (host.state() != SessionState::kStreaming || joiner.state() != SessionState::kStreaming) &&
        seconds_since(start) < 30.0) {
      host.service(seconds_since(start), 1);
      joiner.service(seconds_since(start), 1);
    }
    if (joiner.state() != SessionState::kStreaming) {
      state.SkipWithError("the handshake did not finish");
      return;
    }
    state.SetIterationTime(seconds_since(start));
  }
}
BENCHMARK(BM_Handshake)
    ->Arg(0)
    ->Arg(1)
    ->ArgNames({"moderate"})
    ->UseManualTime()
    ->Iterations(5)
    ->Unit(benchmark::kMillisecond);

// The delay choice: 3000 frames with Gaussian transit jitter (std `jitter_ms`) through a jitter
// buffer with `delay_ms` of delay. Counters: the share of frames that came too late (played as
// missed tracking) and the mean time a frame waited in the buffer.
void BM_JitterDelay(benchmark::State& state) {
  JitterConfig config;
  config.delay = static_cast<double>(state.range(0)) / 1000.0;
  const double jitter = static_cast<double>(state.range(1)) / 1000.0;
  constexpr int kFrames = 3000;
  double late_share = 0.0, waited = 0.0;
  for (auto _ : state) {
    JitterBuffer buffer(config);
    std::mt19937_64 rng(7);
    std::normal_distribution<double> gaussian(0.0, 1.0);
    std::vector<std::pair<double, std::uint32_t>> arrivals;
    for (std::uint32_t s = 0; s < kFrames; ++s) {
      arrivals.push_back({s * kTick + std::max(0.0, 0.040 + jitter * gaussian(rng)), s});
    }
    std::sort(arrivals.begin(), arrivals.end());
    TrackingFrame frame;
    std::size_t next = 0;
    for (double now = 0.0; next < arrivals.size(); now += 0.001) {
      while (next < arrivals.size() && arrivals[next].first <= now) {
        frame.time = arrivals[next].second * kTick;
        buffer.push(arrivals[next].second, frame, arrivals[next].first);
        ++next;
      }
      for (Playout p = buffer.pop(now);
           p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed; p = buffer.pop(now)) {
      }
    }
    late_share = static_cast<double>(buffer.stats().late) / kFrames;
    waited = buffer.stats().waited_sum /
             static_cast<double>(std::max<std::uint64_t>(1, buffer.stats().played));
  }
  state.counters["late_pct"] = 100.0 * late_share;
  state.counters["mean_wait_ms"] = 1000.0 * waited;
}
BENCHMARK(BM_JitterDelay)
    ->ArgsProduct({{0, 17, 33, 50, 67, 100}, {0, 5, 10, 20}})
    ->ArgNames({"delay_ms", "jitter_ms"})
    ->Unit(benchmark::kMillisecond);

// ---- The relay (docs/relay.md) ----

// A room member that counts what reaches it.
class CountingMember : public RelayListener {
 public:
  void on_relay_ready() override {
    const std::array<std::uint8_t, 16> announce{};
    client->enter({}, announce);
  }
  void on_entered(MemberId, std::span<const std::uint8_t>, std::span<const RoomMember>) override {}
  void on_member_joined(const RoomMember&) override {}
  void on_member_left(MemberId) override {}
  void on_payload(MemberId, Channel, std::span<const std::uint8_t>) override { ++received; }
  void on_refused(RelayRefusal) override {}
  void on_relay_lost() override {}

  RelayClient* client = nullptr;
  std::uint64_t received = 0;
};

// A relay as `deixis relay` runs it (its link's peer limits, its defaults), with budgets opened
// up: the benchmarks send far beyond what one member may.
struct BenchRelay {
  BenchRelay()
      : link(EnetLink::host("127.0.0.1", 0, HostLimits{RelayServerConfig{}.max_connections, 64})),
        server(*link, config()) {}
  static RelayServerConfig config() {
    RelayServerConfig c;
    c.max_people = kMaxRoomPeople;
    c.budget.packets_per_second = 1e9;
    c.budget.bytes_per_second = 1e12;
    c.logger = std::make_shared<spdlog::logger>("bench");  // no sinks: quiet
    return c;
  }
  std::unique_ptr<EnetLink> link;
  RelayServer server;
};

struct BenchRoom {
  explicit BenchRoom(BenchRelay& relay, std::size_t people) : relay_(relay) {
    RelayClientOptions o;
    o.port = relay.link->port();
    o.room = room_token("bench");
    o.logger = std::make_shared<spdlog::logger>("bench");
    members.resize(people);
    for (std::size_t i = 0; i < people; ++i) {
      clients.push_back(std::make_unique<RelayClient>(o, seconds()));
      members[i].client = clients.back().get();
    }
    while (seconds() < 10.0 && relay.server.members_in(o.room) < people) {
      step();
    }
    while (seconds() < 10.0 && !std::all_of(clients.begin(), clients.end(),
                                            [](const auto& c) { return c->in_room(); })) {
      step();
    }
  }
  bool ready() const {
    return std::all_of(clients.begin(), clients.end(), [](const auto& c) { return c->in_room(); });
  }
  double seconds() const { return seconds_since(start); }
  void poll_members() {
    for (std::size_t i = 0; i < clients.size(); ++i) {
      clients[i]->poll(seconds(), members[i]);
    }
  }
  void step() {
    relay_.server.service(seconds(), 0);
    poll_members();
  }
  std::uint64_t received() const {
    std::uint64_t n = 0;
    for (const CountingMember& m : members) {
      n += m.received;
    }
    return n;
  }

  BenchRelay& relay_;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  std::vector<std::unique_ptr<RelayClient>> clients;
  std::vector<CountingMember> members;
};

// CPU time of this thread (s): what the relay's work costs a core, whatever else the machine runs.
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// The relay's forwarding rate on one core: every member of a room of N sends one tracking-sized
// forward (100 bytes: a sealed tracking packet of docs/rooms-protocol.md) to everyone else, and
// only the CPU time inside the relay's service() calls is counted (manual time), until all N·(N−1)
// copies reached their members. What the relay does per datagram is all here: ENet's receive,
// decoding, the fan-out, one send and flush per copy, the kernel's loopback.
void BM_RelayForward(benchmark::State& state) {
  const auto people = static_cast<std::size_t>(state.range(0));
  BenchRelay relay;
  BenchRoom room(relay, people);
  if (!room.ready()) {
    state.SkipWithError("the room did not fill over loopback");
    return;
  }
  const std::vector<std::uint8_t> payload(100, 0x5A);
  const std::uint64_t out_before = relay.server.stats().forwards_out;
  const std::uint64_t in_before = relay.server.stats().forwards_in;
  double relay_seconds = 0.0;
  for (auto _ : state) {
    const std::uint64_t expected = room.received() + people * (people - 1);
    for (auto& c : room.clients) {
      c->send(kAllMembers, Channel::kTracking, payload);
    }
    double busy = 0.0;
    const double give_up = room.seconds() + 5.0;
    while (room.received() < expected && room.seconds() < give_up) {
      const double t0 = thread_cpu_seconds();
      relay.server.service(room.seconds(), 0);
      busy += thread_cpu_seconds() - t0;
      room.poll_members();
    }
    state.SetIterationTime(busy);
    relay_seconds += busy;
  }
  const auto out = static_cast<double>(relay.server.stats().forwards_out - out_before);
  const auto in = static_cast<double>(relay.server.stats().forwards_in - in_before);
  state.counters["forwards_out_per_s"] = out / std::max(relay_seconds, 1e-9);
  state.counters["datagrams_per_s"] = (in + out) / std::max(relay_seconds, 1e-9);
  state.counters["us_per_forward_in"] = 1e6 * relay_seconds / std::max(in, 1.0);
  // Rooms of eight at 30 Hz: each member's tracking in, and out to seven others.
  state.counters["rooms_of_8_at_30Hz"] =
      (in + out) / std::max(relay_seconds, 1e-9) / (30.0 * 8.0 * (1.0 + 7.0));
}
BENCHMARK(BM_RelayForward)->Arg(2)->Arg(4)->Arg(8)->ArgNames({"people"})->UseManualTime();

// One 100-byte tracking packet from one site to another on 127.0.0.1, until the receiver has
// it: directly (via_relay:0, one ENet link, as a direct session's tracking goes) or through a
// relay in the same process (via_relay:1: forward, fan-out, forwarded). Wall-clock time; the
// difference is what the relay adds on loopback.
void BM_RelayLatency(benchmark::State& state) {
  const bool via_relay = state.range(0) != 0;
  const std::vector<std::uint8_t> payload(100, 0x5A);
  const auto start = std::chrono::steady_clock::now();
  if (via_relay) {
    BenchRelay relay;
    BenchRoom room(relay, 2);
    if (!room.ready()) {
      state.SkipWithError("the room did not fill over loopback");
      return;
    }
    for (auto _ : state) {
      const std::uint64_t before = room.members[1].received;
      room.clients[0]->send(kAllMembers, Channel::kTracking, payload);
      while (room.members[1].received == before && seconds_since(start) < 60.0) {
        relay.server.service(room.seconds(), 0);
        room.clients[1]->poll(room.seconds(), room.members[1]);
      }
      room.clients[0]->poll(room.seconds(), room.members[0]);  // acknowledgements, keepalives
    }
    return;
  }
  auto receiver = EnetLink::host("127.0.0.1", 0);
  auto sender = EnetLink::join("127.0.0.1", receiver->port());
  const PeerId to = sender->connect();
  bool up_sender = false, up_receiver = false;
  while ((!up_sender || !up_receiver) && seconds_since(start) < 10.0) {
    const bool s = sender->next_event(1).kind == LinkEvent::Kind::kConnected;
    const bool r = receiver->next_event(1).kind == LinkEvent::Kind::kConnected;
    up_sender = up_sender || s;
    up_receiver = up_receiver || r;
  }
  if (!up_sender || !up_receiver) {
    state.SkipWithError("could not connect over loopback");
    return;
  }
  const auto bytes = std::as_bytes(std::span(payload));
  for (auto _ : state) {
    sender->send(to, Channel::kTracking, bytes);
    while (receiver->next_event(0).kind != LinkEvent::Kind::kReceived &&
           seconds_since(start) < 60.0) {
    }
    sender->next_event(0);  // acknowledgements
  }
}
BENCHMARK(BM_RelayLatency)->Arg(0)->Arg(1)->ArgNames({"via_relay"})->UseRealTime();

}  // namespace
