// The `deixis` command line: a table of commands. Each row adds a subcommand with its flags and
// hands back what runs once it is parsed (app/command_table.h); main() walks the table, refuses a
// command that does not exist, parses, and runs the one that was given.
//
// Where CLI11 lives (decided when main() became this table): CLI11's headers are slow to
// compile, so two translation units include them, this one (the program, parsing, exit codes)
// and app/command_table.cpp (every subcommand's flags, one add_<command> per row). The
// <command>_command.cpp files do the work from plain option structs (app/commands.h) and never
// see CLI11, so editing a command's work does not recompile the flags. Shared defaults (the
// weights and reference directories, the demo's sites, the evaluation's data), the passphrase
// and the rules for hosting are in one place, app/defaults.h.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "app/command_table.h"
#include "app/crash_report.h"

namespace {

// The table, in the order `deixis --help` lists the commands.
constexpr deixis::app::AddCommand kCommands[] = {
    deixis::app::add_parity,   // parity_command.cpp
    deixis::app::add_avatar,   // avatar_command.cpp: avatar generate, avatar info
    deixis::app::add_capture,  // capture_command.cpp: capture generate, preview, csv, judge
    deixis::app::add_host,     // site_command.cpp
    deixis::app::add_join,     // site_command.cpp
    deixis::app::add_relay,    // relay_command.cpp
    deixis::app::add_demo,     // demo_command.cpp
    deixis::app::add_xr,       // xr_command.cpp
    deixis::app::add_sim,      // sim/sim_run.cpp
    deixis::app::add_eval,     // eval_command.cpp
};

// A word of the command line that names no command where one is expected (`deixis frob`, `deixis
// avatar frob`, with or without --help): exit 2 naming it (CLI11 alone would print the main help
// and exit 0 for `deixis frob --help`). Only levels that hold subcommands are checked; they take
// no option with a value, so every word there that is not a flag is a command. Returns whether
// the command line is refused.
bool refuse_unknown_command(CLI::App& program, int argc, char** argv) {
  CLI::App* level = &program;
  std::string path = "deixis";
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word == "--") {
      return false;
    }
    if (word.starts_with('-')) {
      continue;
    }
    const std::vector<CLI::App*> commands = level->get_subcommands([](CLI::App*) { return true; });
    if (commands.empty()) {
      return false;
    }
    const auto named = std::find_if(commands.begin(), commands.end(),
                                    [&word](CLI::App* c) { return c->check_name(word); });
    if (named == commands.end()) {
      std::string names;
      for (const CLI::App* c : commands) {
        names += (names.empty() ? "" : ", ") + c->get_name();
      }
      std::fprintf(stderr,
                   "%s: unknown command \"%s\"; the commands are %s (`%s --help` describes "
                   "them)\n",
                   path.c_str(), word.c_str(), names.c_str(), path.c_str());
      return true;
    }
    level = *named;
    path += " " + word;
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  deixis::app::install_crash_report();
  CLI::App program{
      "Deixis: real-time translation of upper-body gestures (gaze, pointing, touching, free-form) "
      "to avatars in dissimilar telepresence rooms."};
  program.require_subcommand(1);
  const deixis::app::Invocation invocation{argc, argv};
  std::vector<deixis::app::Runner> runners;
  for (const deixis::app::AddCommand add : kCommands) {
    add(program, invocation, runners);
  }
  if (refuse_unknown_command(program, argc, argv)) {
    return 2;
  }
  // Bad flags exit 2 (as bad files do), with CLI11's message naming the flag; --help exits 0.
  try {
    program.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = program.exit(e);
    return code == 0 ? 0 : 2;
  }
  for (const deixis::app::Runner& runner : runners) {
    if (runner.command->parsed()) {
      return runner.run();
    }
  }
  return 0;
}
