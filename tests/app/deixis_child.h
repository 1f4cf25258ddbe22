#pragma once
// A built `deixis` run as a child process (posix_spawn) with its standard output and error on
// pipes: the port a host prints, the exit code, everything it wrote. For the tests that run the
// real command line (sites over real ENet sockets, the OpenXR front end).

#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "test_support.h"

extern char** environ;

namespace deixis::app {

using Clock = std::chrono::steady_clock;

inline constexpr auto kDeadline = std::chrono::seconds(90);  // a hung child fails the test, not CI

// The demo's site files, and the authors' weights.
inline std::filesystem::path site(const char* name) {
  return deixis::testing::source_dir() / "assets/sites" / name;
}

inline std::string weights_dir() {
  return (deixis::testing::reference_dir() / "weights").string();
}

// `deixis` with `args`; standard output and standard error each on a pipe.
class Deixis {
 public:
  explicit Deixis(const std::vector<std::string>& args) : Deixis(DEIXIS_EXE, args) {}
  // Another program (a wrapper such as tools/monado-env that runs `deixis` in turn).
  Deixis(const std::string& program, const std::vector<std::string>& args) : program_(program) {
    int out[2];
    int err[2];
    if (pipe(out) != 0 || pipe(err) != 0) {
      ADD_FAILURE() << "pipe failed";
      return;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, err[1], STDERR_FILENO);
    posix_spawn_file_actions_addclose(&actions, out[0]);
    posix_spawn_file_actions_addclose(&actions, err[0]);
    std::vector<char*> argv = {const_cast<char*>(program.c_str())};
    for (const std::string& a : args) {
      argv.push_back(const_cast<char*>(a.c_str()));
    }
    argv.push_back(nullptr);
    if (posix_spawn(&pid_, program.c_str(), &actions, nullptr, argv.data(), environ) != 0) {
      ADD_FAILURE() << "cannot start " << program;
      pid_ = -1;
    }
    posix_spawn_file_actions_destroy(&actions);
    close(out[1]);
    close(err[1]);
    fds_[0] = out[0];
    fds_[1] = err[0];
  }
  ~Deixis() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);  // only when a test failed before the child finished
      waitpid(pid_, nullptr, 0);
    }
    for (int fd : fds_) {
      if (fd >= 0) {
        close(fd);
      }
    }
  }
  Deixis(const Deixis&) = delete;
  Deixis& operator=(const Deixis&) = delete;

  // The port a host printed ("port N"), or 0.
  int port() {
    const auto end = Clock::now() + kDeadline;
    while (Clock::now() < end) {
      const std::size_t at = text_[0].find("port ");
      const std::size_t newline = text_[0].find('\n', at == std::string::npos ? 0 : at);
      if (at != std::string::npos && newline != std::string::npos) {
        return std::stoi(text_[0].substr(at + 5, newline - at - 5));
      }
      if (!read_some(100)) {
        return 0;
      }
    }
    return 0;
  }

  // Waits for the exit code (everything printed is in out() and err()); -1 on time-out.
  int wait() {
    const auto end = Clock::now() + kDeadline;
    while (Clock::now() < end && read_some(100)) {
    }
    if (Clock::now() >= end) {
      // A child that hangs (a window waiting for nobody) fails its test rather than block it.
      ADD_FAILURE() << program_ << " did not finish within the deadline";
      kill(pid_, SIGKILL);
    }
    int status = 0;
    if (waitpid(pid_, &status, 0) != pid_) {
      return -1;
    }
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }

  // Sends `signal` to the child (the relay's SIGTERM test), while it runs.
  void send_signal(int signal) {
    if (pid_ > 0) {
      kill(pid_, signal);
    }
  }

  // Reads the child's output until its standard output or error holds `text` (true), or it ends
  // or `seconds` pass (false), while it keeps running.
  bool wait_for_text(const std::string& text, double seconds) {
    const auto end = Clock::now() + std::chrono::duration<double>(seconds);
    while (text_[0].find(text) == std::string::npos && text_[1].find(text) == std::string::npos) {
      if (Clock::now() >= end || !read_some(100)) {
        return false;
      }
    }
    return true;
  }

  const std::string& out() const { return text_[0]; }
  const std::string& err() const { return text_[1]; }

 private:
  // Reads what is there on either pipe; false once both have ended.
  bool read_some(int wait_ms) {
    pollfd p[2];
    int n = 0;
    for (int fd : fds_) {
      if (fd >= 0) {
        p[n++] = {fd, POLLIN, 0};
      }
    }
    if (n == 0) {
      return false;
    }
    if (::poll(p, static_cast<nfds_t>(n), wait_ms) <= 0) {
      return true;
    }
    for (int k = 0; k < n; ++k) {
      if ((p[k].revents & (POLLIN | POLLHUP)) == 0) {
        continue;
      }
      const int which = p[k].fd == fds_[0] ? 0 : 1;
      char buffer[4096];
      const ssize_t got = read(p[k].fd, buffer, sizeof buffer);
      if (got <= 0) {
        close(fds_[which]);
        fds_[which] = -1;
      } else {
        text_[which].append(buffer, static_cast<std::size_t>(got));
      }
    }
    return true;
  }

  std::string program_;
  pid_t pid_ = -1;
  int fds_[2] = {-1, -1};
  std::string text_[2];
};

// A command line `deixis` must refuse: exit 2 with `names` (the flag or file) in its error.
struct BadInput {
  std::vector<std::string> args;
  std::string names;  // what the message must name
};

// Runs every case, each with `extra` appended (e.g. a --seconds that ends a run a wrongly
// accepted flag would start), and expects exit 2 naming what is wrong.
inline void expect_refused(const std::vector<BadInput>& cases,
                           const std::vector<std::string>& extra = {}) {
  for (const BadInput& c : cases) {
    SCOPED_TRACE(c.args[0] + " … " + c.args.back());
    std::vector<std::string> args = c.args;
    args.insert(args.end(), extra.begin(), extra.end());
    Deixis d(args);
    EXPECT_EQ(d.wait(), 2) << d.err();
    EXPECT_NE(d.err().find(c.names), std::string::npos) << d.err();
  }
}

inline std::vector<std::string> operator+(std::vector<std::string> a,
                                          const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace deixis::app
