// Khronos' sample OpenXR application, hello_xr (Debian's libopenxr-utils), on the project's test
// runtime: `hello_xr -g OpenGL` through Debian's loader with XR_APILAYER_LUNARG_core_validation,
// in a GLX window on a private Xorg server with the dummy driver, the headset paced to the wall
// clock. The runtime must be what the spec says for an application that was never written for it
// (issue 25): its interaction profiles, its action states driven by the script's buttons, haptics,
// the Xlib/GLX binding, blend modes. (hello_xr checks the blend mode it is asked for against the
// runtime's list itself, so xrEndFrame's refusal of another is tested in
// xr_runtime_input_test.) Each run ends the way a user ends it — the scripted user
// presses the button hello_xr quits on, hello_xr asks xrRequestExitSession and leaves when the
// session is EXITING — and a run must exit 0 with no XrResult failure and no validation error.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/xr/xorg_dummy_server.h"
#include "tests/xr/xr_fixture.h"

extern char** environ;

namespace deixis::xr {
namespace {

constexpr const char* kHelloXr = "/usr/bin/hello_xr";
constexpr auto kDeadline = std::chrono::seconds(60);  // a hung hello_xr fails the test

struct HelloXrRun {
  int exit_code = -1;  // 128 + signal when killed
  std::string output;  // standard output and error together
};

class HelloXr : public XrRuntimeTest {
 protected:
  HelloXr() : XrRuntimeTest("deixis_hello_xr_") {}

  void SetUp() override {
    XrRuntimeTest::SetUp();
    if (access(kHelloXr, X_OK) != 0) {
      GTEST_SKIP() << kHelloXr << " is not installed (Debian: libopenxr-utils; tools/install-deps)";
    }
    server_ = std::make_unique<testing::XorgDummyServer>(dir_);
    if (server_->missing()) {
      GTEST_SKIP() << server_->error();
    }
    ASSERT_TRUE(server_->ready()) << server_->error();
    // The layer writes into hello_xr's output, where the checks below read it.
    unsetenv("XR_CORE_VALIDATION_FILE_NAME");
  }

  // hello_xr with `args` until it exits. Its standard input is a pipe held open: hello_xr quits
  // as soon as it reads anything or end of file ("Press any key to shutdown").
  HelloXrRun run_hello_xr(const std::vector<std::string>& args) {
    HelloXrRun run;
    const std::string log = (dir_ / "hello_xr.txt").string();
    int in[2];
    if (pipe2(in, O_CLOEXEC) != 0) {
      ADD_FAILURE() << "pipe failed";
      return run;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, in[0], STDIN_FILENO);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    std::vector<std::string> all = {kHelloXr};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : all) {
      argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    pid_t pid = -1;
    const int spawned = posix_spawn(&pid, kHelloXr, &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(in[0]);
    if (spawned != 0) {
      close(in[1]);
      ADD_FAILURE() << "cannot start " << kHelloXr;
      return run;
    }
    int status = 0;
    const auto end = std::chrono::steady_clock::now() + kDeadline;
    while (waitpid(pid, &status, WNOHANG) == 0) {
      if (std::chrono::steady_clock::now() > end) {
        ADD_FAILURE() << "hello_xr did not finish within the deadline";
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    close(in[1]);
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    std::ifstream text(log);
    std::stringstream s;
    s << text.rdbuf();
    run.output = s.str();
    return run;
  }

  // What every clean run shows: exit 0, no failed call, no validation message, the session
  // through to EXITING with every frame a projection layer of both views, nothing refused.
  void expect_clean(const HelloXrRun& run, const nlohmann::json& rec) {
    EXPECT_EQ(run.exit_code, 0) << run.output;
    EXPECT_EQ(run.output.find("XrResult failure"), std::string::npos) << run.output;
    EXPECT_EQ(run.output.find("VALID_ERROR"), std::string::npos) << run.output;
    EXPECT_EQ(rec["refusals"].size(), 0u) << rec["refusals"].dump();
    ASSERT_FALSE(rec["states"].empty());
    EXPECT_EQ(rec["states"].back(), "EXITING");
    EXPECT_EQ(rec["graphics"], "xlib");
    // A layer on every frame the runtime said shouldRender: all but the one waited before the
    // session was VISIBLE and the one waited as it stopped.
    std::size_t without_layer = 0;
    for (const auto& f : rec["frames"]) {
      if (f["layers"].get<int>() == 0) {
        ++without_layer;
        continue;
      }
      ASSERT_EQ(f["layers"].get<int>(), 1) << f.dump();
      EXPECT_EQ(f["layer_list"][0]["type"], "projection");
      EXPECT_EQ(f["projection_views"].get<int>(), 2);
    }
    EXPECT_LE(without_layer, 2u);
  }

  std::unique_ptr<testing::XorgDummyServer> server_;
};

// Several seconds of hello_xr: the scripted user holds select on the right controller from 1 s to
// 2 s (hello_xr's grab action, which vibrates that hand while grabbing) and presses menu at 4 s
// (hello_xr's quit action). The headset offers all three blend modes, see-through ones listed.
TEST_F(HelloXr, RunsUntilTheUserQuitsUnderCoreValidation) {
  write_script(R"({"display_hz": 90, "realtime": true, "frames": 900, "capture_frames": [45],
    "blend_modes": ["OPAQUE", "ALPHA_BLEND", "ADDITIVE"],
    "keys": [{"t": 0}, {"t": 1, "input": {"right": {"select": true}}}, {"t": 2},
             {"t": 4, "input": {"left": {"menu": true}}}, {"t": 5}]})");
  const HelloXrRun run = run_hello_xr({"-g", "OpenGL"});
  const nlohmann::json rec = record();
  expect_clean(run, rec);
  EXPECT_NE(run.output.find("Environment Blend Mode (XR_ENVIRONMENT_BLEND_MODE_ALPHA_BLEND)"),
            std::string::npos)
      << run.output;
  // hello_xr read the profile, the bound sources and their names.
  EXPECT_NE(run.output.find("Grab action is bound to 'Left Hand Simple Controller Select Click' "
                            "and 'Right Hand Simple Controller Select Click'"),
            std::string::npos)
      << run.output;
  EXPECT_EQ(rec["profiles"]["/user/hand/right"], "/interaction_profiles/khr/simple_controller");
  // Quit on the menu press at 4 s (frame 360 at 90 Hz), not on the script's frame limit.
  const std::size_t frames = rec["frames"].size();
  EXPECT_GE(frames, 360u);
  EXPECT_LT(frames, 380u);
  // The grab vibrated the right hand while select was held, and only then.
  ASSERT_FALSE(rec["haptics"].empty());
  for (const auto& h : rec["haptics"]) {
    EXPECT_EQ(h["outputs"], nlohmann::json::array({"/user/hand/right/output/haptic"})) << h;
    const double t = static_cast<double>(h["time"].get<std::int64_t>() - 1'000'000'000) * 1e-9;
    EXPECT_GE(t, 1.0) << h;
    EXPECT_LE(t, 2.0 + 1.0 / 90) << h;
  }
  // Frame 45 kept: both views, hello_xr's opaque clear colour everywhere (alpha 255).
  const auto& layer = rec["frames"][45]["layer_list"][0];
  ASSERT_EQ(layer["images"].size(), 2u) << layer.dump();
  for (const auto& image : layer["images"]) {
    EXPECT_TRUE(std::filesystem::exists(image["file"].get<std::string>()));
    EXPECT_EQ(image["opaque"].get<std::uint64_t>(), 512u * 512u) << image;
  }
}

// A headset whose controllers are Index controllers: hello_xr's suggested Index bindings are the
// ones bound (grab on squeeze/force, quit on b/click), so squeezing vibrates and b quits.
TEST_F(HelloXr, TakesTheProfileTheHeadsetHas) {
  write_script(R"({"display_hz": 90, "realtime": true, "frames": 900,
    "profiles": ["/interaction_profiles/valve/index_controller"],
    "keys": [{"t": 0}, {"t": 0.5, "input": {"left": {"squeeze": 1.0}}}, {"t": 1},
             {"t": 2, "input": {"right": {"b": true}}}, {"t": 3}]})");
  const HelloXrRun run = run_hello_xr({"-g", "OpenGL"});
  const nlohmann::json rec = record();
  expect_clean(run, rec);
  EXPECT_EQ(rec["profiles"]["/user/hand/left"], "/interaction_profiles/valve/index_controller");
  EXPECT_NE(run.output.find("Left Hand Index Controller Squeeze Force"), std::string::npos)
      << run.output;
  EXPECT_GE(rec["frames"].size(), 180u);
  EXPECT_LT(rec["frames"].size(), 200u);
  ASSERT_FALSE(rec["haptics"].empty());
  EXPECT_EQ(rec["haptics"][0]["outputs"], nlohmann::json::array({"/user/hand/left/output/haptic"}));
}

// hello_xr in ALPHA_BLEND on a headset that offers it: every frame says so.
TEST_F(HelloXr, SubmitsTheSeeThroughModeOffered) {
  write_script(R"({"display_hz": 90, "realtime": true, "frames": 900,
    "blend_modes": ["ALPHA_BLEND", "OPAQUE"],
    "keys": [{"t": 0}, {"t": 1, "input": {"right": {"menu": true}}}, {"t": 2}]})");
  const HelloXrRun run = run_hello_xr({"-g", "OpenGL", "-bm", "AlphaBlend"});
  const nlohmann::json rec = record();
  expect_clean(run, rec);
  ASSERT_GE(rec["frames"].size(), 90u);
  for (const auto& f : rec["frames"]) {
    EXPECT_EQ(f["blend_mode"], "ALPHA_BLEND") << f.dump();
  }
}

}  // namespace
}  // namespace deixis::xr
