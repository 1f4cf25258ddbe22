// The `deixis` command line. This is the only translation unit that includes CLI11 (it is slow to
// compile); it parses flags and hands plain option structs to the commands in commands.h.

#include <CLI/CLI.hpp>
#include <cstdlib>

#include "app/commands.h"

namespace {

std::filesystem::path default_reference_dir() {
  if (const char* env = std::getenv("DEIXIS_REFERENCE_DIR")) {
    return env;
  }
  return "../shared/reference";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Deixis: real-time translation of upper-body gestures (gaze, pointing, touching, free-form) "
      "to avatars in dissimilar telepresence rooms."};
  app.require_subcommand(1);

  deixis::app::ParityOptions parity;
  parity.reference_dir = default_reference_dir();
  CLI::App* parity_cmd = app.add_subcommand(
      "parity",
      "Run the authors' parity fixtures through Deixis' networks and print the largest absolute "
      "error per reference output; exits 1 if one is over tolerance, 2 if a fixture is unreadable");
  parity_cmd->add_option("fixture", parity.fixtures, "Fixture files (safetensors)")
      ->required()
      ->check(CLI::ExistingFile);
  parity_cmd
      ->add_option("--reference-dir", parity.reference_dir,
                   "Directory that the fixtures' checkpoint paths are relative to "
                   "(default: $DEIXIS_REFERENCE_DIR or ../shared/reference)")
      ->check(CLI::ExistingDirectory);

  CLI11_PARSE(app, argc, argv);

  if (parity_cmd->parsed()) {
    return deixis::app::run_parity(parity);
  }
  return 0;
}
