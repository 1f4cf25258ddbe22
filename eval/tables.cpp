#include "eval/tables.h"

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

namespace deixis::eval {

namespace {

std::string number(double v, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

std::string cell(const std::optional<double>& v, const std::optional<double>& spread,
                 int decimals) {
  if (!v) {
    return "n/a";
  }
  std::string s = number(*v, decimals);
  if (spread) {
    s += " ± " + number(*spread, decimals);
  }
  return s;
}

std::string header(const Table& t, const std::string& first) {
  std::string s = "| " + first + " | weights |";
  std::string rule = "|---|---|";
  for (const Column& c : t.columns) {
    s += " " + c.name + (c.unit.empty() ? "" : " (" + c.unit + ")") +
         (c.lower_is_better ? " ↓ |" : " |");
    rule += "---:|";
  }
  return s + "\n" + rule + "\n";
}

std::string label_of(const TableRow& r) {
  return r.note.empty() ? r.label : r.label + " — " + r.note;
}

void table_markdown(const Table& t, const std::vector<std::string>& subjects,
                    std::ostringstream& out) {
  out << "## Table " << t.id << ". " << t.title << "\n\n" << header(t, "row");
  for (const TableRow& r : t.rows) {
    const auto mean = r.mean(t.columns.size());
    out << "| " << label_of(r) << " | " << (r.weights.empty() ? "—" : r.weights) << " |";
    for (std::size_t c = 0; c < t.columns.size(); ++c) {
      const std::optional<double> spread = c < r.spread.size() ? r.spread[c] : std::nullopt;
      out << " " << cell(mean[c], spread, t.columns[c].decimals) << " |";
    }
    out << "\n";
  }
  out << "\n";
  for (const std::string& n : t.notes) {
    out << "- " << n << "\n";
  }
  std::ostringstream rows;
  for (const TableRow& r : t.rows) {
    for (const std::string& s : subjects) {
      const auto it = r.per_subject.find(s);
      if (it == r.per_subject.end()) {
        continue;
      }
      rows << "| " << r.label << ", " << s << " | " << (r.weights.empty() ? "—" : r.weights)
           << " |";
      for (std::size_t c = 0; c < t.columns.size(); ++c) {
        rows << " " << cell(it->second[c], std::nullopt, t.columns[c].decimals) << " |";
      }
      rows << "\n";
    }
  }
  // Table II is measured once per machine, not per subject: no empty breakdown for it.
  if (!rows.view().empty()) {
    out << "\n<details><summary>Table " << t.id << " per subject</summary>\n\n"
        << header(t, "row, subject") << rows.view() << "\n</details>\n";
  }
  out << "\n";
}

// The real-motion section: every recording's rows side by side, then each weight set's mean over
// the recordings when there are several.
void real_motion_markdown(const RealMotionSection& section, std::ostringstream& out) {
  out << "# Real motion (BVH)\n\n"
      << "Free-form motion of real people in the recordings below, with no labelled pointing: "
         "these figures say how the translator behaves on real movement, not how accurately it "
         "points (that accuracy is measured on the synthetic test subjects above, or by `deixis "
         "eval --data`). How each is computed: docs/eval.md#real-motion-bvh.\n\n";
  for (const std::string& n : section.notes) {
    out << "- " << n << "\n";
  }
  out << "\n";
  for (const Table& t : section.tables) {
    out << "## Table " << t.id << ". " << t.title << "\n\n" << header(t, "recording");
    for (const std::string& recording : section.recordings) {
      for (const TableRow& r : t.rows) {
        const auto it = r.per_subject.find(recording);
        if (it == r.per_subject.end()) {
          continue;
        }
        out << "| " << recording << " | " << (r.weights.empty() ? "—" : r.weights) << " |";
        for (std::size_t c = 0; c < t.columns.size(); ++c) {
          out << " " << cell(it->second[c], std::nullopt, t.columns[c].decimals) << " |";
        }
        out << "\n";
      }
    }
    for (const TableRow& r : t.rows) {
      if (section.recordings.size() < 2 || r.per_subject.empty()) {
        continue;
      }
      const auto mean = r.mean(t.columns.size());
      out << "| mean of " << r.per_subject.size() << " | " << (r.weights.empty() ? "—" : r.weights)
          << " |";
      for (std::size_t c = 0; c < t.columns.size(); ++c) {
        out << " " << cell(mean[c], std::nullopt, t.columns[c].decimals) << " |";
      }
      out << "\n";
    }
    out << "\n";
    for (const std::string& n : t.notes) {
      out << "- " << n << "\n";
    }
    out << "\n";
  }
}

nlohmann::json optional_json(const std::optional<double>& v) {
  return v && std::isfinite(*v) ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

nlohmann::json values_json(const std::vector<std::optional<double>>& values) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& v : values) {
    a.push_back(optional_json(v));
  }
  return a;
}

// `per`: the key of a row's breakdown ("per_subject", or "per_recording" for real motion).
nlohmann::json tables_json(const std::vector<Table>& tables, const char* per) {
  nlohmann::json out = nlohmann::json::array();
  for (const Table& t : tables) {
    nlohmann::json jt;
    jt["id"] = t.id;
    jt["title"] = t.title;
    jt["notes"] = t.notes;
    nlohmann::json columns = nlohmann::json::array();
    for (const Column& c : t.columns) {
      columns.push_back({{"name", c.name}, {"unit", c.unit}});
    }
    jt["columns"] = columns;
    nlohmann::json rows = nlohmann::json::array();
    for (const TableRow& r : t.rows) {
      nlohmann::json jr;
      jr["label"] = r.label;
      jr["weights"] = r.weights;
      jr["note"] = r.note;
      jr["mean"] = values_json(r.mean(t.columns.size()));
      jr["spread"] = values_json(r.spread);
      nlohmann::json breakdown = nlohmann::json::object();
      for (const auto& [key, values] : r.per_subject) {
        breakdown[key] = values_json(values);
      }
      jr[per] = breakdown;
      rows.push_back(jr);
    }
    jt["rows"] = rows;
    out.push_back(jt);
  }
  return out;
}

nlohmann::json real_motion_json(const RealMotionSection& section) {
  nlohmann::json j;
  j["recordings"] = section.recordings;
  j["notes"] = section.notes;
  j["tables"] = tables_json(section.tables, "per_recording");
  nlohmann::json series = nlohmann::json::array();
  for (const PerSecondSeries& s : section.per_second) {
    series.push_back({{"recording", s.recording},
                      {"weights", s.weights},
                      {"head_cm", values_json(s.values[0])},
                      {"head_deg", values_json(s.values[1])},
                      {"hand_cm", values_json(s.values[2])},
                      {"hand_deg", values_json(s.values[3])}});
  }
  j["following_per_second"] = series;
  return j;
}

}  // namespace

std::vector<std::optional<double>> TableRow::mean(std::size_t columns) const {
  std::vector<std::optional<double>> out(columns);
  for (std::size_t c = 0; c < columns; ++c) {
    double sum = 0.0;
    int n = 0;
    for (const auto& [subject, values] : per_subject) {
      if (c < values.size() && values[c]) {
        sum += *values[c];
        ++n;
      }
    }
    if (n > 0) {
      out[c] = sum / n;
    }
  }
  return out;
}

std::string markdown(const Report& report) {
  std::ostringstream out;
  if (report.tables.empty()) {
    out << "# Deixis evaluation\n\nProduced by `" << report.command << "` in "
        << number(report.wall_seconds, 1) << " s on " << report.machine
        << ". Real motion only (--bvh without --data): no synthetic tables.\n\n";
    real_motion_markdown(report.real_motion, out);
    return out.str();
  }
  out << "# Deixis evaluation"
      << (report.quick ? " (--quick: a tiny sample, not the protocol)" : "") << "\n\n"
      << "Produced by `" << report.command << "` on `" << report.data_dir << "` in "
      << number(report.wall_seconds, 1) << " s on " << report.machine << ". Test subjects:";
  for (const std::string& s : report.subjects) {
    out << " " << s;
  }
  out << ". Values are means over subjects (docs/eval.md says how each is computed); ↓ lower "
         "is better.\n\n";
  for (const std::string& n : report.notes) {
    out << "- " << n << "\n";
  }
  out << "\n";
  for (const Table& t : report.tables) {
    table_markdown(t, report.subjects, out);
  }
  if (!report.figure5.empty()) {
    out << "## Fig. 5. Impact of missed tracking duration on motion quality\n\n"
        << "![Fig. 5](fig5.png)\n\n";
  }
  if (!report.real_motion.recordings.empty()) {
    real_motion_markdown(report.real_motion, out);
  }
  return out.str();
}

std::string json(const Report& report) {
  nlohmann::json j;
  j["command"] = report.command;
  j["data"] = report.data_dir;
  j["quick"] = report.quick;
  j["wall_seconds"] = report.wall_seconds;
  j["machine"] = report.machine;
  j["subjects"] = report.subjects;
  j["notes"] = report.notes;
  j["tables"] = tables_json(report.tables, "per_subject");
  nlohmann::json fig = nlohmann::json::array();
  for (const Figure5Series& s : report.figure5) {
    fig.push_back({{"label", s.label},
                   {"seconds", s.seconds},
                   {"MPJPE_cm", s.values[0]},
                   {"MPJRE_deg", s.values[1]},
                   {"MPJLVE_cm_s", s.values[2]},
                   {"MPJAVE_deg_s", s.values[3]}});
  }
  j["figure5"] = fig;
  if (!report.real_motion.recordings.empty()) {
    j["real_motion"] = real_motion_json(report.real_motion);
  }
  return j.dump(2) + "\n";
}

}  // namespace deixis::eval
