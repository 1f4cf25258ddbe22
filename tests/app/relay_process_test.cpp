// `deixis relay` as a real process (docs/relay.md): it prints "port N" for --port 0, lets a room
// member in, exits 0 on SIGTERM (its member notices the relay gone), is found again by its member
// within 5 s when killed and started again on the same port, and refuses bad flags with
// exit 2. Every wait is bounded.

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/deixis_child.h"
#include "net/relay_client.h"

namespace deixis::app {
namespace {

// A room member on the relay at `port`: enters when the relay is ready, counts losses, and polls
// on its own clock.
class Member : public net::RelayListener {
 public:
  Member(int port, const std::string& room) : client_(options(port, room), 0.0) {}

  void on_relay_ready() override {
    const std::uint8_t params[1] = {1};
    const std::uint8_t announce[1] = {2};
    client_.enter(params, announce);
  }
  void on_entered(net::MemberId, std::span<const std::uint8_t>,
                  std::span<const net::RoomMember>) override {}
  void on_member_joined(const net::RoomMember&) override {}
  void on_member_left(net::MemberId) override {}
  void on_payload(net::MemberId, net::Channel, std::span<const std::uint8_t>) override {}
  void on_refused(net::RelayRefusal) override {}
  void on_relay_lost() override { ++lost; }

  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  // Polls until `done` or `seconds` more pass; whether `done`.
  bool poll_until(const std::function<bool()>& done, double seconds_more) {
    const double until = seconds() + seconds_more;
    while (!done() && seconds() < until) {
      client_.poll(seconds(), *this, 5);
    }
    return done();
  }
  bool in_room() const { return client_.in_room(); }
  net::MemberId self() const { return client_.self(); }

  int lost = 0;

 private:
  static net::RelayClientOptions options(int port, const std::string& room) {
    net::RelayClientOptions o;
    o.port = static_cast<std::uint16_t>(port);
    o.room = net::room_token(room);
    return o;
  }
  Clock::time_point start_ = Clock::now();
  net::RelayClient client_;
};

TEST(RelayCommand, ServesAMemberAndExitsZeroOnSigterm) {
  Deixis relay({"relay", "--port", "0", "--max-people", "4"});
  const int port = relay.port();
  ASSERT_GT(port, 0) << relay.err();
  Member member(port, "process");
  ASSERT_TRUE(member.poll_until([&] { return member.in_room(); }, 5.0));
  EXPECT_GE(member.self(), net::kFirstMember);
  relay.send_signal(SIGTERM);
  EXPECT_TRUE(member.poll_until([&] { return member.lost == 1; }, 5.0))
      << "the member hears the relay go";
  EXPECT_EQ(relay.wait(), 0) << relay.err();
  const std::string log = relay.out() + relay.err();  // spdlog writes to standard output
  EXPECT_NE(log.find("entered"), std::string::npos) << "joins are logged: " << log;
  EXPECT_NE(log.find("SIGTERM"), std::string::npos) << log;
}

TEST(RelayCommand, AMemberIsBackWithin5sOfAKilledRelayStartedAgain) {
  auto relay = std::make_unique<Deixis>(std::vector<std::string>{"relay", "--port", "0"});
  const int port = relay->port();
  ASSERT_GT(port, 0) << relay->err();
  Member member(port, "restart");
  ASSERT_TRUE(member.poll_until([&] { return member.in_room(); }, 5.0));
  relay->send_signal(SIGKILL);  // no goodbye: the member has only the silence to go by
  relay->wait();
  const double killed = member.seconds();
  ASSERT_TRUE(member.poll_until([&] { return member.lost == 1; }, 5.0));
  EXPECT_LT(member.seconds() - killed, 2.0) << "a dead relay is noticed within 2 s";
  relay =
      std::make_unique<Deixis>(std::vector<std::string>{"relay", "--port", std::to_string(port)});
  ASSERT_EQ(relay->port(), port) << relay->err();
  const double listening = member.seconds();
  ASSERT_TRUE(member.poll_until([&] { return member.in_room(); }, 10.0));
  EXPECT_LT(member.seconds() - listening, 5.0) << "back in the room within 5 s";
  relay->send_signal(SIGTERM);
  EXPECT_EQ(relay->wait(), 0);
}

TEST(RelayCommand, ACrashSaysItsSignalAndStackAndDiesOfIt) {
  // Any `deixis` that crashes reports where (app/crash_report.h); a SIGSEGV sent to a waiting
  // relay stands in for a fault of its own: the handler runs the same either way.
#if defined(DEIXIS_SANITIZED)
  GTEST_SKIP() << "AddressSanitizer reports crashes in this build";
#endif
  Deixis relay({"relay", "--port", "0"});
  ASSERT_GT(relay.port(), 0) << relay.err();
  relay.send_signal(SIGSEGV);
  EXPECT_EQ(relay.wait(), 128 + SIGSEGV) << "dies of the signal, as without the report";
  const std::string& err = relay.err();
  EXPECT_NE(err.find("deixis: crashed: SIGSEGV"), std::string::npos) << err;
  EXPECT_NE(err.find("run_relay"), std::string::npos) << "the stack names the function: " << err;
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
