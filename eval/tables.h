#pragma once
// The evaluation's results laid out like the paper's Tables I–IV (plus the robustness table
// behind Fig. 5), each with a per-subject breakdown, as Markdown and JSON. A cell is a per-subject
// value or missing (n/a, with the reason in the table's notes); the row's value is the mean over
// the subjects that have one (the paper: "averaged over test subjects").

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace deixis::eval {

struct Column {
  std::string name;  // "HE"
  std::string unit;  // "°"
  int decimals = 2;
  bool lower_is_better = true;  // the header's ↓
};

struct TableRow {
  std::string label;    // "MoE (AC)"
  std::string weights;  // the weight set ("authors", "deixis"); empty for baselines
  // subject → one value per column (nullopt: not computed).
  std::map<std::string, std::vector<std::optional<double>>> per_subject;
  // Population standard deviation per column over every sample (FMD: subjects × trials).
  std::vector<std::optional<double>> spread;
  std::string note;  // shown in the row's label cell (e.g. why a row has no numbers)

  std::vector<std::optional<double>> mean(std::size_t columns) const;
};

struct Table {
  std::string id;     // "I"
  std::string title;  // the paper's caption
  std::vector<Column> columns;
  std::vector<TableRow> rows;
  std::vector<std::string> notes;
};

// Fig. 5: metric values (averaged over subjects) against missed-tracking duration.
struct Figure5Series {
  std::string label;
  std::vector<double> seconds;                // 0.2 … 1.0
  std::array<std::vector<double>, 4> values;  // MPJPE, MPJRE, MPJLVE, MPJAVE per duration
};

// One recording's following errors second by second (deixis eval --bvh), for one weight set:
// head cm, head °, hand cm, hand °; a second without free frames has none.
struct PerSecondSeries {
  std::string recording;
  std::string weights;
  std::array<std::vector<std::optional<double>>, 4> values;
};

// The real-motion section (deixis eval --bvh; eval/real_motion_eval.h): tables of its own, never
// mixed with the synthetic ones. Each row is a weight set; its per_subject map is keyed by
// recording, and the Markdown shows every recording's rows side by side.
struct RealMotionSection {
  std::vector<std::string> recordings;  // "01_01.bvh"
  std::vector<Table> tables;
  std::vector<PerSecondSeries> per_second;
  std::vector<std::string> notes;
};

struct Report {
  std::string command;
  std::string data_dir;
  bool quick = false;
  double wall_seconds = 0.0;
  std::string machine;                // where wall_seconds was spent (core/io/machine.h)
  std::vector<std::string> subjects;  // "161", "173 (L)"
  std::vector<Table> tables;
  std::vector<Figure5Series> figure5;
  std::vector<std::string> notes;
  RealMotionSection real_motion;  // empty unless --bvh
};

std::string markdown(const Report& report);
std::string json(const Report& report);

}  // namespace deixis::eval
