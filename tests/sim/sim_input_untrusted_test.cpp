// A scripted-input file (deixis sim --input) is untrusted like any file: deep nesting,
// duplicate keys, integers past INT64_MAX and scripts that expand into too many events are each a
// clear error naming the file and the place.

#include <gtest/gtest.h>

#include "core/error.h"
#include "sim/sim_input.h"

namespace deixis::sim {
namespace {

std::string script_of(const std::string& events, const std::string& version = "1") {
  return R"({"format": "deixis-sim-input", "version": )" + version + R"(, "events": [)" + events +
         "]}";
}

std::string error_of(const std::string& text) {
  try {
    parse_input_script(text, "in.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(SimInputUntrusted, DeepNestingIsRefusedBeforeParsing) {
  const std::string deep = std::string(65, '[') + std::string(65, ']');
  EXPECT_EQ(error_of(script_of(R"({"t": 0, "type": "key", "key": "e", "x": )" + deep + "}"))
                .rfind("in.json: nested deeper than 64 levels", 0),
            0u);
}

TEST(SimInputUntrusted, DuplicateKeysAreNamed) {
  EXPECT_EQ(error_of(script_of(R"({"t": 0, "type": "key", "key": "e"},
                                  {"t": 1, "type": "move", "x": 1, "y": 2, "x": 3})")),
            "in.json: duplicate key 'x' in events[1]");
  EXPECT_EQ(error_of(R"({"format": "deixis-sim-input", "version": 1, "events": [], "events": []})"),
            "in.json: duplicate key 'events' in the top-level object");
}

TEST(SimInputUntrusted, HugeIntegersDoNotWrap) {
  EXPECT_NE(error_of(script_of("", "18446744073709551615"))
                .find("in.json: version: expected an integer from 0 to 1000"),
            std::string::npos);
}

TEST(SimInputUntrusted, ExpansionAndTextAreBounded) {
  // Each 600 s drag is 18 000 moves: 12 of them pass the 200 000-event bound.
  std::string drags;
  for (int i = 0; i < 12; ++i) {
    drags += std::string(i ? "," : "") + R"({"t": )" + std::to_string(i * 601) +
             R"(, "type": "drag", "from": [0, 0], "to": [1, 1], "seconds": 600})";
  }
  EXPECT_EQ(error_of(script_of(drags)),
            "in.json: events[11]: the script expands into more than 200000 events (drags make one "
            "a tick)");
  EXPECT_NE(
      error_of(script_of(R"({"t": 0, "type": "text", "text": ")" + std::string(257, 'a') + "\"}"))
          .find("events[0].text: expected 1 to 256 characters"),
      std::string::npos);
  EXPECT_NE(error_of(script_of(R"({"t": 0, "type": "click", "widget": ")" + std::string(300, 'w') +
                               "\"}"))
                .find("events[0].widget: expected a widget's label of 1 to 256 bytes"),
            std::string::npos);
  EXPECT_THROW(read_input_script("/dev/zero"), Error);
}

}  // namespace
}  // namespace deixis::sim
