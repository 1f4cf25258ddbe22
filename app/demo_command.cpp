// `deixis demo` (docs/demo.md): two real sites on loopback. This process starts itself twice —
// `deixis host` with site A on a port the system picks, then `deixis join` with site B — waits
// for both, and puts their outputs together: demo.mp4 (top: A's user | A's avatar in room B;
// bottom: B's user | B's avatar in room A), contact_sheet.png and summary.json.

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/child_process.h"
#include "app/commands.h"
#include "core/error.h"
#include "site/endpoint.h"

namespace deixis::app {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr double kListenTimeout = 60.0;  // s for the host's setup (weights, avatar, script)
constexpr double kFfmpegTimeout = 120.0;

fs::path own_executable() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) {
    throw Error("cannot find this program's executable (/proc/self/exe): " + ec.message());
  }
  return self;
}

std::vector<std::string> site_args(const DemoOptions& o, const fs::path& site,
                                   const fs::path& out) {
  std::vector<std::string> args = {"--site",        site.string(),          "--out",  out.string(),
                                   "--weights-dir", o.weights_dir.string(), "--wait", "60"};
  if (o.seconds > 0.0) {
    args.insert(args.end(), {"--seconds", std::to_string(o.seconds)});
  }
  return args;  // the passphrase goes through the environment (pass_passphrase), never argv
}

std::string failure(const ChildProcess& child) {
  return child.name() + " failed with exit code " + std::to_string(child.exit_code()) +
         " (its messages are above)";
}

// Waits for both sites; a failure of either ends the other.
void wait_for_sites(ChildProcess& host, ChildProcess& join, double timeout) {
  const double deadline = ChildProcess::now() + timeout;
  while (true) {
    bool all_done = true;
    for (ChildProcess* c : {&host, &join}) {
      const bool done = c->poll();
      if (done && c->exit_code() != 0) {
        host.terminate();
        join.terminate();
        throw Error(failure(*c));
      }
      all_done = all_done && done;
    }
    if (all_done) {
      return;
    }
    if (ChildProcess::now() > deadline) {
      std::string late = host.poll() ? "" : "site A (host) ";
      late += join.poll() ? "" : "site B (join) ";
      host.terminate();
      join.terminate();
      throw Error(late + "did not finish within " + std::to_string(timeout) + " s (--timeout)");
    }
    usleep(20'000);
  }
}

// The sites read the passphrase from DEIXIS_PASSPHRASE, which they inherit: on their command
// lines other users of the machine could read it (ps). Without one, none is inherited either.
void pass_passphrase(const DemoOptions& o) {
  const int failed = o.passphrase.empty()
                         ? unsetenv(site::kPassphraseVariable)
                         : setenv(site::kPassphraseVariable, o.passphrase.c_str(), 1);
  if (failed != 0) {
    throw Error(std::string("cannot set ") + site::kPassphraseVariable + " for the sites");
  }
}

void run_sites(const DemoOptions& o, const fs::path& self) {
  pass_passphrase(o);
  ChildProcess host("site A (host)", self.string(), [&] {
    std::vector<std::string> a = {"host", "--port", "0", "--bind", "127.0.0.1"};
    const auto rest = site_args(o, o.site_a, o.out_dir / "A");
    a.insert(a.end(), rest.begin(), rest.end());
    return a;
  }());
  const std::optional<std::string> port =
      host.line_starting("port ", ChildProcess::now() + kListenTimeout);
  if (!port) {
    throw Error(host.poll() ? failure(host)
                            : "site A (host) did not start listening within " +
                                  std::to_string(kListenTimeout) + " s");
  }
  ChildProcess join("site B (join)", self.string(), [&] {
    std::vector<std::string> a = {"join", "--connect", "127.0.0.1:" + port->substr(5)};
    const auto rest = site_args(o, o.site_b, o.out_dir / "B");
    a.insert(a.end(), rest.begin(), rest.end());
    return a;
  }());
  wait_for_sites(host, join, o.timeout);
}

void ffmpeg(const std::vector<std::string>& args, const std::string& what) {
  std::vector<std::string> all = {"-hide_banner", "-loglevel", "error", "-y"};
  all.insert(all.end(), args.begin(), args.end());
  const int code = run_to_completion("ffmpeg (" + what + ")", "ffmpeg", all, kFfmpegTimeout);
  if (code != 0) {
    throw Error("ffmpeg failed making " + what + " (exit code " + std::to_string(code) + ")");
  }
}

// Each site's video is [its user | the other's avatar]; the demo pairs each user with their own
// avatar in the other room.
void compose_video(const fs::path& out) {
  const std::string filter =
      "[0:v]split=2[a1][a2];[1:v]split=2[b1][b2];"
      "[a1]crop=iw/2:ih:0:0[au];[a2]crop=iw/2:ih:iw/2:0[aa];"
      "[b1]crop=iw/2:ih:0:0[bu];[b2]crop=iw/2:ih:iw/2:0[ba];"
      "[au][ba]hstack[top];[bu][aa]hstack[bottom];[top][bottom]vstack,format=yuv420p[v]";
  ffmpeg({"-i", (out / "A/views.mp4").string(), "-i", (out / "B/views.mp4").string(),
          "-filter_complex", filter, "-map", "[v]", "-shortest", "-c:v", "libx264", "-preset",
          "veryfast", "-crf", "23", (out / "demo.mp4").string()},
         "demo.mp4");
}

void contact_sheet(const fs::path& out, double seconds) {
  // Twelve frames spread over the run, 4 × 3.
  const double rate = 12.0 / std::max(seconds, 1.0);
  ffmpeg({"-i", (out / "demo.mp4").string(), "-vf",
          "fps=" + std::to_string(rate) + ",scale=480:-2,tile=4x3", "-frames:v", "1",
          (out / "contact_sheet.png").string()},
         "contact_sheet.png");
}

json read_json(const fs::path& path) {
  std::ifstream in(path);
  if (!in) {
    throw Error(path.string() + ": missing (the site did not write its report)");
  }
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw Error(path.string() + ": " + e.what());
  }
}

std::string figure(const json& v, int decimals) {
  if (!v.is_number()) {
    return "-";
  }
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, v.get<double>());
  return text;
}

void print_row(const char* label, const std::string& a, const std::string& b) {
  std::printf("  %-44s %-24s %-24s\n", label, a.c_str(), b.c_str());
}

// The summary table: one column per site; a site's avatar figures are about the *other* person.
void print_summary(const json& a, const json& b, double wall) {
  std::printf("\nDeixis demo: two sites over ENet on 127.0.0.1 (wall time %.1f s)\n", wall);
  print_row("", "site A (host)", "site B (join)");
  const auto both = [&](const char* label, const auto& get) { print_row(label, get(a), get(b)); };
  both("ticks (30 Hz) / late", [](const json& s) {
    return std::to_string(s["ticks"].get<long>()) + " / " +
           std::to_string(s["late_ticks"].get<long>());
  });
  both("tracking sent / received", [](const json& s) {
    return std::to_string(s["network"]["tracking_sent"].get<long>()) + " / " +
           std::to_string(s["network"]["tracking_received"].get<long>());
  });
  both("frames lost / packets rejected", [](const json& s) {
    return std::to_string(s["network"]["frames_lost"].get<long>()) + " / " +
           std::to_string(s["network"]["rejected"].get<long>());
  });
  both("tracking frame bytes (mean UDP datagram)", [](const json& s) {
    return std::to_string(s["network"]["bytes_per_frame"].get<long>()) + " (" +
           figure(s["network"]["udp_payload_bytes_per_datagram"], 0) + ")";
  });
  both("translation + IK ms p50 / p99", [](const json& s) {
    return figure(s["translation_ms"]["p50"], 2) + " / " + figure(s["translation_ms"]["p99"], 2);
  });
  both("render ms p50 / p99 (two views)", [](const json& s) {
    return figure(s["render_ms"]["p50"], 1) + " / " + figure(s["render_ms"]["p99"], 1);
  });
  both("other's pointing: completions",
       [](const json& s) { return std::to_string(s["pointing"]["count"].get<long>()); });
  both("  avatar HE / VE (deg)", [](const json& s) {
    return figure(s["pointing"]["avatar_horizontal_deg"], 1) + " / " +
           figure(s["pointing"]["avatar_vertical_deg"], 1);
  });
  both("  copy-paste HE / VE (deg)", [](const json& s) {
    return figure(s["pointing"]["copy_horizontal_deg"], 1) + " / " +
           figure(s["pointing"]["copy_vertical_deg"], 1);
  });
  both("other's touching: completions",
       [](const json& s) { return std::to_string(s["touching"]["count"].get<long>()); });
  both("  avatar / copy-paste (cm from surface)", [](const json& s) {
    return figure(s["touching"]["avatar_touch_cm"], 1) + " / " +
           figure(s["touching"]["copy_touch_cm"], 1);
  });
}

}  // namespace

int run_demo(const DemoOptions& o) {
  const double start = ChildProcess::now();
  try {
    std::error_code ec;
    for (const char* sub : {"A", "B"}) {
      fs::create_directories(o.out_dir / sub, ec);
      if (ec) {
        throw Error((o.out_dir / sub).string() + ": cannot create: " + ec.message());
      }
    }
    std::printf("deixis demo: site A hosts, site B joins on 127.0.0.1; outputs in %s\n",
                o.out_dir.string().c_str());
    std::fflush(stdout);
    run_sites(o, own_executable());
    const json a = read_json(o.out_dir / "A/session.json");
    const json b = read_json(o.out_dir / "B/session.json");
    compose_video(o.out_dir);
    contact_sheet(o.out_dir, std::max(a["seconds"].get<double>(), b["seconds"].get<double>()));
    const double wall = ChildProcess::now() - start;
    const json summary = {{"format", "deixis-demo"},
                          {"version", 1},
                          {"wall_seconds", wall},
                          {"video", "demo.mp4"},
                          {"contact_sheet", "contact_sheet.png"},
                          {"sites", {{"A", a}, {"B", b}}}};
    std::ofstream file(o.out_dir / "summary.json");
    file << summary.dump(2) << '\n';
    if (!file) {
      throw Error((o.out_dir / "summary.json").string() + ": cannot write");
    }
    print_summary(a, b, wall);
    std::printf("\nwrote %s, %s and %s\n", (o.out_dir / "demo.mp4").string().c_str(),
                (o.out_dir / "contact_sheet.png").string().c_str(),
                (o.out_dir / "summary.json").string().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "deixis demo: %s\n", e.what());
    return 1;
  }
}

}  // namespace deixis::app
