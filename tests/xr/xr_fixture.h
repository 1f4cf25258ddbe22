#pragma once
// What every OpenXR test sets up: a per-test directory, Debian's loader pointed at the project's
// test runtime (XR_RUNTIME_JSON) with XR_APILAYER_LUNARG_core_validation writing its messages to
// a file, the runtime's record of submitted frames, and the script of head, gaze and hand poses.
// (Under ASan, the OpenXR loader's own leak is suppressed for every executable:
// app/sanitizer_options.cpp.)

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

namespace deixis::xr {

class XrRuntimeTest : public ::testing::Test {
 protected:
  // `prefix` names the per-test directory under the system's temporary directory.
  explicit XrRuntimeTest(const std::string& prefix) : prefix_(prefix) {}

  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           (prefix_ + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    setenv("XR_RUNTIME_JSON", DEIXIS_XR_RUNTIME_JSON, 1);
    setenv("XR_ENABLE_API_LAYERS", "XR_APILAYER_LUNARG_core_validation", 1);
    setenv("XR_API_LAYER_PATH", "/usr/share/openxr/1/api_layers/explicit.d", 1);
    setenv("XR_CORE_VALIDATION_EXPORT_TYPE", "text", 1);
    setenv("XR_CORE_VALIDATION_FILE_NAME", (dir_ / "validation.txt").c_str(), 1);
    setenv("DEIXIS_XR_RECORD", (dir_ / "record.json").c_str(), 1);
    unsetenv("DEIXIS_XR_HIDE_EXTENSIONS");
  }

  // The runtime's script (xr_test_runtime/: display rate, frame count, timed pose keys).
  void write_script(const std::string& json) {
    std::ofstream(dir_ / "script.json") << json;
    setenv("DEIXIS_XR_SCRIPT", (dir_ / "script.json").c_str(), 1);
  }

  // What the runtime recorded of the session: frames, their display times, submitted views.
  nlohmann::json record() const {
    std::ifstream in(dir_ / "record.json");
    EXPECT_TRUE(in) << "the runtime wrote no record";
    return in ? nlohmann::json::parse(in) : nlohmann::json();
  }

  // Everything the validation layer wrote.
  std::string validation_messages() const {
    std::ifstream in(dir_ / "validation.txt");
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

  // The layer's errors only (its file also carries informational lines): empty when none.
  std::string validation_errors() const {
    const std::string text = validation_messages();
    return text.find("Error") != std::string::npos || text.find("VUID") != std::string::npos
               ? text
               : std::string();
  }

  std::filesystem::path dir_;

 private:
  std::string prefix_;
};

}  // namespace deixis::xr
