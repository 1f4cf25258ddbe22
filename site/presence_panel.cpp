#include "site/presence_panel.h"

#include <algorithm>
#include <cstdio>

namespace deixis::site {

std::string_view session_state_words(const LivePeer& peer) {
  if (peer.in_room()) {
    return peer.connected() ? "in the room" : "entering the room";
  }
  return peer.connected() ? "connected" : "waiting for the other site";
}

void PresencePanel::set_line(std::size_t i, std::size_t length) {
  lines_[i] = std::string_view(text_[i].data(), std::min(length, kLineChars - 1));
}

void PresencePanel::update(double now, const LivePeer& peer, bool force) {
  if (built_ && !force && now - rebuilt_ < kRefresh) {
    return;
  }
  built_ = true;
  rebuilt_ = now;
  const std::size_t people = peer.list_people(people_);
  const std::size_t shown = std::min(people, kMaxPeople);
  const std::string_view state = session_state_words(peer);
  int n = std::snprintf(text_[0].data(), kLineChars, "Deixis: %.*s, %zu %s here",
                        static_cast<int>(state.size()), state.data(), people,
                        people == 1 ? "person" : "people");
  set_line(0, n < 0 ? 0 : static_cast<std::size_t>(n));
  count_ = 1;
  for (std::size_t k = 0; k < shown; ++k, ++count_) {
    set_line(count_, format_link_line(people_[k].site, people_[k].link, text_[count_]));
  }
  if (people > shown) {
    n = std::snprintf(text_[count_].data(), kLineChars, "and %zu more", people - shown);
    set_line(count_++, n < 0 ? 0 : static_cast<std::size_t>(n));
  }
}

}  // namespace deixis::site
