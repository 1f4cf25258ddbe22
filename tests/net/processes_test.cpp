// Two real processes (net_peer) over real ENet sockets on 127.0.0.1: hello, target map and
// tracking both ways, open and with a passphrase; a wrong passphrase refused; a peer that ignores
// the protocol gets no tracking decoded; a joiner that reconnects when its host restarts; and a
// short soak whose heap stays flat (it runs in the ASan build too, under ASan's own heap count).
// Hosts listen on port 0 and print the port the system chose, so no test guesses free ports.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "net_child.h"

namespace deixis::net {
namespace {

void expect_exchange(const Result& r, long long frames) {
  EXPECT_EQ(num(r, "timed_out"), 0);
  EXPECT_EQ(num(r, "streams"), 1);
  EXPECT_EQ(num(r, "hello_ok"), 1) << "the hello is the other side's";
  EXPECT_EQ(num(r, "map_ok"), 1) << "the target map is the other side's";
  EXPECT_EQ(num(r, "sent"), frames);
  EXPECT_GE(num(r, "tracking_received"), frames - 2) << "loopback loses nothing";
  // How many came in time to be played depends on the machine's load (ctest runs tests side by
  // side); on an idle machine it is every frame.
  EXPECT_GE(num(r, "played"), frames / 2);
  EXPECT_EQ(num(r, "bad"), 0) << "every frame is what the sender's tracker produced";
  EXPECT_EQ(num(r, "out_of_order"), 0);
  EXPECT_EQ(num(r, "duplicates_played"), 0);
  EXPECT_EQ(num(r, "drops"), 0);
}

TEST(RealProcesses, ExchangeHelloTargetMapAndTracking) {
  Child host({"--role", "host", "--site", "A", "--peer-site", "B", "--frames", "45"});
  const std::string port = start_host(host);
  Child joiner(
      {"--role", "join", "--site", "B", "--peer-site", "A", "--port", port, "--frames", "45"});
  const Result h = finish(host);
  const Result j = finish(joiner);
  expect_exchange(h, 45);
  expect_exchange(j, 45);
  EXPECT_EQ(num(h, "sealed"), 0);
}

TEST(RealProcesses, PassphraseSessionSealsEverythingEndToEnd) {
  const std::vector<std::string> secret = {"--passphrase", "correct horse battery staple", "--kdf",
                                           "interactive"};
  std::vector<std::string> host_args = {"--role",      "host", "--site",   "A",
                                        "--peer-site", "B",    "--frames", "45"};
  host_args.insert(host_args.end(), secret.begin(), secret.end());
  Child host(host_args);
  const std::string port = start_host(host);
  std::vector<std::string> joiner_args = {"--role", "join",   "--site", "B",        "--peer-site",
                                          "A",      "--port", port,     "--frames", "45"};
  joiner_args.insert(joiner_args.end(), secret.begin(), secret.end());
  Child joiner(joiner_args);
  const Result h = finish(host);
  const Result j = finish(joiner);
  expect_exchange(h, 45);
  expect_exchange(j, 45);
  EXPECT_EQ(num(j, "sealed"), 1);
}

TEST(RealProcesses, AWrongPassphraseIsRefused) {
  Child host({"--role", "host", "--site", "A", "--peer-site", "B", "--passphrase", "right", "--kdf",
              "interactive", "--until", "refused"});
  const std::string port = start_host(host);
  Child joiner({"--role", "join", "--site", "B", "--peer-site", "A", "--port", port, "--passphrase",
                "wrong", "--kdf", "interactive", "--until", "refused"});
  const Result h = finish(host);
  const Result j = finish(joiner);
  EXPECT_EQ(j.at("state"), "refused");
  EXPECT_EQ(num(j, "last_bye"), 4) << "authentication failed";
  EXPECT_EQ(num(j, "hello_ok"), 0);
  EXPECT_EQ(num(j, "map_ok"), 0);
  EXPECT_EQ(num(j, "tracking_received"), 0);
  EXPECT_EQ(num(h, "auth_failures"), 1);
  EXPECT_EQ(num(h, "streams"), 0);
  EXPECT_EQ(num(h, "hello_ok"), 0);
  EXPECT_EQ(num(h, "tracking_received"), 0);
  EXPECT_EQ(num(h, "timed_out"), 0);
}

TEST(RealProcesses, APeerIgnoringTheProtocolHasNoTrackingDecoded) {
  Child host({"--role", "host", "--site", "A", "--peer-site", "M", "--passphrase", "right",
              "--until", "refused"});
  const std::string port = start_host(host);
  Child rogue({"--role", "rogue", "--site", "M", "--port", port, "--passphrase", "guess",
               "--deadline", "10"});
  const Result h = finish(host);
  const Result m = finish(rogue);
  EXPECT_EQ(num(h, "tracking_received"), 0) << "not one tracking frame decoded";
  EXPECT_EQ(num(h, "hello_ok"), 0);
  // It sprays more packets than a handshake needs before its join: the host lets it go as
  // chatty (docs/protocol.md §6) without reading its proof.
  EXPECT_EQ(num(h, "chatty"), 1);
  EXPECT_GE(num(h, "unauthenticated"), 1) << "what it sent first, counted and dropped";
  EXPECT_LE(num(m, "got_welcome"), 1);
  EXPECT_EQ(num(m, "disconnected"), 1);
  EXPECT_EQ(num(m, "other_messages"), 0) << "it learned nothing but, at most, the welcome";
}

TEST(RealProcesses, AJoinerReconnectsWhenItsHostRestarts) {
  Child first({"--role", "host", "--site", "A", "--peer-site", "B", "--frames", "30", "--until",
               "streams2"});
  const std::string port = start_host(first);
  Child joiner({"--role", "join", "--site", "B", "--peer-site", "A", "--port", port, "--frames",
                "100000", "--until", "streams2"});
  const Result h1 = finish(first);  // leaves after 30 frames, saying bye
  EXPECT_EQ(num(h1, "streams"), 1);
  Child second({"--role", "host", "--site", "A", "--peer-site", "B", "--port", port, "--frames",
                "100000", "--until", "streamed"});
  EXPECT_EQ(start_host(second), port);
  const Result j = finish(joiner);
  const Result h2 = finish(second);
  EXPECT_EQ(num(j, "streams"), 2) << "connected, lost its host, connected again by itself";
  EXPECT_GE(num(j, "second_stream_played"), 15);
  EXPECT_EQ(num(j, "bad"), 0);
  EXPECT_EQ(num(j, "timed_out"), 0);
  EXPECT_EQ(num(h2, "streams"), 1);
}

TEST(RealProcesses, SoakKeepsTheHeapFlat) {
  // 5 s both ways at 30 Hz, with a target-map update every 0.25 s on the reliable channel.
  Child host({"--role", "host", "--site", "A", "--peer-site", "B", "--frames", "150", "--map-every",
              "0.25"});
  const std::string port = start_host(host);
  Child joiner({"--role", "join", "--site", "B", "--peer-site", "A", "--port", port, "--frames",
                "150", "--map-every", "0.25"});
  const Result h = finish(host);
  const Result j = finish(joiner);
  for (const Result* r : {&h, &j}) {
    expect_exchange(*r, 150);
    EXPECT_GE(num(*r, "maps_received"), 10);
    const long long warm = num(*r, "heap_warm");
    const long long end = num(*r, "heap_end");
    ASSERT_GT(warm, 0);
    EXPECT_LT(end - warm, 64 * 1024) << "heap after 1 s: " << warm << ", at the end: " << end;
  }
}

}  // namespace
}  // namespace deixis::net
