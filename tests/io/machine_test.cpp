// The machine description that timings carry (core/io/machine.h).

#include "core/io/machine.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <thread>

namespace {

// Whether /proc/cpuinfo names a model at all (some virtual CPUs and architectures do not).
bool cpuinfo_names_a_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      return true;
    }
  }
  return false;
}

TEST(Machine, TheCpuModelIsCpuinfosModelNameWithoutItsLabel) {
  const std::string model = deixis::cpu_model();
  ASSERT_FALSE(model.empty());
  if (!cpuinfo_names_a_model()) {
    EXPECT_EQ(model, "unknown CPU");
    return;
  }
  EXPECT_NE(model, "unknown CPU");
  EXPECT_EQ(model.find("model name"), std::string::npos) << model;
  EXPECT_NE(model.front(), ' ');
  EXPECT_NE(model.front(), ':');
  EXPECT_NE(model.back(), '\n');
}

TEST(Machine, TheDescriptionNamesTheCpuAndHowManyThereAre) {
  const std::string description = deixis::machine_description();
  EXPECT_EQ(description.rfind(deixis::cpu_model() + ", ", 0), 0u) << description;
  const unsigned cpus = std::thread::hardware_concurrency();
  if (cpus > 0) {
    EXPECT_NE(description.find(", " + std::to_string(cpus) + " logical CPUs"), std::string::npos)
        << description;
  }
}

}  // namespace
