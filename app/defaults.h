#pragma once
// What every `deixis` command shares, in one place: where the networks' weights, the authors'
// reference data, the demo's sites and the evaluation's test sets are looked for; how a command's
// passphrase is read (--passphrase, --passphrase-file, --ask-passphrase, else DEIXIS_PASSPHRASE);
// and who may host beyond loopback (site/endpoint.h, docs/security.md). No CLI11 here:
// app/command_table.cpp binds the flags to these.

#include <filesystem>
#include <string>

namespace deixis::app {

// ---- Defaults ----

// The authors' reference data: $DEIXIS_REFERENCE_DIR, else ../shared/reference (relative to the
// working directory, as the parity fixtures' paths are).
std::filesystem::path default_reference_dir();

// The authors' MoE weights (right/ and left/): $DEIXIS_REFERENCE_DIR/weights, else
// ../shared/reference/weights next to the repository.
std::filesystem::path authors_weights_dir();

// The project's own weights, assets/weights in the repository.
std::filesystem::path project_weights_dir();

// The MoE weights the runtime commands (host, join, demo, xr, sim) use: the project's once all
// four networks are there, else the authors'.
std::filesystem::path default_weights_dir();

// One of the demo's site files (assets/sites/), the default of the commands that run two sites.
std::filesystem::path demo_site(const char* file);

// Where `deixis eval` reads the test sets unless --data says otherwise: out/data in the
// repository, where `deixis capture generate` writes them in docs/eval.md and `tools/run train`.
std::filesystem::path default_eval_data_dir();

// ---- The passphrase and who may reach a host ----

// A command's passphrase flags as given: --passphrase TEXT (`text_given`: the flag was there,
// even empty), --passphrase-file FILE, --ask-passphrase; and --open (host beyond loopback without
// a passphrase, knowingly).
struct PassphraseInput {
  std::string text;
  bool text_given = false;
  std::string file;
  bool ask = false;
  bool open = false;
};

// Before a session starts: the passphrase `input` gives (empty: none) into `passphrase`, and when
// `hosting`, the rule for a host on `address` (beyond loopback without a passphrase it needs
// --open; an open session is announced with a warning; the process-wide permission
// site::SiteSession checks again is set). False after saying why on stderr, naming `command`: the
// command exits 2.
bool prepare_session(const char* command, const PassphraseInput& input, bool hosting,
                     const std::string& address, std::string& passphrase);

// Before `deixis join --room` (or sim/xr, `command`) enters a room through the relay at `relay`:
// an open room (no passphrase) beyond loopback needs --open, and is announced with a warning.
// False after saying why on stderr: the command exits 2.
bool may_enter_room(const PassphraseInput& input, const std::string& relay,
                    const std::string& passphrase, const char* command = "join");

}  // namespace deixis::app
