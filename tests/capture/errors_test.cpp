// Bad parameters and corrupt files give clear errors naming what and where.

#include <gtest/gtest.h>

#include "capture/generate.h"
#include "capture/script.h"
#include "capture/tracker_noise.h"
#include "core/error.h"
#include "core/io/safetensors.h"
#include "dataset/dataset.h"
#include "error_of.h"
#include "test_support.h"

namespace deixis::capture {
namespace {

namespace fs = std::filesystem;

using deixis::testing::error_of;

TEST(CaptureErrors, BadSubjectParametersNameTheSubjectAndField) {
  struct Case {
    void (*edit)(Subject&);
    const char* expected;
  };
  const Case cases[] = {
      {[](Subject& s) { s.height = -1.70f; }, "subject 'x': height -1.700 m is not in"},
      {[](Subject& s) { s.height = 0.0f / 0.0f; }, "height"},
      {[](Subject& s) { s.arm_length = 0.2f; }, "arm_length 0.200 m"},
      {[](Subject& s) { s.arm_length = 1.0f; }, "arm_length/height"},
      {[](Subject& s) { s.shoulder_width = 0.9f; }, "shoulder_width"},
      {[](Subject& s) { s.speed = 0.0f; }, "speed"},
      {[](Subject& s) { s.style.arm_extension = 1.2f; }, "style.arm_extension"},
      {[](Subject& s) { s.style.head_share = -0.1f; }, "style.head_share"},
      {[](Subject& s) { s.name.clear(); }, "empty name"},
  };
  for (const Case& c : cases) {
    Subject s = find_subject("170");
    s.name.assign(1, 'x');  // not = "x": GCC 12 -O3 reports a false -Wrestrict there
    c.edit(s);
    const std::string message = error_of([&] { perform(s, Category::kPointingSingle, 1); });
    EXPECT_NE(message.find(c.expected), std::string::npos) << message;
  }
}

TEST(CaptureErrors, UnknownNamesListTheKnownOnes) {
  std::string m = error_of([] { dataset::parse_category("pointing-twice"); });
  EXPECT_NE(m.find("unknown category 'pointing-twice'"), std::string::npos) << m;
  EXPECT_NE(m.find("touching-transition"), std::string::npos) << m;
  m = error_of([] { find_subject("999"); });
  EXPECT_NE(m.find("unknown subject '999'"), std::string::npos) << m;
  EXPECT_NE(m.find("161"), std::string::npos) << m;
  m = error_of([] { tracker_noise("loud"); });
  EXPECT_NE(m.find("none, mocap, headset"), std::string::npos) << m;
}

TEST(CaptureErrors, GenerateRejectsBadOptions) {
  deixis::testing::ScratchDir dir;
  const GenerateProgress quiet = [](const std::string&, std::size_t, std::size_t, std::size_t) {};
  GenerateOptions o;
  o.out_dir = dir.path();
  o.sets = {"training"};
  EXPECT_NE(error_of([&] { generate_datasets(o, quiet); }).find("unknown set 'training'"),
            std::string::npos);
  o.sets = {"test"};
  o.subjects = {"170"};  // the training subject is in no test set
  EXPECT_NE(error_of([&] { generate_datasets(o, quiet); }).find("nothing to generate"),
            std::string::npos);
  o.subjects = {"161"};
  o.count_scale = -1;
  EXPECT_NE(error_of([&] { generate_datasets(o, quiet); }).find("count scale"), std::string::npos);
  o.count_scale = 0.01;
  o.test_noise = "quiet";
  EXPECT_NE(error_of([&] { generate_datasets(o, quiet); }).find("unknown tracker noise 'quiet'"),
            std::string::npos);
  EXPECT_TRUE(fs::is_empty(dir.path()));  // nothing half-written
}

TEST(CaptureErrors, DatasetReaderRejectsOtherAndCorruptFiles) {
  deixis::testing::ScratchDir dir;
  GenerateOptions o;
  o.out_dir = dir.path();
  o.sets = {"test"};
  o.subjects = {"161"};
  o.count_scale = 0.01;
  generate_datasets(o, [](const std::string&, std::size_t, std::size_t, std::size_t) {});
  const fs::path good = dir.path() / "test_161.safetensors";
  const SafetensorsFile original = SafetensorsFile::read(good);

  // Rewrites the file with one tensor replaced (or dropped) and one metadata entry changed.
  auto rewrite = [&](const std::string& replace, const std::vector<float>* values,
                     const std::string& schema) {
    SafetensorsWriter w;
    for (const auto& [key, value] : original.metadata()) {
      w.set_metadata(key, key == "schema" ? schema : value);
    }
    for (const TensorInfo& t : original.tensors()) {
      if (t.name != replace) {
        w.add(t.name, t.dtype, t.shape, original.bytes(t));
      } else if (values) {
        w.add_f32(t.name, t.shape, *values);
      }
    }
    const fs::path bad = dir.path() / "bad.safetensors";
    w.write(bad);
    return error_of([&] { dataset::Dataset::read(bad); });
  };
  EXPECT_NE(rewrite("", nullptr, "something-else").find("not a capture dataset"),
            std::string::npos);
  EXPECT_NE(rewrite("mpnet_features", nullptr, dataset::kSchema).find("mpnet_features"),
            std::string::npos);
  std::vector<float> labels = original.read_f32("labels", original.shape_of("labels"));
  labels[3 * 10 + 2] = 1.5f;
  const std::string m = rewrite("labels", &labels, dataset::kSchema);
  EXPECT_NE(m.find("tensor 'labels': value 1.5"), std::string::npos) << m;
  EXPECT_NE(m.find("frame 10"), std::string::npos) << m;
  EXPECT_NE(m.find("bad.safetensors"), std::string::npos) << m;
}

}  // namespace
}  // namespace deixis::capture
