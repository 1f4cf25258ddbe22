// deixis eval: the quick run writes well-formed tables; DIP through the evaluation's
// own chain reads a fingertip offset by a known angle as that HE and VE to 0.01°; identical
// motion gives FMD 0; a known hold pattern gives the expected MPJPE; training-subject data is
// refused.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>

#include "capture/generate.h"
#include "core/error.h"
#include "core/io/machine.h"
#include "core/io/safetensors.h"
#include "eval/evaluation.h"
#include "eval/perturbation.h"
#include "eval/runs.h"
#include "test_support.h"

namespace deixis::eval {
namespace {

namespace fs = std::filesystem;
using deixis::testing::ScratchDir;

float radians(double degrees) {
  return static_cast<float>(degrees * std::numbers::pi / 180.0);
}

// Upright head at the root looking along +Z (network frame); the fingertip 0.54 m from the head
// in the direction (yaw, pitch) through an identity hand frame.
EndEffectors pointing(double yaw_deg, double pitch_deg) {
  const float yaw = radians(yaw_deg), pitch = radians(pitch_deg);
  const Vec3 dir(std::sin(yaw) * std::cos(pitch), std::sin(pitch), std::cos(yaw) * std::cos(pitch));
  EndEffectors x{};
  set_vec3(x, ee::kGaze, Vec3(0, 0, 1));
  set_vec3(x, ee::kHeadForward, Vec3(0, 0, 1));
  set_vec3(x, ee::kHeadUp, Vec3(0, 1, 0));
  set_vec3(x, ee::kHandForward, Vec3(0, 0, 1));
  set_vec3(x, ee::kHandUp, Vec3(0, 1, 0));
  set_vec3(x, ee::kHandPosition, dir * 0.44f);
  set_vec3(x, ee::kFingertip, dir * 0.10f);
  return x;
}

AlignedPair pair_ending_in(const EndEffectors& last, std::size_t frames) {
  AlignedPair pair;
  pair.frames.resize(frames);
  for (TranslationInput& f : pair.frames) {
    f.user_x = pointing(0.0, 0.0);
  }
  pair.frames.back().user_x = last;
  pair.avatar_target = Vec3(0.0f, 0.0f, 2.0f);  // straight ahead of H, 2 m
  return pair;
}

TEST(EvalDip, AFingertipOffsetByAKnownAngleGivesThatHeAndVe) {
  for (const auto& [yaw, pitch] : {std::pair{3.0, 0.0}, {0.0, 2.0}, {-4.5, 0.0}, {0.0, -1.25}}) {
    const AlignedPair pair = pair_ending_in(pointing(yaw, pitch), 12);
    const std::vector<EndEffectors> x = run_chain(Generator{}, pair, 1.0f, 1);  // copy-paste
    ASSERT_EQ(x.size(), pair.frames.size());
    const PointingError e = dip_pointing(x.back(), pair.avatar_target);
    EXPECT_NEAR(e.horizontal_deg, std::abs(yaw), 0.01) << yaw << ", " << pitch;
    EXPECT_NEAR(e.vertical_deg, std::abs(pitch), 0.01) << yaw << ", " << pitch;
  }
}

// run_chains() is run_chain() on each pair: with a diffusion UGNet, chains of different lengths
// advance in lockstep and UGNet denoises them as one batch, each chain keeping its own draws.
// Five aligned pairs of random frames (31–60 frames each) and a seed for each.
struct RandomPairs {
  std::vector<AlignedPair> pairs;
  std::vector<std::uint64_t> seeds;
};
RandomPairs random_pairs() {
  RandomPairs r;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  for (const std::size_t frames : {37, 52, 31, 45, 60}) {
    AlignedPair pair;
    pair.avatar_initial = pointing(0.0, -20.0);
    for (std::size_t k = 0; k < frames; ++k) {
      TranslationInput f;
      std::ranges::generate(f.user_features, [&] { return value(rng); });
      std::ranges::generate(f.avatar_target, [&] { return value(rng); });
      f.user_x =
          pointing(30.0 * static_cast<double>(value(rng)), 20.0 * static_cast<double>(value(rng)));
      pair.frames.push_back(f);
    }
    r.pairs.push_back(pair);
    r.seeds.push_back(rng());
  }
  return r;
}

// The largest end-effector difference between run_chains() (in lockstep, batched) and
// run_chain() on each pair alone.
double batched_chains_difference(const Generator& g, const RandomPairs& r,
                                 std::vector<std::vector<EndEffectors>>& batched) {
  batched = run_chains(g, r.pairs, 1.05f, r.seeds);
  EXPECT_EQ(batched.size(), r.pairs.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < r.pairs.size() && i < batched.size(); ++i) {
    const std::vector<EndEffectors> one = run_chain(g, r.pairs[i], 1.05f, r.seeds[i]);
    EXPECT_EQ(batched[i].size(), one.size()) << "pair " << i;
    for (std::size_t k = 0; k < one.size() && k < batched[i].size(); ++k) {
      for (int c = 0; c < kEndEffectorSize; ++c) {
        worst = std::max(worst, static_cast<double>(std::abs(batched[i][k][c] - one[k][c])));
      }
    }
  }
  return worst;
}

TEST(EvalChains, BatchedDiffusionChainsAreEachPairsOwnChain) {
  const fs::path w = deixis::testing::reference_dir() / "weights/left";
  const nn::Mpnet mpnet = nn::Mpnet::load(w / "MPNet(MoE)(AC)80.safetensors");
  const nn::Ugnet ugnet = nn::Ugnet::load(w / "UGNet(Diffusion)(AC)120.safetensors");
  const Generator g{&mpnet, &ugnet};
  const RandomPairs r = random_pairs();
  std::vector<std::vector<EndEffectors>> batched;
  const double worst = batched_chains_difference(g, r, batched);
  std::printf("[ measured ] batched vs one-by-one diffusion chains: max |error| %.2g\n", worst);
  EXPECT_LT(worst, 1e-4);
  // The draws matter (the comparison above could tell chains apart): another seed moves them.
  const std::vector<EndEffectors> reseeded = run_chain(g, r.pairs[0], 1.05f, r.seeds[0] + 1);
  double moved = 0.0;
  for (int c = 0; c < kEndEffectorSize; ++c) {
    moved =
        std::max(moved, static_cast<double>(std::abs(reseeded.back()[c] - batched[0].back()[c])));
  }
  EXPECT_GT(moved, 1e-3);
}

// MPNet's outputs computed ahead (user_progressions()) give the same chains as MPNet run inside
// the loop, chain by chain and in lockstep; wrong ones would not.
TEST(EvalChains, KnownProgressionsGiveTheSameChains) {
  const fs::path w = deixis::testing::reference_dir() / "weights/right";
  const nn::Mpnet mpnet = nn::Mpnet::load(w / "MPNet(MoE)(AC)80.safetensors");
  const nn::Ugnet moe = nn::Ugnet::load(w / "UGNet(MoE)(AC)120.safetensors");
  const nn::Ugnet diffusion = nn::Ugnet::load(w / "UGNet(Diffusion)(AC)120.safetensors");
  const RandomPairs r = random_pairs();
  std::vector<std::vector<nn::Progression>> known;
  for (const AlignedPair& pair : r.pairs) {
    known.push_back(user_progressions(mpnet, pair));
    ASSERT_EQ(known.back().size(), pair.frames.size() - 1);
  }
  for (const nn::Ugnet* ugnet : {&moe, &diffusion}) {  // one by one; in lockstep
    const Generator g{&mpnet, ugnet};
    const std::vector<std::span<const nn::Progression>> spans(known.begin(), known.end());
    EXPECT_EQ(run_chains(g, r.pairs, 1.05f, r.seeds, spans), run_chains(g, r.pairs, 1.05f, r.seeds))
        << (ugnet == &moe ? "MoE" : "diffusion");
  }
  // Another pair's progressions change the chain.
  const Generator g{&mpnet, &moe};
  EXPECT_NE(run_chain(g, r.pairs[0], 1.05f, r.seeds[0], known[1]),
            run_chain(g, r.pairs[0], 1.05f, r.seeds[0]));
}

// The Transformer UGNet's chains run in lockstep too (its products batched over the chains'
// windows of a frame); each is the pair's own chain.
TEST(EvalChains, BatchedTransformerChainsAreEachPairsOwnChain) {
  const fs::path w = deixis::testing::reference_dir() / "weights/right";
  const nn::Mpnet mpnet = nn::Mpnet::load(w / "MPNet(MoE)(AC)80.safetensors");
  const nn::Ugnet ugnet = nn::Ugnet::load(w / "UGNet(Transformer)(AC)120.safetensors");
  ASSERT_TRUE(ugnet.gains_from_batch());
  const RandomPairs r = random_pairs();
  std::vector<std::vector<EndEffectors>> batched;
  const double worst = batched_chains_difference({&mpnet, &ugnet}, r, batched);
  std::printf("[ measured ] batched vs one-by-one Transformer chains: max |error| %.2g\n", worst);
  EXPECT_LT(worst, 1e-4);
}

TEST(EvalRobustness, AKnownHoldPatternGivesTheExpectedMpjpe) {
  // The head slides 1 cm per frame along x; the hand stays. Each drop holds the frame before
  // it, so the k-th held frame of a drop is k cm behind: MPJPE = Σ k / 2 / frames (head and
  // hand averaged).
  constexpr std::size_t kFrames = 150;
  constexpr int kDrop = 6;
  std::vector<TranslationInput> frames(kFrames);
  for (std::size_t t = 0; t < kFrames; ++t) {
    frames[t].user_x = pointing(0.0, 0.0);
    set_vec3(frames[t].user_x, ee::kHeadPosition, Vec3(0.01f * static_cast<float>(t), 0, 0));
    frames[t].user_features[0] = static_cast<float>(t);
  }
  const std::vector<TranslationInput> clean = frames;
  std::mt19937_64 rng(7);
  std::size_t held = 0;
  // Draw until at least one drop happened away from frame 0 (its hold is frame 0 itself).
  while (held == 0 || frames[0].user_features[0] != clean[0].user_features[0]) {
    frames = clean;
    held = apply_missed_tracking(frames, kDrop, rng);
  }
  double expected_cm = 0.0;
  for (std::size_t start = 0; start < kFrames; start += 30) {
    if (frames[start].user_features[0] == clean[start].user_features[0] && start != 0) {
      continue;  // not dropped
    }
    const std::size_t hold = start == 0 ? 0 : start - 1;
    for (std::size_t k = start; k < start + kDrop; ++k) {
      if (start == 0 && frames[1].user_features[0] == 1.0f) {
        break;  // frame 0 was not dropped
      }
      EXPECT_EQ(frames[k].user_features[0], static_cast<float>(hold)) << k;
      expected_cm += static_cast<double>(k - hold) / 2.0;
    }
  }
  const MotionDeviation d =
      motion_deviation(run_chain(Generator{}, AlignedPair{clean, {}, {}, 0}, 1.0f, 1),
                       run_chain(Generator{}, AlignedPair{frames, {}, {}, 0}, 1.0f, 1));
  EXPECT_NEAR(d.position_cm, expected_cm / kFrames, 1e-4);
  EXPECT_NEAR(d.rotation_deg, 0.0, 1e-6);
}

// A motion encoder with random weights: FMD's distance needs some map to codes, not a trained
// one, to show that identical motion is at distance 0.
void write_random_encoder(const fs::path& dir) {
  std::mt19937 rng(3);
  std::normal_distribution<float> n(0.0f, 0.05f);
  const auto values = [&](std::size_t count) {
    std::vector<float> v(count);
    for (float& x : v) {
      x = n(rng);
    }
    return v;
  };
  for (const char* hand : {"right", "left"}) {
    SafetensorsWriter w;
    w.add_f32("conv_encode1.weight", {256, 18, 15}, values(256 * 18 * 15));
    w.add_f32("conv_encode1.bias", {256}, values(256));
    w.add_f32("conv_encode2.weight", {128, 256, 16}, values(128 * 256 * 16));
    w.add_f32("conv_encode2.bias", {128}, values(128));
    fs::create_directories(dir / hand);
    w.write(dir / hand / "AutoEncoder.safetensors");
  }
}

// Tiny test sets of a right- and a left-handed subject, made once for the suite.
class EvalRun : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scratch_ = new ScratchDir();
    capture::GenerateOptions g;
    g.out_dir = scratch_->path() / "data";
    g.sets = {"test"};
    g.subjects = {"161", "173"};
    g.count_scale = 0.12;  // at least two sequences per category: DR needs a second target
    capture::generate_datasets(g, [](const std::string&, std::size_t, std::size_t, std::size_t) {});
    write_random_encoder(scratch_->path() / "encoder");
  }
  static void TearDownTestSuite() {
    delete scratch_;
    scratch_ = nullptr;
  }
  static fs::path data() { return scratch_->path() / "data"; }
  static fs::path encoder() { return scratch_->path() / "encoder"; }
  static EvalOptions quick_options() {
    EvalOptions o;
    o.data_dir = data();
    o.weights = {{"authors", deixis::testing::reference_dir() / "weights"}};
    o.encoder_dir = encoder();
    o.quick = true;
    o.sampling = quick_sampling();
    o.command = "eval_test";
    return o;
  }
  // A weight set "short" in `dir` holding two of the authors' right-hand networks under the file
  // names given (a stem with other epochs stands for a run with fewer), evaluated on subject 161.
  static EvalOptions renamed_pair(const ScratchDir& dir, const std::string& mpnet_from,
                                  const std::string& mpnet_to, const std::string& ugnet_from,
                                  const std::string& ugnet_to) {
    const fs::path mine = dir.path() / "right";
    const fs::path authors = deixis::testing::reference_dir() / "weights/right";
    fs::create_directories(mine);
    fs::copy_file(authors / (mpnet_from + ".safetensors"), mine / (mpnet_to + ".safetensors"));
    fs::copy_file(authors / (ugnet_from + ".safetensors"), mine / (ugnet_to + ".safetensors"));
    EvalOptions o = quick_options();
    o.weights = {{"short", dir.path()}};
    o.subjects = {"161"};
    return o;
  }
  // The message with which evaluate() refuses `o`; a failure (`why` says what got through) and
  // an empty message when it does not.
  static std::string refusal(const EvalOptions& o, const char* why) {
    try {
      evaluate(o);
    } catch (const Error& e) {
      return e.what();
    }
    ADD_FAILURE() << why;
    return "";
  }
  static ScratchDir* scratch_;
};
ScratchDir* EvalRun::scratch_ = nullptr;

TEST_F(EvalRun, IdenticalMotionGivesFmdZero) {
  const TestSet set = TestSet::read(data() / "test_161.safetensors");
  const nn::MotionEncoder enc =
      nn::MotionEncoder::load(encoder() / "right/AutoEncoder.safetensors");
  Sampling s = quick_sampling();
  s.fmd_trials = 2;
  const std::vector<double> fmd = run_fmd(Generator{}, enc, set, s);  // copy-paste = the user
  ASSERT_EQ(fmd.size(), 2u);
  for (const double v : fmd) {
    EXPECT_NEAR(v, 0.0, 1e-6);
  }
}

// run_fmd() reuses the codes of a user's own motion and, without noise, of a pair drawn again;
// that changes no figure. Few sequences per category, so that pairs recur across the trials
// (with one, every sequence is its own partner in every trial).
TEST_F(EvalRun, FmdReusingRecurringPairsChangesNothing) {
#ifdef DEIXIS_SANITIZED
  // Twelve FMD runs of the MoE and Diffusion UGNets: 6 s in the release suite, which runs it,
  // 200 s under ASan; run_fmd's memory is exercised under ASan by IdenticalMotionGivesFmdZero.
  GTEST_SKIP() << "the release suite runs it (200 s under ASan)";
#endif
  const TestSet set = TestSet::read(data() / "test_161.safetensors");
  const nn::MotionEncoder enc =
      nn::MotionEncoder::load(encoder() / "right/AutoEncoder.safetensors");
  const fs::path w = deixis::testing::reference_dir() / "weights/right";
  const nn::Mpnet mpnet = nn::Mpnet::load(w / "MPNet(MoE)(AC)80.safetensors");
  const nn::Ugnet moe = nn::Ugnet::load(w / "UGNet(MoE)(AC)120.safetensors");
  const nn::Ugnet diffusion = nn::Ugnet::load(w / "UGNet(Diffusion)(AC)120.safetensors");
  // With reuse and without, the same FMD per trial; the first two trials differ (other partners
  // or other noise), so codes reused where they should not be would show.
  const auto expect_reuse_exact = [&](const nn::Ugnet& ugnet, int trials,
                                      std::size_t per_category) {
    Sampling s = quick_sampling();
    s.fmd_trials = trials;
    s.per_category = per_category;
    const Generator g{&mpnet, &ugnet};
    const std::vector<double> reused = run_fmd(g, enc, set, s, FmdReuse::kOn);
    EXPECT_EQ(reused, run_fmd(g, enc, set, s, FmdReuse::kOff));
    ASSERT_EQ(reused.size(), static_cast<std::size_t>(trials));
    EXPECT_NE(reused[0], reused[1]);
  };
  // The MoE runs chain by chain, so reuse is exact.
  expect_reuse_exact(moe, 4, 2);
  // The diffusion UGNet draws new noise for every chain, so only its real side may be reused;
  // its chains (same seeds, same batches) are exact too. One sequence per category: each is its
  // own partner in every trial.
  expect_reuse_exact(diffusion, 2, 1);
}

TEST_F(EvalRun, QuickRunWritesWellFormedTables) {
#ifdef DEIXIS_SANITIZED
  // Every network of every table over two subjects: 20 s in the release suite, which runs it,
  // but over 6 minutes under ASan (the Transformer and Diffusion UGNets). The metrics and the
  // run's pieces are covered here by the other tests.
  GTEST_SKIP() << "the whole quick evaluation runs in the release suite (too slow under ASan)";
#endif
  const Report report = evaluate(quick_options());
  const nlohmann::json j = nlohmann::json::parse(json(report));
  EXPECT_EQ(j["subjects"], nlohmann::json({"161", "173"}));
  const std::map<std::string, std::vector<std::string>> expected = {
      {"I", {"HE", "VE", "PE", "FMD"}},
      {"II", {"parameters", "size", "inference"}},
      {"III", {"MPE", "SS"}},
      {"IV", {"HE", "VE", "PE", "HL", "VL", "PL", "FMD"}},
      {"V", {"MPJPE", "MPJRE", "MPJLVE", "MPJAVE"}}};
  ASSERT_EQ(j["tables"].size(), expected.size());
  for (const auto& t : j["tables"]) {
    const std::vector<std::string>& columns = expected.at(t["id"].get<std::string>());
    ASSERT_EQ(t["columns"].size(), columns.size()) << t["id"];
    for (std::size_t c = 0; c < columns.size(); ++c) {
      EXPECT_EQ(t["columns"][c]["name"], columns[c]);
    }
    for (const auto& r : t["rows"]) {
      ASSERT_EQ(r["mean"].size(), columns.size()) << r["label"];
      for (const auto& [subject, values] : r["per_subject"].items()) {
        ASSERT_EQ(values.size(), columns.size()) << r["label"] << " " << subject;
        for (const auto& v : values) {
          EXPECT_TRUE(v.is_null() || std::isfinite(v.get<double>())) << r["label"];
        }
      }
    }
  }
  // Every expected row has its numbers.
  const auto row = [&](const std::string& table, const std::string& label,
                       const std::string& weights) {
    for (const auto& t : j["tables"]) {
      if (t["id"] == table) {
        for (const auto& r : t["rows"]) {
          if (r["label"] == label && r["weights"] == weights) {
            return r;
          }
        }
      }
    }
    ADD_FAILURE() << "no row " << label << " in table " << table;
    return nlohmann::json();
  };
  // Rows are copies: bind them before iterating (a range-for over a temporary's member would
  // read freed memory).
  const nlohmann::json moe = row("I", "MoE (AC)", "authors");
  for (const auto& v : moe["mean"]) {
    EXPECT_TRUE(v.is_number());
  }
  for (const char* label : {"MoE (DG)", "copy-paste"}) {
    const std::string weights = std::string(label) == "copy-paste" ? "" : "authors";
    const nlohmann::json r = row("I", label, weights);
    for (const auto& v : r["mean"]) {
      EXPECT_TRUE(v.is_number()) << label;
    }
  }
  EXPECT_TRUE(row("I", "AMNet_DG", "")["mean"][0].is_null());
  for (const char* label : {"MLP", "GRU-MoE", "Transformer"}) {
    const auto r = row("III", label, "authors");
    EXPECT_TRUE(r["mean"][0].is_number() && r["mean"][1].is_number()) << label;
  }
  for (const char* label : {"MLP", "MoE (AC)", "Diffusion", "Transformer"}) {
    const nlohmann::json r = row("IV", label, "authors");
    for (const auto& v : r["mean"]) {
      EXPECT_TRUE(v.is_number()) << label << ": " << r.dump();
    }
  }
  EXPECT_TRUE(row("V", "MoE (AC), missed 1.0 s", "authors")["mean"][0].is_number());
  ASSERT_EQ(j["figure5"].size(), 1u);
  EXPECT_EQ(j["figure5"][0]["seconds"].size(), 5u);
  const std::string md = markdown(report);
  EXPECT_NE(md.find("## Table IV."), std::string::npos);
  // Every per-subject breakdown has rows below its header (Table II, measured once per
  // machine, has none and so no breakdown).
  for (const char* id : {"I", "III", "IV", "V"}) {
    const std::size_t open = md.find(std::string("Table ") + id + " per subject</summary>");
    ASSERT_NE(open, std::string::npos) << "Table " << id;
    const std::string block = md.substr(open, md.find("</details>", open) - open);
    EXPECT_NE(block.find(", 161 |"), std::string::npos) << block;
  }
  EXPECT_EQ(md.find("Table II per subject"), std::string::npos);
  // The wall time says which machine spent it.
  EXPECT_EQ(j["machine"], deixis::machine_description());
  EXPECT_NE(md.find(" s on " + deixis::machine_description() + "."), std::string::npos);
  // Table I's notes say which encoder measured FMD, per hand (this random one has no manifest,
  // so its reconstruction errors are said to be unknown rather than invented).
  const std::string notes = j["tables"][0]["notes"].dump();
  for (const char* hand : {"FMD encoder, right hand", "FMD encoder, left hand"}) {
    EXPECT_NE(notes.find(hand), std::string::npos) << notes;
  }
  EXPECT_NE(notes.find("no manifest"), std::string::npos) << notes;
}

// Units of work run on several threads and are merged in order: the tables (Table II's timings
// aside) are the same for one thread and for three, row for row and value for value.
TEST_F(EvalRun, TheThreadCountDoesNotChangeTheTables) {
  ScratchDir dir;
  // The authors' deictic-only MoE pair only, so the comparison is quick even under ASan: its
  // chain has DIP and FMD but no DR or robustness runs, and the other rows are missing.
  for (const char* hand : {"right", "left"}) {
    fs::create_directories(dir.path() / hand);
    for (const char* file : {"MPNet(MoE)(DG)80.safetensors", "UGNet(MoE)(DG)120.safetensors"}) {
      fs::copy_file(deixis::testing::reference_dir() / "weights" / hand / file,
                    dir.path() / hand / file);
    }
  }
  EvalOptions o = quick_options();
  o.weights = {{"moe", dir.path()}};
  const auto tables_of = [&](int threads) {
    o.threads = threads;
    nlohmann::json j = nlohmann::json::parse(json(evaluate(o)));
    j.erase("wall_seconds");
    for (auto& t : j["tables"]) {
      if (t["id"] == "II") {
        t["rows"] = nullptr;  // measured times
      }
    }
    return j;
  };
  const nlohmann::json one = tables_of(1);
  const nlohmann::json three = tables_of(3);
  EXPECT_EQ(one, three);
  // And there is something to compare: the MoE row of Table I has HE for both subjects.
  bool found = false;
  for (const auto& r : one["tables"][0]["rows"]) {
    if (r["label"] == "MoE (DG)" && r["weights"] == "moe") {
      found = true;
      for (const char* subject : {"161", "173"}) {
        EXPECT_TRUE(r["per_subject"][subject][0].is_number()) << subject << ": " << r.dump();
      }
    }
  }
  EXPECT_TRUE(found) << one["tables"][0].dump();
}

// A network trained with its schedule compressed (deixis-train --compress-to; tools/train-set
// names it by its epochs) stands in for the full schedule's file, and its rows say so; two such
// files for one network are an error naming both.
TEST_F(EvalRun, ACompressedRunIsEvaluatedUnderItsOwnEpochs) {
  ScratchDir dir;
  const fs::path mine = dir.path() / "right";
  const fs::path authors = deixis::testing::reference_dir() / "weights/right";
  const EvalOptions o = renamed_pair(dir, "MPNet(MoE)(DG)80", "MPNet(MoE)(DG)80",
                                     "UGNet(MoE)(DG)120", "UGNet(MoE)(DG)12");
  const nlohmann::json j = nlohmann::json::parse(json(evaluate(o)));
  bool found = false;
  for (const auto& r : j["tables"][0]["rows"]) {
    EXPECT_NE(r["label"], "MoE (DG)") << "a compressed run's row must say its epochs";
    if (r["label"] == "MoE (DG) (UGNet: 12 of 120 epochs)" && r["weights"] == "short") {
      found = r["per_subject"]["161"][0].is_number();
    }
  }
  EXPECT_TRUE(found) << j["tables"][0].dump();

  // Both networks of the row with fewer epochs: the label names each.
  fs::rename(mine / "MPNet(MoE)(DG)80.safetensors", mine / "MPNet(MoE)(DG)40.safetensors");
  const nlohmann::json both = nlohmann::json::parse(json(evaluate(o)));
  found = false;
  for (const auto& r : both["tables"][0]["rows"]) {
    found |= r["label"] == "MoE (DG) (MPNet: 40 of 80 epochs; UGNet: 12 of 120 epochs)";
  }
  EXPECT_TRUE(found) << both["tables"][0].dump();

  // A network with other epochs in the other hand would split its row: refused, naming both.
  fs::create_directories(dir.path() / "left");
  fs::copy_file(authors / "UGNet(MoE)(DG)120.safetensors",
                dir.path() / "left/UGNet(MoE)(DG)120.safetensors");
  const std::string mixed = refusal(o, "a network with other epochs in each hand was not refused");
  EXPECT_NE(mixed.find("right/UGNet(MoE)(DG)12"), std::string::npos) << mixed;
  EXPECT_NE(mixed.find("left/UGNet(MoE)(DG)120"), std::string::npos) << mixed;
  fs::remove_all(dir.path() / "left");

  fs::copy_file(authors / "UGNet(MoE)(DG)120.safetensors", mine / "UGNet(MoE)(DG)13.safetensors");
  const std::string two = refusal(o, "two candidates for one network were not refused");
  EXPECT_NE(two.find("UGNet(MoE)(DG)12"), std::string::npos) << two;
  EXPECT_NE(two.find("UGNet(MoE)(DG)13"), std::string::npos) << two;
}

// The robustness rows of a MoE (AC) pair with fewer epochs carry its label, and Fig. 5 still
// plots them under it.
TEST_F(EvalRun, Figure5FollowsAMoePairWithFewerEpochs) {
#ifdef DEIXIS_SANITIZED
  // Figure 5's timed chains: 3 s in the release suite, which runs it, 130 s under ASan; the
  // evaluation's pieces run under ASan in ACompressedRunIsEvaluatedUnderItsOwnEpochs.
  GTEST_SKIP() << "the release suite runs it (130 s under ASan)";
#endif
  ScratchDir dir;
  const Report report = evaluate(renamed_pair(dir, "MPNet(MoE)(AC)80", "MPNet(MoE)(AC)80",
                                              "UGNet(MoE)(AC)120", "UGNet(MoE)(AC)60"));
  ASSERT_EQ(report.figure5.size(), 1u);
  EXPECT_EQ(report.figure5[0].label, "MoE (AC) (UGNet: 60 of 120 epochs), short weights");
  EXPECT_EQ(report.figure5[0].seconds.size(), 5u);
}

// A weight set with one hand (e.g. a run in progress exported with deixis-train --export-to) is
// evaluated on that hand's subjects; a subject of the other hand is refused, naming what is
// missing, before any work starts.
TEST_F(EvalRun, AOneHandedWeightSetServesItsHandsSubjectsOnly) {
  ScratchDir dir;
  fs::create_directories(dir.path() / "right");
  for (const char* file : {"MPNet(MoE)(DG)80.safetensors", "UGNet(MoE)(DG)120.safetensors"}) {
    fs::copy_file(deixis::testing::reference_dir() / "weights/right" / file,
                  dir.path() / "right" / file);
  }
  EvalOptions o = quick_options();
  o.weights = {{"half", dir.path()}};
  o.subjects = {"161"};
  const nlohmann::json j = nlohmann::json::parse(json(evaluate(o)));
  bool found = false;
  for (const auto& r : j["tables"][0]["rows"]) {
    if (r["label"] == "MoE (DG)" && r["weights"] == "half") {
      found = r["per_subject"]["161"][0].is_number();
    }
  }
  EXPECT_TRUE(found) << j["tables"][0].dump();

  o.subjects = {"161", "173"};
  const std::string what =
      refusal(o, "a left-handed subject was evaluated without left-hand networks");
  EXPECT_NE(what.find((dir.path() / "left").string()), std::string::npos) << what;
  EXPECT_NE(what.find("subject 173"), std::string::npos) << what;
}

TEST_F(EvalRun, RefusesTrainingSubjectData) {
  ScratchDir dir;
  capture::GenerateOptions g;
  g.out_dir = dir.path();
  g.sets = {"train"};
  g.count_scale = 0.01;
  capture::generate_datasets(g, [](const std::string&, std::size_t, std::size_t, std::size_t) {});
  try {
    TestSet::read(dir.path() / "train_right.safetensors");
    ADD_FAILURE() << "training data was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("training subject"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("train_right.safetensors"), std::string::npos);
  }
  // Renamed as if it were a test set: still refused (the metadata names the subject).
  fs::copy_file(dir.path() / "train_right.safetensors", dir.path() / "test_170.safetensors");
  EvalOptions o = quick_options();
  o.data_dir = dir.path();
  o.subjects = {"170"};
  EXPECT_THROW(evaluate(o), Error);
}

}  // namespace
}  // namespace deixis::eval
