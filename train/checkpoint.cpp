#include "train/checkpoint.h"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/io/safetensors.h"

namespace deixis::train {

namespace {

using nlohmann::json;

// NaN (no validation data) is stored as null: JSON has no NaN.
json number_or_null(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}

template <typename T>
T field(const json& object, const char* key, const std::string& where) {
  if (!object.contains(key)) {
    throw Error(where + ": field '" + key + "' missing");
  }
  try {
    return object.at(key).get<T>();
  } catch (const json::exception&) {
    throw Error(where + ": field '" + key + "' has the wrong type");
  }
}

double number_field(const json& object, const char* key, const std::string& where) {
  if (object.contains(key) && object.at(key).is_null()) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return field<double>(object, key, where);
}

}  // namespace

void write_checkpoint(const std::filesystem::path& path, const Checkpoint& c) {
  json history = json::array();
  for (const EpochReport& r : c.history) {
    history.push_back({{"epoch", r.epoch},
                       {"train_loss", number_or_null(r.train_loss)},
                       {"validation_loss", number_or_null(r.validation_loss)},
                       {"learning_rate", r.learning_rate},
                       {"teacher_forcing", r.teacher_forcing},
                       {"seconds", r.seconds}});
  }
  const json state = {{"fingerprint", c.fingerprint},
                      {"epoch", c.epoch},
                      {"batch", c.batch},
                      {"step", c.step},
                      {"loss_sum", c.loss_sum},
                      {"loss_count", c.loss_count},
                      {"epoch_seconds", c.epoch_seconds},
                      {"train_seconds", c.train_seconds},
                      {"history", history},
                      {"trainers", c.trainers}};
  SafetensorsWriter writer;
  const auto n = static_cast<std::int64_t>(c.parameters.size());
  writer.add_f32("parameters", {n}, c.parameters);
  writer.add_f32("exp_avg", {n}, c.exp_avg);
  writer.add_f32("exp_avg_sq", {n}, c.exp_avg_sq);
  writer.set_metadata("format", "deixis-train checkpoint 1");
  writer.set_metadata("state", state.dump());
  writer.write(path);
}

Checkpoint read_checkpoint(const std::filesystem::path& path) {
  const SafetensorsFile file = SafetensorsFile::read(path);
  const std::string where = file.source();
  if (file.metadata_value("format") != "deixis-train checkpoint 1") {
    throw Error(where + ": metadata 'format' is '" + file.metadata_value("format") +
                "', expected 'deixis-train checkpoint 1'");
  }
  json state;
  try {
    state = json::parse(file.metadata_value("state"));
  } catch (const json::exception& e) {
    throw Error(where + ": metadata 'state' is not valid JSON (" + e.what() + ")");
  }
  Checkpoint c;
  const std::string state_where = where + ": metadata 'state'";
  c.fingerprint = field<std::string>(state, "fingerprint", state_where);
  c.epoch = field<int>(state, "epoch", state_where);
  c.batch = field<std::int64_t>(state, "batch", state_where);
  c.step = field<std::int64_t>(state, "step", state_where);
  c.loss_sum = field<double>(state, "loss_sum", state_where);
  c.loss_count = field<std::int64_t>(state, "loss_count", state_where);
  c.epoch_seconds = field<double>(state, "epoch_seconds", state_where);
  c.train_seconds = field<double>(state, "train_seconds", state_where);
  if (c.epoch < 1 || c.batch < 0 || c.step < 0 || c.loss_count < 0) {
    throw Error(state_where + ": negative or zero epoch, batch, step or loss count");
  }
  const json history = state.contains("history") ? state.at("history") : json();
  if (!history.is_array()) {
    throw Error(state_where + ": field 'history' missing or not an array");
  }
  for (const json& entry : history) {
    const std::string entry_where = state_where + " history entry";
    EpochReport r;
    r.epoch = field<int>(entry, "epoch", entry_where);
    r.train_loss = number_field(entry, "train_loss", entry_where);
    r.validation_loss = number_field(entry, "validation_loss", entry_where);
    r.learning_rate = field<double>(entry, "learning_rate", entry_where);
    r.teacher_forcing = field<double>(entry, "teacher_forcing", entry_where);
    r.seconds = field<double>(entry, "seconds", entry_where);
    c.history.push_back(r);
  }
  if (!state.contains("trainers")) {
    if (c.step > 0) {
      c.trainers.emplace_back("unrecorded");  // written before checkpoints kept the list
    }
  } else {
    c.trainers = field<std::vector<std::string>>(state, "trainers", state_where);
  }
  const std::vector<std::int64_t>& shape = file.shape_of("parameters");
  if (shape.size() != 1) {
    throw Error(where + ": tensor 'parameters': expected one dimension, found " +
                shape_string(shape));
  }
  c.parameters = file.read_f32("parameters", shape);
  c.exp_avg = file.read_f32("exp_avg", shape);
  c.exp_avg_sq = file.read_f32("exp_avg_sq", shape);
  return c;
}

}  // namespace deixis::train
