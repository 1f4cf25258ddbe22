#include "site/endpoint.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>

namespace deixis::site {

std::string parse_endpoint(const std::string& text, std::string& address, std::uint16_t& port) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) {
    return "expected HOST:PORT, e.g. 127.0.0.1:7350";
  }
  try {
    std::size_t used = 0;
    const int number = std::stoi(text.substr(colon + 1), &used);
    if (used != text.size() - colon - 1 || number < 1 || number > 65535) {
      return "the port must be 1 to 65535";
    }
    address = text.substr(0, colon);
    port = static_cast<std::uint16_t>(number);
  } catch (const std::exception&) {
    return "the port must be a number";
  }
  return {};
}

// ---- Who may reach a host ----

namespace {

std::atomic<bool> open_sessions{false};

bool in_loopback_net(const sockaddr* address) {
  sockaddr_in in{};
  std::memcpy(&in, address, sizeof in);
  return (ntohl(in.sin_addr.s_addr) >> 24) == 127u;
}

}  // namespace

bool binds_loopback_only(const std::string& address) {
  if (address.empty()) {
    return false;
  }
  addrinfo hints{};
  hints.ai_family = AF_INET;  // ENet binds IPv4
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  if (getaddrinfo(address.c_str(), nullptr, &hints, &found) != 0 || found == nullptr) {
    return false;
  }
  bool loopback = true;
  for (const addrinfo* a = found; a != nullptr; a = a->ai_next) {
    loopback = loopback && a->ai_family == AF_INET &&
               a->ai_addrlen >= static_cast<socklen_t>(sizeof(sockaddr_in)) &&
               in_loopback_net(a->ai_addr);
  }
  freeaddrinfo(found);
  return loopback;
}

void allow_open_sessions(bool allow) {
  open_sessions = allow;
}

bool open_sessions_allowed() {
  return open_sessions;
}

std::string host_exposure_problem(const std::string& address, bool has_passphrase) {
  if (has_passphrase || open_sessions_allowed() || binds_loopback_only(address)) {
    return {};
  }
  return "binding " + (address.empty() ? std::string("\"\"") : address) +
         " reaches beyond this machine, and the session has no passphrase: anyone who can reach "
         "the port could join and receive this site's motion. Give a passphrase (the " +
         std::string(kPassphraseVariable) +
         " environment variable, --passphrase-file FILE or --ask-passphrase), or pass --open to "
         "run an unprotected session knowingly (or bind 127.0.0.1, the default)";
}

std::string open_session_warning(const std::string& address) {
  return "warning: an open session (--open, no passphrase) listening on " + address +
         ": anyone who can reach the port can join and read this site's motion (head, hands, "
         "gaze, body measurements and the room's targets), unencrypted";
}

std::string open_room_problem(const std::string& relay, bool has_passphrase) {
  if (has_passphrase || open_sessions_allowed() || binds_loopback_only(relay)) {
    return {};
  }
  return "the relay " + (relay.empty() ? std::string("\"\"") : relay) +
         " is beyond this machine, and the room has no passphrase: the relay's operator and "
         "anyone on the path could read this site's motion. Give the room's passphrase (the " +
         std::string(kPassphraseVariable) +
         " environment variable, --passphrase-file FILE or --ask-passphrase), or pass --open to "
         "enter an open room knowingly";
}

// ---- Passphrase input ----

std::string read_passphrase_file(const std::filesystem::path& file, std::string& passphrase,
                                 std::string& warning) {
  warning.clear();
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    return file.string() + ": cannot read the passphrase file (" + std::strerror(errno) + ")";
  }
  std::string line;
  std::getline(in, line);
  if (in.bad()) {
    return file.string() + ": cannot read the passphrase file";
  }
  if (!line.empty() && line.back() == '\r') {
    line.pop_back();
  }
  if (line.empty()) {
    return file.string() + ": the passphrase file's first line is empty";
  }
  struct stat st {};
  if (stat(file.c_str(), &st) == 0 && (st.st_mode & (S_IRWXG | S_IRWXO)) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    warning = "warning: " + file.string() + " is open to other users (mode " + mode +
              "); chmod 600 " + file.string();
  }
  passphrase = std::move(line);
  return {};
}

namespace {

// The terminal's settings while echo is off, restored if a signal ends the prompt.
int tty_fd = -1;
termios tty_saved{};
volatile std::sig_atomic_t tty_echo_off = 0;

void restore_tty_and_reraise(int signal) {
  if (tty_echo_off != 0) {
    tcsetattr(tty_fd, TCSAFLUSH, &tty_saved);
    static const char newline = '\n';
    [[maybe_unused]] const ssize_t n = write(tty_fd, &newline, 1);
  }
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

}  // namespace

std::string ask_passphrase(const std::string& prompt, std::string& passphrase) {
  const int fd = open("/dev/tty", O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) {
    return "--ask-passphrase: no terminal to ask on (" + std::string(std::strerror(errno)) +
           "); use the " + std::string(kPassphraseVariable) +
           " environment variable or --passphrase-file FILE";
  }
  termios saved{};
  const bool is_tty = tcgetattr(fd, &saved) == 0;
  using Handler = void (*)(int);
  Handler previous[3] = {};
  const int signals[3] = {SIGINT, SIGTERM, SIGHUP};
  if (is_tty) {
    tty_fd = fd;
    tty_saved = saved;
    for (int i = 0; i < 3; ++i) {
      previous[i] = std::signal(signals[i], restore_tty_and_reraise);
    }
    termios quiet = saved;
    quiet.c_lflag &= ~static_cast<tcflag_t>(ECHO);
    quiet.c_lflag |= ECHONL;
    tty_echo_off = 1;
    tcsetattr(fd, TCSAFLUSH, &quiet);
  }
  // The prompt only once echo is off: TCSAFLUSH discards what was typed before it, so an answer
  // typed after a prompt shown earlier could be echoed and then lost.
  [[maybe_unused]] ssize_t n = write(fd, prompt.data(), prompt.size());
  std::string line;
  char c = 0;
  bool ended = false;
  while (read(fd, &c, 1) == 1) {
    if (c == '\n') {
      ended = true;
      break;
    }
    if (line.size() < 4096) {
      line.push_back(c);
    }
  }
  if (is_tty) {
    tcsetattr(fd, TCSAFLUSH, &saved);
    tty_echo_off = 0;
    for (int i = 0; i < 3; ++i) {
      std::signal(signals[i], previous[i]);
    }
  }
  if (!ended) {
    n = write(fd, "\n", 1);
  }
  close(fd);
  if (!line.empty() && line.back() == '\r') {
    line.pop_back();
  }
  if (line.empty()) {
    return "--ask-passphrase: no passphrase given";
  }
  passphrase = std::move(line);
  return {};
}

}  // namespace deixis::site
