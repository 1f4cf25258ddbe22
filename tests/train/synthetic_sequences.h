#pragma once
// Small, learnable sequences for the training tests: smooth features whose progression labels
// are a function of them, and a pose that moves smoothly, so a few optimiser steps must lower
// the loss. Not motion data: the synthetic capture (capture/) makes those.

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/target_map.h"
#include "dataset/dataset.h"
#include "train/clips.h"

namespace deixis::train::test_data {

inline std::vector<Sequence> synthetic_sequences(int count, int frames, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> phase(0.0f, 6.28f);
  std::vector<Sequence> out;
  for (int s = 0; s < count; ++s) {
    Sequence seq;
    seq.category = static_cast<Category>(s % kCategoryCount);
    seq.frames = frames;
    const float ph = phase(rng);
    for (int f = 0; f < frames; ++f) {
      const float t = static_cast<float>(f) / 30.0f;
      for (int k = 0; k < kFeatureColumns; ++k) {
        seq.features.push_back(std::cos(t * static_cast<float>(k + 1) * 0.5f + ph));
      }
      const float gaze = std::clamp(std::sin(t + ph), 0.0f, 1.0f);
      const float deictic = std::clamp(std::sin(0.7f * t + ph), 0.0f, 1.0f);
      seq.progression.insert(seq.progression.end(),
                             {gaze, deictic, gaze == 0.0f && deictic == 0.0f ? 1.0f : 0.0f});
      for (int k = 0; k < kPoseColumns; ++k) {
        seq.pose.push_back(0.3f * std::sin(0.5f * t * static_cast<float>(k + 1) + ph));
      }
    }
    out.push_back(std::move(seq));
  }
  return out;
}

// The sequences as a dataset file (docs/dataset.md): their network columns and labels, a person
// standing still with one target in front of them (training reads only the network columns).
inline dataset::DatasetWriter dataset_writer(const std::vector<Sequence>& sequences) {
  dataset::DatasetWriter writer;
  writer.set_metadata("deictic_hand", "right");
  const std::vector<TargetObject> targets = {
      {1, "target", TargetKind::kSphere, Vec3(0.0f, 1.2f, -1.0f), Vec3::Constant(0.1f)}};
  for (const Sequence& s : sequences) {
    std::vector<TrackingFrame> frames(static_cast<std::size_t>(s.frames));
    std::vector<dataset::Labels> labels(frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i) {
      frames[i].time = static_cast<double>(i) / 30.0;
      std::copy_n(s.progression.begin() + static_cast<std::ptrdiff_t>(i * kProgressionColumns),
                  kProgressionColumns, labels[i].begin());
    }
    const std::vector<std::uint8_t> phase_keys(frames.size(), 0);
    dataset::SequenceRows rows;
    rows.category = s.category;
    rows.source = writer.next_index();
    rows.targets = targets;
    rows.frames = frames;
    rows.labels = labels;
    rows.phase_keys = phase_keys;
    rows.mpnet_features = s.features;
    rows.end_effectors = s.pose;
    writer.add(rows);
  }
  return writer;
}

}  // namespace deixis::train::test_data
