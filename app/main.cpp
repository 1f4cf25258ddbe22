// The `deixis` command line. This is the only translation unit that includes CLI11 (it is slow to
// compile); it parses flags and hands plain option structs to the commands in commands.h.

#include <CLI/CLI.hpp>
#include <cstdlib>

#include "app/commands.h"

namespace {

std::filesystem::path default_reference_dir() {
  if (const char* env = std::getenv("DEIXIS_REFERENCE_DIR")) {
    return env;
  }
  return "../shared/reference";
}

}  // namespace

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

  CLI11_PARSE(app, argc, argv);

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
  if (capture_judge_cmd->parsed()) {
    return deixis::app::run_capture_judge(capture_judge);
  }
  return 0;
}
