#pragma once
// The rows of the `deixis` command table that main.cpp walks. Each add_<command> adds its CLI11
// subcommand(s) with their flags and defaults (app/defaults.h) to the program, and for each
// subcommand that does work a runner: what runs, with the parsed options, once that subcommand
// was parsed (the run_<command> functions of commands.h, in <command>_command.cpp). The flags
// themselves are in command_table.cpp, the one file besides main.cpp that includes CLI11.

#include <functional>
#include <vector>

namespace CLI {
class App;
}

namespace deixis::app {

// How `deixis` was started: `deixis eval` records its command line and names the program in the
// command it suggests.
struct Invocation {
  int argc = 0;
  char** argv = nullptr;
};

// A subcommand's work: `run` returns the exit code once `command` was parsed.
struct Runner {
  const CLI::App* command = nullptr;
  std::function<int()> run;
};

// One row of the table.
using AddCommand = void (*)(CLI::App& program, const Invocation& invocation,
                            std::vector<Runner>& runners);

void add_parity(CLI::App& program, const Invocation& invocation, std::vector<Runner>& runners);
void add_avatar(CLI::App& program, const Invocation& invocation, std::vector<Runner>& runners);
void add_capture(CLI::App& program, const Invocation& invocation, std::vector<Runner>& runners);
void add_host(CLI::App& program, const Invocation& invocation, std::vector<Runner>& runners);
void add_join(CLI::App& program, const Invocation& invocation, std::vector<Runner>& runners);
void add_relay(CLI::App& program, const Invocation& invocation, std::vector<Runner>& runners);
void add_demo(CLI::App& program, const Invocation& invocation, std::vector<Runner>& runners);
void add_xr(CLI::App& program, const Invocation& invocation, std::vector<Runner>& runners);
void add_sim(CLI::App& program, const Invocation& invocation, std::vector<Runner>& runners);
void add_eval(CLI::App& program, const Invocation& invocation, std::vector<Runner>& runners);

}  // namespace deixis::app
