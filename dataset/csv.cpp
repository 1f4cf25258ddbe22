#include "dataset/csv.h"

#include <array>
#include <cstdio>
#include <string>

#include "core/error.h"

namespace deixis::dataset {

namespace {

constexpr std::array<const char*, 11> kFeatureNames = {
    "f_ET_H",    "f_FT_H",  "f_IT_R",    "f_FI",    "f_I",  "f_d",
    "f_theta_H", "f_phi_H", "f_theta_R", "f_phi_R", "f_r_R"};
constexpr std::array<const char*, 8> kEndEffectorNames = {"x_gaze",     "x_head_fwd", "x_head_up",
                                                          "x_head_pos", "x_hand_fwd", "x_hand_up",
                                                          "x_hand_pos", "x_tip"};

void vector_names(std::ostream& out, const std::string& name, int width) {
  for (int k = 0; k < width; ++k) {
    out << ',' << name << '_' << "xyzw"[k];
  }
}

void header(std::ostream& out) {
  out << "sequence,category,frame,time,valid,phase_key";
  write_tracking_column_names(out);
  const auto vec = [&](const std::string& name, int width) { vector_names(out, name, width); };
  out << ",head_target,hand_target";
  vec("head_target", 3);
  vec("hand_target", 3);
  out << ",label_gaze,label_deictic,label_idle";
  for (const char* f : kFeatureNames) {
    out << ',' << f;
  }
  for (const char* e : kEndEffectorNames) {
    vec(e, 3);
  }
  out << '\n';
}

void values(std::ostream& out, const std::vector<float>& v, std::size_t row, int width) {
  char buffer[32];
  for (int k = 0; k < width; ++k) {
    std::snprintf(buffer, sizeof buffer, ",%.6g",
                  static_cast<double>(
                      v[row * static_cast<std::size_t>(width) + static_cast<std::size_t>(k)]));
    out << buffer;
  }
}

}  // namespace

void write_tracking_column_names(std::ostream& out) {
  vector_names(out, "head", 3);
  vector_names(out, "head_q", 4);
  vector_names(out, "gaze", 3);
  for (const char* hand : {"left", "right"}) {
    vector_names(out, std::string(hand) + "_wrist", 3);
    vector_names(out, std::string(hand) + "_wrist_q", 4);
    vector_names(out, std::string(hand) + "_tip", 3);
  }
}

void write_csv(const Dataset& d, std::optional<std::size_t> sequence, std::ostream& out) {
  if (sequence && *sequence >= d.sequences()) {
    throw Error(d.source + ": no sequence " + std::to_string(*sequence) + " (the file has " +
                std::to_string(d.sequences()) + ")");
  }
  header(out);
  const std::size_t first = sequence ? *sequence : 0;
  const std::size_t last = sequence ? *sequence + 1 : d.sequences();
  for (std::size_t s = first; s < last; ++s) {
    const std::string category(category_name(static_cast<Category>(d.sequence_category[s])));
    for (std::size_t i = d.begin(s); i < d.end(s); ++i) {
      out << s << ',' << category << ',' << (i - d.begin(s));
      values(out, d.time, i, 1);
      out << ',' << static_cast<int>(d.valid[i]) << ',' << static_cast<int>(d.phase_key[i]);
      values(out, d.head_position, i, 3);
      values(out, d.head_rotation, i, 4);
      values(out, d.gaze, i, 3);
      for (std::size_t h = 0; h < 2; ++h) {
        values(out, d.wrist_position, 2 * i + h, 3);
        values(out, d.wrist_rotation, 2 * i + h, 4);
        values(out, d.index_tip, 2 * i + h, 3);
      }
      out << ',' << d.head_target_id[i] << ',' << d.hand_target_id[i];
      values(out, d.head_target_position, i, 3);
      values(out, d.hand_target_position, i, 3);
      values(out, d.labels, i, 3);
      values(out, d.mpnet_features, i, 11);
      values(out, d.end_effectors, i, 24);
      out << '\n';
    }
  }
}

}  // namespace deixis::dataset
