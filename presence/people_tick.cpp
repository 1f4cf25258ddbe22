#include "presence/people_tick.h"

namespace deixis::presence {

void tick_people(std::span<const PersonTick> people, const LocalTargets& room,
                 PeopleTickBuffers& buffers) {
  TranslatorBatch& batch = buffers.batch();
  for (const PersonTick& person : people) {
    if (person.avatar != nullptr && person.avatar->begin_tick(person.frame, room)) {
      batch.add(person.avatar->translator());
    }
  }
  batch.run();
  for (const PersonTick& person : people) {
    if (person.avatar != nullptr) {
      person.avatar->finish_tick(room);
    }
  }
}

}  // namespace deixis::presence
