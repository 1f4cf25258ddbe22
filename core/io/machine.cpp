#include "core/io/machine.h"

#include <fstream>
#include <thread>

namespace deixis {

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const std::size_t colon = line.find(':');
      const std::size_t first =
          line.find_first_not_of(" \t", colon == std::string::npos ? line.size() : colon + 1);
      if (first != std::string::npos) {
        return line.substr(first);
      }
    }
  }
  return "unknown CPU";
}

std::string machine_description() {
  const unsigned cpus = std::thread::hardware_concurrency();
  return cpu_model() + ", " + (cpus ? std::to_string(cpus) : std::string("an unknown number of")) +
         " logical CPUs";
}

}  // namespace deixis
