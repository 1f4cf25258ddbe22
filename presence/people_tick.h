#pragma once
// One site tick of many remote people (docs/scaling.md): every person's avatar ticks as it would
// alone (RemoteAvatar::tick), except that the translators' networks run as batches across people
// (gesture/translator_batch.h: for the MoE networks, every expert's products for the whole batch
// as matrix products, then each person's blend), then touch contact and IK per person. Results
// are those of ticking each avatar alone, bit for bit (tests/presence/people_tick_test.cpp);
// nothing allocates once the buffers have held this many people.

#include <span>

#include "gesture/translator_batch.h"
#include "presence/remote_avatar.h"

namespace deixis::presence {

// One person's part of a site tick: their avatar and their frame for this tick (null: their
// frame was due and did not come; the avatar holds, like RemoteAvatar::tick(nullptr, …)).
struct PersonTick {
  RemoteAvatar* avatar = nullptr;
  const TrackingFrame* frame = nullptr;
};

// The working memory of tick_people (one per site, one thread).
class PeopleTickBuffers {
 public:
  // Sizes everything for `people` avatars running `mpnet` and `ugnet` (otherwise the first tick
  // of that many people does).
  void reserve(std::size_t people, const nn::Mpnet& mpnet, const nn::Ugnet& ugnet) {
    batch_.reserve(people, mpnet, ugnet);
  }
  TranslatorBatch& batch() { return batch_; }

 private:
  TranslatorBatch batch_;
};

// Ticks every person's avatar with this room's targets: afterwards each avatar's visible(),
// frame(), model_pose() … are what RemoteAvatar::tick would have left. Entries with a null
// avatar are skipped; an avatar must appear at most once.
void tick_people(std::span<const PersonTick> people, const LocalTargets& room,
                 PeopleTickBuffers& buffers);

}  // namespace deixis::presence
