#include "app/endpoint.h"

#include <exception>

namespace deixis::app {

std::string parse_endpoint(const std::string& text, std::string& address, std::uint16_t& port) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) {
    return "expected HOST:PORT, e.g. 127.0.0.1:7350";
  }
  try {
    std::size_t used = 0;
    const int number = std::stoi(text.substr(colon + 1), &used);
    if (used != text.size() - colon - 1 || number < 1 || number > 65535) {
      return "the port must be 1 to 65535";
    }
    address = text.substr(0, colon);
    port = static_cast<std::uint16_t>(number);
  } catch (const std::exception&) {
    return "the port must be a number";
  }
  return {};
}

}  // namespace deixis::app
