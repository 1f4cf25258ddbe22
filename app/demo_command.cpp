// `deixis demo` (docs/demo.md): two real sites on loopback. This process starts itself twice —
// `deixis host` with site A on a port the system picks, then `deixis join` with site B — waits
// for both, and puts their outputs together: demo.mp4 (top: A's user | A's avatar in room B;
// bottom: B's user | B's avatar in room A), contact_sheet.png and summary.json.
//
// `deixis demo --people 3`: a room of three. This process starts `deixis relay` and three
// `deixis join --room` sites (A, B, C), and demo.mp4 has a row per person: their user, then the
// other two rooms, where their avatar stands beside the third person's.

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
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

std::vector<std::string> site_args(const DemoOptions& o, const fs::path& site,
                                   const fs::path& out) {
  std::vector<std::string> args = {"--site",        site.string(),          "--out",  out.string(),
                                   "--weights-dir", o.weights_dir.string(), "--wait", "60"};
  if (o.seconds > 0.0) {
    args.insert(args.end(), {"--seconds", std::to_string(o.seconds)});
  }
  return args;  // the passphrase goes through the environment (pass_passphrase), never argv
}

void run_sites(const DemoOptions& o, const fs::path& self) {
  pass_passphrase(o.passphrase);
  run_host_and_join(self, site_args(o, o.site_a, o.out_dir / "A"),
                    site_args(o, o.site_b, o.out_dir / "B"), kListenTimeout, o.timeout);
}

// A relay and three sites in the room "demo"; the relay ends with the sites.
void run_room_sites(const DemoOptions& o, const fs::path& self) {
  pass_passphrase(o.passphrase);
  ChildProcess relay("the relay", self.string(), {"relay", "--port", "0", "--bind", "127.0.0.1"});
  const std::optional<std::string> port =
      relay.line_starting("port ", ChildProcess::now() + kListenTimeout);
  if (!port) {
    throw Error(relay.poll() ? failure(relay) : "the relay did not start listening");
  }
  const auto site_process = [&](const char* label, const fs::path& site, const char* out) {
    std::vector<std::string> a = {"join", "--connect", "127.0.0.1:" + port->substr(5), "--room",
                                  "demo"};
    const auto rest = site_args(o, site, o.out_dir / out);
    a.insert(a.end(), rest.begin(), rest.end());
    return std::make_unique<ChildProcess>(label, self.string(), a);
  };
  const auto a = site_process("site A", o.site_a, "A");
  const auto b = site_process("site B", o.site_b, "B");
  const auto c = site_process("site C", o.site_c, "C");
  wait_for_all({a.get(), b.get(), c.get()}, o.timeout);
  relay.terminate();
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

// Each site's video is [its user | its room with the other two avatars]; a row per person: their
// user, then the two other rooms (where their avatar stands).
void compose_room_video(const fs::path& out) {
  // Per input: its user (left half) once, its room (right half) twice.
  const std::string filter =
      "[0:v]split=3[a0][a1][a2];[1:v]split=3[b0][b1][b2];[2:v]split=3[c0][c1][c2];"
      "[a0]crop=iw/2:ih:0:0[au];[a1]crop=iw/2:ih:iw/2:0[ar1];[a2]crop=iw/2:ih:iw/2:0[ar2];"
      "[b0]crop=iw/2:ih:0:0[bu];[b1]crop=iw/2:ih:iw/2:0[br1];[b2]crop=iw/2:ih:iw/2:0[br2];"
      "[c0]crop=iw/2:ih:0:0[cu];[c1]crop=iw/2:ih:iw/2:0[cr1];[c2]crop=iw/2:ih:iw/2:0[cr2];"
      "[au][br1][cr1]hstack=inputs=3[rowa];[bu][ar1][cr2]hstack=inputs=3[rowb];"
      "[cu][ar2][br2]hstack=inputs=3[rowc];[rowa][rowb][rowc]vstack=inputs=3,format=yuv420p[v]";
  ffmpeg({"-i", (out / "A/views.mp4").string(), "-i", (out / "B/views.mp4").string(), "-i",
          (out / "C/views.mp4").string(), "-filter_complex", filter, "-map", "[v]", "-shortest",
          "-c:v", "libx264", "-preset", "veryfast", "-crf", "23", (out / "demo.mp4").string()},
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

// Per pair: how each remote person's avatar pointed and looked in each room, against their pose
// copied onto the avatar (copy-paste).
void print_room_summary(const std::vector<std::pair<std::string, json>>& sites, double wall) {
  std::printf(
      "\nDeixis demo: three people in one room through a relay on 127.0.0.1 (wall time "
      "%.1f s)\n",
      wall);
  std::printf("  %-10s %-8s %7s %7s %10s %12s %8s %12s\n", "in room", "person", "frames", "points",
              "HE / VE", "copy HE / VE", "looks", "gaze error");
  for (const auto& [room, session] : sites) {
    for (const json& p : session.value("people", json::array())) {
      std::printf("  %-10s %-8s %7ld %7ld %10s %12s %8ld %12s\n", room.c_str(),
                  p.value("site", "?").c_str(), p.value("frames_played", 0L),
                  p.value("pointing_count", 0L),
                  (figure(p["he_deg"], 1) + " / " + figure(p["ve_deg"], 1)).c_str(),
                  (figure(p["copy_he_deg"], 1) + " / " + figure(p["copy_ve_deg"], 1)).c_str(),
                  p.value("gaze_count", 0L), (figure(p["gaze_deg"], 1) + "°").c_str());
    }
  }
}

int run_room_demo(const DemoOptions& o, double start) {
  std::printf(
      "deixis demo: three sites (A, B, C) in one room through a relay on 127.0.0.1; "
      "outputs in %s\n",
      o.out_dir.string().c_str());
  std::fflush(stdout);
  run_room_sites(o, own_executable());
  std::vector<std::pair<std::string, json>> sites;
  double seconds = 0.0;
  for (const char* s : {"A", "B", "C"}) {
    sites.emplace_back(s, read_json(o.out_dir / s / "session.json"));
    seconds = std::max(seconds, sites.back().second["seconds"].get<double>());
  }
  compose_room_video(o.out_dir);
  contact_sheet(o.out_dir, seconds);
  const double wall = ChildProcess::now() - start;
  json by_site = json::object();
  for (const auto& [name, session] : sites) {
    by_site[name] = session;
  }
  const json summary = {
      {"format", "deixis-demo"}, {"version", 1},        {"people", 3},
      {"wall_seconds", wall},    {"video", "demo.mp4"}, {"contact_sheet", "contact_sheet.png"},
      {"sites", by_site}};
  std::ofstream file(o.out_dir / "summary.json");
  file << summary.dump(2) << '\n';
  if (!file) {
    throw Error((o.out_dir / "summary.json").string() + ": cannot write");
  }
  print_room_summary(sites, wall);
  return 0;
}

}  // namespace

int run_demo(const DemoOptions& o) {
  const double start = ChildProcess::now();
  try {
    std::error_code ec;
    for (const char* sub : {"A", "B", "C"}) {
      if (sub[0] == 'C' && o.people < 3) {
        break;
      }
      fs::create_directories(o.out_dir / sub, ec);
      if (ec) {
        throw Error((o.out_dir / sub).string() + ": cannot create: " + ec.message());
      }
    }
    if (o.people == 3) {
      const int code = run_room_demo(o, start);
      std::printf("\nwrote %s, %s and %s\n", (o.out_dir / "demo.mp4").string().c_str(),
                  (o.out_dir / "contact_sheet.png").string().c_str(),
                  (o.out_dir / "summary.json").string().c_str());
      return code;
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
