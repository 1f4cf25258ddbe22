// The hostile-network suite (docs/security.md): real processes on loopback, each attack from
// another loopback address (a stranger on another machine) against a host and its rightful
// joiner, both net_peer processes with the passphrase at libsodium's INTERACTIVE cost. Each test
// asserts that the legitimate session survives: the joiner streams within 2 s of starting, plays
// at least 95 % of the frames the host sent, and no process exits non-zero; and prints what it
// threw at it. Each is bounded in time by its processes' deadlines.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "net/protocol.h"
#include "net_child.h"

namespace deixis::net {
namespace {

const std::vector<std::string> kSecret = {"--passphrase", "correct horse battery staple", "--kdf",
                                          "interactive"};

std::vector<std::string> with_secret(std::vector<std::string> args) {
  args.insert(args.end(), kSecret.begin(), kSecret.end());
  return args;
}

std::vector<std::string> host_args(std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {"--role",      "host", "--site",   "A",
                                   "--peer-site", "B",    "--frames", "150"};
  args.insert(args.end(), extra.begin(), extra.end());
  return with_secret(args);
}

Result run_joiner(const std::string& port, std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {"--role", "join",   "--site", "B",        "--peer-site",
                                   "A",      "--port", port,     "--frames", "150"};
  args.insert(args.end(), extra.begin(), extra.end());
  Child joiner(with_secret(args));
  return finish(joiner);
}

// The rightful session came through: in within 2 s, ≥ 95 % of the host's frames played.
void expect_session_survived(const Result& host, const Result& joiner) {
  EXPECT_EQ(num(joiner, "timed_out"), 0);
  EXPECT_EQ(num(joiner, "hello_ok"), 1);
  EXPECT_EQ(num(joiner, "bad"), 0);
  const double first_stream = std::stod(joiner.at("first_stream"));
  EXPECT_GE(first_stream, 0.0) << "the joiner never streamed";
  EXPECT_LT(first_stream, 2.0) << "the joiner got in more than 2 s after trying";
  const long long sent = num(host, "sent");
  EXPECT_GE(static_cast<double>(num(joiner, "played")), 0.95 * static_cast<double>(sent))
      << "played " << num(joiner, "played") << " of the " << sent << " frames sent";
  std::printf("rightful joiner: streaming after %.2f s, played %lld of %lld frames\n", first_stream,
              num(joiner, "played"), sent);
}

struct Outcome {
  Result host, joiner, attacker;
};

// A host, then the attacker (net_peer --role `role` from 127.0.0.2 with `args`), once it says it
// started and `head_start` later the rightful joiner; what each of the three reported.
Outcome attack(const std::string& role, std::vector<std::string> args,
               std::chrono::milliseconds head_start = std::chrono::milliseconds(0)) {
  Child host(host_args());
  const std::string port = start_host(host);
  std::vector<std::string> attacker_args = {"--role", role, "--port", port, "--local", "127.0.0.2"};
  attacker_args.insert(attacker_args.end(), args.begin(), args.end());
  Child attacker(attacker_args);
  EXPECT_FALSE(attacker.line_starting(role + " started").empty());
  std::this_thread::sleep_for(head_start);
  Outcome o;
  o.joiner = run_joiner(port);
  o.host = finish(host);
  o.attacker = finish(attacker);
  return o;
}

TEST(Hostile, GarbageUdpFloodDuringASession) {
  const Outcome o = attack("garbage", {"--count", "20000", "--deadline", "8"});
  expect_session_survived(o.host, o.joiner);
  std::printf("thrown: %lld datagrams of random bytes at %s a second\n", num(o.attacker, "sent"),
              o.attacker.at("per_second").c_str());
}

TEST(Hostile, StormOfSilentConnectionsDoesNotKeepTheJoinerOut) {
  // A second for the storm to take what it can before the joiner tries.
  const Outcome o =
      attack("storm", {"--count", "32", "--deadline", "9"}, std::chrono::milliseconds(1000));
  const Result& h = o.host;
  expect_session_survived(h, o.joiner);
  EXPECT_GT(num(h, "over_budget") + num(h, "stranger_timeouts") + num(h, "evicted"), 0)
      << "the storm was turned away or let go";
  std::printf(
      "thrown: 32 silent connections from one address, %lld connection attempts; the host took "
      "%lld into its handshake table, turned %lld away at once, timed %lld out\n",
      num(o.attacker, "connects"), num(h, "strangers"), num(h, "over_budget"),
      num(h, "stranger_timeouts"));
}

TEST(Hostile, WrongPassphraseHammeringIsHeldBack) {
  const Outcome o = attack("hammer", {"--site", "M", "--passphrase", "guess", "--deadline", "8"});
  const Result& m = o.attacker;
  expect_session_survived(o.host, o.joiner);
  EXPECT_GT(num(m, "held_back"), 0) << "the guesser was held back";
  EXPECT_EQ(num(o.host, "auth_failures"), num(m, "refused")) << "every verified guess, counted";
  const double minutes = std::stod(m.at("seconds")) / 60.0;
  std::printf(
      "thrown: %lld wrong-passphrase joins from one address in %.1f s; %lld verified and "
      "refused (%.0f guesses a minute), %lld held back\n",
      num(m, "guesses"), minutes * 60.0, num(m, "refused"),
      static_cast<double>(num(m, "refused")) / minutes, num(m, "held_back"));
}

TEST(Hostile, AnAuthenticatedPeerFloodingTrackingIsCutOff) {
  Child host(host_args({"--until", "stream-with:B"}));
  const std::string port = start_host(host);
  Child flooder(
      with_secret({"--role", "join", "--site", "F", "--peer-site", "A", "--port", port, "--frames",
                   "100000", "--rate", "300", "--until", "cut", "--deadline", "10"}));
  const Result f = finish(flooder);
  EXPECT_EQ(num(f, "last_bye"), static_cast<int>(ByeReason::kFlooding)) << "cut off, told why";
  EXPECT_EQ(num(f, "timed_out"), 0);
  const Result j = run_joiner(port);
  const Result h = finish(host);
  EXPECT_GE(num(h, "floods_cut"), 1);
  expect_session_survived(h, j);
  std::printf("thrown: valid tracking at 300 Hz (ten times the rate), %lld frames before the cut\n",
              num(f, "sent"));
}

TEST(Hostile, SpoofedDisconnectDataDoesNotEndTheJoinerForGood) {
  // The host drops the connection halfway with disconnect data 4 ("wrong passphrase") and no
  // bye: what a spoofed ENet disconnect looks like to the joiner. It must come back.
  Child host(host_args({"--drop-with", "4", "--frames", "200", "--until", "streams2"}));
  const std::string port = start_host(host);
  const Result j = run_joiner(port, {"--until", "streams2", "--frames", "200"});
  const Result h = finish(host);
  EXPECT_NE(j.at("state"), "refused");
  EXPECT_GE(num(j, "streams"), 2) << "it reconnected";
  EXPECT_GE(num(j, "second_stream_played"), 15);
  std::printf("thrown: ENet disconnect data 4 mid-stream; the joiner reconnected (%lld streams)\n",
              num(j, "streams"));
}

TEST(Hostile, AHostAnnouncingAWeakKeyCostIsRefused) {
  Child host({"--role", "host", "--site", "A", "--peer-site", "B", "--passphrase", "pw", "--kdf",
              "weak", "--until", "deadline", "--deadline", "4"});
  const std::string port = start_host(host);
  Child joiner({"--role", "join", "--site", "B", "--peer-site", "A", "--port", port, "--passphrase",
                "pw", "--kdf", "interactive", "--until", "refused", "--deadline", "4"});
  const Result j = finish(joiner);
  const Result h = finish(host);
  EXPECT_EQ(j.at("state"), "refused");
  EXPECT_EQ(num(j, "last_bye"), static_cast<int>(ByeReason::kWeakKeyCost));
  EXPECT_EQ(num(h, "auth_failures"), 0) << "no proof was sent to test guesses against";
  std::printf("thrown: a host announcing Argon2id at 1 pass and 8 KiB; the joiner refused it\n");
}

}  // namespace
}  // namespace deixis::net
