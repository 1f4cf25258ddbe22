// `deixis sim` as a real process: under a private Xvfb, scripted input drags an object across the
// remote room (B) and makes the user point at their own room's copy (A); the last frame's
// screenshot shows the object where the drag left it and not where it was, and the avatar in B's
// view, and the avatar points at the object's new place. Bad flags and files exit 2 naming them.

#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "render/image.h"
#include "render/render_fixtures.h"
#include "render/xvfb_server.h"
#include "sim/sim_views.h"
#include "site/site_config.h"
#include "test_support.h"

extern char** environ;

namespace deixis::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using render::testing::Rgb;

constexpr int kWidth = 640;  // the private Xvfb's screen
constexpr int kHeight = 480;

struct Finished {
  int code = -1;
  std::string out;
  std::string err;
};

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// `deixis` with `args`, its output in files of `dir`; killed after 120 s.
Finished deixis(const std::vector<std::string>& args, const fs::path& dir) {
  const fs::path out = dir / "stdout.txt";
  const fs::path err = dir / "stderr.txt";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<char*> argv = {const_cast<char*>(DEIXIS_EXE)};
  for (const std::string& a : args) {
    argv.push_back(const_cast<char*>(a.c_str()));
  }
  argv.push_back(nullptr);
  pid_t pid = -1;
  Finished run;
  if (posix_spawn(&pid, DEIXIS_EXE, &actions, nullptr, argv.data(), environ) != 0) {
    posix_spawn_file_actions_destroy(&actions);
    ADD_FAILURE() << "cannot start " << DEIXIS_EXE;
    return run;
  }
  posix_spawn_file_actions_destroy(&actions);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      ADD_FAILURE() << "deixis sim did not finish in 120 s";
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  run.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  run.out = slurp(out);
  run.err = slurp(err);
  return run;
}

// One private X server for the test program; the simulators it starts inherit its DISPLAY.
const render::testing::XvfbServer& display() {
  static render::testing::XvfbServer server;
  return server;
}

std::string weights() {
  return (deixis::testing::reference_dir() / "weights").string();
}

void write(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// Rooms of the test's own, with Jupiter large and in view of both sites' cameras.
const Vec3 kJupiterA(0.2f, 1.5f, -2.6f);
const Vec3 kJupiterB(-0.6f, 1.2f, -1.0f);
const Vec3 kJupiterMoved(0.9f, 1.2f, -1.2f);  // where the test drags B's Jupiter

std::string room(const char* site, const Vec3& jupiter) {
  std::ostringstream s;
  s << R"({"format": "deixis-target-map", "version": 1, "site": ")" << site
    << R"(", "objects": [{"id": 1, "name": "Jupiter", "kind": "sphere", "position": [)"
    << jupiter.x() << ", " << jupiter.y() << ", " << jupiter.z()
    << R"(], "size": [0.45, 0.45, 0.45]}, {"id": 4, "name": "Cube", "kind": "box", )"
       R"("position": [0.36, 1.02, -0.42], "size": [0.14, 0.14, 0.14]}]})";
  return s.str();
}

std::string site(const char* name, const char* room_file, float camera_x) {
  const fs::path avatar = deixis::testing::source_dir() / "assets/avatars/default.glb";
  std::ostringstream s;
  s << R"({"format": "deixis-site", "version": 1, "site": ")" << name << R"(", "target_map": ")"
    << room_file << R"(", "user": {"floor": [0, 0, 0], "yaw_degrees": 0},)"
    << R"( "remote_avatar": {"floor": [0, 0, -2.2], "yaw_degrees": 180, "avatar": ")"
    << avatar.string() << R"("}, "camera": {"position": [)" << camera_x
    << R"(, 1.6, 0.9], "look_at": [0, 1.15, -1.1], "fov_degrees": 55}})";
  return s.str();
}

class SimProcessTest : public ::testing::Test {
 protected:
  void SetUp() override {
    write(dir() / "room_a.json", room("A", kJupiterA));
    write(dir() / "room_b.json", room("B", kJupiterB));
    write(dir() / "a.json", site("A", "room_a.json", 1.2f));
    write(dir() / "b.json", site("B", "room_b.json", -1.2f));
  }
  const fs::path& dir() const { return scratch_.path(); }

  std::vector<std::string> flags() const {
    return {"sim",
            "--site-a",
            (dir() / "a.json").string(),
            "--site-b",
            (dir() / "b.json").string(),
            "--weights-dir",
            weights(),
            "--width",
            std::to_string(kWidth),
            "--height",
            std::to_string(kHeight)};
  }

  deixis::testing::ScratchDir scratch_;
};

std::string pixel(const render::Vec2& p) {
  return "[" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + "]";
}

// The window pixel of a world point in one of the views.
render::Vec2 in_window(const sim::ViewRect& rect, const render::Camera& camera, const Vec3& p) {
  const auto local = render::project_to_pixel(camera, rect.width, rect.height, p);
  EXPECT_TRUE(local.has_value());
  const render::Vec2 at =
      *local + render::Vec2(static_cast<float>(rect.x), static_cast<float>(rect.y));
  EXPECT_TRUE(rect.contains(at)) << at.transpose();
  return at;
}

// How many pixels of the (2r+1)² square around `p` pass `test`.
int around(const render::Image& image, const render::Vec2& p, int r,
           const std::function<bool(const Rgb&)>& test) {
  const int cx = static_cast<int>(p.x());
  const int cy = static_cast<int>(p.y());
  return render::testing::count_pixels(image, {cx - r, cy - r, cx + r + 1, cy + r + 1}, test);
}

float angle(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0f, 1.0f));
}

Vec3 vec3(const json& j) {
  return {j[0].get<float>(), j[1].get<float>(), j[2].get<float>()};
}

TEST_F(SimProcessTest, ADraggedObjectMovesAndTheAvatarPointsAtItsNewPlace) {
  const render::testing::XvfbServer& xvfb = display();
  if (xvfb.missing()) {
    GTEST_SKIP() << xvfb.error();
  }
  ASSERT_TRUE(xvfb.ready()) << xvfb.error();
  const sim::SimLayout layout = sim::sim_layout(kWidth, kHeight);
  const site::SiteConfig a = site::read_site_config(dir() / "a.json");
  const site::SiteConfig b = site::read_site_config(dir() / "b.json");
  const render::Camera camera_a =
      site::site_camera(a.camera, layout.local.width, layout.local.height);
  const render::Camera camera_b =
      site::site_camera(b.camera, layout.remote.width, layout.remote.height);
  const render::Vec2 from = in_window(layout.remote, camera_b, kJupiterB);
  const render::Vec2 to = in_window(layout.remote, camera_b, kJupiterMoved);
  const render::Vec2 jupiter_a = in_window(layout.local, camera_a, kJupiterA);
  write(dir() / "input.json",
        R"({"format": "deixis-sim-input", "version": 1, "events": [
             {"t": 0.5, "type": "drag", "from": )" +
            pixel(from) + R"(, "to": )" + pixel(to) +
            R"(, "seconds": 0.5},
             {"t": 1.5, "type": "click", "x": )" +
            std::to_string(jupiter_a.x()) + R"(, "y": )" + std::to_string(jupiter_a.y()) + "}]}");
  const fs::path shot = dir() / "shot.png";
  const fs::path report_file = dir() / "report.json";
  std::vector<std::string> args = flags();
  args.insert(args.end(), {"--input", (dir() / "input.json").string(), "--seconds", "5",
                           "--screenshot", shot.string(), "--report", report_file.string()});
  const Finished run = deixis(args, dir());
  ASSERT_EQ(run.code, 0) << run.err;
  const json report = json::parse(slurp(report_file));
  EXPECT_EQ(report["frames"].get<int>(), 150);
  EXPECT_EQ(report["views"]["remote"],
            json({layout.remote.x, layout.remote.y, layout.remote.width, layout.remote.height}));
  EXPECT_EQ(report["status"], "Pointing at Jupiter");

  // The drag put B's Jupiter where the mouse left it (a pixel is about 1 cm there).
  const Vec3 moved = vec3(report["remote_objects"][0]["position"]);
  EXPECT_LT((moved - kJupiterMoved).norm(), 0.03f) << moved.transpose();

  const render::Image image = render::read_png(shot);
  ASSERT_EQ(image.width, kWidth);
  ASSERT_EQ(image.height, kHeight);
  const render::Colour red = render::target_colour(1);
  const auto is_jupiter = [&](const Rgb& p) { return render::testing::same_hue(p, red); };
  EXPECT_GE(around(image, to, 3, is_jupiter), 45) << "Jupiter is not at its new place";
  EXPECT_EQ(around(image, from, 3, is_jupiter), 0) << "Jupiter is still at its old place";
  EXPECT_GE(around(image, jupiter_a, 3, is_jupiter), 45) << "A's Jupiter moved too";

  // The avatar stands in B's view: the default avatar's dark blue shirt covers its chest (the
  // floor and sky behind it are a pale grey-blue, blue less than 1.4 times red).
  const Vec3 chest = b.remote_avatar.floor + Vec3(0, 1.25f, 0);
  const auto is_avatar = [](const Rgb& p) { return p[2] > 2 * p[0] && p[2] > p[1] + 20; };
  EXPECT_GE(around(image, in_window(layout.remote, camera_b, chest), 4, is_avatar), 40);

  // And it points at Jupiter's new place: the eye–fingertip ray within a few degrees of it.
  const json& avatar = report["avatar"];
  ASSERT_TRUE(avatar["visible"].get<bool>());
  EXPECT_EQ(avatar["hand_target"].get<int>(), 1);
  EXPECT_GT(avatar["progression"][1].get<float>(), 0.9f);
  const Vec3 eye = vec3(avatar["eye"]);
  const Vec3 tip = vec3(avatar["fingertip"]);
  EXPECT_LT(angle(tip - eye, moved - eye), 0.1f);
  EXPECT_GT(angle(tip - eye, kJupiterB - eye), 0.5f);
}

TEST_F(SimProcessTest, AScriptedUserRunsHandsFree) {
  const render::testing::XvfbServer& xvfb = display();
  if (xvfb.missing()) {
    GTEST_SKIP() << xvfb.error();
  }
  ASSERT_TRUE(xvfb.ready()) << xvfb.error();
  // The demo's sites: site A's virtual_user looks at the other person, then points at Jupiter
  // (its step 1 completes within 3 s).
  const fs::path report_file = dir() / "report.json";
  const Finished run =
      deixis({"sim", "--script", "--fixed-step", "--frames", "100", "--weights-dir", weights(),
              "--width", std::to_string(kWidth), "--height", std::to_string(kHeight), "--report",
              report_file.string()},
             dir());
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.out.find("frames 100, ticks 100"), std::string::npos) << run.out;
  const json report = json::parse(slurp(report_file));
  EXPECT_EQ(report["status"], "The user follows the site's script");
  EXPECT_GE(report["visible_ticks"].get<int>(), 99);
  EXPECT_EQ(report["user"]["hand_target"].get<int>(), 1);
  EXPECT_EQ(report["avatar"]["hand_target"].get<int>(), 1);
}

TEST_F(SimProcessTest, BadFlagsAndFilesExitTwoNamingThem) {
  // The test's flags with `extra` added; a flag given in both takes extra's value.
  const auto with = [&](const std::vector<std::string>& extra) {
    std::vector<std::string> args = flags();
    for (std::size_t i = 0; i + 1 < extra.size(); i += 2) {
      const auto same = std::find(args.begin(), args.end(), extra[i]);
      if (same != args.end()) {
        args.erase(same, same + 2);
      }
    }
    args.insert(args.end(), extra.begin(), extra.end());
    return deixis(args, dir());
  };
  struct Case {
    std::vector<std::string> args;
    std::vector<std::string> named;
  };
  write(dir() / "bad_input.json",
        R"({"format": "deixis-sim-input", "version": 1, "events": [{"t": 1, "type": "fly"}]})");
  write(dir() / "broken_site.json", "{ not json");
  const std::string missing = (dir() / "missing.json").string();
  const std::vector<Case> cases = {
      {{"--frames", "0"}, {"--frames"}},
      {{"--seconds", "-3"}, {"--seconds"}},
      {{"--width", "10"}, {"--width"}},
      {{"--no-such-flag"}, {"--no-such-flag"}},
      {{"--site-a", missing}, {"--site-a", "missing.json"}},
      {{"--avatar", (dir() / "missing.glb").string()}, {"--avatar", "missing.glb"}},
      {{"--input", missing}, {"--input", "missing.json"}},
      {{"--screenshot", (dir() / "no/such/dir/shot.png").string()},
       {"--screenshot", "no/such/dir"}},
      {{"--input", (dir() / "bad_input.json").string()}, {"bad_input.json", "events[0].type"}},
      {{"--site-b", (dir() / "broken_site.json").string()}, {"broken_site.json", "not valid JSON"}},
      {{"--weights-dir", dir().string()}, {dir().string()}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args.front() + " " + c.args.back());
    const Finished run = with(c.args);
    EXPECT_EQ(run.code, 2) << run.err;
    for (const std::string& name : c.named) {
      EXPECT_NE(run.err.find(name), std::string::npos) << run.err;
    }
  }
  const Finished help = deixis({"sim", "--help"}, dir());
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("--screenshot"), std::string::npos);
}

}  // namespace
}  // namespace deixis::app
