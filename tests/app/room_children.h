#pragma once
// Rooms of several people as real processes (rooms_process_test, rooms_lifecycle_test): the
// command line of a site joining a relay room, what its session.json says of the people it saw,
// the passphrase each child inherits, counting what a child logged. Built on deixis_child.h; every
// wait is bounded.

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "app/deixis_child.h"

namespace deixis::app {

using json = nlohmann::json;

// A site (`site_file`: its config) that joins room `room` on the relay at `port`, for `seconds`,
// writing into `out`.
inline std::vector<std::string> join_args(int port, const std::string& room,
                                          const std::filesystem::path& site_file,
                                          const std::filesystem::path& out, double seconds) {
  return {"join",
          "--connect",
          "127.0.0.1:" + std::to_string(port),
          "--room",
          room,
          "--site",
          site_file.string(),
          "--no-video",
          "--seconds",
          std::to_string(seconds),
          "-o",
          out.string(),
          "--weights-dir",
          weights_dir(),
          "--wait",
          "20"};
}

// The same with one of the demo's site files (assets/sites/`site_file`).
inline std::vector<std::string> join_args(int port, const std::string& room, const char* site_file,
                                          const std::filesystem::path& out, double seconds) {
  return join_args(port, room, site(site_file), out, seconds);
}

inline json session_of(const std::filesystem::path& out) {
  std::ifstream in(out / "session.json");
  EXPECT_TRUE(in) << (out / "session.json");
  return in ? json::parse(in) : json();
}

// The people a session.json lists, by site name.
inline std::map<std::string, json> people_of(const json& session) {
  std::map<std::string, json> people;
  if (session.contains("people")) {
    for (const json& p : session["people"]) {
      people[p["site"].get<std::string>()] = p;
    }
  }
  return people;
}

// The passphrase reaches a site through DEIXIS_PASSPHRASE (never its command line); each child
// inherits the value set when it starts.
inline void set_passphrase(const char* passphrase) {
  if (passphrase == nullptr) {
    unsetenv("DEIXIS_PASSPHRASE");
  } else {
    setenv("DEIXIS_PASSPHRASE", passphrase, 1);
  }
}

// Every site ends well, then the relay, on SIGTERM.
inline void finish(Deixis& relay, std::initializer_list<Deixis*> sites) {
  for (Deixis* site : sites) {
    EXPECT_EQ(site->wait(), 0) << site->err();
  }
  set_passphrase(nullptr);
  relay.send_signal(SIGTERM);
  EXPECT_EQ(relay.wait(), 0) << relay.err();
}

// How many times `text` occurs in what the child wrote so far (standard output and error).
inline int count_of(const Deixis& child, const std::string& text) {
  int n = 0;
  for (const std::string* s : {&child.out(), &child.err()}) {
    for (std::size_t at = s->find(text); at != std::string::npos; at = s->find(text, at + 1)) {
      ++n;
    }
  }
  return n;
}

// Reads the child's output until `text` occurred `times` times (true), or it ends or `seconds`
// pass (false).
inline bool wait_for_count(Deixis& child, const std::string& text, int times, double seconds) {
  const auto end = Clock::now() + std::chrono::duration<double>(seconds);
  while (count_of(child, text) < times) {
    if (Clock::now() >= end) {
      return false;
    }
    // A text no child writes: reads for 50 ms (at once false when the child's output ended,
    // which then cannot change: wait the 50 ms rather than spin).
    const auto before = Clock::now();
    if (!child.wait_for_text("\x01 (never written)", 0.05) &&
        Clock::now() - before < std::chrono::milliseconds(40)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
  return true;
}

}  // namespace deixis::app
