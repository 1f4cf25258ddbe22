#include "train/manifest.h"

#include <sodium.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <span>

#include "build_commit.h"  // generated: DEIXIS_BUILD_COMMIT
#include "core/error.h"
#include "core/io/atomic_file.h"

namespace deixis::train {

namespace {

using nlohmann::json;

json number_or_null(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}

std::string hex(const unsigned char* bytes, std::size_t n) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s;
  for (std::size_t i = 0; i < n; ++i) {
    s += kDigits[bytes[i] >> 4];
    s += kDigits[bytes[i] & 15];
  }
  return s;
}

}  // namespace

std::string sha256_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw Error(path.string() + ": cannot open for hashing");
  }
  crypto_hash_sha256_state state;
  crypto_hash_sha256_init(&state);
  std::array<char, 1 << 16> buffer{};
  while (in) {
    in.read(buffer.data(), buffer.size());
    const std::streamsize n = in.gcount();
    if (n > 0) {
      crypto_hash_sha256_update(&state, reinterpret_cast<const unsigned char*>(buffer.data()),
                                static_cast<unsigned long long>(n));
    }
  }
  std::array<unsigned char, crypto_hash_sha256_BYTES> digest{};
  crypto_hash_sha256_final(&state, digest.data());
  return hex(digest.data(), digest.size());
}

std::string dataset_hash(const std::vector<std::filesystem::path>& files) {
  std::string joined;
  for (const auto& f : files) {
    joined += sha256_file(f);
  }
  std::array<unsigned char, crypto_hash_sha256_BYTES> digest{};
  crypto_hash_sha256(digest.data(), reinterpret_cast<const unsigned char*>(joined.data()),
                     joined.size());
  return hex(digest.data(), digest.size());
}

std::string build_commit() {
  return DEIXIS_BUILD_COMMIT;
}

void write_manifest(const std::filesystem::path& path, const Manifest& m) {
  json history = json::array();
  for (const EpochReport& r : m.history) {
    history.push_back({{"epoch", r.epoch},
                       {"train_loss", number_or_null(r.train_loss)},
                       {"validation_loss", number_or_null(r.validation_loss)},
                       {"learning_rate", r.learning_rate},
                       {"teacher_forcing", r.teacher_forcing},
                       {"seconds", r.seconds}});
  }
  const EpochReport last = m.history.empty() ? EpochReport{} : m.history.back();
  const json schedule = {{"epochs", m.schedule.epochs},
                         {"batch_size", m.schedule.batch_size},
                         {"learning_rate", m.schedule.learning_rate},
                         {"learning_rate_decay", m.schedule.learning_rate_decay},
                         {"weight_decay", m.schedule.weight_decay},
                         {"scheduled_sampling", m.schedule.scheduled_sampling},
                         {"teacher_forcing_epochs", m.schedule.teacher_forcing_epochs},
                         {"autoregressive_from_epoch", m.schedule.autoregressive_from_epoch},
                         {"clip_rows", kClipRows},
                         {"clip_hop", kClipHop},
                         {"windows_per_clip", kWindowsPerClip}};
  json manifest = {{"weights", m.weights_file},
                   {"network", m.network},
                   {"variant", m.variant},
                   {"hand", m.hand},
                   {"command_line", m.command_line},
                   {"seed", m.seed},
                   {"threads", m.threads},
                   {"commit", m.commit},
                   {"trained_by", m.trained_by},
                   {"dataset_hash", m.dataset_hash},
                   {"dataset_files", m.dataset_files},
                   {"train_examples", m.train_examples},
                   {"validation_examples", m.validation_examples},
                   {"parameter_count", m.parameter_count},
                   {"schedule", schedule},
                   {"wall_seconds", m.train_seconds},
                   {"final_train_loss", number_or_null(last.train_loss)},
                   {"final_validation_loss", number_or_null(last.validation_loss)},
                   {"history", history},
                   {"complete", m.complete}};
  if (m.initial_weights) {
    manifest["initial_weights"] = {{"file", m.initial_weights->file},
                                   {"sha256", m.initial_weights->sha256}};
  }
  if (!m.complete) {
    manifest["stopped_at"] = {{"epoch", m.stopped_at_epoch}, {"batch", m.stopped_at_batch}};
  }
  if (m.training_reconstruction || m.validation_reconstruction) {
    // Per frame, head and hand averaged: the figures the paper gives for its encoder (§V).
    auto entry = [&](const std::optional<ReconstructionError>& e) {
      return e ? json{{"position_cm", number_or_null(e->position_cm)},
                      {"rotation_deg", number_or_null(e->rotation_deg)},
                      {"segments", e->segments}}
               : json(nullptr);
    };
    manifest["reconstruction"] = {{"training", entry(m.training_reconstruction)},
                                  {"validation", entry(m.validation_reconstruction)}};
  }
  const std::string text = manifest.dump(2) + "\n";
  write_file_atomically(path, std::as_bytes(std::span(text)));
}

}  // namespace deixis::train
