#include "app/child_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include "core/error.h"
#include "site/endpoint.h"

extern char** environ;

namespace deixis::app {

ChildProcess::ChildProcess(const std::string& name, const std::string& program,
                           const std::vector<std::string>& args, bool search_path)
    : name_(name) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) {
    throw Error(name + ": cannot make a pipe: " + std::strerror(errno));
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(program.c_str()));
  for (const std::string& a : args) {
    argv.push_back(const_cast<char*>(a.c_str()));
  }
  argv.push_back(nullptr);
  const int rc = search_path
                     ? posix_spawnp(&pid_, program.c_str(), &actions, nullptr, argv.data(), environ)
                     : posix_spawn(&pid_, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(fds[1]);
  out_ = fds[0];
  if (rc != 0) {
    close(out_);
    out_ = -1;
    pid_ = -1;
    throw Error(name + ": cannot start " + program + ": " + std::strerror(rc));
  }
}

ChildProcess::~ChildProcess() {
  if (pid_ > 0 && !exited_) {
    terminate();
  }
  if (out_ >= 0) {
    close(out_);
  }
}

double ChildProcess::now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

bool ChildProcess::read_some(int wait_ms) {
  if (out_ < 0) {
    return false;
  }
  pollfd p{out_, POLLIN, 0};
  if (::poll(&p, 1, wait_ms) <= 0) {
    return false;
  }
  char buffer[4096];
  const ssize_t n = read(out_, buffer, sizeof buffer);
  if (n <= 0) {
    close(out_);
    out_ = -1;  // the child closed its output (it is exiting)
    return false;
  }
  output_.append(buffer, static_cast<std::size_t>(n));
  return true;
}

std::optional<std::string> ChildProcess::line_starting(const std::string& prefix, double deadline) {
  while (true) {
    std::size_t newline;
    while ((newline = output_.find('\n', consumed_)) != std::string::npos) {
      const std::string line = output_.substr(consumed_, newline - consumed_);
      consumed_ = newline + 1;
      if (line.rfind(prefix, 0) == 0) {
        return line;
      }
    }
    const double left = deadline - now();
    if (left <= 0.0 || out_ < 0) {
      return std::nullopt;
    }
    read_some(static_cast<int>(std::min(left, 0.1) * 1000.0) + 1);
  }
}

bool ChildProcess::poll() {
  while (read_some(0)) {
  }
  if (exited_ || pid_ <= 0) {
    return exited_;
  }
  int status = 0;
  if (waitpid(pid_, &status, WNOHANG) == pid_) {
    exited_ = true;
    exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  return exited_;
}

void ChildProcess::terminate() {
  if (pid_ <= 0 || exited_) {
    return;
  }
  kill(pid_, SIGTERM);
  for (int i = 0; i < 20 && !poll(); ++i) {
    usleep(50'000);
  }
  if (!exited_) {
    kill(pid_, SIGKILL);
    int status = 0;
    waitpid(pid_, &status, 0);
    exited_ = true;
    exit_code_ = 128 + SIGKILL;
  }
}

int run_to_completion(const std::string& name, const std::string& program,
                      const std::vector<std::string>& args, double timeout) {
  ChildProcess child(name, program, args, true);
  const double deadline = ChildProcess::now() + timeout;
  while (!child.poll()) {
    if (ChildProcess::now() > deadline) {
      child.terminate();
      throw Error(name + ": did not finish within " + std::to_string(timeout) + " s");
    }
    usleep(20'000);
  }
  return child.exit_code();
}

namespace fs = std::filesystem;

fs::path own_executable() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) {
    throw Error("cannot find this program's executable (/proc/self/exe): " + ec.message());
  }
  return self;
}

std::string failure(const ChildProcess& child) {
  return child.name() + " failed with exit code " + std::to_string(child.exit_code()) +
         " (its messages are above)";
}

void wait_for_all(std::initializer_list<ChildProcess*> children, double timeout) {
  const double deadline = ChildProcess::now() + timeout;
  const auto stop_all = [&] {
    for (ChildProcess* c : children) {
      c->terminate();
    }
  };
  while (true) {
    bool all_done = true;
    for (ChildProcess* c : children) {
      const bool done = c->poll();
      if (done && c->exit_code() != 0) {
        stop_all();
        throw Error(failure(*c));
      }
      all_done = all_done && done;
    }
    if (all_done) {
      return;
    }
    if (ChildProcess::now() > deadline) {
      std::string late;
      for (ChildProcess* c : children) {
        late += c->poll() ? "" : c->name() + " ";
      }
      stop_all();
      throw Error(late + "did not finish within " + std::to_string(timeout) + " s (--timeout)");
    }
    usleep(20'000);
  }
}

void run_host_and_join(const fs::path& self, const std::vector<std::string>& host_args,
                       const std::vector<std::string>& join_args, double listen_timeout,
                       double timeout) {
  std::vector<std::string> a = {"host", "--port", "0", "--bind", "127.0.0.1"};
  a.insert(a.end(), host_args.begin(), host_args.end());
  ChildProcess host("site A (host)", self.string(), a);
  const std::optional<std::string> port =
      host.line_starting("port ", ChildProcess::now() + listen_timeout);
  if (!port) {
    throw Error(host.poll() ? failure(host)
                            : "site A (host) did not start listening within " +
                                  std::to_string(listen_timeout) + " s");
  }
  std::vector<std::string> b = {"join", "--connect", "127.0.0.1:" + port->substr(5)};
  b.insert(b.end(), join_args.begin(), join_args.end());
  ChildProcess join("site B (join)", self.string(), b);
  wait_for_all({&host, &join}, timeout);
}

void pass_passphrase(const std::string& passphrase) {
  const int failed = passphrase.empty() ? unsetenv(site::kPassphraseVariable)
                                        : setenv(site::kPassphraseVariable, passphrase.c_str(), 1);
  if (failed != 0) {
    throw Error(std::string("cannot set ") + site::kPassphraseVariable + " for the sites");
  }
}

}  // namespace deixis::app
