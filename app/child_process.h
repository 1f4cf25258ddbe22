#pragma once
// A child process for `deixis demo` and `deixis eval --live-rooms`: started with posix_spawn, its
// standard output on a pipe we read line by line (standard error stays ours, so its messages reach
// the user as they come), waited for with a deadline, and killed if it is still running when the
// object goes.

#include <sys/types.h>

#include <filesystem>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

namespace deixis::app {

class ChildProcess {
 public:
  // Starts `program` (a path, or a name looked up on PATH when `search_path`) with `args`.
  // Throws deixis::Error naming the program when it cannot be started.
  ChildProcess(const std::string& name, const std::string& program,
               const std::vector<std::string>& args, bool search_path = false);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  const std::string& name() const { return name_; }

  // The next line of standard output that starts with `prefix`, waiting until `deadline` (a
  // steady-clock time in seconds, see now()); empty when the output ended or time ran out.
  std::optional<std::string> line_starting(const std::string& prefix, double deadline);
  // Reads whatever output is waiting (so the child never blocks on a full pipe) and reaps the
  // child if it has exited; true once it has.
  bool poll();
  // The exit code (128 + signal for a signal); valid once poll() returned true.
  int exit_code() const { return exit_code_; }
  const std::string& output() const { return output_; }
  void terminate();

  static double now();  // steady clock, seconds

 private:
  bool read_some(int wait_ms);

  std::string name_;
  pid_t pid_ = -1;
  int out_ = -1;
  std::string output_;  // everything read so far
  std::size_t consumed_ = 0;
  bool exited_ = false;
  int exit_code_ = -1;
};

// Runs `program` to completion (stdout discarded into output()); the exit code, or throws
// deixis::Error if it does not finish by `timeout` seconds.
int run_to_completion(const std::string& name, const std::string& program,
                      const std::vector<std::string>& args, double timeout);

// This program's executable (/proc/self/exe), to start itself as sites; throws deixis::Error.
std::filesystem::path own_executable();

// "<name> failed with exit code N (its messages are above)".
std::string failure(const ChildProcess& child);

// Waits for every child to exit 0; the first that fails, or `timeout` seconds passing, ends the
// others and throws deixis::Error naming it (or those still running).
void wait_for_all(std::initializer_list<ChildProcess*> children, double timeout);

// Site A as `deixis host --port 0 --bind 127.0.0.1` followed by `host_args`, and once it prints
// "port N" (within `listen_timeout` s), site B as `deixis join --connect 127.0.0.1:N` followed by
// `join_args`, both this program (`self`); then waits for both (wait_for_all). Throws
// deixis::Error naming the site that failed or did not listen.
void run_host_and_join(const std::filesystem::path& self, const std::vector<std::string>& host_args,
                       const std::vector<std::string>& join_args, double listen_timeout,
                       double timeout);

// Sites started after this read `passphrase` from DEIXIS_PASSPHRASE, which they inherit: on
// their command lines other users of the machine could read it (ps). Empty: none is inherited.
void pass_passphrase(const std::string& passphrase);

}  // namespace deixis::app
