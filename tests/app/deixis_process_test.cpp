// `deixis host`, `deixis join` and `deixis demo` as real processes (the built `deixis`), over real
// ENet sockets on 127.0.0.1: tracking flows both ways and each receiving avatar follows its
// person (the pointing error at the remote completion state beats copying the pose); a wrong
// passphrase is refused; bad flags and files exit 2 naming what is wrong; a short demo writes a
// well-formed summary.json, a video and a contact sheet. Hosts listen on port 0 and print the
// port, so no test guesses a free port. Safe defaults (docs/security.md): a host binds
// 127.0.0.1 unless --bind says otherwise, and beyond loopback it needs a passphrase or --open;
// the passphrase comes from DEIXIS_PASSPHRASE, --passphrase-file or (with a warning) --passphrase.

#include <gtest/gtest.h>

#include <poll.h>
#include <pty.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/deixis_child.h"
#include "test_support.h"

namespace deixis::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

json read_json(const fs::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  return in ? json::parse(in) : json();
}

std::vector<std::string> site_flags(const char* site_file, const fs::path& out,
                                    const std::string& seconds, const std::string& wait = "30") {
  return {"--site",        site(site_file).string(),
          "--out",         out.string(),
          "--weights-dir", weights_dir(),
          "--seconds",     seconds,
          "--wait",        wait};
}

// DEIXIS_PASSPHRASE as the children inherit it, for one scope (unset when `value` is empty);
// restored after. No test depends on the variable of the environment ctest runs in.
class ScopedPassphrase {
 public:
  explicit ScopedPassphrase(const std::string& value) {
    if (const char* old = std::getenv("DEIXIS_PASSPHRASE")) {
      saved_ = old;
    }
    set(value);
  }
  ~ScopedPassphrase() { set(saved_.value_or("")); }
  ScopedPassphrase(const ScopedPassphrase&) = delete;
  ScopedPassphrase& operator=(const ScopedPassphrase&) = delete;
  static void set(const std::string& value) {
    if (value.empty()) {
      unsetenv("DEIXIS_PASSPHRASE");
    } else {
      setenv("DEIXIS_PASSPHRASE", value.c_str(), 1);
    }
  }

 private:
  std::optional<std::string> saved_;
};

// Every test starts without DEIXIS_PASSPHRASE.
class NoPassphraseInTheEnvironment : public ::testing::Environment {
 public:
  void SetUp() override { unsetenv("DEIXIS_PASSPHRASE"); }
};
const auto* const no_passphrase_environment =
    ::testing::AddGlobalTestEnvironment(new NoPassphraseInTheEnvironment);

// Whether a UDP socket of this machine is bound to `address` (as /proc/net/udp writes it: the
// IPv4 address in hex, host byte order) and `port`.
bool udp_bound(const char* address, int port) {
  std::ifstream in("/proc/net/udp");
  char wanted[32];
  std::snprintf(wanted, sizeof wanted, "%s:%04X", address, static_cast<unsigned>(port));
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string slot;
    std::string local;
    fields >> slot >> local;
    if (local == wanted) {
      return true;
    }
  }
  return false;
}

// A passphrase file with `text` and `mode`.
fs::path passphrase_file(const fs::path& dir, const char* name, const std::string& text,
                         mode_t mode = 0600) {
  const fs::path path = dir / name;
  std::ofstream(path) << text;
  chmod(path.c_str(), mode);
  return path;
}

double sum_of_angles(const json& pointing, const char* who) {
  return pointing[std::string(who) + "_horizontal_deg"].get<double>() +
         pointing[std::string(who) + "_vertical_deg"].get<double>();
}

TEST(DeixisSites, TwoProcessesExchangeTrackingAndTheAvatarsFollow) {
  // 8 s: each script's pointing hold (done at about 4 s) ends well before the run does, so it is
  // measured at its end even when a slow (sanitizer) build runs late.
  deixis::testing::ScratchDir dir;
  Deixis host(std::vector<std::string>{"host", "--port", "0", "--bind", "127.0.0.1", "--no-video"} +
              site_flags("a.json", dir.path() / "A", "8"));
  const int port = host.port();
  ASSERT_GT(port, 0) << host.err();
  Deixis join(std::vector<std::string>{"join", "--connect", "127.0.0.1:" + std::to_string(port),
                                       "--no-video"} +
              site_flags("b.json", dir.path() / "B", "8"));
  ASSERT_EQ(join.wait(), 0) << join.err();
  ASSERT_EQ(host.wait(), 0) << host.err();

  for (const char* name : {"A", "B"}) {
    SCOPED_TRACE(name);
    const json s = read_json(dir.path() / name / "session.json");
    EXPECT_EQ(s["format"], "deixis-site-run");
    EXPECT_EQ(s["site"], name);
    EXPECT_EQ(s["peer_site"], std::string(name) == "A" ? "B" : "A");
    EXPECT_GE(s["ticks"].get<int>(), 239);
    const json& net = s["network"];
    EXPECT_GT(net["tracking_received"].get<int>(), 100);
    EXPECT_GT(net["frames_played"].get<int>(), 100);
    EXPECT_EQ(net["rejected"].get<int>(), 0);
    EXPECT_EQ(net["bytes_per_frame"].get<int>(), 82);
    // The avatar was shown for most of the run and translation took time.
    EXPECT_GT(s["avatar_visible_ticks"].get<int>(), 100);
    EXPECT_GT(s["translation_ms"]["count"].get<int>(), 100);
    // The other person pointed: the avatar's ray is finite and closer to this room's target than
    // the pose copied unchanged.
    const json& pointing = s["pointing"];
    ASSERT_GE(pointing["count"].get<int>(), 1) << s.dump(2);
    EXPECT_TRUE(std::isfinite(sum_of_angles(pointing, "avatar")));
    EXPECT_LT(sum_of_angles(pointing, "avatar"), sum_of_angles(pointing, "copy")) << s.dump(2);
    EXPECT_LT(pointing["avatar_horizontal_deg"].get<double>(), 10.0);
  }
}

TEST(DeixisSites, AWrongPassphraseIsRefused) {
  deixis::testing::ScratchDir dir;
  Deixis host(std::vector<std::string>{"host", "--port", "0", "--bind", "127.0.0.1", "--no-video",
                                       "--passphrase", "blue whale"} +
              site_flags("a.json", dir.path() / "A", "2", "4"));
  const int port = host.port();
  ASSERT_GT(port, 0) << host.err();
  Deixis join(std::vector<std::string>{"join", "--connect", "127.0.0.1:" + std::to_string(port),
                                       "--no-video", "--passphrase", "green whale"} +
              site_flags("b.json", dir.path() / "B", "2"));
  EXPECT_EQ(join.wait(), 1);
  EXPECT_NE(join.err().find("refused this site: wrong passphrase"), std::string::npos)
      << join.err();
  EXPECT_NE(join.err().find("passphrases differ"), std::string::npos) << join.err();
  // The host never streamed with it and says why nobody joined.
  EXPECT_EQ(host.wait(), 1);
  EXPECT_NE(host.err().find("wrong passphrase"), std::string::npos) << host.err();
  EXPECT_FALSE(fs::exists(dir.path() / "B/session.json"));
  EXPECT_FALSE(fs::exists(dir.path() / "A/session.json"));
}

TEST(DeixisSafeDefaults, AHostBindsLoopbackAndTheEnvironmentOrAFileGivesThePassphrase) {
  // No --bind: the host listens on 127.0.0.1 only. Its passphrase comes from DEIXIS_PASSPHRASE,
  // the joiner's from a file; they match, so the joiner gets in and the session is sealed.
  deixis::testing::ScratchDir dir;
  const fs::path file = passphrase_file(dir.path(), "pass", "blue whale\n");
  std::optional<Deixis> host;
  {
    const ScopedPassphrase env("blue whale");
    host.emplace(std::vector<std::string>{"host", "--port", "0", "--no-video"} +
                 site_flags("a.json", dir.path() / "A", "1", "10"));
  }
  const int port = host->port();
  ASSERT_GT(port, 0) << host->err();
  EXPECT_TRUE(udp_bound("0100007F", port)) << "bound to 127.0.0.1:" << port;
  EXPECT_FALSE(udp_bound("00000000", port)) << "not to every interface";
  Deixis join(std::vector<std::string>{"join", "--connect", "127.0.0.1:" + std::to_string(port),
                                       "--no-video", "--passphrase-file", file.string()} +
              site_flags("b.json", dir.path() / "B", "1"));
  ASSERT_EQ(join.wait(), 0) << join.err();
  ASSERT_EQ(host->wait(), 0) << host->err();
  for (const char* name : {"A", "B"}) {
    EXPECT_TRUE(read_json(dir.path() / name / "session.json")["network"]["sealed"].get<bool>())
        << name;
  }
  EXPECT_EQ(join.err().find("warning"), std::string::npos) << join.err();
  EXPECT_EQ(host->err().find("warning"), std::string::npos) << host->err();
}

TEST(DeixisSafeDefaults, AWrongPassphraseFromTheEnvironmentIsRefused) {
  deixis::testing::ScratchDir dir;
  const fs::path file = passphrase_file(dir.path(), "pass", "blue whale\r\nsecond line\n");
  Deixis host(std::vector<std::string>{"host", "--port", "0", "--no-video", "--passphrase-file",
                                       file.string()} +
              site_flags("a.json", dir.path() / "A", "1", "4"));
  const int port = host.port();
  ASSERT_GT(port, 0) << host.err();
  const ScopedPassphrase env("green whale");
  Deixis join(std::vector<std::string>{"join", "--connect", "127.0.0.1:" + std::to_string(port),
                                       "--no-video"} +
              site_flags("b.json", dir.path() / "B", "1"));
  EXPECT_EQ(join.wait(), 1);
  EXPECT_NE(join.err().find("refused this site: wrong passphrase"), std::string::npos)
      << join.err();
  EXPECT_EQ(host.wait(), 1);
  EXPECT_NE(host.err().find("wrong passphrase"), std::string::npos) << host.err();
}

TEST(DeixisSafeDefaults, BeyondLoopbackAHostNeedsAPassphraseOrOpen) {
  deixis::testing::ScratchDir dir;
  const std::vector<std::string> a = site_flags("a.json", dir.path() / "A", "1", "1");
  // Without a passphrase: exit 2 at once, saying what to do.
  for (const char* bind : {"0.0.0.0", "192.0.2.1"}) {
    Deixis host(std::vector<std::string>{"host", "--port", "0", "--no-video", "--bind", bind} + a);
    EXPECT_EQ(host.wait(), 2) << host.err();
    for (const char* says : {"reaches beyond this machine", "DEIXIS_PASSPHRASE",
                             "--passphrase-file", "--ask-passphrase", "--open"}) {
      EXPECT_NE(host.err().find(says), std::string::npos) << says << "\n" << host.err();
    }
    EXPECT_EQ(host.out().find("port "), std::string::npos) << "never listened";
  }
  {
    // `xr --host` and `sim --host` are held to the same rule before anything starts.
    Deixis xr({"xr", "--host", "--headless", "--port", "0", "--bind", "0.0.0.0"});
    EXPECT_EQ(xr.wait(), 2) << xr.err();
    EXPECT_NE(xr.err().find("--open"), std::string::npos) << xr.err();
    Deixis sim({"sim", "--host", "--port", "0", "--bind", "0.0.0.0", "--frames", "1"});
    EXPECT_EQ(sim.wait(), 2) << sim.err();
    EXPECT_NE(sim.err().find("--open"), std::string::npos) << sim.err();
  }
  {
    // With --open it starts, warning that anyone who reaches the port can read the motion
    // (nobody joins: exit 1 after --wait 1).
    Deixis host(std::vector<std::string>{"host", "--port", "0", "--no-video", "--bind", "0.0.0.0",
                                         "--open"} +
                a);
    EXPECT_GT(host.port(), 0) << host.err();
    EXPECT_EQ(host.wait(), 1) << host.err();
    EXPECT_NE(host.err().find("warning: an open session"), std::string::npos) << host.err();
    EXPECT_NE(host.err().find("anyone who can reach the port"), std::string::npos) << host.err();
  }
  {
    // A passphrase from the environment is enough.
    const ScopedPassphrase env("blue whale");
    Deixis host(std::vector<std::string>{"host", "--port", "0", "--no-video", "--bind", "0.0.0.0"} +
                a);
    EXPECT_GT(host.port(), 0) << host.err();
    EXPECT_EQ(host.wait(), 1) << host.err();
    EXPECT_EQ(host.err().find("warning"), std::string::npos) << host.err();
  }
}

TEST(DeixisSafeDefaults, PassphraseInputIsCheckedAndTheCommandLineOneWarns) {
  deixis::testing::ScratchDir dir;
  const std::vector<std::string> a = site_flags("a.json", dir.path() / "A", "1", "1");
  const std::vector<std::string> host = {"host", "--port", "0", "--no-video"};
  {
    Deixis d(host + std::vector<std::string>{"--passphrase", "blue whale"} + a);
    EXPECT_GT(d.port(), 0) << d.err();
    EXPECT_EQ(d.wait(), 1) << d.err();  // nobody joined
    EXPECT_NE(d.err().find("warning: a passphrase given with --passphrase can be read by other "
                           "users"),
              std::string::npos)
        << d.err();
  }
  {
    // A file other users may read: used, with a warning.
    const fs::path open_file = passphrase_file(dir.path(), "open", "blue whale\n", 0644);
    Deixis d(host + std::vector<std::string>{"--passphrase-file", open_file.string()} + a);
    EXPECT_GT(d.port(), 0) << d.err();
    EXPECT_EQ(d.wait(), 1) << d.err();
    EXPECT_NE(d.err().find("is open to other users (mode 0644)"), std::string::npos) << d.err();
  }
  const fs::path empty = passphrase_file(dir.path(), "empty", "");
  const fs::path blank = passphrase_file(dir.path(), "blank", "\nblue whale\n");
  const std::vector<BadInput> cases = {
      {host + std::vector<std::string>{"--passphrase-file", empty.string()} + a,
       "first line is empty"},
      {host + std::vector<std::string>{"--passphrase-file", blank.string()} + a,
       "first line is empty"},
      {host + std::vector<std::string>{"--passphrase-file", (dir.path() / "none").string()} + a,
       "cannot read the passphrase file"},
      {std::vector<std::string>{"join", "--connect", "127.0.0.1:7350", "--passphrase-file",
                                (dir.path() / "none").string()} +
           a,
       "cannot read the passphrase file"},
      {host + std::vector<std::string>{"--passphrase", "x", "--passphrase-file", empty.string()} +
           a,
       "excludes"},
      {std::vector<std::string>{"join", "--connect", "127.0.0.1:7350", "--open"} + a, "--open"},
  };
  expect_refused(cases);
}

TEST(DeixisSafeDefaults, AskPassphrasePromptsOnTheTerminalWithoutEcho) {
  // `deixis host --ask-passphrase` on a pseudo-terminal of its own (its controlling terminal):
  // it asks, the answer is not echoed, and with it the host may bind beyond loopback.
  deixis::testing::ScratchDir dir;
  std::vector<std::string> args = {DEIXIS_EXE,         "host",   "--port", "0", "--no-video",
                                   "--ask-passphrase", "--bind", "0.0.0.0"};
  args = args + site_flags("a.json", dir.path() / "A", "1", "1");
  std::vector<char*> argv;
  for (std::string& a : args) {
    argv.push_back(a.data());
  }
  argv.push_back(nullptr);
  int terminal = -1;
  const pid_t pid = forkpty(&terminal, nullptr, nullptr, nullptr);
  ASSERT_GE(pid, 0) << "forkpty";
  if (pid == 0) {
    execv(DEIXIS_EXE, argv.data());
    _exit(127);
  }
  std::string seen;
  const auto read_until = [&](const std::string& text, double seconds) {
    const auto end = Clock::now() + std::chrono::duration<double>(seconds);
    while (seen.find(text) == std::string::npos && Clock::now() < end) {
      pollfd p{terminal, POLLIN, 0};
      if (::poll(&p, 1, 100) > 0) {
        char buffer[1024];
        const ssize_t got = read(terminal, buffer, sizeof buffer);
        if (got <= 0) {
          return;
        }
        seen.append(buffer, static_cast<std::size_t>(got));
      }
    }
  };
  read_until("passphrase: ", 20.0);
  EXPECT_NE(seen.find("deixis host: passphrase: "), std::string::npos) << seen;
  const std::string answer = "blue whale\n";
  ASSERT_EQ(write(terminal, answer.data(), answer.size()), static_cast<ssize_t>(answer.size()));
  read_until("no site joined", 30.0);  // it listened (port N), nobody came within --wait 1
  int status = 0;
  kill(pid, SIGKILL);  // if it is still there after the deadline
  waitpid(pid, &status, 0);
  close(terminal);
  EXPECT_NE(seen.find("port "), std::string::npos) << seen;
  EXPECT_EQ(seen.find("blue whale"), std::string::npos) << "echoed: " << seen;
  EXPECT_EQ(seen.find("reaches beyond"), std::string::npos) << seen;
}

TEST(DeixisSites, BadFlagsAndFilesExit2NamingWhatIsWrong) {
  deixis::testing::ScratchDir dir;
  const fs::path bad_site = dir.path() / "bad.json";
  {
    std::ifstream in(site("a.json"));
    std::stringstream read;
    read << in.rdbuf();
    std::string text = read.str();
    text.replace(text.find("\"subject\": \"172\""), 16, "\"subject\": \"999\"");
    const std::string assets = (deixis::testing::source_dir() / "assets").string();
    for (const std::string relative : {"../rooms/", "../avatars/"}) {
      text.replace(text.find(relative), 2, assets);  // the file lives elsewhere now
    }
    std::ofstream(bad_site) << text;
  }
  const std::string a = site("a.json").string();
  const std::vector<BadInput> cases = {
      {{"host", "--site", a, "--port", "seventy"}, "--port"},
      {{"host", "--site", a, "--seconds", "-3"}, "--seconds"},
      {{"host", "--site", (dir.path() / "missing.json").string()}, "--site"},
      {{"host"}, "--site"},
      {{"host", "--site", a, "--frobnicate"}, "--frobnicate"},
      {{"join", "--site", a, "--connect", "localhost"}, "--connect"},
      {{"join", "--site", a, "--connect", "127.0.0.1:99999"}, "--connect"},
      {{"join", "--site", a}, "--connect"},
      {{"demo", "--seconds", "0"}, "--seconds"},
      {{"host", "--site", a, "--weights-dir", (dir.path() / "nowhere").string()}, "--weights-dir"},
      // A readable file with a bad field: named with the file.
      {{"host", "--site", bad_site.string(), "--port", "0"}, "bad.json"},
      {{"host", "--site", bad_site.string(), "--port", "0"}, "999"},
  };
  expect_refused(cases);
}

TEST(DeixisSites, HelpOfEveryCommandExits0) {
  for (const char* command : {"host", "join", "demo"}) {
    Deixis d({command, "--help"});
    EXPECT_EQ(d.wait(), 0) << command;
    EXPECT_NE(d.out().find("--seconds"), std::string::npos) << command << d.out();
    for (const char* flag : {"--passphrase-file", "--ask-passphrase", "DEIXIS_PASSPHRASE"}) {
      EXPECT_NE(d.out().find(flag), std::string::npos) << command << " " << flag;
    }
    // host: --open to host beyond loopback without a passphrase; join: to enter an open room
    // through a relay beyond loopback (--room).
    EXPECT_EQ(d.out().find("--open") != std::string::npos, std::string(command) != "demo")
        << command;
    EXPECT_EQ(d.out().find("--room") != std::string::npos, std::string(command) == "join")
        << command;
  }
  // sim and xr can both host and enter a room: their --open speaks of both.
  for (const char* command : {"sim", "xr"}) {
    Deixis d({command, "--help"});
    EXPECT_EQ(d.wait(), 0) << command;
    const std::size_t open = d.out().find("\n  --open");
    ASSERT_NE(open, std::string::npos) << command << d.out();
    const std::string help = d.out().substr(open, d.out().find("\n  -", open + 1) - open);
    EXPECT_NE(help.find("--bind"), std::string::npos) << command << help;
    EXPECT_NE(help.find("relay"), std::string::npos) << command << help;
  }
}

TEST(DeixisCommands, AnUnknownCommandExits2NamingIt) {
  // With or without --help, at the top or under a command that has subcommands: exit 2 naming the
  // word and the commands there are, not the main help with exit 0.
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"frob", "--help"}, "deixis: unknown command \"frob\""},
      {{"frob"}, "deixis: unknown command \"frob\""},
      {{"--help", "frob"}, "deixis: unknown command \"frob\""},
      {{"avatar", "frob", "--help"}, "deixis avatar: unknown command \"frob\""},
      {{"capture", "frob"}, "deixis capture: unknown command \"frob\""},
  };
  for (const auto& [args, names] : cases) {
    SCOPED_TRACE(args.front() + " … " + args.back());
    Deixis d(args);
    EXPECT_EQ(d.wait(), 2) << d.err();
    EXPECT_NE(d.err().find(names), std::string::npos) << d.err();
    EXPECT_EQ(d.out().find("Subcommands:"), std::string::npos) << d.out();
  }
  Deixis top({"frob"});
  ASSERT_EQ(top.wait(), 2);
  for (const char* command : {"parity", "avatar", "capture", "host", "join", "demo", "xr", "sim",
                              "eval", "deixis --help"}) {
    EXPECT_NE(top.err().find(command), std::string::npos) << command << ": " << top.err();
  }
  // Real commands' help is unchanged: exit 0.
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"--help"}, {"avatar", "--help"}, {"capture", "generate", "--help"}}) {
    Deixis d(args);
    EXPECT_EQ(d.wait(), 0) << args[0] << ": " << d.err();
    EXPECT_NE(d.out().find("Usage:"), std::string::npos) << d.out();
  }
}

TEST(DeixisDemo, AShortDemoWritesItsSummaryVideoAndContactSheet) {
  deixis::testing::ScratchDir dir;
  const auto start = Clock::now();
  // A passphrase from the environment: the demo hands it to its sites in theirs (not on their
  // command lines), so both sessions are sealed.
  std::optional<Deixis> started;
  {
    const ScopedPassphrase env("blue whale");
    started.emplace(std::vector<std::string>{"demo", "--seconds", "6", "--out", dir.path().string(),
                                             "--weights-dir", weights_dir()});
  }
  Deixis& demo = *started;
  ASSERT_EQ(demo.wait(), 0) << demo.err();
  EXPECT_EQ(demo.err().find("warning"), std::string::npos) << demo.err();
  const double wall = std::chrono::duration<double>(Clock::now() - start).count();
  std::printf("demo --seconds 6: %.1f s wall\n", wall);
  EXPECT_NE(demo.out().find("tracking sent / received"), std::string::npos) << demo.out();

  const json summary = read_json(dir.path() / "summary.json");
  EXPECT_EQ(summary["format"], "deixis-demo");
  EXPECT_GT(summary["wall_seconds"].get<double>(), 6.0);
  for (const char* name : {"A", "B"}) {
    SCOPED_TRACE(name);
    const json& s = summary["sites"][name];
    EXPECT_EQ(s["site"], name);
    EXPECT_NEAR(s["ticks"].get<double>(), 180.0, 1.0);
    EXPECT_GT(s["network"]["tracking_received"].get<int>(), 120);
    EXPECT_TRUE(s["network"]["sealed"].get<bool>());
    EXPECT_GT(s["avatar_visible_ticks"].get<int>(), 120);
    EXPECT_GT(s["render_ms"]["count"].get<int>(), 170);
    EXPECT_TRUE(s["render_ms"]["p50"].is_number());
    EXPECT_EQ(s["video"], "views.mp4");
  }
  // A non-empty MP4 (an ISO BMFF "ftyp" box up front) and a PNG contact sheet.
  for (const auto& [file, magic] : {std::pair<const char*, std::string>{"demo.mp4", "ftyp"},
                                    {"contact_sheet.png", "\x89PNG"}}) {
    SCOPED_TRACE(file);
    const fs::path path = dir.path() / file;
    ASSERT_TRUE(fs::exists(path));
    EXPECT_GT(fs::file_size(path), 10'000u);
    std::ifstream in(path, std::ios::binary);
    std::string head(12, '\0');
    in.read(head.data(), 12);
    EXPECT_NE(head.find(magic), std::string::npos);
  }
}

}  // namespace
}  // namespace deixis::app
