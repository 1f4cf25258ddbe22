// Rooms of several people through an in-process relay (tests/net/room_fixture.h): three members
// verify each other and exchange hellos, maps and tracking; a wrong passphrase sees no one and is
// seen by no one; leaving and rejoining, time-outs, byes, a relay restart; replayed and forged
// packets; loss and silence on one member's link affect only that member's stream.

#include <gtest/gtest.h>

#include <map>
#include <thread>

#include "core/error.h"
#include "net/room_session.h"
#include "room_fixture.h"

namespace deixis::net {
namespace {

using testing::kTick;
using testing::room_config;
using testing::RoomHarness;

std::vector<RoomEvent> events_of(RoomSession& s) {
  std::vector<RoomEvent> out;
  for (RoomEvent e; s.next_event(e);) {
    out.push_back(e);
  }
  return out;
}

bool sees(const RoomSession& s, MemberId id) {
  const auto p = s.people();
  return std::find(p.begin(), p.end(), id) != p.end();
}

// Every member sends one frame a tick and plays what is due; counts frames played and missed
// per (receiver, sender) over `ticks` ticks.
struct Streams {
  std::map<std::pair<std::size_t, MemberId>, std::uint64_t> played, missed, no_stream;
  std::map<std::pair<std::size_t, MemberId>, std::uint32_t> last_sequence;
  bool in_order = true;
};

Streams stream(RoomHarness& room, int ticks, std::uint32_t first = 0) {
  Streams s;
  for (int t = 0; t < ticks; ++t) {
    const std::uint32_t seq = first + static_cast<std::uint32_t>(t);
    for (auto& m : room.members) {
      const Vec3 root = m->config().hello.avatar.body.T_world_root.translation;
      m->send_tracking(testing::moving_frame(seq, root), seq * kTick);
    }
    for (int k = 0; k < 3; ++k) {
      room.step(kTick / 3);
    }
    for (std::size_t i = 0; i < room.members.size(); ++i) {
      RoomSession& m = *room.members[i];
      for (const MemberId person : m.people()) {
        for (Playout p = m.next_playout(person, room.now);
             p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed;
             p = m.next_playout(person, room.now)) {
          auto& last = s.last_sequence[{i, person}];
          if (p.kind == PlayoutKind::kFrame) {
            ++s.played[{i, person}];
            s.in_order = s.in_order && (last == 0 || p.sequence > last);
          } else {
            ++s.missed[{i, person}];
          }
          last = p.sequence;
        }
        if (m.next_playout(person, room.now).kind == PlayoutKind::kNoStream) {
          ++s.no_stream[{i, person}];
        }
      }
    }
  }
  return s;
}

// Three members A, B, C entering one after the other.
struct ThreeInARoom : RoomHarness {
  explicit ThreeInARoom(const std::string& pa = "pw", const std::string& pb = "pw",
                        const std::string& pc = "pw") {
    add(room_config("A", pa, 1.72f));
    run_until([] { return false; }, 0.1);
    add(room_config("B", pb, 1.64f));
    run_until([] { return false; }, 0.1);
    add(room_config("C", pc, 1.80f));
  }
  MemberId id(std::size_t i) const { return members[i]->self(); }
};

TEST(Room, ThreeMembersVerifyEachOtherAndExchangeHellosMapsAndTracking) {
  ThreeInARoom room;
  std::vector<std::vector<std::uint8_t>> seen;
  room.relay.on_forward = [&](testing::FakeRelay::Forward& f) {
    seen.push_back(f.bytes);
    return true;
  };
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({0, 1, 2}, 2); }, 2.0));
  for (std::size_t i = 0; i < 3; ++i) {
    RoomSession& m = *room.members[i];
    EXPECT_TRUE(m.sealed());
    EXPECT_EQ(m.state(), RoomState::kInRoom);
    for (std::size_t j = 0; j < 3; ++j) {
      if (i == j) {
        continue;
      }
      const Hello* h = m.hello(room.id(j));
      ASSERT_NE(h, nullptr);
      EXPECT_EQ(h->site, room.members[j]->config().hello.site);
      EXPECT_FLOAT_EQ(h->avatar.body.height, room.members[j]->config().hello.avatar.body.height);
      ASSERT_TRUE(room.run_until([&] { return m.target_map(room.id(j)) != nullptr; }, 0.5));
      EXPECT_EQ(m.target_map(room.id(j))->objects.size(), 3u);
    }
    const auto ev = events_of(m);
    EXPECT_EQ(std::count_if(ev.begin(), ev.end(),
                            [](const RoomEvent& e) { return e.kind == RoomEventKind::kArrived; }),
              2);
    EXPECT_EQ(m.stats().verified, 2u);
    EXPECT_EQ(m.stats().auth_failures, 0u);
  }
  const Streams s = stream(room, 90);
  EXPECT_TRUE(s.in_order);
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      if (i != j) {
        EXPECT_GE((s.played.at({i, room.id(j)})), 85u) << i << " from " << j;
      }
    }
  }
  // What a frame says arrives: A's view of B's head.
  RoomSession& a = *room.members[0];
  const Vec3 b_root = room.members[1]->config().hello.avatar.body.T_world_root.translation;
  room.members[1]->send_tracking(testing::moving_frame(500, b_root), 90 * kTick);
  room.run_until([] { return false; }, 0.2);
  bool checked = false;
  for (Playout p = a.next_playout(room.id(1), room.now);
       p.kind != PlayoutKind::kPending && p.kind != PlayoutKind::kNoStream;
       p = a.next_playout(room.id(1), room.now)) {
    if (p.kind == PlayoutKind::kFrame && p.sequence == 90) {
      const TrackingFrame sent = testing::moving_frame(500, b_root);
      EXPECT_LT((p.frame->T_world_head.translation - sent.T_world_head.translation).norm(), 2e-3f);
      checked = true;
    }
  }
  EXPECT_TRUE(checked);
  // The relay saw no site name and no hello in the clear.
  for (const auto& bytes : seen) {
    ASSERT_FALSE(bytes.empty());
    EXPECT_TRUE(bytes[0] == 0x20 || bytes[0] == kKeyMessageType) << int(bytes[0]);
    const std::string text(bytes.begin(), bytes.end());
    EXPECT_EQ(text.find("Jüpiter"), std::string::npos);
  }
}

TEST(Room, ANewHelloOrTargetMapReachesEveryoneAsAChange) {
  ThreeInARoom room;
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({0, 1, 2}, 2); }, 2.0));
  room.run_until([] { return false; }, 0.2);
  for (auto& m : room.members) {
    events_of(*m);
  }
  Hello taller = room.members[0]->config().hello;
  taller.avatar.body.height = 1.9f;
  room.members[0]->set_hello(taller);
  room.members[0]->set_target_map(testing::make_target_map("A", 5));
  room.run_until([] { return false; }, 0.2);
  for (std::size_t i : {1u, 2u}) {
    RoomSession& m = *room.members[i];
    const auto ev = events_of(m);
    ASSERT_EQ(ev.size(), 2u);
    EXPECT_EQ(ev[0].kind, RoomEventKind::kHelloChanged);
    EXPECT_EQ(ev[1].kind, RoomEventKind::kTargetMapChanged);
    EXPECT_FLOAT_EQ(m.hello(room.id(0))->avatar.body.height, 1.9f);
    EXPECT_EQ(m.target_map(room.id(0))->objects.size(), 5u);
  }
  taller.site = "Z";
  EXPECT_THROW(room.members[0]->set_hello(taller), deixis::Error);
}

TEST(Room, AChosenAvatarFileGoesOnlyToTheMemberThatAsksAndArrivesWhole) {
  std::vector<std::byte> file(100'000);
  for (std::size_t i = 0; i < file.size(); ++i) {
    file[i] = static_cast<std::byte>((i * 7919u) >> 3);
  }
  RoomHarness room;
  RoomConfig a = room_config("A", "pw");
  a.avatar_file = std::make_shared<const std::vector<std::byte>>(file);
  room.add(a);
  room.run_until([] { return false; }, 0.1);
  room.add(room_config("B", "pw"));
  room.run_until([] { return false; }, 0.1);
  room.add(room_config("C", "pw"));
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({0, 1, 2}, 2); }, 2.0));
  RoomSession& b = *room.members[1];
  const MemberId a_id = room.members[0]->self();
  ASSERT_TRUE(b.avatar_hash(a_id));
  EXPECT_EQ(*b.avatar_hash(a_id), avatar_hash(file));
  EXPECT_FALSE(b.avatar_hash(room.members[2]->self()));  // C chose none
  events_of(b);
  ASSERT_TRUE(b.request_avatar(a_id));
  ASSERT_TRUE(room.run_until(
      [&] { return b.avatar_download(a_id)->status() == AvatarReceiveStatus::kComplete; }, 3.0));
  const auto got = b.avatar_download(a_id)->file();
  EXPECT_TRUE(std::equal(got.begin(), got.end(), file.begin(), file.end()));
  const auto ev = events_of(b);
  EXPECT_TRUE(std::any_of(ev.begin(), ev.end(),
                          [](const RoomEvent& e) { return e.kind == RoomEventKind::kAvatarFile; }));
  EXPECT_EQ(room.members[2]->person_stats(a_id)->avatar_chunks_received, 0u);
  EXPECT_EQ(room.members[2]->drops()[DropReason::kUnexpected], 0u);  // C was sent no chunk
  EXPECT_GE(room.members[0]->stats().avatar_chunks_sent, 7u);
  EXPECT_EQ(room.members[0]->stats().avatar_requests_received, 1u);
}

TEST(Room, AMemberBeyondWhatASiteHoldsIsIgnoredAndSentNothing) {
  RoomHarness room;
  RoomConfig small = room_config("A", "pw");
  small.max_members = 2;
  RoomSession& a = room.add(small);
  for (const char* site : {"B", "C", "D"}) {
    room.run_until([] { return false; }, 0.1);
    room.add(room_config(site, "pw"));
  }
  const MemberId a_id = a.self();
  std::uint64_t a_to_d = 0;
  room.relay.on_forward = [&](testing::FakeRelay::Forward& f) {
    a_to_d += (f.from == a_id && f.to == room.endpoints[3]) ? 1 : 0;
    return true;
  };
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({1, 2}, 3); }, 2.0));
  stream(room, 30);
  EXPECT_EQ(a.people().size(), 2u);
  EXPECT_EQ(a.stats().over_capacity, 1u);
  EXPECT_EQ(room.members[3]->people().size(), 2u);  // B and C, not A
  EXPECT_FALSE(sees(*room.members[3], a_id));
  EXPECT_EQ(a_to_d, 0u);
}

TEST(Room, AnOpenRoomExchangesEverythingInTheClear) {
  ThreeInARoom room("", "", "");
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({0, 1, 2}, 2); }, 2.0));
  EXPECT_FALSE(room.members[0]->sealed());
  const Streams s = stream(room, 60);
  EXPECT_GE((s.played.at({2, room.id(0)})), 55u);
  EXPECT_EQ(room.endpoints[0]->received_by_type[0x20], 0u);
  EXPECT_GT(room.endpoints[0]->received_by_type[0x10], 100u);
}

TEST(Room, AWrongPassphraseSeesNoOneAndIsSeenByNoOne) {
  // W enters second: it proves to A (which refuses), and B, entering after it, proves to W
  // (which cannot open it, so it never answers).
  RoomHarness room;
  RoomSession& a = room.add(room_config("A", "pw"));
  room.run_until([] { return false; }, 0.1);
  RoomSession& w = room.add(room_config("W", "guess"));
  room.run_until([] { return false; }, 0.1);
  RoomSession& b = room.add(room_config("B", "pw"));
  ASSERT_TRUE(
      room.run_until([&] { return a.people().size() == 1 && b.people().size() == 1; }, 2.0));
  const Streams s = stream(room, 60);
  room.run_until([] { return false; }, 4.0);  // heartbeats, time-outs: nothing changes
  EXPECT_TRUE(w.people().empty());
  EXPECT_TRUE(events_of(w).empty());
  EXPECT_FALSE(sees(a, w.self()));
  EXPECT_FALSE(sees(b, w.self()));
  EXPECT_TRUE(sees(a, b.self()));
  EXPECT_GE(a.stats().auth_failures, 1u);  // W's proof
  EXPECT_GE(w.stats().auth_failures, 1u);  // B's proof, under another passphrase
  EXPECT_EQ(w.stats().verified, 0u);
  // W got nothing but B's key message: no answer from A, nothing sealed from A or B.
  const auto& got = room.endpoints[1]->received_by_type;
  EXPECT_EQ(got[kKeyMessageType], 1u);
  EXPECT_EQ(room.endpoints[1]->payloads_received, 1u);
  // A and B each sent W at most B's one proof; nothing W sent reached anyone's people.
  EXPECT_EQ(a.unverified(), 1u);
  EXPECT_GE((s.played.at({0, b.self()})), 55u);
}

TEST(Room, ARelayThatChangesAnAnnounceGetsNoOneVerified) {
  // The relay swaps B's exchange key for one of its own (a man in the middle): A's transcript
  // and pair secret then differ from B's, B's proof does not open at A, and A never answers.
  RoomHarness room;
  RoomSession& a = room.add(room_config("A", "pw"));
  room.run_until([] { return false; }, 0.1);
  const Entry relay_keys = make_entry(AuthMode::kPassphrase);
  room.relay.on_announce = [&](std::vector<std::uint8_t>& announce) {
    std::copy(relay_keys.announce.key.begin(), relay_keys.announce.key.end(),
              reinterpret_cast<std::byte*>(announce.data()) + 39);
  };
  RoomSession& b = room.add(room_config("B", "pw"));
  room.run_until([] { return false; }, 1.0);
  EXPECT_TRUE(a.people().empty());
  EXPECT_TRUE(b.people().empty());
  EXPECT_EQ(a.stats().auth_failures, 1u);
  EXPECT_EQ(a.stats().key_messages_sent, 0u);  // nothing derived from the passphrase went back
  EXPECT_EQ(b.stats().verified, 0u);
}

TEST(Room, AMemberWithoutAPassphraseRefusesASealedRoomClearlyAndViceVersa) {
  RoomHarness room;
  room.add(room_config("A", "pw"));
  room.run_until([] { return false; }, 0.1);
  RoomSession& open = room.add(room_config("O", ""));
  ASSERT_TRUE(room.run_until([&] { return open.state() == RoomState::kRefused; }, 1.0));
  EXPECT_EQ(open.refusal(), RoomRefusal::kPassphraseRequired);
  EXPECT_NE(open.refusal_text().find("passphrase"), std::string::npos);
  EXPECT_TRUE(room.members[0]->people().empty());

  RoomHarness open_room;
  open_room.add(room_config("A", ""));
  open_room.run_until([] { return false; }, 0.1);
  RoomSession& sealed = open_room.add(room_config("S", "pw"));
  ASSERT_TRUE(open_room.run_until([&] { return sealed.state() == RoomState::kRefused; }, 1.0));
  EXPECT_EQ(sealed.refusal(), RoomRefusal::kPassphraseUnexpected);
  EXPECT_TRUE(open_room.members[0]->people().empty());
}

TEST(Room, ARoomCostBelowAMembersFloorIsRefused) {
  RoomHarness room;
  room.add(room_config("A", "pw"));  // proposes 1 pass, 8 KiB
  room.run_until([] { return false; }, 0.1);
  RoomConfig strict = room_config("B", "pw");
  strict.kdf = kInteractiveKdf;
  strict.min_kdf = kInteractiveKdf;
  RoomSession& b = room.add(strict);
  ASSERT_TRUE(room.run_until([&] { return b.state() == RoomState::kRefused; }, 1.0));
  EXPECT_EQ(b.refusal(), RoomRefusal::kWeakKeyCost);
  EXPECT_FALSE(b.deriving_key());
  // A cost above the ceiling cannot even be proposed.
  RoomConfig heavy = room_config("H", "pw");
  heavy.kdf = {5, 8};
  EXPECT_THROW(RoomSession(*room.endpoints[0], heavy), deixis::Error);
}

TEST(Room, AMemberLeavingAndRejoiningGetsANewIdAndIsVerifiedAgain) {
  ThreeInARoom room;
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({0, 1, 2}, 2); }, 2.0));
  for (auto& m : room.members) {
    events_of(*m);
  }
  const MemberId old_c = room.id(2);
  stream(room, 10);
  const std::uint64_t from_old_c = room.members[0]->person_stats(old_c)->tracking_received;
  EXPECT_GE(from_old_c, 8u);
  room.relay.disconnect(*room.endpoints[2]);
  room.members[2]->on_relay_lost();
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({0, 1}, 1); }, 1.0));
  for (std::size_t i : {0u, 1u}) {
    const auto ev = events_of(*room.members[i]);
    ASSERT_EQ(ev.size(), 1u);
    EXPECT_EQ(ev[0].kind, RoomEventKind::kLeft);
    EXPECT_EQ(ev[0].person, old_c);
    EXPECT_EQ(ev[0].why, LeftBecause::kLeft);
    EXPECT_EQ(room.members[i]->next_playout(old_c, room.now).kind, PlayoutKind::kNoStream);
  }
  room.relay.connect(*room.endpoints[2]);
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({0, 1, 2}, 2); }, 2.0));
  const MemberId new_c = room.id(2);
  EXPECT_NE(new_c, old_c);
  EXPECT_TRUE(sees(*room.members[0], new_c));
  EXPECT_FALSE(sees(*room.members[0], old_c));
  EXPECT_EQ(room.members[0]->stats().verified, 3u);  // B, C, and C again
  const Streams s = stream(room, 30);
  EXPECT_GE((s.played.at({0, new_c})), 25u);
  // The running total keeps the frames of the C that left, besides B's and the new C's.
  const RoomSession& a = *room.members[0];
  EXPECT_EQ(a.stats().tracking_received, a.person_stats(room.id(1))->tracking_received +
                                             from_old_c + a.person_stats(new_c)->tracking_received);
}

TEST(Room, ReplayedForgedAndMisattributedPacketsAreDropped) {
  ThreeInARoom room;
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({0, 1, 2}, 2); }, 2.0));
  const MemberId a = room.id(0), c = room.id(2);
  RoomSession& b = *room.members[1];
  std::vector<std::uint8_t> tracking_from_a, key_message_from_a;
  std::vector<std::uint8_t> reliable_from_a;
  room.relay.on_forward = [&](testing::FakeRelay::Forward& f) {
    if (f.from == a && f.channel == Channel::kTracking && tracking_from_a.empty()) {
      tracking_from_a = f.bytes;
    }
    if (f.from == a && f.channel == Channel::kReliable && reliable_from_a.empty()) {
      reliable_from_a = f.bytes;
    }
    return true;
  };
  stream(room, 10);
  ASSERT_FALSE(tracking_from_a.empty());
  ASSERT_FALSE(reliable_from_a.empty());
  const DropCounters before = b.drops();
  const std::uint64_t received = b.person_stats(a)->tracking_received;
  auto inject = [&](MemberId from, Channel ch, std::vector<std::uint8_t> bytes) {
    room.relay.inject(*room.endpoints[1], from, ch, bytes);
    room.step(0.001);
  };
  inject(a, Channel::kTracking, tracking_from_a);  // replayed
  inject(a, Channel::kReliable, reliable_from_a);  // a heartbeat replayed
  auto flipped = tracking_from_a;
  flipped[20] ^= 1;
  flipped[1] ^= 0x40;  // a fresh counter, so the window lets it through to the tag
  inject(a, Channel::kTracking, flipped);  // forged
  auto moved = tracking_from_a;
  moved[1] ^= 0x40;
  inject(c, Channel::kTracking, moved);               // A's packet said to be C's
  inject(a, Channel::kReliable, {0x06, 1, 0, 0, 0});  // a plain heartbeat in a sealed room
  inject(99, Channel::kTracking, tracking_from_a);    // nobody in the room
  std::vector<std::uint8_t> fake_key(kKeyMessageBytes, 0);
  fake_key[0] = kKeyMessageType;
  inject(a, Channel::kReliable, fake_key);  // a key message from someone already verified
  const DropCounters& after = b.drops();
  EXPECT_EQ(after[DropReason::kReplayed] - before[DropReason::kReplayed], 2u);
  EXPECT_EQ(after[DropReason::kDecryptFailed] - before[DropReason::kDecryptFailed], 2u);
  EXPECT_EQ(after[DropReason::kUnauthenticated] - before[DropReason::kUnauthenticated], 1u);
  EXPECT_EQ(after[DropReason::kUnknownPeer] - before[DropReason::kUnknownPeer], 1u);
  EXPECT_EQ(after[DropReason::kUnexpected] - before[DropReason::kUnexpected], 1u);
  EXPECT_LE(b.person_stats(a)->tracking_received, received + 1);  // only real frames in flight
  EXPECT_EQ(b.people().size(), 2u);                               // nothing of it ended anyone
  EXPECT_GT(b.drop_log().lines_written(), 0u);
}

TEST(Room, LossOnOneMembersLinkAffectsOnlyThatMembersStream) {
  ThreeInARoom room;
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({0, 1, 2}, 2); }, 2.0));
  room.endpoints[2]->uplink.tracking_loss = 0.2;
  const Streams s = stream(room, 300);
  const MemberId b = room.id(1), c = room.id(2);
  for (std::size_t i : {0u, 1u}) {
    const double c_missed = static_cast<double>(s.missed.at({i, c})) / 300.0;
    EXPECT_GT(c_missed, 0.10) << i;
    EXPECT_LT(c_missed, 0.30) << i;
  }
  EXPECT_LE(s.missed.count({0, b}) ? s.missed.at({0, b}) : 0u, 2u);
  EXPECT_LE(s.missed.count({2, room.id(0)}) ? s.missed.at({2, room.id(0)}) : 0u, 2u);
  EXPECT_GE((s.played.at({2, b})), 295u);  // C still hears everyone in full
}

TEST(Room, JitterAndSilenceArePerPerson) {
  ThreeInARoom room;
  room.endpoints[1]->uplink.latency = 0.040;
  room.endpoints[1]->uplink.jitter = 0.020;
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({0, 1, 2}, 2); }, 2.0));
  const MemberId b = room.id(1), c = room.id(2);
  const Streams s = stream(room, 150);
  EXPECT_GE((s.played.at({0, b})), 140u);
  EXPECT_GE((s.played.at({0, c})), 145u);
  const JitterStats& jb = *room.members[0]->jitter(b);
  const JitterStats& jc = *room.members[0]->jitter(c);
  // Each person's buffer schedules on its own offset: C's frames all wait the delay (and the
  // steps' rounding), B's (whose transit varies by 20 ms) wait less on average.
  const double b_wait = jb.waited_sum / static_cast<double>(jb.played);
  const double c_wait = jc.waited_sum / static_cast<double>(jc.played);
  EXPECT_GE(c_wait, 0.050);
  EXPECT_LT(b_wait, c_wait - 0.004);
  // B falls silent for a second: its stream stops at A, C's plays on.
  room.endpoints[1]->uplink.blocked = true;
  const Streams quiet = stream(room, 30, 150);
  EXPECT_GT((quiet.no_stream.at({0, b})), 5u);
  EXPECT_EQ(quiet.no_stream.count({0, c}), 0u);
  EXPECT_GE((quiet.played.at({0, c})), 29u);
  room.endpoints[1]->uplink.blocked = false;
  const Streams back = stream(room, 30, 180);
  EXPECT_GE((back.played.at({0, b})), 20u);
}

TEST(Room, ASilentPersonTimesOutAndAByeIsHeard) {
  ThreeInARoom room;
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({0, 1, 2}, 2); }, 2.0));
  for (auto& m : room.members) {
    events_of(*m);
  }
  const MemberId b = room.id(1), c = room.id(2);
  room.endpoints[1]->uplink.blocked = true;  // B's packets no longer arrive; it stays in the room
  const double t0 = room.now;
  ASSERT_TRUE(room.run_until([&] { return !sees(*room.members[0], b); }, 4.0));
  EXPECT_GE(room.now - t0, 2.9);
  auto ev = events_of(*room.members[0]);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].why, LeftBecause::kTimedOut);
  EXPECT_EQ(room.members[0]->stats().timeouts, 1u);
  EXPECT_TRUE(sees(*room.members[0], c));

  room.members[2]->leave(room.now);
  ASSERT_TRUE(room.run_until([&] { return !sees(*room.members[0], c); }, 0.5));
  ev = events_of(*room.members[0]);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].why, LeftBecause::kBye);
  EXPECT_TRUE(room.members[2]->people().empty());
}

TEST(Room, EveryoneIsBackAfterTheRelayRestarts) {
  ThreeInARoom room;
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({0, 1, 2}, 2); }, 2.0));
  for (auto& m : room.members) {
    events_of(*m);
  }
  const double t0 = room.now;
  room.relay.restart(1.0);
  room.step();
  for (auto& m : room.members) {
    EXPECT_TRUE(m->people().empty());
    const auto ev = events_of(*m);
    EXPECT_EQ(ev.size(), 2u);
    EXPECT_EQ(ev[0].why, LeftBecause::kRelayLost);
  }
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({0, 1, 2}, 2); }, 2.0));
  EXPECT_LT(room.now - t0, 2.0);
  const Streams s = stream(room, 30);
  EXPECT_GE((s.played.at({1, room.id(2)})), 25u);
}

TEST(Room, AFloodingMemberIsNoLongerListenedTo) {
  ThreeInARoom room;
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({0, 1, 2}, 2); }, 2.0));
  const MemberId c = room.id(2);
  const Vec3 root = room.members[2]->config().hello.avatar.body.T_world_root.translation;
  for (std::uint32_t i = 0; i < 600 && sees(*room.members[0], c); ++i) {
    room.members[2]->send_tracking(testing::moving_frame(i, root), i * kTick);
    room.step(0.002);  // 500 a second
  }
  EXPECT_FALSE(sees(*room.members[0], c));
  EXPECT_EQ(room.members[0]->stats().floods, 1u);
  EXPECT_TRUE(sees(*room.members[0], room.id(1)));
}

TEST(Room, TheKeyIsDerivedOffTheCallersThread) {
  RoomHarness room;
  RoomConfig a = room_config("A", "pw");
  RoomConfig b = room_config("B", "pw");
  a.derive_on_this_thread = false;
  b.derive_on_this_thread = false;
  room.add(a);
  room.run_until([] { return false; }, 0.05);
  room.add(b);
  bool saw_deriving = false;
  for (int i = 0; i < 2000 && !room.everyone_sees({0, 1}, 1); ++i) {
    saw_deriving = saw_deriving || room.members[1]->deriving_key();
    room.step();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_TRUE(room.everyone_sees({0, 1}, 1));
  EXPECT_TRUE(saw_deriving);
}

}  // namespace
}  // namespace deixis::net
