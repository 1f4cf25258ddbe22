#pragma once
// A private Xorg server with the dummy video driver, for OpenXR applications that need an X
// server with the XFree86-VidMode extension (Khronos' hello_xr calls it when it makes its GLX
// window; Xvfb lacks it and hello_xr crashes there by itself). The configuration is written into
// the test's directory, Xorg picks a free display itself (-displayfd), DISPLAY points at it and
// the server is stopped at the end. Xorg reads a configuration outside /etc/X11 only as root, so
// under another account the server is "missing" and its tests skip saying why.

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

extern char** environ;

namespace deixis::xr::testing {

class XorgDummyServer {
 public:
  // `dir`: where the configuration and the server's log go.
  explicit XorgDummyServer(const std::filesystem::path& dir) {
    if (!std::filesystem::exists("/usr/lib/xorg/modules/drivers/dummy_drv.so") ||
        !std::filesystem::exists("/usr/lib/xorg/Xorg")) {
      error_ =
          "Xorg or its dummy driver is not installed (Debian: xserver-xorg-core, "
          "xserver-xorg-video-dummy; tools/install-deps)";
      missing_ = true;
      return;
    }
    if (geteuid() != 0) {  // a developer's own account: the test cannot run here, not a failure
      error_ =
          "Xorg reads a configuration outside /etc/X11 only as root (run the suite as root, "
          "as README.md's test command does)";
      missing_ = true;
      return;
    }
    const std::filesystem::path config = dir / "xorg-dummy.conf";
    std::filesystem::create_directories(dir / "xorg.conf.d");  // none of the system's snippets
    std::ofstream(config) << kConfig;
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) {
      error_ = "pipe failed";
      return;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[1], 3);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    std::vector<std::string> args = {"/usr/lib/xorg/Xorg",
                                     "-displayfd",
                                     "3",
                                     "-config",
                                     config.string(),
                                     "-configdir",
                                     (dir / "xorg.conf.d").string(),
                                     "-logfile",
                                     (dir / "xorg.log").string(),
                                     "-nolisten",
                                     "tcp",
                                     "-noreset",
                                     "-novtswitch",
                                     "-sharevts"};
    std::vector<char*> argv;
    for (std::string& a : args) {
      argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    const int spawned = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(fds[1]);
    if (spawned != 0) {
      pid_ = -1;
      close(fds[0]);
      error_ = "cannot start /usr/lib/xorg/Xorg";
      return;
    }
    display_ = read_display(fds[0]);
    close(fds[0]);
    if (display_.empty()) {
      error_ =
          "Xorg reported no display within 20 s (its log: " + (dir / "xorg.log").string() + ")";
      return;
    }
    setenv("DISPLAY", (":" + display_).c_str(), 1);
  }

  ~XorgDummyServer() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      waitpid(pid_, nullptr, 0);
    }
  }
  XorgDummyServer(const XorgDummyServer&) = delete;
  XorgDummyServer& operator=(const XorgDummyServer&) = delete;

  bool ready() const { return !display_.empty(); }
  bool missing() const { return missing_; }
  const std::string& error() const { return error_; }

 private:
  // One 1024x768 screen on the dummy driver, no input devices (none are needed, and probing
  // them needs udev).
  static constexpr const char* kConfig = R"(Section "ServerFlags"
  Option "AutoAddDevices" "false"
  Option "AutoEnableDevices" "false"
  Option "DontVTSwitch" "true"
EndSection
Section "Device"
  Identifier "dummy"
  Driver "dummy"
  VideoRam 65536
EndSection
Section "Monitor"
  Identifier "monitor"
  HorizSync 28.0-80.0
  VertRefresh 48.0-75.0
  Modeline "1024x768" 65.00 1024 1048 1184 1344 768 771 777 806 -hsync -vsync
EndSection
Section "Screen"
  Identifier "screen"
  Device "dummy"
  Monitor "monitor"
  DefaultDepth 24
  SubSection "Display"
    Depth 24
    Modes "1024x768"
  EndSubSection
EndSection
)";

  static std::string read_display(int fd) {
    std::string number;
    pollfd p{fd, POLLIN, 0};
    while (poll(&p, 1, 20000) > 0) {
      char c = 0;
      if (read(fd, &c, 1) != 1 || c == '\n') {
        break;
      }
      number += c;
    }
    return number;
  }

  pid_t pid_ = -1;
  std::string display_;
  std::string error_;
  bool missing_ = false;
};

}  // namespace deixis::xr::testing
