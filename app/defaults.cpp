// The defaults and rules every `deixis` command shares (app/defaults.h).

#include "app/defaults.h"

#include <cstdio>
#include <cstdlib>

#include "site/endpoint.h"

namespace deixis::app {

namespace fs = std::filesystem;

namespace {

const fs::path kSource = DEIXIS_SOURCE_DIR;

// The passphrase `input` gives (empty: none) into `passphrase`. False after saying why when it
// cannot be read.
bool read_passphrase(const char* command, const PassphraseInput& input, std::string& passphrase) {
  passphrase.clear();
  if (input.text_given) {
    passphrase = input.text;
    if (!passphrase.empty()) {
      std::fprintf(stderr,
                   "deixis %s: warning: a passphrase given with --passphrase can be read by other "
                   "users of this machine (ps, /proc); prefer %s, --passphrase-file or "
                   "--ask-passphrase\n",
                   command, site::kPassphraseVariable);
    }
    return true;
  }
  std::string problem;
  if (!input.file.empty()) {
    std::string warning;
    problem = site::read_passphrase_file(input.file, passphrase, warning);
    if (problem.empty() && !warning.empty()) {
      std::fprintf(stderr, "deixis %s: %s\n", command, warning.c_str());
    }
  } else if (input.ask) {
    problem = site::ask_passphrase("deixis " + std::string(command) + ": passphrase: ", passphrase);
  } else if (const char* env = std::getenv(site::kPassphraseVariable)) {
    passphrase = env;
  }
  if (!problem.empty()) {
    std::fprintf(stderr, "deixis %s: %s\n", command, problem.c_str());
    return false;
  }
  return true;
}

// A host's start: beyond loopback without a passphrase it needs --open (else false after saying
// what to do); an open session is announced with a warning. Sets the process-wide permission
// that site::SiteSession checks again below the command line.
bool may_host(const char* command, const PassphraseInput& input, const std::string& address,
              const std::string& passphrase) {
  site::allow_open_sessions(input.open);
  const std::string problem = site::host_exposure_problem(address, !passphrase.empty());
  if (!problem.empty()) {
    std::fprintf(stderr, "deixis %s: %s\n", command, problem.c_str());
    return false;
  }
  if (input.open && passphrase.empty()) {
    std::fprintf(stderr, "deixis %s: %s\n", command, site::open_session_warning(address).c_str());
  }
  return true;
}

}  // namespace

fs::path default_reference_dir() {
  if (const char* env = std::getenv("DEIXIS_REFERENCE_DIR")) {
    return env;
  }
  return "../shared/reference";
}

fs::path authors_weights_dir() {
  if (const char* env = std::getenv("DEIXIS_REFERENCE_DIR")) {
    return fs::path(env) / "weights";
  }
  return (kSource / "../shared/reference/weights").lexically_normal();
}

fs::path project_weights_dir() {
  return kSource / "assets/weights";
}

fs::path default_weights_dir() {
  const fs::path own = project_weights_dir();
  for (const char* hand : {"right", "left"}) {
    for (const char* file : {"MPNet(MoE)(AC)80.safetensors", "UGNet(MoE)(AC)120.safetensors"}) {
      if (!fs::exists(own / hand / file)) {
        return authors_weights_dir();
      }
    }
  }
  return own;
}

fs::path demo_site(const char* file) {
  return kSource / "assets/sites" / file;
}

fs::path default_eval_data_dir() {
  return kSource / "out/data";
}

bool prepare_session(const char* command, const PassphraseInput& input, bool hosting,
                     const std::string& address, std::string& passphrase) {
  return read_passphrase(command, input, passphrase) &&
         (!hosting || may_host(command, input, address, passphrase));
}

bool may_enter_room(const PassphraseInput& input, const std::string& relay,
                    const std::string& passphrase, const char* command) {
  site::allow_open_sessions(input.open);
  const std::string problem = site::open_room_problem(relay, !passphrase.empty());
  if (!problem.empty()) {
    std::fprintf(stderr, "deixis %s: %s\n", command, problem.c_str());
    return false;
  }
  if (passphrase.empty() && !site::binds_loopback_only(relay)) {
    std::fprintf(stderr,
                 "deixis %s: warning: an open room (--open, no passphrase) through the relay at "
                 "%s: its operator and anyone on the path can read this site's motion\n",
                 command, relay.c_str());
  }
  return true;
}

}  // namespace deixis::app
