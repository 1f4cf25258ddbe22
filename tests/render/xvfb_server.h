#pragma once
// A private X server for window tests: starts Xvfb on a display it picks itself (-displayfd, so
// parallel tests never collide), points DISPLAY at it, and stops it at the end. Tests skip only
// when no Xvfb binary exists.

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <vector>

extern char** environ;

namespace deixis::render::testing {

class XvfbServer {
 public:
  XvfbServer() {
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) {
      error_ = "pipe failed";
      return;
    }
    // -displayfd makes Xvfb choose a free display and write its number to this descriptor.
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[1], 3);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    std::vector<std::string> args = {"Xvfb",       "-displayfd", "3",   "-screen", "0",
                                     "640x480x24", "-nolisten",  "tcp", "-noreset"};
    std::vector<char*> argv;
    for (std::string& a : args) {
      argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    const int spawned = posix_spawnp(&pid_, "Xvfb", &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(fds[1]);
    if (spawned != 0) {
      pid_ = -1;
      close(fds[0]);
      error_ = "Xvfb is not installed (Debian: xvfb; tools/install-deps)";
      missing_ = true;
      return;
    }
    display_ = read_display(fds[0]);
    close(fds[0]);
    if (display_.empty()) {
      error_ = "Xvfb started but reported no display within 10 s";
      return;
    }
    setenv("DISPLAY", (":" + display_).c_str(), 1);
  }

  ~XvfbServer() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      int status = 0;
      waitpid(pid_, &status, 0);
    }
  }
  XvfbServer(const XvfbServer&) = delete;
  XvfbServer& operator=(const XvfbServer&) = delete;

  bool ready() const { return !display_.empty(); }
  bool missing() const { return missing_; }
  const std::string& error() const { return error_; }

 private:
  static std::string read_display(int fd) {
    std::string number;
    pollfd p{fd, POLLIN, 0};
    while (poll(&p, 1, 10000) > 0) {
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

}  // namespace deixis::render::testing
