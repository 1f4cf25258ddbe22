#pragma once
// net_peer as a child process, for the real-process tests (processes_test.cpp, hostile_test.cpp):
// start it with arguments, read the lines it prints ("port N", "result key=value ..."), wait for
// its exit. A child that hangs fails its test after kDeadline instead of hanging CI.

#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <map>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace deixis::net {
namespace {

using Clock = std::chrono::steady_clock;
constexpr auto kDeadline = std::chrono::seconds(60);  // a hung child fails the test, not CI

class Child {
 public:
  explicit Child(const std::vector<std::string>& args) {
    int fds[2];
    if (pipe(fds) != 0) {
      ADD_FAILURE() << "pipe failed";
      return;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, fds[0]);
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(NET_PEER_PATH));
    for (const std::string& a : args) {
      argv.push_back(const_cast<char*>(a.c_str()));
    }
    argv.push_back(nullptr);
    if (posix_spawn(&pid_, NET_PEER_PATH, &actions, nullptr, argv.data(), environ) != 0) {
      ADD_FAILURE() << "cannot start " << NET_PEER_PATH;
      pid_ = -1;
    }
    posix_spawn_file_actions_destroy(&actions);
    close(fds[1]);
    out_ = fds[0];
  }
  ~Child() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);  // only reached when a test failed before the child finished
      waitpid(pid_, nullptr, 0);
    }
    if (out_ >= 0) {
      close(out_);
    }
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  // The next line of output that starts with `prefix`, waiting up to the deadline.
  std::string line_starting(const std::string& prefix) {
    const auto end = Clock::now() + kDeadline;
    while (true) {
      std::size_t newline;
      while ((newline = buffer_.find('\n')) != std::string::npos) {
        const std::string line = buffer_.substr(0, newline);
        buffer_.erase(0, newline + 1);
        if (line.rfind(prefix, 0) == 0) {
          return line;
        }
      }
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now()).count();
      if (left <= 0 || !read_some(static_cast<int>(left))) {
        return "";
      }
    }
  }

  // Waits for the process to exit; its exit code, or -1 if it did not exit normally.
  int wait() {
    if (pid_ <= 0) {
      return -1;
    }
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

 private:
  bool read_some(int timeout_ms) {
    pollfd p{out_, POLLIN, 0};
    if (poll(&p, 1, timeout_ms) <= 0) {
      return false;
    }
    char chunk[4096];
    const ssize_t n = read(out_, chunk, sizeof chunk);
    if (n <= 0) {
      return false;
    }
    buffer_.append(chunk, static_cast<std::size_t>(n));
    return true;
  }

  pid_t pid_ = -1;
  int out_ = -1;
  std::string buffer_;
};

using Result = std::map<std::string, std::string>;

Result parse_result(const std::string& line) {
  Result r;
  std::istringstream in(line);
  std::string word;
  in >> word;  // "result"
  while (in >> word) {
    const auto eq = word.find('=');
    if (eq != std::string::npos) {
      r[word.substr(0, eq)] = word.substr(eq + 1);
    }
  }
  return r;
}

long long num(const Result& r, const std::string& key) {
  const auto it = r.find(key);
  return it == r.end() ? -1 : std::stoll(it->second);
}

// Starts a host on a free port; returns the port it printed.
std::string start_host(Child& host) {
  const std::string line = host.line_starting("port ");
  EXPECT_FALSE(line.empty()) << "the host did not report its port";
  return line.empty() ? "0" : line.substr(5);
}

Result finish(Child& child) {
  const Result r = parse_result(child.line_starting("result "));
  EXPECT_EQ(child.wait(), 0);
  return r;
}

}  // namespace
}  // namespace deixis::net
