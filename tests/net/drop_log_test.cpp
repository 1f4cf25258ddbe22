// Bad packets are counted every time but logged at a limited rate on the caller's clock, each
// line naming the peer, the message type and the reason.

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <sstream>

#include "net/drop_log.h"

namespace deixis::net {
namespace {

std::size_t lines(const std::string& s) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n'));
}

TEST(DropLog, AFloodCostsAFewLinesASecondAndEveryPacketIsCounted) {
  std::ostringstream out;
  auto logger = std::make_shared<spdlog::logger>(
      "drops", std::make_shared<spdlog::sinks::ostream_sink_mt>(out));
  DropLog log(logger);
  // 10 s of 1,000 bad packets a second.
  for (int i = 0; i < 10000; ++i) {
    log.drop(i * 0.001, "10.0.0.7:4000", Channel::kTracking, 0x10,
             wire_error(DropReason::kOutOfRange, "tracking.valid"));
  }
  EXPECT_EQ(log.counters().total, 10000u);
  EXPECT_EQ(log.counters()[DropReason::kOutOfRange], 10000u);
  // A burst of 5, then 2 a second.
  EXPECT_GE(lines(out.str()), 5u + 19u);
  EXPECT_LE(lines(out.str()), 5u + 21u);
  EXPECT_EQ(log.lines_written(), lines(out.str()));
  EXPECT_EQ(log.lines_written() + log.lines_suppressed(), 10000u);
  const std::string first = out.str().substr(0, out.str().find('\n'));
  EXPECT_NE(first.find("10.0.0.7:4000"), std::string::npos) << first;
  EXPECT_NE(first.find("tracking"), std::string::npos) << first;
  EXPECT_NE(first.find("value out of range"), std::string::npos) << first;
  EXPECT_NE(first.find("tracking.valid"), std::string::npos) << first;
  // Later lines say how many were held back.
  EXPECT_NE(out.str().find("similar lines held back"), std::string::npos);
}

TEST(DropLog, QuietPeriodsRefillTheBurst) {
  std::ostringstream out;
  auto logger = std::make_shared<spdlog::logger>(
      "drops", std::make_shared<spdlog::sinks::ostream_sink_mt>(out));
  DropLog log(logger);
  for (int round = 0; round < 3; ++round) {
    for (int i = 0; i < 100; ++i) {
      log.drop(round * 60.0, "peer", Channel::kReliable, kNoType,
               wire_error(DropReason::kEmpty, "packet"));
    }
  }
  EXPECT_EQ(log.lines_written(), 15u) << "a full burst after each quiet minute";
  EXPECT_NE(out.str().find("empty"), std::string::npos);
}

}  // namespace
}  // namespace deixis::net
