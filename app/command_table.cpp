// The flags of every `deixis` subcommand (CLI11, which only this file and main.cpp include): one
// add_<command> per row of main.cpp's table, each binding its flags to the plain option struct
// of commands.h and handing back the runner that calls run_<command>. Defaults, the passphrase
// and the host rules come from app/defaults.h.

#include "app/command_table.h"

#include <CLI/CLI.hpp>
#include <array>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/defaults.h"
#include "core/io/text_rules.h"
#include "site/endpoint.h"
#include "xr/blend_mode.h"

namespace deixis::app {

namespace {

namespace fs = std::filesystem;

// A HOST:PORT option (join's --connect, xr's and sim's --join) into `address` and `port`; `then`
// runs after a valid endpoint was read.
CLI::Option* add_endpoint_option(CLI::App* cmd, const std::string& flag, std::string& address,
                                 std::uint16_t& port, std::function<void()> then,
                                 const std::string& help) {
  return cmd->add_option_function<std::string>(
      flag,
      [flag, &address, &port, then = std::move(then)](const std::string& endpoint) {
        const std::string problem = site::parse_endpoint(endpoint, address, port);
        if (!problem.empty()) {
          throw CLI::ValidationError(flag, endpoint + ": " + problem);
        }
        then();
      },
      help);
}

// --weights-dir, as every command that drives the MoE networks takes it.
void add_weights_dir_flag(CLI::App* cmd, fs::path& weights_dir) {
  cmd->add_option("--weights-dir", weights_dir,
                  "Directory with right/ and left/ MoE weights (default: assets/weights, "
                  "$DEIXIS_REFERENCE_DIR/weights or ../shared/reference/weights)")
      ->check(CLI::ExistingDirectory);
}

// The flags host and join share.
void add_site_flags(CLI::App* cmd, site::SiteRunOptions& o) {
  cmd->add_option("--site", o.site, "Site configuration (JSON, docs/site-config.md)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--seconds", o.seconds,
                  "How long to stream, from when the sites connect (default: the virtual user's "
                  "script, or its BVH recording once)")
      ->check(CLI::Range(0.0, 3600.0));
  cmd->add_option("--wait", o.wait, "Seconds to wait for the other site")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 3600.0));
  cmd->add_option("-o,--out", o.out_dir,
                  "Output directory for session.json and views.mp4 (default: out/<command>)");
  add_weights_dir_flag(cmd, o.weights_dir);
  cmd->add_option("--view-width", o.view_width, "Width of each of the two views (even)")
      ->capture_default_str()
      ->check(CLI::Range(64, 3840));
  cmd->add_option("--view-height", o.view_height, "Height of the views (even)")
      ->capture_default_str()
      ->check(CLI::Range(64, 2160));
  cmd->add_flag_callback(
      "--no-video", [&o] { o.video = false; }, "Do not render (no EGL context, no ffmpeg)");
  cmd->add_option("--avatar", o.avatar,
                  "The avatar this site's user chose (glTF/GLB, VRM or Mixamo bone names; "
                  "docs/avatars.md): checked here first (exit 2 if it does not load), then sent "
                  "once to the sites that lack it; they show this person wearing it")
      ->check(CLI::ExistingFile);
  cmd->add_option("--remote-avatar", o.remote_avatar,
                  "Show every remote person wearing this avatar here, whatever they chose (a "
                  "local override; default: their chosen avatar, else the site's own)")
      ->check(CLI::ExistingFile);
}

// ---- The passphrase and who may reach a host (docs/security.md) ----

// A command's passphrase flags: what they gave, and the --passphrase option, whose presence
// (even with an empty value) decides.
struct PassphraseFlags {
  PassphraseInput input;
  CLI::Option* text_option = nullptr;

  const PassphraseInput& given() {
    input.text_given = text_option->count() > 0;
    return input;
  }
};

// The same passphrase options for every command that takes one (host, join, demo, sim, xr);
// `host`: the command's --host flag, which --open needs; `hosts`: whether the command can host at
// all (--open is offered only then); `open_help`: --open's help when it means more than hosting
// (sim and xr, which can also enter a room).
void add_passphrase_flags(CLI::App* cmd, PassphraseFlags& f, bool hosts,
                          CLI::Option* host = nullptr, const char* open_help = nullptr) {
  f.text_option = cmd->add_option(
      "--passphrase", f.input.text,
      "The session's passphrase (both sites give the same; peers without it are refused and "
      "everything after the handshake is encrypted). On the command line other users of this "
      "machine can read it (ps): prefer DEIXIS_PASSPHRASE, --passphrase-file or "
      "--ask-passphrase. Without any of the three flags, DEIXIS_PASSPHRASE is used if set");
  CLI::Option* file = cmd->add_option("--passphrase-file", f.input.file,
                                      "Read the passphrase from the first line of FILE (keep it "
                                      "private: chmod 600)");
  CLI::Option* ask = cmd->add_flag("--ask-passphrase", f.input.ask,
                                   "Ask for the passphrase on the terminal, not echoed");
  f.text_option->excludes(file)->excludes(ask);
  file->excludes(ask);
  if (hosts) {
    CLI::Option* open = cmd->add_flag(
        "--open", f.input.open,
        open_help != nullptr
            ? open_help
            : "Host without a passphrase although --bind reaches beyond this machine (anything "
              "but 127.x.x.x, e.g. 0.0.0.0): anyone who can reach the port can join and read this "
              "site's motion. Without a passphrase and without --open, such a host exits 2");
    if (host != nullptr) {
      open->needs(host);
    }
  }
}

// A room's name as the relay takes it (docs/relay.md).
CLI::Validator room_name() {
  return CLI::Validator(
      [](std::string& name) -> std::string {
        return !name.empty() && name.size() <= 64 && is_wire_text(name)
                   ? std::string()
                   : "a room name is 1 to 64 bytes of UTF-8 without control characters";
      },
      "NAME");
}

// A live user's site on the network (`deixis xr`, `deixis sim`): --host, or --join HOST:PORT,
// with --port/--bind for a host, or --connect HOST:PORT --room NAME (a room on a relay, as
// `deixis join --room`), the passphrase flags and --wait. `Options` has network, host, address,
// port, room and wait. Returns --host, --join and --connect, for flags that exclude networking.
template <class Options>
std::array<CLI::Option*, 3> add_network_flags(CLI::App* cmd, Options& o, PassphraseFlags& pass,
                                              const std::string& host_help) {
  CLI::Option* host = cmd->add_flag(
      "--host", [&o](std::int64_t) { o.network = o.host = true; }, host_help);
  const auto joins = [&o] {
    o.network = true;
    o.host = false;
  };
  CLI::Option* join =
      add_endpoint_option(cmd, "--join", o.address, o.port, joins, "Join the host at HOST:PORT")
          ->excludes(host);
  CLI::Option* connect = add_endpoint_option(cmd, "--connect", o.address, o.port, joins,
                                             "With --room: the relay (`deixis relay`), HOST:PORT")
                             ->excludes(host)
                             ->excludes(join);
  CLI::Option* room = cmd->add_option("--room", o.room,
                                      "Enter the room NAME on the relay --connect names, as "
                                      "`deixis join --room` does: everyone else in it is an "
                                      "avatar on this site's spots, and a target. Everyone in a "
                                      "room gives the same passphrase; without one the room is "
                                      "open, and readable by the relay's operator")
                          ->check(room_name())
                          ->needs(connect)
                          ->excludes(host)
                          ->excludes(join);
  connect->needs(room);
  cmd->add_option("--port", o.port, "With --host: UDP port (0: any free port)")
      ->capture_default_str()
      ->needs(host);
  cmd->add_option("--bind", o.address,
                  "With --host: address to listen on (beyond 127.x.x.x: needs a passphrase or "
                  "--open)")
      ->capture_default_str()
      ->needs(host);
  // --open: with --host (a host beyond loopback) or --room (an open room through a relay beyond
  // loopback); checked by live_session_ready, as CLI11 cannot say "one of two".
  add_passphrase_flags(
      cmd, pass, true, nullptr,
      "Go ahead without a passphrase where that exposes this site's motion: with --host, a "
      "--bind beyond this machine (anything but 127.x.x.x, e.g. 0.0.0.0), where anyone who can "
      "reach the port can join; with --room, a relay beyond this machine, whose operator and "
      "anyone on the path can read it. Without a passphrase and without --open, such a site "
      "exits 2");
  cmd->add_option("--wait", o.wait, "Seconds to wait for the other site, or to enter the room")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 3600.0));
  return {host, join, connect};
}

// Before a live user's site (sim, xr) starts: the passphrase read, --open only where it means
// something, a host beyond loopback and an open room beyond loopback allowed only with --open
// (site/endpoint.h). False after saying why on stderr: the command exits 2.
template <class Options>
bool live_session_ready(const char* command, PassphraseFlags& pass, Options& o) {
  const PassphraseInput& input = pass.given();
  if (input.open && !(o.network && (o.host || !o.room.empty()))) {
    std::fprintf(stderr, "deixis %s: --open needs --host, or --connect with --room\n", command);
    return false;
  }
  if (!prepare_session(command, input, o.network && o.host, o.address, o.passphrase)) {
    return false;
  }
  return o.room.empty() || may_enter_room(input, o.address, o.passphrase, command);
}

// A command's options with its passphrase flags, kept alive by its runner.
template <class Options>
struct WithPassphrase {
  Options options;
  PassphraseFlags pass;
};

}  // namespace

// `deixis parity`: parity_command.cpp.
void add_parity(CLI::App& program, const Invocation&, std::vector<Runner>& runners) {
  auto parity = std::make_shared<ParityOptions>();
  parity->reference_dir = default_reference_dir();
  CLI::App* cmd = program.add_subcommand(
      "parity",
      "Run the authors' parity fixtures through Deixis' networks and print the largest absolute "
      "error per reference output; exits 1 if one is over tolerance, 2 if a fixture is unreadable");
  cmd->add_option("fixture", parity->fixtures, "Fixture files (safetensors)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--reference-dir", parity->reference_dir,
                  "Directory that the fixtures' checkpoint paths are relative to "
                  "(default: $DEIXIS_REFERENCE_DIR or ../shared/reference)")
      ->check(CLI::ExistingDirectory);
  runners.push_back({cmd, [parity] { return run_parity(*parity); }});
}

// `deixis avatar generate` and `deixis avatar info`: avatar_command.cpp.
void add_avatar(CLI::App& program, const Invocation&, std::vector<Runner>& runners) {
  CLI::App* avatar =
      program.add_subcommand("avatar", "Generate and inspect avatars (skinned glTF humanoids)");
  avatar->require_subcommand(1);

  auto generate = std::make_shared<AvatarGenerateOptions>();
  CLI::App* generate_cmd = avatar->add_subcommand(
      "generate",
      "Write Deixis' default avatar, a parametric skinned humanoid, as binary glTF (.glb); the "
      "same parameters give identical bytes. Exit 2 on bad parameters or an unwritable file");
  generate_cmd
      ->add_option("--height", generate->height,
                   "Height, floor to top of head, in metres (0.5 to 2.5)")
      ->capture_default_str();
  generate_cmd
      ->add_option("--arm-length", generate->arm_length,
                   "Upper-arm joint to index fingertip, in metres (0.30 to 0.60 x height)")
      ->capture_default_str();
  generate_cmd->add_option("-o,--output", generate->output, "Output .glb file")->required();
  runners.push_back({generate_cmd, [generate] { return run_avatar_generate(*generate); }});

  auto info = std::make_shared<AvatarInfoOptions>();
  CLI::App* info_cmd = avatar->add_subcommand(
      "info",
      "Load avatars (.glb or .gltf) as Deixis does and print how their bones were found, their "
      "measurements and mesh sizes; exit 2 if one cannot be loaded");
  info_cmd->add_option("file", info->files, "Avatar files")->required()->check(CLI::ExistingFile);
  runners.push_back({info_cmd, [info] { return run_avatar_info(*info); }});
}

// `deixis capture generate|preview|csv|judge`, the synthetic capture (capture/):
// capture_command.cpp.
void add_capture(CLI::App& program, const Invocation&, std::vector<Runner>& runners) {
  CLI::App* capture = program.add_subcommand(
      "capture",
      "The synthetic capture: a procedural person performing the paper's ten gesture categories "
      "with exact progression labels (datasets, previews, CSV, and the authors' MPNet as judge)");
  capture->require_subcommand(1);

  auto generate = std::make_shared<CaptureGenerateOptions>();
  CLI::App* generate_cmd = capture->add_subcommand(
      "generate",
      "Write the training set (train_right, train_left = mirrored), test sets (test_<subject>) "
      "and validation sets (validation_<subject>) as safetensors into a directory; the same "
      "options give identical files. Progress on stderr, a summary table on stdout");
  generate_cmd->add_option("-o,--out", generate->out_dir, "Output directory")->required();
  generate_cmd->add_option("--seed", generate->seed, "Seed of every sequence")
      ->capture_default_str();
  generate_cmd
      ->add_option("--sets", generate->sets,
                   "Sets to write: train, test, validation (default: all)")
      ->delimiter(',');
  generate_cmd
      ->add_option("--subjects", generate->subjects,
                   "Only these subjects, e.g. 170,161,173 (default: every subject of the sets)")
      ->delimiter(',');
  generate_cmd
      ->add_option("--count-scale", generate->count_scale,
                   "Scale every category's sequence count (e.g. 0.05 for a quick small set)")
      ->capture_default_str();
  generate_cmd->add_flag(
      "!--without-low-targets", generate->low_targets,
      "The training set without its low-target pointing sequences: the capture as it was "
      "before they were added, for comparisons (docs/dataset.md)");
  generate_cmd
      ->add_option("--train-noise", generate->train_noise,
                   "Tracker noise of the training set: none, mocap, headset")
      ->capture_default_str();
  generate_cmd
      ->add_option("--test-noise", generate->test_noise,
                   "Tracker noise of the test and validation sets: none, mocap, headset")
      ->capture_default_str();
  runners.push_back({generate_cmd, [generate] { return run_capture_generate(*generate); }});

  auto preview = std::make_shared<CapturePreviewOptions>();
  preview->reference_dir = default_reference_dir();
  CLI::App* preview_cmd = capture->add_subcommand(
      "preview",
      "Perform one sequence (as `generate` records it) and draw it as a PNG: progression labels "
      "over time, and the motion from above and from the side with targets");
  preview_cmd->add_option("--subject", preview->subject, "Subject name")->capture_default_str();
  preview_cmd
      ->add_option("--category", preview->category,
                   "Category, e.g. pointing-single, touching-transition")
      ->capture_default_str();
  preview_cmd->add_option("--index", preview->index, "Sequence index")->capture_default_str();
  preview_cmd->add_option("--seed", preview->seed, "Seed (as for generate)")->capture_default_str();
  preview_cmd->add_option("--set", preview->set, "train, test or validation")
      ->capture_default_str();
  preview_cmd->add_flag("--with-mpnet", preview->with_mpnet,
                        "Overlay the authors' MPNet MoE predictions");
  preview_cmd->add_option(
      "--noise", preview->noise,
      "Tracker noise for the MPNet overlay (default: the set's, mocap or headset)");
  preview_cmd->add_option("--reference-dir", preview->reference_dir,
                          "The authors' reference data (default: $DEIXIS_REFERENCE_DIR or "
                          "../shared/reference)");
  preview_cmd->add_option("-o,--output", preview->output, "Output .png")->required();
  runners.push_back({preview_cmd, [preview] { return run_capture_preview(*preview); }});

  auto csv = std::make_shared<CaptureCsvOptions>();
  CLI::App* csv_cmd = capture->add_subcommand(
      "csv", "Write a capture dataset as CSV, one row per frame (stdout unless --output)");
  csv_cmd->add_option("dataset", csv->dataset, "Dataset (.safetensors)")
      ->required()
      ->check(CLI::ExistingFile);
  csv_cmd->add_option("--sequence", csv->sequence, "Only this sequence (index in the file)");
  csv_cmd->add_option("-o,--output", csv->output, "Output .csv");
  runners.push_back({csv_cmd, [csv] { return run_capture_csv(*csv); }});

  auto bvh = std::make_shared<CaptureBvhOptions>();
  CLI::App* bvh_cmd = capture->add_subcommand(
      "bvh",
      "Derive the tracking a site would send (head H, gaze, wrists, index tips) from a BVH motion "
      "recording and write it as CSV with the columns of `capture csv` that exist for it "
      "(docs/bvh.md); stdout unless --csv");
  bvh_cmd->add_option("file", bvh->file, "Recording (.bvh)")->required()->check(CLI::ExistingFile);
  bvh_cmd->add_option("--csv", bvh->csv, "Output .csv");
  bvh_cmd
      ->add_option("--unit", bvh->unit,
                   "Length unit of the file: m, cm, mm, inch, cmu (the CMU conversion's 1/0.45 "
                   "inch) or auto (from the rest pose's height)")
      ->capture_default_str()
      ->check(CLI::IsMember({"m", "cm", "mm", "inch", "cmu", "auto"}));
  bvh_cmd->add_option("--from", bvh->from, "First frame")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  bvh_cmd->add_option("--to", bvh->to, "One past the last frame (default: the end)");
  bvh_cmd
      ->add_option("--rate", bvh->rate,
                   "Resample the tracking at this rate in Hz (e.g. 30, the networks' and the "
                   "wire's), interpolated as a site plays a recording; row k is sample k from "
                   "--from's time (default: the file's own frames)")
      ->check(CLI::Range(1.0, 1000.0));
  runners.push_back({bvh_cmd, [bvh] { return run_capture_bvh(*bvh); }});

  auto judge = std::make_shared<CaptureJudgeOptions>();
  judge->reference_dir = default_reference_dir();
  CLI::App* judge_cmd = capture->add_subcommand(
      "judge",
      "Run the authors' MPNet MoE (right, and left for left-handed subjects) on the test sets "
      "like their test_MPNet.py and print the MPE per category and subject; exit 1 if above "
      "--max-mpe");
  judge_cmd
      ->add_option("dataset_dir", judge->dataset_dir, "Directory with test_<subject>.safetensors")
      ->required()
      ->check(CLI::ExistingDirectory);
  judge_cmd->add_option("--subjects", judge->subjects, "Only these test subjects")->delimiter(',');
  judge_cmd->add_option("--max-mpe", judge->max_mpe,
                        "Fail (exit 1) when the overall MPE is above this");
  judge_cmd
      ->add_option("--reference-dir", judge->reference_dir,
                   "The authors' reference data (default: $DEIXIS_REFERENCE_DIR or "
                   "../shared/reference)")
      ->check(CLI::ExistingDirectory);
  runners.push_back({judge_cmd, [judge] { return run_capture_judge(*judge); }});
}

// `deixis host` (docs/demo.md): site_command.cpp.
void add_host(CLI::App& program, const Invocation&, std::vector<Runner>& runners) {
  auto host = std::make_shared<WithPassphrase<site::SiteRunOptions>>();
  site::SiteRunOptions& o = host->options;
  o.weights_dir = default_weights_dir();
  o.out_dir = "out/host";
  CLI::App* cmd = program.add_subcommand(
      "host",
      "Run a site that others join: its virtual user's tracking goes out, the other site's "
      "person comes in as a translated avatar in this room, rendered headlessly. Listens on "
      "127.0.0.1 unless --bind says otherwise; beyond loopback it needs a passphrase or --open. "
      "Prints \"port N\" once listening; exit 1 if the session fails, 2 for bad flags or files "
      "(or a host beyond loopback with neither)");
  add_site_flags(cmd, o);
  cmd->add_option("--port", o.port, "UDP port to listen on (0: any free port)")
      ->capture_default_str();
  cmd->add_option("--bind", o.address,
                  "Address to listen on (beyond 127.x.x.x, e.g. 0.0.0.0: needs a passphrase or "
                  "--open)")
      ->capture_default_str();
  add_passphrase_flags(cmd, host->pass, true);
  runners.push_back(
      {cmd, [host] {
         site::SiteRunOptions& r = host->options;
         if (!prepare_session("host", host->pass.given(), true, r.address, r.passphrase)) {
           return 2;
         }
         return run_site(r);
       }});
}

// `deixis join` (docs/demo.md): site_command.cpp.
void add_join(CLI::App& program, const Invocation&, std::vector<Runner>& runners) {
  auto join = std::make_shared<WithPassphrase<site::SiteRunOptions>>();
  site::SiteRunOptions& o = join->options;
  o.host = false;
  o.weights_dir = default_weights_dir();
  o.out_dir = "out/join";
  CLI::App* cmd = program.add_subcommand(
      "join",
      "Run a site that joins a host (as host does otherwise); exit 1 if the host refuses or "
      "cannot be reached, 2 for bad flags or files");
  add_site_flags(cmd, o);
  add_passphrase_flags(cmd, join->pass, false);
  add_endpoint_option(
      cmd, "--connect", o.address, o.port, [] {},
      "The host, HOST:PORT; with --room, the relay (`deixis relay`)")
      ->required();
  CLI::Option* room =
      cmd->add_option("--room", o.room,
                      "Enter the room NAME on the relay --connect names, with everyone else who "
                      "enters it (docs/relay.md): each remote person is an avatar on one of the "
                      "site's spots. Everyone in a room gives the same passphrase; without one "
                      "the room is open, and readable by the relay's operator")
          ->check(CLI::Validator(
              [](std::string& name) -> std::string {
                return !name.empty() && name.size() <= 64 && is_wire_text(name)
                           ? std::string()
                           : "a room name is 1 to 64 bytes of UTF-8 without control characters";
              },
              "NAME"));
  cmd->add_flag("--open", join->pass.input.open,
                "Enter an open room (no passphrase) through a relay beyond this machine: its "
                "operator and anyone on the path can read this site's motion. Without a "
                "passphrase and without --open, such a join exits 2")
      ->needs(room);
  cmd->add_option("--drop-tracking", o.drop_tracking,
                  "Rehearse a bad link: leave this share (0 to 0.9) of the user's frames unsent")
      ->check(CLI::Range(0.0, 0.9))
      ->needs(room);
  runners.push_back(
      {cmd, [join] {
         site::SiteRunOptions& r = join->options;
         if (!prepare_session("join", join->pass.given(), false, r.address, r.passphrase)) {
           return 2;
         }
         if (!r.room.empty() && !may_enter_room(join->pass.given(), r.address, r.passphrase)) {
           return 2;
         }
         return run_site(r);
       }});
}

// `deixis relay` (docs/relay.md): relay_command.cpp.
void add_relay(CLI::App& program, const Invocation&, std::vector<Runner>& runners) {
  auto o = std::make_shared<RelayOptions>();
  CLI::App* cmd = program.add_subcommand(
      "relay",
      "A room server for meetings of several people: sites join a named room on it (join/sim/xr "
      "--connect HOST:PORT --room NAME) and it forwards their tracking, hellos and target maps "
      "to the others in the room and tells them who joined and left. It holds no passphrase and "
      "sees rooms only by a hash of their names. Rooms with a passphrase are sealed end to end "
      "(the relay sees sizes and timing only); rooms WITHOUT a passphrase are readable by "
      "whoever runs the relay. Prints \"port N\" once listening; runs until SIGINT or SIGTERM, "
      "then exits 0; exit 2 for bad flags or an address it cannot bind");
  cmd->add_option("--port", o->port, "UDP port to listen on (0: any free port)")
      ->capture_default_str();
  cmd->add_option("--bind", o->bind,
                  "Address to listen on (e.g. 0.0.0.0 to serve other machines: the relay holds "
                  "no secrets, but open rooms are readable by its operator)")
      ->capture_default_str();
  cmd->add_option("--max-people", o->max_people,
                  "People per room; one more is refused with \"room full\"")
      ->capture_default_str()
      ->check(CLI::Range(2, 64));
  cmd->add_option("--max-rooms", o->max_rooms, "Rooms at once; more are refused as \"relay full\"")
      ->capture_default_str()
      ->check(CLI::Range(1, 1024));
  runners.push_back({cmd, [o] { return run_relay(*o); }});
}

// `deixis demo` (docs/demo.md): demo_command.cpp.
void add_demo(CLI::App& program, const Invocation&, std::vector<Runner>& runners) {
  auto demo = std::make_shared<WithPassphrase<DemoOptions>>();
  DemoOptions& o = demo->options;
  o.weights_dir = default_weights_dir();
  o.site_a = demo_site("a.json");
  o.site_b = demo_site("b.json");
  o.site_c = demo_site("c.json");
  CLI::App* cmd = program.add_subcommand(
      "demo",
      "Two sites for real: starts `deixis host` (site A) and `deixis join` (site B) as two "
      "processes on loopback, then writes demo.mp4 (each user beside their avatar in the other "
      "room), contact_sheet.png and summary.json, and prints the summary");
  cmd->add_option("-o,--out", o.out_dir, "Output directory")->capture_default_str();
  cmd->add_option("--seconds", o.seconds, "Seconds to stream (default: the scripts')")
      ->check(CLI::Range(1.0, 600.0));
  cmd->add_option("--site-a", o.site_a, "Site A (the host)")->check(CLI::ExistingFile);
  cmd->add_option("--site-b", o.site_b, "Site B (joins A)")->check(CLI::ExistingFile);
  cmd->add_option("--site-c", o.site_c, "Site C (with --people 3)")->check(CLI::ExistingFile);
  cmd->add_option("--people", o.people,
                  "2: site A hosts and B joins; 3: `deixis relay` and sites A, B and C join one "
                  "room, and demo.mp4 has a row per person (their user, then their avatar in the "
                  "two other rooms)")
      ->capture_default_str()
      ->check(CLI::Range(2, 3));
  cmd->add_option("--weights-dir", o.weights_dir, "As for host and join")
      ->check(CLI::ExistingDirectory);
  add_passphrase_flags(cmd, demo->pass, false);
  cmd->add_option("--timeout", o.timeout, "Seconds before a site process is given up on")
      ->capture_default_str()
      ->check(CLI::Range(5.0, 3600.0));
  runners.push_back({cmd, [demo] {
                       DemoOptions& r = demo->options;
                       if (!prepare_session("demo", demo->pass.given(), false, {}, r.passphrase)) {
                         return 2;
                       }
                       return run_demo(r);
                     }});
}

// `deixis xr` (docs/xr.md): xr_command.cpp.
void add_xr(CLI::App& program, const Invocation&, std::vector<Runner>& runners) {
  auto xr = std::make_shared<WithPassphrase<XrRunOptions>>();
  XrRunOptions& o = xr->options;
  o.weights_dir = default_weights_dir();
  o.site = demo_site("a.json");
  o.remote_site = demo_site("b.json");
  CLI::App* cmd = program.add_subcommand(
      "xr",
      "The headset user's side through OpenXR (the runtime the loader finds, or XR_RUNTIME_JSON): "
      "both eyes see this site's room and the remote person's avatar. With --host or --join the "
      "site meets another (deixis host/join/xr); with --connect and --room it enters a room of "
      "several people on a relay (deixis relay): the headset user, calibrated standing upright "
      "at the start (and again on the menu button of the hand that does not point), is tracked "
      "out with the targets they look and point at (objects and "
      "people), and every other person comes in as a translated avatar. Without, the remote "
      "person is "
      "--remote-site's scripted virtual user, performed locally. Prints the runtime, then "
      "frames, tracking and network counts; exit 1 if OpenXR or the session fails, 2 for bad "
      "flags or files");
  cmd->add_option("--site", o.site, "This site (the headset user's room)")
      ->capture_default_str()
      ->check(CLI::ExistingFile);
  cmd->add_option("--remote-site", o.remote_site,
                  "Without --host/--join: the other site, whose virtual_user plays the remote "
                  "person")
      ->capture_default_str()
      ->check(CLI::ExistingFile);
  cmd->add_option("--seconds", o.seconds,
                  "Ask the runtime to end the session after this much display time (default: "
                  "until the runtime ends it)")
      ->check(CLI::Range(0.0, 3600.0));
  add_weights_dir_flag(cmd, o.weights_dir);
  cmd->add_flag("--headless", o.headless,
                "XR_MND_headless: a session without graphics (nothing is rendered)");
  add_network_flags(cmd, o, xr->pass,
                    "Host a session others join (prints \"port N\" once the user is calibrated)");
  cmd->add_option("--hand", o.hand, "The headset user's pointing hand")
      ->capture_default_str()
      ->check(CLI::IsMember({"right", "left"}));
  cmd->add_option("--height", o.height,
                  "The headset user's stature in m (default: from the eye height when the "
                  "session starts)")
      ->check(CLI::Range(1.0, 2.3));
  cmd->add_option("--avatar", o.avatar,
                  "The avatar the headset user chose (glTF/GLB, VRM or Mixamo bone names; "
                  "docs/avatars.md): sent once to the sites met, which show the user wearing it; "
                  "exit 2 if it does not load")
      ->check(CLI::ExistingFile);
  cmd->add_option("--remote-avatar", o.remote_avatar,
                  "Show every remote person wearing this avatar, whatever they chose (a local "
                  "override; default: their chosen avatar, else the site's own)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--blend", o.blend,
                  "Environment blend mode: auto prefers alpha (passthrough), then additive "
                  "(see-through), then opaque, among those the headset offers. In alpha and "
                  "additive only the remote people's avatars are drawn, over the real room; "
                  "in opaque, this site's virtual room too. Exit 1 if the headset lacks the "
                  "mode asked for")
      ->capture_default_str()
      ->check(CLI::IsMember(
          std::vector<std::string>(xr::kBlendChoiceNames.begin(), xr::kBlendChoiceNames.end())));
  cmd->add_flag("--no-panel", o.no_panel,
                "Hide the presence panel (shown head-locked below the line of sight while "
                "networked: each remote person's link, round trip, jitter-buffer delay and "
                "frames dropped in the last 5 s)");
  cmd->add_flag("--setup", o.setup,
                "Set up the room from inside the headset instead of meeting anyone: put each "
                "object of --site's target map on the real object it stands for (touch it, or "
                "point at it from two places), move and resize it, recalibrate; the map is saved "
                "after every change (docs/xr.md \"Setting up the room\")");
  cmd->add_option("--save", o.save,
                  "With --setup: where the target map goes (default: the site's target map "
                  "file, the previous one kept as FILE.bak)");
  runners.push_back({cmd, [xr] {
                       XrRunOptions& r = xr->options;
                       if (!live_session_ready("xr", xr->pass, r)) {
                         return 2;
                       }
                       if (r.setup && r.network) {
                         std::fprintf(stderr,
                                      "deixis xr: --setup is a session of its own: no --host, "
                                      "--join or --connect\n");
                         return 2;
                       }
                       if (!r.setup && !r.save.empty()) {
                         std::fprintf(stderr, "deixis xr: --save goes with --setup\n");
                         return 2;
                       }
                       return run_xr(r);
                     }});
}

// `deixis sim` (docs/sim.md): sim/sim_run.cpp.
void add_sim(CLI::App& program, const Invocation&, std::vector<Runner>& runners) {
  auto sim = std::make_shared<WithPassphrase<sim::SimOptions>>();
  sim::SimOptions& o = sim->options;
  o.weights_dir = default_weights_dir();
  o.site_a = demo_site("a.json");
  o.site_b = demo_site("b.json");
  CLI::App* cmd = program.add_subcommand(
      "sim",
      "The desktop simulator: a window with the local room (site A) and its virtual user, "
      "driven by mouse and keys (right-drag looks, click points, shift-click touches, E "
      "explains, R rests, P looks at the other person) or by the site's script, and the remote "
      "room (site B) with the avatar translated from the user's tracking; drag B's objects and "
      "the avatar adapts. Both sites in this process. With --host/--join the user meets another "
      "site; with --connect and --room, everyone in a room on a relay. Exit 0 when closed or "
      "done, 1 if the window, OpenGL or the session fails, 2 for bad flags or files");
  cmd->add_option("--site-a", o.site_a, "The user's site (its room and subject)")
      ->capture_default_str()
      ->check(CLI::ExistingFile);
  cmd->add_option("--site-b", o.site_b, "The remote site, where the avatar stands")
      ->capture_default_str()
      ->check(CLI::ExistingFile);
  add_weights_dir_flag(cmd, o.weights_dir);
  cmd->add_option("--avatar", o.avatar,
                  "The avatar the user chose (glTF/GLB, VRM or Mixamo bone names; "
                  "docs/avatars.md): their avatar in B wears it, and a session sends it once to "
                  "the sites met, which show the user wearing it (default: site B's, nothing "
                  "sent); exit 2 if it does not load")
      ->check(CLI::ExistingFile);
  cmd->add_option("--remote-avatar", o.remote_avatar,
                  "Show every other person in A wearing this avatar, whatever they chose (a "
                  "local override; default: their chosen avatar, else site A's)")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--script", o.script,
                "The user performs site A's virtual_user script (hands-free)");
  cmd->add_option("--input", o.input,
                  "Scripted mouse, key and text events (JSON, docs/sim.md); one tick per frame "
                  "until a session starts from the panel")
      ->check(CLI::ExistingFile);
  CLI::Option* fixed_step = cmd->add_flag(
      "--fixed-step", o.fixed_step,
      "Every frame advances the simulator by one 30 Hz tick (reproducible runs; not with a "
      "network, whose sites follow the wall clock)");
  cmd->add_option("--frames", o.frames, "Quit after this many frames")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{100'000'000}));
  cmd->add_option("--seconds", o.seconds, "Quit after this many seconds of simulator time")
      ->check(CLI::Range(0.001, 86400.0));
  const auto existing_parent = [](const std::string& file) -> std::string {
    const fs::path parent = fs::path(file).parent_path();
    if (!parent.empty() && !fs::is_directory(parent)) {
      return "directory does not exist: " + parent.string();
    }
    return {};
  };
  cmd->add_option("--screenshot", o.screenshot, "Save the last frame's window as a PNG")
      ->check(existing_parent);
  cmd->add_option("--report", o.report,
                  "Write a JSON report at the end (B's objects, the avatar's eye and fingertip, "
                  "timings)")
      ->check(existing_parent);
  cmd->add_option("--width", o.width, "Window width")
      ->capture_default_str()
      ->check(CLI::Range(320, 7680));
  cmd->add_option("--height", o.height, "Window height")
      ->capture_default_str()
      ->check(CLI::Range(240, 4320));
  for (CLI::Option* network : add_network_flags(
           cmd, o, sim->pass, "Be site A of a session others join (prints \"port N\" at once)")) {
    fixed_step->excludes(network);
  }
  runners.push_back({cmd, [sim] {
                       sim::SimOptions& r = sim->options;
                       if (!live_session_ready("sim", sim->pass, r)) {
                         return 2;
                       }
                       return sim::run_sim(r);
                     }});
}

// `deixis eval` (docs/eval.md): eval_command.cpp.
void add_eval(CLI::App& program, const Invocation& invocation, std::vector<Runner>& runners) {
  auto eval = std::make_shared<EvalOptions>();
  eval->data_dir = default_eval_data_dir();
  eval->reference_weights = authors_weights_dir();
  eval->project_weights = project_weights_dir();
  eval->program = invocation.argc > 0 ? invocation.argv[0] : "deixis";
  for (int i = 0; i < invocation.argc; ++i) {
    eval->command_line += (i ? " " : "") + std::string(i ? invocation.argv[i] : "deixis");
  }
  CLI::App* cmd = program.add_subcommand(
      "eval",
      "The paper's Tables I-IV and Fig. 5 on the held-out test subjects: MPE and SS (MPNet), "
      "DIP, DR and FMD (the chained networks), robustness to missed tracking, jitter and noise; "
      "every architecture, the copy-paste baseline. With --bvh: the translator on recordings of "
      "real motion, a section of its own. Writes tables.md, results.json and fig5.png; progress "
      "on stderr; exit 2 for bad flags or files");
  // As CLI::ExistingDirectory (same "DIR" in the help), but a missing directory's message says
  // how to make the test sets.
  const CLI::Validator data_dir(
      [exe = eval->program](std::string& dir) -> std::string {
        return fs::is_directory(dir) ? std::string() : eval_data_problem(dir, exe);
      },
      "DIR");
  cmd->add_option("--data", eval->data_dir, "Directory with test_<subject>.safetensors")
      ->capture_default_str()
      ->check(data_dir)
      ->each([eval](const std::string&) { eval->data_given = true; });
  cmd->add_option(
      "--weights", eval->weights,
      "A weight set LABEL=DIR (DIR holds right/ and left/ with the authors' file names); "
      "repeatable. Default: authors=$DEIXIS_REFERENCE_DIR/weights or ../shared/reference/weights, "
      "plus deixis=assets/weights when present");
  cmd->add_option("--fmd-encoder", eval->encoder_dir,
                  "Directory with right/ and left/AutoEncoder.safetensors (deixis-train "
                  "autoencoder); default: looked for in the weight sets, else FMD is n/a")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("-o,--out", eval->out_dir, "Output directory")->capture_default_str();
  cmd->add_option("--subjects", eval->subjects, "Only these test subjects, e.g. 161,173")
      ->delimiter(',');
  cmd->add_option("--threads", eval->threads,
                  "Units of work (a subject's rows of one weight set) run at a time; 0: one "
                  "per core. The tables are the same for any count")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  cmd->add_flag("--quick", eval->quick,
                "A tiny sample (2 sequences per category and subject): seconds, for CI");
  cmd->add_option("--bvh", eval->bvh,
                  "BVH recordings of real motion (several after one --bvh, or repeated): the "
                  "translator of each weight set over each, in a room of targets around the "
                  "person, in a section 'Real motion (BVH)' of its own (docs/eval.md). Alone it "
                  "needs no test sets; with --data the synthetic tables run too")
      ->check(CLI::ExistingFile)
      ->type_name("FILE");
  auto live = std::make_shared<LiveRoomsOptions>();
  live->weights_dir = default_weights_dir();
  live->avatar = demo_site("a.json").parent_path().parent_path() / "avatars/default.glb";
  live->command_line = eval->command_line;
  CLI::Option* live_rooms =
      cmd->add_option("--live-rooms", live->pairs,
                      "Instead of the tables: N room pairs laid out at random under the rules of "
                      "docs/live-rooms.md, each run as deixis host + join on loopback "
                      "with held-out subjects (--subjects to choose); the completions both sites "
                      "observed, pooled into live_rooms.md, .json and .png under --out")
          ->check(CLI::Range(1, 1000));
  cmd->add_option("--seed", live->seed, "With --live-rooms: the seed the rooms are laid out from")
      ->capture_default_str()
      ->needs(live_rooms);
  cmd->add_option("--rules", live->rules,
                  "With --live-rooms: a JSON file of room rules to lay the pairs out by instead of "
                  "the defaults (docs/live-rooms.md, 'Other rules'); any field left out keeps its "
                  "default")
      ->check(CLI::ExistingFile)
      ->needs(live_rooms);
  cmd->add_option("--weights-dir", live->weights_dir,
                  "With --live-rooms: the weight set both sites run (right/ and left/ with the "
                  "authors' file names, as host and join take it), e.g. a training run's "
                  "out/train/weights")
      ->capture_default_str()
      ->check(CLI::ExistingDirectory)
      ->needs(live_rooms);
  cmd->add_option("--pair-timeout", live->timeout,
                  "With --live-rooms: seconds a pair's two sites may take")
      ->capture_default_str()
      ->check(CLI::Range(10.0, 3600.0))
      ->needs(live_rooms);
  runners.push_back({cmd, [eval, live] {
                       if (live->pairs > 0) {
                         live->subjects = eval->subjects;
                         live->out_dir = eval->out_dir;
                         return run_eval_live_rooms(*live);
                       }
                       return run_eval(*eval);
                     }});
}

}  // namespace deixis::app
