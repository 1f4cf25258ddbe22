// `deixis relay` as a real process (docs/relay.md): it prints "port N" for --port 0, lets a room
// member in, exits 0 on SIGTERM (its member notices the relay gone), and refuses bad flags with
// exit 2. Every wait is bounded.

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "app/deixis_child.h"
#include "net/relay_client.h"

namespace deixis::app {
namespace {

// Enters when the relay is ready; counts what happens.
struct Entering : net::RelayListener {
  net::RelayClient* client = nullptr;
  int lost = 0;
  void on_relay_ready() override {
    const std::uint8_t params[1] = {1};
    const std::uint8_t announce[1] = {2};
    client->enter(params, announce);
  }
  void on_entered(net::MemberId, std::span<const std::uint8_t>,
                  std::span<const net::RoomMember>) override {}
  void on_member_joined(const net::RoomMember&) override {}
  void on_member_left(net::MemberId) override {}
  void on_payload(net::MemberId, net::Channel, std::span<const std::uint8_t>) override {}
  void on_refused(net::RelayRefusal) override {}
  void on_relay_lost() override { ++lost; }
};

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

TEST(RelayCommand, ServesAMemberAndExitsZeroOnSigterm) {
  Deixis relay({"relay", "--port", "0", "--max-people", "4"});
  const int port = relay.port();
  ASSERT_GT(port, 0) << relay.err();
  net::RelayClientOptions o;
  o.port = static_cast<std::uint16_t>(port);
  o.room = net::room_token("process");
  const auto start = Clock::now();
  net::RelayClient client(o, 0.0);
  Entering member;
  member.client = &client;
  while (!client.in_room() && seconds_since(start) < 5.0) {
    client.poll(seconds_since(start), member, 5);
  }
  ASSERT_TRUE(client.in_room());
  EXPECT_GE(client.self(), net::kFirstMember);
  relay.send_signal(SIGTERM);
  while (member.lost == 0 && seconds_since(start) < 10.0) {
    client.poll(seconds_since(start), member, 5);
  }
  EXPECT_EQ(member.lost, 1) << "the member hears the relay go";
  EXPECT_EQ(relay.wait(), 0) << relay.err();
  const std::string log = relay.out() + relay.err();  // spdlog writes to standard output
  EXPECT_NE(log.find("entered"), std::string::npos) << "joins are logged: " << log;
  EXPECT_NE(log.find("SIGTERM"), std::string::npos) << log;
}

TEST(RelayCommand, HelpSaysOpenRoomsAreReadableByTheOperator) {
  Deixis help({"relay", "--help"});
  EXPECT_EQ(help.wait(), 0);
  EXPECT_NE(help.out().find("readable"), std::string::npos) << help.out();
  EXPECT_NE(help.out().find("--max-people"), std::string::npos) << help.out();
}

TEST(RelayCommand, BadFlagsExit2) {
  expect_refused({{{"relay", "--max-people", "1"}, "--max-people"},
                  {{"relay", "--max-people", "65"}, "--max-people"},
                  {{"relay", "--bind", "not an address"}, "not an address"},
                  {{"relay", "--port", "70000"}, "--port"}});
}

}  // namespace
}  // namespace deixis::app
