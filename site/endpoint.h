#pragma once
// A host's endpoint as a person types it, "HOST:PORT" (`--join`, `--connect`, the simulator's
// panel): one reading for the command line and the window, so both accept and refuse the same.
// Next to it, who may reach a host (docs/security.md): a host binds 127.0.0.1 unless told
// otherwise, and one reachable beyond loopback needs a passphrase or an explicit --open; and how a
// passphrase is read without putting it on the command line (an environment variable, a file, a
// prompt on the terminal).

#include <cstdint>
#include <filesystem>
#include <string>

namespace deixis::site {

// Splits `text` into `address` and `port` (1 to 65535). Returns what is wrong with it, e.g. "the
// port must be a number", or an empty string when it is fine (then, only, the outputs are set).
std::string parse_endpoint(const std::string& text, std::string& address, std::uint16_t& port);

// ---- Who may reach a host ----

// The address a host binds unless told otherwise (--bind).
inline constexpr const char* kDefaultBind = "127.0.0.1";

// Whether binding `address` keeps a host on this machine: it resolves (IPv4, as ENet binds) into
// 127.0.0.0/8 only. "0.0.0.0" (every interface), any other address, a name that does not resolve
// and an empty one are beyond loopback.
bool binds_loopback_only(const std::string& address);

// An unprotected session beyond loopback, asked for knowingly (`--open`): process-wide, set once
// by the command line before any session starts, so that every path to a host — `deixis host`,
// `xr --host`, `sim --host` and the simulator's panel — is held to the same rule.
void allow_open_sessions(bool allow);
bool open_sessions_allowed();

// Why a host on `address` may not start (empty: it may): it would be reachable beyond loopback
// with no passphrase, and open sessions were not allowed. The text says what to do.
std::string host_exposure_problem(const std::string& address, bool has_passphrase);

// The warning an open session prints when it starts (--open, no passphrase).
std::string open_session_warning(const std::string& address);

// Why a site may not enter an open room (no passphrase) through the relay at `relay` (empty: it
// may): the relay is beyond this machine, so its operator and anyone on the path would read this
// site's motion, and open sessions were not allowed (--open). The text says what to do.
std::string open_room_problem(const std::string& relay, bool has_passphrase);

// ---- Passphrase input ----

// The environment variable a passphrase is read from when no flag gives one.
inline constexpr const char* kPassphraseVariable = "DEIXIS_PASSPHRASE";

// The passphrase in the first line of `file` (its line break, "\n" or "\r\n", stripped) into
// `passphrase`. Returns what is wrong (unreadable, empty first line), or an empty string. A file
// that other users may read is accepted, with a warning in `warning` (else it is left empty).
std::string read_passphrase_file(const std::filesystem::path& file, std::string& passphrase,
                                 std::string& warning);

// Asks for the passphrase on the controlling terminal (/dev/tty, echo off), showing `prompt`.
// Returns what is wrong (no terminal, an empty answer), or an empty string.
std::string ask_passphrase(const std::string& prompt, std::string& passphrase);

}  // namespace deixis::site
