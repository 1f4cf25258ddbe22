// The `deixis` command line. This is the only translation unit that includes CLI11 (it is slow to
// compile); it parses flags and hands plain option structs to the commands in commands.h.

#include <CLI/CLI.hpp>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>

#include "app/commands.h"
#include "site/endpoint.h"

namespace {

std::filesystem::path default_reference_dir() {
  if (const char* env = std::getenv("DEIXIS_REFERENCE_DIR")) {
    return env;
  }
  return "../shared/reference";
}

// The MoE weights (right/ and left/): the project's own in assets/weights/ once all four
// networks are there, else the authors' in $DEIXIS_REFERENCE_DIR/weights, else
// ../shared/reference/weights next to the repository.
std::filesystem::path default_weights_dir() {
  const std::filesystem::path source = DEIXIS_SOURCE_DIR;
  const std::filesystem::path own = source / "assets/weights";
  bool complete = true;
  for (const char* hand : {"right", "left"}) {
    for (const char* file : {"MPNet(MoE)(AC)80.safetensors", "UGNet(MoE)(AC)120.safetensors"}) {
      complete = complete && std::filesystem::exists(own / hand / file);
    }
  }
  if (complete) {
    return own;
  }
  if (const char* env = std::getenv("DEIXIS_REFERENCE_DIR")) {
    return std::filesystem::path(env) / "weights";
  }
  return (source / "../shared/reference/weights").lexically_normal();
}

// A HOST:PORT option (join's --connect, xr's and sim's --join) into `address` and `port`; `then`
// runs after a valid endpoint was read.
CLI::Option* add_endpoint_option(CLI::App* cmd, const std::string& flag, std::string& address,
                                 std::uint16_t& port, std::function<void()> then,
                                 const std::string& help) {
  return cmd->add_option_function<std::string>(
      flag,
      [flag, &address, &port, then = std::move(then)](const std::string& endpoint) {
        const std::string problem = deixis::app::parse_endpoint(endpoint, address, port);
        if (!problem.empty()) {
          throw CLI::ValidationError(flag, endpoint + ": " + problem);
        }
        then();
      },
      help);
}

// --weights-dir, as every command that drives the MoE networks takes it.
void add_weights_dir_flag(CLI::App* cmd, std::filesystem::path& weights_dir) {
  cmd->add_option("--weights-dir", weights_dir,
                  "Directory with right/ and left/ MoE weights (default: assets/weights, "
                  "$DEIXIS_REFERENCE_DIR/weights or ../shared/reference/weights)")
      ->check(CLI::ExistingDirectory);
}

// One of the demo's site files (assets/sites/), the default of the commands that run two sites.
std::filesystem::path demo_site(const char* file) {
  return std::filesystem::path(DEIXIS_SOURCE_DIR) / "assets/sites" / file;
}

// The flags host and join share.
void add_site_flags(CLI::App* cmd, deixis::app::SiteRunOptions& o) {
  cmd->add_option("--site", o.site, "Site configuration (JSON, docs/site-config.md)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--seconds", o.seconds,
                  "How long to stream, from when the sites connect (default: the virtual user's "
                  "script)")
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
}

// ---- The passphrase and who may reach a host (docs/security.md) ----

// Where a command's passphrase comes from: one of --passphrase TEXT, --passphrase-file FILE and
// --ask-passphrase, else the DEIXIS_PASSPHRASE environment variable. --open: host beyond loopback
// without one, knowingly.
struct PassphraseFlags {
  std::string text;
  std::string file;
  bool ask = false;
  bool open = false;
  CLI::Option* text_option = nullptr;
};

// The same passphrase options for every command that takes one (host, join, demo, sim, xr);
// `host`: the command's --host flag (sim, xr), which --open needs; `hosts`: whether the command
// can host at all (--open is offered only then).
void add_passphrase_flags(CLI::App* cmd, PassphraseFlags& f, bool hosts,
                          CLI::Option* host = nullptr) {
  f.text_option = cmd->add_option(
      "--passphrase", f.text,
      "The session's passphrase (both sites give the same; peers without it are refused and "
      "everything after the handshake is encrypted). On the command line other users of this "
      "machine can read it (ps): prefer DEIXIS_PASSPHRASE, --passphrase-file or "
      "--ask-passphrase. Without any of the three flags, DEIXIS_PASSPHRASE is used if set");
  CLI::Option* file = cmd->add_option("--passphrase-file", f.file,
                                      "Read the passphrase from the first line of FILE (keep it "
                                      "private: chmod 600)");
  CLI::Option* ask = cmd->add_flag("--ask-passphrase", f.ask,
                                   "Ask for the passphrase on the terminal, not echoed");
  f.text_option->excludes(file)->excludes(ask);
  file->excludes(ask);
  if (hosts) {
    CLI::Option* open = cmd->add_flag(
        "--open", f.open,
        "Host without a passphrase although --bind reaches beyond this machine (anything but "
        "127.x.x.x, e.g. 0.0.0.0): anyone who can reach the port can join and read this site's "
        "motion. Without a passphrase and without --open, such a host exits 2");
    if (host != nullptr) {
      open->needs(host);
    }
  }
}

// The passphrase `f` gives (empty: none) into `passphrase`. False after saying why when it cannot
// be read: the command exits 2.
bool read_passphrase(const char* command, const PassphraseFlags& f, std::string& passphrase) {
  passphrase.clear();
  if (f.text_option->count() > 0) {
    passphrase = f.text;
    if (!passphrase.empty()) {
      std::fprintf(stderr,
                   "deixis %s: warning: a passphrase given with --passphrase can be read by other "
                   "users of this machine (ps, /proc); prefer %s, --passphrase-file or "
                   "--ask-passphrase\n",
                   command, deixis::app::kPassphraseVariable);
    }
    return true;
  }
  std::string problem;
  if (!f.file.empty()) {
    std::string warning;
    problem = deixis::app::read_passphrase_file(f.file, passphrase, warning);
    if (problem.empty() && !warning.empty()) {
      std::fprintf(stderr, "deixis %s: %s\n", command, warning.c_str());
    }
  } else if (f.ask) {
    problem = deixis::app::ask_passphrase("deixis " + std::string(command) + ": passphrase: ",
                                          passphrase);
  } else if (const char* env = std::getenv(deixis::app::kPassphraseVariable)) {
    passphrase = env;
  }
  if (!problem.empty()) {
    std::fprintf(stderr, "deixis %s: %s\n", command, problem.c_str());
    return false;
  }
  return true;
}

// A host's start: beyond loopback without a passphrase it needs --open (else false after saying
// what to do: the command exits 2); an open session is announced with a warning. Sets the
// process-wide permission that SiteSession checks again below the command line.
bool may_host(const char* command, const PassphraseFlags& f, const std::string& address,
              const std::string& passphrase) {
  deixis::app::allow_open_sessions(f.open);
  const std::string problem = deixis::app::host_exposure_problem(address, !passphrase.empty());
  if (!problem.empty()) {
    std::fprintf(stderr, "deixis %s: %s\n", command, problem.c_str());
    return false;
  }
  if (f.open && passphrase.empty()) {
    std::fprintf(stderr, "deixis %s: %s\n", command,
                 deixis::app::open_session_warning(address).c_str());
  }
  return true;
}

}  // namespace

// A live user's site on the network (`deixis xr`, `deixis sim`): --host, or --join HOST:PORT,
// with --port/--bind for a host, the passphrase flags and --wait. `Options` has network, host,
// address, port and wait. Returns --host and --join, for flags that exclude networking.
template <class Options>
std::array<CLI::Option*, 2> add_network_flags(CLI::App* cmd, Options& o, PassphraseFlags& pass,
                                              const std::string& host_help) {
  CLI::Option* host = cmd->add_flag(
      "--host", [&o](std::int64_t) { o.network = o.host = true; }, host_help);
  CLI::Option* join = add_endpoint_option(
                          cmd, "--join", o.address, o.port,
                          [&o] {
                            o.network = true;
                            o.host = false;
                          },
                          "Join the host at HOST:PORT")
                          ->excludes(host);
  cmd->add_option("--port", o.port, "With --host: UDP port (0: any free port)")
      ->capture_default_str()
      ->needs(host);
  cmd->add_option("--bind", o.address,
                  "With --host: address to listen on (beyond 127.x.x.x: needs a passphrase or "
                  "--open)")
      ->capture_default_str()
      ->needs(host);
  add_passphrase_flags(cmd, pass, true, host);
  cmd->add_option("--wait", o.wait, "Seconds to wait for the other site")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 3600.0));
  return {host, join};
}

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

  deixis::app::AvatarGenerateOptions avatar_generate;
  deixis::app::AvatarInfoOptions avatar_info;
  CLI::App* avatar_cmd =
      app.add_subcommand("avatar", "Generate and inspect avatars (skinned glTF humanoids)");
  avatar_cmd->require_subcommand(1);
  CLI::App* avatar_generate_cmd = avatar_cmd->add_subcommand(
      "generate",
      "Write Deixis' default avatar, a parametric skinned humanoid, as binary glTF (.glb); the "
      "same parameters give identical bytes. Exit 2 on bad parameters or an unwritable file");
  avatar_generate_cmd
      ->add_option("--height", avatar_generate.height,
                   "Height, floor to top of head, in metres (0.5 to 2.5)")
      ->capture_default_str();
  avatar_generate_cmd
      ->add_option("--arm-length", avatar_generate.arm_length,
                   "Upper-arm joint to index fingertip, in metres (0.30 to 0.60 x height)")
      ->capture_default_str();
  avatar_generate_cmd->add_option("-o,--output", avatar_generate.output, "Output .glb file")
      ->required();
  CLI::App* avatar_info_cmd = avatar_cmd->add_subcommand(
      "info",
      "Load avatars (.glb or .gltf) as Deixis does and print how their bones were found, their "
      "measurements and mesh sizes; exit 2 if one cannot be loaded");
  avatar_info_cmd->add_option("file", avatar_info.files, "Avatar files")
      ->required()
      ->check(CLI::ExistingFile);

  // `deixis capture …`: the synthetic capture (capture/).
  deixis::app::CaptureGenerateOptions capture_generate;
  deixis::app::CapturePreviewOptions capture_preview;
  capture_preview.reference_dir = default_reference_dir();
  deixis::app::CaptureCsvOptions capture_csv;
  deixis::app::CaptureJudgeOptions capture_judge;
  capture_judge.reference_dir = default_reference_dir();
  CLI::App* capture_cmd = app.add_subcommand(
      "capture",
      "The synthetic capture: a procedural person performing the paper's ten gesture categories "
      "with exact progression labels (datasets, previews, CSV, and the authors' MPNet as judge)");
  capture_cmd->require_subcommand(1);
  CLI::App* capture_generate_cmd = capture_cmd->add_subcommand(
      "generate",
      "Write the training set (train_right, train_left = mirrored), test sets (test_<subject>) "
      "and validation sets (validation_<subject>) as safetensors into a directory; the same "
      "options give identical files. Progress on stderr, a summary table on stdout");
  capture_generate_cmd->add_option("-o,--out", capture_generate.out_dir, "Output directory")
      ->required();
  capture_generate_cmd->add_option("--seed", capture_generate.seed, "Seed of every sequence")
      ->capture_default_str();
  capture_generate_cmd
      ->add_option("--sets", capture_generate.sets,
                   "Sets to write: train, test, validation (default: all)")
      ->delimiter(',');
  capture_generate_cmd
      ->add_option("--subjects", capture_generate.subjects,
                   "Only these subjects, e.g. 170,161,173 (default: every subject of the sets)")
      ->delimiter(',');
  capture_generate_cmd
      ->add_option("--count-scale", capture_generate.count_scale,
                   "Scale every category's sequence count (e.g. 0.05 for a quick small set)")
      ->capture_default_str();
  capture_generate_cmd
      ->add_option("--train-noise", capture_generate.train_noise,
                   "Tracker noise of the training set: none, mocap, headset")
      ->capture_default_str();
  capture_generate_cmd
      ->add_option("--test-noise", capture_generate.test_noise,
                   "Tracker noise of the test and validation sets: none, mocap, headset")
      ->capture_default_str();

  CLI::App* capture_preview_cmd = capture_cmd->add_subcommand(
      "preview",
      "Perform one sequence (as `generate` records it) and draw it as a PNG: progression labels "
      "over time, and the motion from above and from the side with targets");
  capture_preview_cmd->add_option("--subject", capture_preview.subject, "Subject name")
      ->capture_default_str();
  capture_preview_cmd
      ->add_option("--category", capture_preview.category,
                   "Category, e.g. pointing-single, touching-transition")
      ->capture_default_str();
  capture_preview_cmd->add_option("--index", capture_preview.index, "Sequence index")
      ->capture_default_str();
  capture_preview_cmd->add_option("--seed", capture_preview.seed, "Seed (as for generate)")
      ->capture_default_str();
  capture_preview_cmd->add_option("--set", capture_preview.set, "train, test or validation")
      ->capture_default_str();
  capture_preview_cmd->add_flag("--with-mpnet", capture_preview.with_mpnet,
                                "Overlay the authors' MPNet MoE predictions");
  capture_preview_cmd->add_option(
      "--noise", capture_preview.noise,
      "Tracker noise for the MPNet overlay (default: the set's, mocap or headset)");
  capture_preview_cmd->add_option("--reference-dir", capture_preview.reference_dir,
                                  "The authors' reference data (default: $DEIXIS_REFERENCE_DIR or "
                                  "../shared/reference)");
  capture_preview_cmd->add_option("-o,--output", capture_preview.output, "Output .png")->required();

  CLI::App* capture_csv_cmd = capture_cmd->add_subcommand(
      "csv", "Write a capture dataset as CSV, one row per frame (stdout unless --output)");
  capture_csv_cmd->add_option("dataset", capture_csv.dataset, "Dataset (.safetensors)")
      ->required()
      ->check(CLI::ExistingFile);
  capture_csv_cmd->add_option("--sequence", capture_csv.sequence,
                              "Only this sequence (index in the file)");
  capture_csv_cmd->add_option("-o,--output", capture_csv.output, "Output .csv");

  CLI::App* capture_judge_cmd = capture_cmd->add_subcommand(
      "judge",
      "Run the authors' MPNet MoE (right, and left for left-handed subjects) on the test sets "
      "like their test_MPNet.py and print the MPE per category and subject; exit 1 if above "
      "--max-mpe");
  capture_judge_cmd
      ->add_option("dataset_dir", capture_judge.dataset_dir,
                   "Directory with test_<subject>.safetensors")
      ->required()
      ->check(CLI::ExistingDirectory);
  capture_judge_cmd->add_option("--subjects", capture_judge.subjects, "Only these test subjects")
      ->delimiter(',');
  capture_judge_cmd->add_option("--max-mpe", capture_judge.max_mpe,
                                "Fail (exit 1) when the overall MPE is above this");
  capture_judge_cmd
      ->add_option("--reference-dir", capture_judge.reference_dir,
                   "The authors' reference data (default: $DEIXIS_REFERENCE_DIR or "
                   "../shared/reference)")
      ->check(CLI::ExistingDirectory);

  // `deixis host` / `deixis join` / `deixis demo` (docs/demo.md).
  deixis::app::SiteRunOptions host;
  host.weights_dir = default_weights_dir();
  host.out_dir = "out/host";
  CLI::App* host_cmd = app.add_subcommand(
      "host",
      "Run a site that others join: its virtual user's tracking goes out, the other site's "
      "person comes in as a translated avatar in this room, rendered headlessly. Listens on "
      "127.0.0.1 unless --bind says otherwise; beyond loopback it needs a passphrase or --open. "
      "Prints \"port N\" once listening; exit 1 if the session fails, 2 for bad flags or files "
      "(or a host beyond loopback with neither)");
  add_site_flags(host_cmd, host);
  host_cmd->add_option("--port", host.port, "UDP port to listen on (0: any free port)")
      ->capture_default_str();
  host_cmd
      ->add_option("--bind", host.address,
                   "Address to listen on (beyond 127.x.x.x, e.g. 0.0.0.0: needs a passphrase or "
                   "--open)")
      ->capture_default_str();
  PassphraseFlags host_pass;
  add_passphrase_flags(host_cmd, host_pass, true);

  deixis::app::SiteRunOptions join;
  join.host = false;
  join.weights_dir = default_weights_dir();
  join.out_dir = "out/join";
  CLI::App* join_cmd = app.add_subcommand(
      "join",
      "Run a site that joins a host (as host does otherwise); exit 1 if the host refuses or "
      "cannot be reached, 2 for bad flags or files");
  add_site_flags(join_cmd, join);
  PassphraseFlags join_pass;
  add_passphrase_flags(join_cmd, join_pass, false);
  add_endpoint_option(
      join_cmd, "--connect", join.address, join.port, [] {}, "The host, HOST:PORT")
      ->required();

  deixis::app::DemoOptions demo;
  demo.weights_dir = default_weights_dir();
  demo.site_a = demo_site("a.json");
  demo.site_b = demo_site("b.json");
  CLI::App* demo_cmd = app.add_subcommand(
      "demo",
      "Two sites for real: starts `deixis host` (site A) and `deixis join` (site B) as two "
      "processes on loopback, then writes demo.mp4 (each user beside their avatar in the other "
      "room), contact_sheet.png and summary.json, and prints the summary");
  demo_cmd->add_option("-o,--out", demo.out_dir, "Output directory")->capture_default_str();
  demo_cmd->add_option("--seconds", demo.seconds, "Seconds to stream (default: the scripts')")
      ->check(CLI::Range(1.0, 600.0));
  demo_cmd->add_option("--site-a", demo.site_a, "Site A (the host)")->check(CLI::ExistingFile);
  demo_cmd->add_option("--site-b", demo.site_b, "Site B (joins A)")->check(CLI::ExistingFile);
  demo_cmd->add_option("--weights-dir", demo.weights_dir, "As for host and join")
      ->check(CLI::ExistingDirectory);
  PassphraseFlags demo_pass;
  add_passphrase_flags(demo_cmd, demo_pass, false);
  demo_cmd->add_option("--timeout", demo.timeout, "Seconds before a site process is given up on")
      ->capture_default_str()
      ->check(CLI::Range(5.0, 3600.0));

  // `deixis xr` (docs/xr.md).
  deixis::app::XrRunOptions xr;
  xr.weights_dir = default_weights_dir();
  xr.site = demo_site("a.json");
  xr.remote_site = demo_site("b.json");
  CLI::App* xr_cmd = app.add_subcommand(
      "xr",
      "The headset user's side through OpenXR (the runtime the loader finds, or XR_RUNTIME_JSON): "
      "both eyes see this site's room and the remote person's avatar. With --host or --join the "
      "site meets another (deixis host/join/xr): the headset user, calibrated standing upright "
      "at the start, is tracked out with the targets they look and point at, and the other "
      "site's person comes in as a translated avatar. Without, the remote person is "
      "--remote-site's scripted virtual user, performed locally. Prints the runtime, then "
      "frames, tracking and network counts; exit 1 if OpenXR or the session fails, 2 for bad "
      "flags or files");
  xr_cmd->add_option("--site", xr.site, "This site (the headset user's room)")
      ->capture_default_str()
      ->check(CLI::ExistingFile);
  xr_cmd
      ->add_option("--remote-site", xr.remote_site,
                   "Without --host/--join: the other site, whose virtual_user plays the remote "
                   "person")
      ->capture_default_str()
      ->check(CLI::ExistingFile);
  xr_cmd
      ->add_option("--seconds", xr.seconds,
                   "Ask the runtime to end the session after this much display time (default: "
                   "until the runtime ends it)")
      ->check(CLI::Range(0.0, 3600.0));
  add_weights_dir_flag(xr_cmd, xr.weights_dir);
  xr_cmd->add_flag("--headless", xr.headless,
                   "XR_MND_headless: a session without graphics (nothing is rendered)");
  PassphraseFlags xr_pass;
  add_network_flags(xr_cmd, xr, xr_pass,
                    "Host a session others join (prints \"port N\" once the user is calibrated)");
  xr_cmd->add_option("--hand", xr.hand, "The headset user's pointing hand")
      ->capture_default_str()
      ->check(CLI::IsMember({"right", "left"}));
  xr_cmd
      ->add_option("--height", xr.height,
                   "The headset user's stature in m (default: from the eye height when the "
                   "session starts)")
      ->check(CLI::Range(1.0, 2.3));

  // `deixis sim` (docs/sim.md).
  deixis::app::SimOptions sim;
  sim.weights_dir = default_weights_dir();
  sim.site_a = demo_site("a.json");
  sim.site_b = demo_site("b.json");
  CLI::App* sim_cmd = app.add_subcommand(
      "sim",
      "The desktop simulator: a window with the local room (site A) and its virtual user, "
      "driven by mouse and keys (right-drag looks, click points, shift-click touches, E "
      "explains, R rests, P looks at the other person) or by the site's script, and the remote "
      "room (site B) with the avatar translated from the user's tracking; drag B's objects and "
      "the avatar adapts. Both sites in this process. Exit 0 when closed or done, 1 if the "
      "window or OpenGL fails, 2 for bad flags or files");
  sim_cmd->add_option("--site-a", sim.site_a, "The user's site (its room and subject)")
      ->capture_default_str()
      ->check(CLI::ExistingFile);
  sim_cmd->add_option("--site-b", sim.site_b, "The remote site, where the avatar stands")
      ->capture_default_str()
      ->check(CLI::ExistingFile);
  add_weights_dir_flag(sim_cmd, sim.weights_dir);
  sim_cmd->add_option("--avatar", sim.avatar, "The avatar in B (.glb; default: site B's)")
      ->check(CLI::ExistingFile);
  sim_cmd->add_flag("--script", sim.script,
                    "The user performs site A's virtual_user script (hands-free)");
  sim_cmd
      ->add_option("--input", sim.input,
                   "Scripted mouse, key and text events (JSON, docs/sim.md); one tick per frame "
                   "until a session starts from the panel")
      ->check(CLI::ExistingFile);
  CLI::Option* fixed_step = sim_cmd->add_flag(
      "--fixed-step", sim.fixed_step,
      "Every frame advances the simulator by one 30 Hz tick (reproducible runs; not with a "
      "network, whose sites follow the wall clock)");
  sim_cmd->add_option("--frames", sim.frames, "Quit after this many frames")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{100'000'000}));
  sim_cmd->add_option("--seconds", sim.seconds, "Quit after this many seconds of simulator time")
      ->check(CLI::Range(0.001, 86400.0));
  const auto existing_parent = [](const std::string& file) -> std::string {
    const std::filesystem::path parent = std::filesystem::path(file).parent_path();
    if (!parent.empty() && !std::filesystem::is_directory(parent)) {
      return "directory does not exist: " + parent.string();
    }
    return {};
  };
  sim_cmd->add_option("--screenshot", sim.screenshot, "Save the last frame's window as a PNG")
      ->check(existing_parent);
  sim_cmd
      ->add_option("--report", sim.report,
                   "Write a JSON report at the end (B's objects, the avatar's eye and fingertip, "
                   "timings)")
      ->check(existing_parent);
  sim_cmd->add_option("--width", sim.width, "Window width")
      ->capture_default_str()
      ->check(CLI::Range(320, 7680));
  sim_cmd->add_option("--height", sim.height, "Window height")
      ->capture_default_str()
      ->check(CLI::Range(240, 4320));
  PassphraseFlags sim_pass;
  for (CLI::Option* network :
       add_network_flags(sim_cmd, sim, sim_pass,
                         "Be site A of a session others join (prints \"port N\" at once)")) {
    fixed_step->excludes(network);
  }

  // `deixis eval` (docs/eval.md).
  deixis::app::EvalOptions eval;
  eval.data_dir = std::filesystem::path(DEIXIS_SOURCE_DIR) / "out/data";
  eval.reference_weights = default_reference_dir() / "weights";
  if (!std::getenv("DEIXIS_REFERENCE_DIR")) {
    eval.reference_weights =
        (std::filesystem::path(DEIXIS_SOURCE_DIR) / "../shared/reference/weights")
            .lexically_normal();
  }
  eval.project_weights = std::filesystem::path(DEIXIS_SOURCE_DIR) / "assets/weights";
  for (int i = 0; i < argc; ++i) {
    eval.command_line += (i ? " " : "") + std::string(i ? argv[i] : "deixis");
  }
  CLI::App* eval_cmd = app.add_subcommand(
      "eval",
      "The paper's Tables I-IV and Fig. 5 on the held-out test subjects: MPE and SS (MPNet), "
      "DIP, DR and FMD (the chained networks), robustness to missed tracking, jitter and noise; "
      "every architecture, the copy-paste baseline. Writes tables.md, results.json and fig5.png; "
      "progress on stderr; exit 2 for bad flags or files");
  eval_cmd->add_option("--data", eval.data_dir, "Directory with test_<subject>.safetensors")
      ->capture_default_str()
      ->check(CLI::ExistingDirectory);
  eval_cmd->add_option(
      "--weights", eval.weights,
      "A weight set LABEL=DIR (DIR holds right/ and left/ with the authors' file names); "
      "repeatable. Default: authors=$DEIXIS_REFERENCE_DIR/weights or ../shared/reference/weights, "
      "plus deixis=assets/weights when present");
  eval_cmd
      ->add_option("--fmd-encoder", eval.encoder_dir,
                   "Directory with right/ and left/AutoEncoder.safetensors (deixis-train "
                   "autoencoder); default: looked for in the weight sets, else FMD is n/a")
      ->check(CLI::ExistingDirectory);
  eval_cmd->add_option("-o,--out", eval.out_dir, "Output directory")->capture_default_str();
  eval_cmd->add_option("--subjects", eval.subjects, "Only these test subjects, e.g. 161,173")
      ->delimiter(',');
  eval_cmd
      ->add_option("--threads", eval.threads,
                   "Units of work (a subject's rows of one weight set) run at a time; 0: one "
                   "per core. The tables are the same for any count")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  eval_cmd->add_flag("--quick", eval.quick,
                     "A tiny sample (2 sequences per category and subject): seconds, for CI");

  // Bad flags exit 2 (as bad files do), with CLI11's message naming the flag; --help exits 0.
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }

  if (parity_cmd->parsed()) {
    return deixis::app::run_parity(parity);
  }
  if (avatar_generate_cmd->parsed()) {
    return deixis::app::run_avatar_generate(avatar_generate);
  }
  if (avatar_info_cmd->parsed()) {
    return deixis::app::run_avatar_info(avatar_info);
  }
  if (capture_generate_cmd->parsed()) {
    return deixis::app::run_capture_generate(capture_generate);
  }
  if (capture_preview_cmd->parsed()) {
    return deixis::app::run_capture_preview(capture_preview);
  }
  if (capture_csv_cmd->parsed()) {
    return deixis::app::run_capture_csv(capture_csv);
  }
  if (host_cmd->parsed()) {
    if (!read_passphrase("host", host_pass, host.passphrase) ||
        !may_host("host", host_pass, host.address, host.passphrase)) {
      return 2;
    }
    return deixis::app::run_site(host);
  }
  if (join_cmd->parsed()) {
    if (!read_passphrase("join", join_pass, join.passphrase)) {
      return 2;
    }
    return deixis::app::run_site(join);
  }
  if (demo_cmd->parsed()) {
    if (!read_passphrase("demo", demo_pass, demo.passphrase)) {
      return 2;
    }
    return deixis::app::run_demo(demo);
  }
  if (xr_cmd->parsed()) {
    if (!read_passphrase("xr", xr_pass, xr.passphrase) ||
        (xr.network && xr.host && !may_host("xr", xr_pass, xr.address, xr.passphrase))) {
      return 2;
    }
    return deixis::app::run_xr(xr);
  }
  if (sim_cmd->parsed()) {
    if (!read_passphrase("sim", sim_pass, sim.passphrase) ||
        (sim.network && sim.host && !may_host("sim", sim_pass, sim.address, sim.passphrase))) {
      return 2;
    }
    return deixis::app::run_sim(sim);
  }
  if (eval_cmd->parsed()) {
    return deixis::app::run_eval(eval);
  }
  if (capture_judge_cmd->parsed()) {
    return deixis::app::run_capture_judge(capture_judge);
  }
  return 0;
}
