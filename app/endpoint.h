#pragma once
// A host's endpoint as a person types it, "HOST:PORT" (`--join`, `--connect`, the simulator's
// panel): one reading for the command line and the window, so both accept and refuse the same.

#include <cstdint>
#include <string>

namespace deixis::app {

// Splits `text` into `address` and `port` (1 to 65535). Returns what is wrong with it, e.g. "the
// port must be a number", or an empty string when it is fine (then, only, the outputs are set).
std::string parse_endpoint(const std::string& text, std::string& address, std::uint16_t& port);

}  // namespace deixis::app
