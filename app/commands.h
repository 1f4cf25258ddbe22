#pragma once
// The `deixis` subcommands. main.cpp walks the command table whose flags command_table.cpp
// defines (CLI11 stays in those two files); each command's work lives in its own file, takes the
// plain option struct below and returns the process exit code.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "sim/sim_options.h"
#include "site/scripted_site.h"

namespace deixis::app {

struct ParityOptions {
  std::vector<std::filesystem::path> fixtures;
  std::filesystem::path reference_dir;
};
int run_parity(const ParityOptions& options);

// `deixis avatar generate`: writes the default avatar (avatar/default_avatar.h) as .glb.
struct AvatarGenerateOptions {
  float height = 1.70f;      // m
  float arm_length = 0.74f;  // m
  std::filesystem::path output;
};
int run_avatar_generate(const AvatarGenerateOptions& options);

// `deixis avatar info`: loads avatars as Deixis does and prints their bones and measurements.
struct AvatarInfoOptions {
  std::vector<std::filesystem::path> files;
};
int run_avatar_info(const AvatarInfoOptions& options);

// `deixis capture …`: the synthetic capture (capture/, docs/conventions.md#synthetic-capture).
struct CaptureGenerateOptions {
  std::filesystem::path out_dir;
  std::uint64_t seed = 1;
  std::vector<std::string> sets;      // train, test, validation; empty: all
  std::vector<std::string> subjects;  // empty: every subject of the chosen sets
  double count_scale = 1.0;
  bool low_targets = true;
  std::string train_noise = "mocap";
  std::string test_noise = "headset";
};
int run_capture_generate(const CaptureGenerateOptions& options);

struct CapturePreviewOptions {
  std::string subject = "170";
  std::string category = "pointing-single";
  int index = 0;
  std::uint64_t seed = 1;
  std::string set = "train";
  std::string noise;  // empty: the set's default
  bool with_mpnet = false;
  std::filesystem::path reference_dir;
  std::filesystem::path output;
};
int run_capture_preview(const CapturePreviewOptions& options);

struct CaptureCsvOptions {
  std::filesystem::path dataset;
  long sequence = -1;            // -1: all
  std::filesystem::path output;  // empty: standard output
};
int run_capture_csv(const CaptureCsvOptions& options);

// `deixis capture bvh`: the tracking a BVH recording gives (mocap/, docs/bvh.md) as CSV.
struct CaptureBvhOptions {
  std::filesystem::path file;
  std::filesystem::path csv;  // empty: standard output
  std::string unit = "auto";  // m, cm, mm, inch, cmu, auto
  long from = 0;              // first frame
  long to = -1;               // one past the last frame; -1: the end
  double rate = 0.0;          // Hz to resample at (the player's interpolation); 0: the file's
};
int run_capture_bvh(const CaptureBvhOptions& options);

struct CaptureJudgeOptions {
  std::filesystem::path dataset_dir;
  std::filesystem::path reference_dir;
  std::vector<std::string> subjects;
  double max_mpe = -1;  // exit 1 when the overall MPE is above it; < 0: report only
};
int run_capture_judge(const CaptureJudgeOptions& options);

// Every command that hosts binds 127.0.0.1 unless --bind says otherwise; beyond loopback it needs
// a passphrase or --open (site/endpoint.h, docs/security.md). `passphrase` fields hold
// the passphrase as app/defaults.h read it: --passphrase, --passphrase-file, --ask-passphrase or
// DEIXIS_PASSPHRASE.

// `deixis host` and `deixis join` (site::SiteRunOptions: site/scripted_site.h).
int run_site(const site::SiteRunOptions& options);

// `deixis demo`: a host (site A) and a joiner (site B) as two real processes on loopback, then
// the side-by-side video, a contact sheet and summary.json in `out_dir`.
struct DemoOptions {
  std::filesystem::path out_dir = "out/demo";
  int people = 2;  // 2: host and join; 3: a relay and three sites in one room
  std::filesystem::path site_a;
  std::filesystem::path site_b;
  std::filesystem::path site_c;  // with people = 3
  std::filesystem::path weights_dir;
  double seconds = 0.0;  // 0: as long as the longer script
  double timeout = 120.0;
  std::string passphrase;
};
int run_demo(const DemoOptions& options);

// `deixis relay` (docs/relay.md): a room server. Prints "port N" once listening; runs until
// SIGINT or SIGTERM, then exits 0; 2 when the address cannot be bound.
struct RelayOptions {
  std::string bind = "127.0.0.1";
  std::uint16_t port = 7351;
  std::size_t max_people = 8;
  std::size_t max_rooms = 128;
};
int run_relay(const RelayOptions& options);

// `deixis eval`: the paper's Tables I–IV and Fig. 5 on the held-out subjects (docs/eval.md).
// Exit 0 done, 2 bad flags or files (including training-subject data).
struct EvalOptions {
  std::filesystem::path data_dir;
  std::vector<std::string> weights;         // "label=DIR"; empty: the defaults
  std::filesystem::path reference_weights;  // the authors' (default rows)
  std::filesystem::path project_weights;    // assets/weights (a default row when present)
  std::filesystem::path encoder_dir;
  std::filesystem::path out_dir = "out/eval";
  std::vector<std::string> subjects;
  bool quick = false;
  int threads = 0;  // units of work at a time; 0: one per core
  std::string command_line;
  std::string program = "deixis";  // as started (argv[0]), in the command a message suggests
  // Recordings of real motion (--bvh): measured in a section of their own; without --data given
  // as well, nothing else runs, so no synthetic test set is needed.
  std::vector<std::filesystem::path> bvh;
  bool data_given = false;  // --data was on the command line
};
int run_eval(const EvalOptions& options);

// `deixis eval --live-rooms N` (docs/live-rooms.md): N room pairs generated under the
// stated rules (eval/room_pairs.h) from `seed`, each run as `deixis host` + `deixis join` on
// loopback (this program started twice), their observers' completions pooled into
// live_rooms.md, live_rooms.json and live_rooms.png under `out_dir` (each pair's sites and
// session.json under live_rooms/pair-NNN/). Exit 0 with the report, 1 when a pair's sites fail,
// 2 for bad flags.
struct LiveRoomsOptions {
  int pairs = 0;
  std::uint64_t seed = 1;
  std::vector<std::string> subjects;  // who performs; empty: every held-out test subject
  std::filesystem::path weights_dir;
  std::filesystem::path avatar;  // what remote people wear in every room
  std::filesystem::path out_dir = "out/eval";
  double timeout = 120.0;       // s per pair
  std::filesystem::path rules;  // room rules (eval/room_rules_file.h); empty: the defaults
  std::string command_line;
};
int run_eval_live_rooms(const LiveRoomsOptions& options);

// Why `dir` cannot be `deixis eval`'s data (missing, not a directory, no
// test_<subject>.safetensors in it), with the command that makes the test sets (`program`
// capture generate --sets test -o DIR); empty when it can.
std::string eval_data_problem(const std::filesystem::path& dir, const std::string& program);

// `deixis xr`: the headset user's side through OpenXR (docs/xr.md). With `network` the site
// hosts or joins another (`deixis host`/`join`/`xr`): the headset user's tracking goes out with
// targets selected from it (gesture/target_selection.h) and a calibration taken from the first
// tracked frame (gesture/upright_calibration.h); the other site's person comes in as a
// translated avatar. Without, the remote person is `remote_site`'s scripted virtual user,
// performed locally. Exit 0 after the session ends, 1 when OpenXR or the session fails (refused,
// nobody came, lost), 2 for bad files.
struct XrRunOptions {
  std::filesystem::path site;
  std::filesystem::path remote_site;
  double seconds = 0.0;  // 0: until the runtime ends the session
  std::filesystem::path weights_dir;
  bool headless = false;  // XR_MND_headless: no rendering (tests, runtimes without GL)
  bool network = false;   // host or join instead of the local remote person
  bool host = true;
  std::string address = "127.0.0.1";  // host: where to listen (--bind); join: the host or relay
  std::uint16_t port = 7350;          // host: 0 picks a free one (printed as "port N")
  std::string room;  // a room on the relay at address:port (--connect --room); empty: direct
  std::string passphrase;
  double wait = 30.0;
  std::string hand = "right";           // the headset user's deictic hand
  float height = 0.0f;                  // m; 0: from the eye height at calibration
  std::filesystem::path avatar;         // the user's chosen avatar, offered to the people met
  std::filesystem::path remote_avatar;  // what every remote person wears here; empty: their choice
  std::string blend = "auto";           // xr/blend_mode.h: auto, opaque, alpha or additive
  bool no_panel = false;                // hide the head-locked presence panel
  bool setup = false;                   // set the room's target map up (app/xr_setup.h)
  std::filesystem::path save;           // setup: where the map goes; empty: the site's map file
};
int run_xr(const XrRunOptions& options);

}  // namespace deixis::app
