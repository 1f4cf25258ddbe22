#include "core/io/safetensors.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <map>
#include <ostream>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "test_support.h"

namespace deixis {
namespace {

using namespace std::string_view_literals;
namespace fs = std::filesystem;
using deixis::testing::ScratchDir;

// ---- helpers -----------------------------------------------------------------------------------

std::vector<std::byte> bytes_of(std::string_view text) {
  const auto bytes = std::as_bytes(std::span<const char>(text));
  return {bytes.begin(), bytes.end()};
}

template <typename T>
std::vector<std::byte> bytes_of_values(const std::vector<T>& values) {
  const auto bytes = std::as_bytes(std::span<const T>(values));
  return {bytes.begin(), bytes.end()};
}

// A safetensors file from its parts. `header_length` is what the 8-byte length field claims; it is
// separate from `header` so that corruption cases can make the two disagree.
std::vector<std::byte> assemble(std::uint64_t header_length, std::string_view header,
                                std::span<const std::byte> data) {
  std::vector<std::byte> file;
  for (int i = 0; i < 8; ++i) {
    file.push_back(static_cast<std::byte>((header_length >> (8 * i)) & 0xff));
  }
  const std::vector<std::byte> header_bytes = bytes_of(header);
  file.insert(file.end(), header_bytes.begin(), header_bytes.end());
  file.insert(file.end(), data.begin(), data.end());
  return file;
}

// Finite, distinct values, each recognisable by its index.
std::vector<float> ramp(std::size_t count, float start, float step) {
  std::vector<float> values(count);
  for (std::size_t i = 0; i < count; ++i) {
    values[i] = start + step * static_cast<float>(i);
  }
  return values;
}

// The valid file every corruption case starts from: weight F32 [2, 3] in data bytes [0, 24), bias
// F32 [3] in [24, 36), and one metadata entry. Written by hand (not by SafetensorsWriter) so that
// each case below reads as "this header, with this one thing changed".
constexpr std::string_view kValidHeader =
    R"({"__metadata__":{"format":"pt"},)"
    R"("weight":{"dtype":"F32","shape":[2,3],"data_offsets":[0,24]},)"
    R"("bias":{"dtype":"F32","shape":[3],"data_offsets":[24,36]}})";

std::vector<std::byte> valid_data() {
  return bytes_of_values(ramp(9, -1.0f, 0.25f));
}

std::vector<std::byte> file_with_header(std::string_view header, std::span<const std::byte> data) {
  return assemble(header.size(), header, data);
}
std::vector<std::byte> file_with_header(std::string_view header) {
  return file_with_header(header, valid_data());
}
std::vector<std::byte> valid_file() {
  return file_with_header(kValidHeader);
}

// kValidHeader with each edit's `from` (which must occur exactly once) replaced by its `to`. A
// typo in `from` would silently test the valid file, so it throws instead.
struct HeaderEdit {
  std::string_view from;
  std::string_view to;
};
std::string edited_header(std::initializer_list<HeaderEdit> edits) {
  std::string header(kValidHeader);
  for (const HeaderEdit& edit : edits) {
    const std::size_t at = header.find(edit.from);
    if (at == std::string::npos || header.find(edit.from, at + 1) != std::string::npos) {
      throw std::logic_error("edited_header: '" + std::string(edit.from) +
                             "' must occur exactly once in the header");
    }
    header.replace(at, edit.from.size(), edit.to);
  }
  return header;
}
std::string edited_header(std::string_view from, std::string_view to) {
  return edited_header({{from, to}});
}

// A data section of `data_size` bytes of finite floats, for cases that change its length.
std::vector<std::byte> with_data(std::size_t data_size) {
  return bytes_of_values(ramp(data_size / 4, 0.5f, 0.5f));
}

// Runs `action`, which must throw deixis::Error, and returns the message ("" if it did not throw).
template <typename Action>
std::string error_message(Action&& action) {
  try {
    action();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a deixis::Error, nothing was thrown";
  return "";
}

// The error message `message` contains `phrase`; on failure gtest prints both.
#define EXPECT_CONTAINS(message, phrase) \
  EXPECT_PRED_FORMAT2(::testing::IsSubstring, phrase, message)

// ---- the valid base file -----------------------------------------------------------------------

TEST(SafetensorsBaseFile, IsAcceptedSoThatEachCorruptionIsTheOnlyFault) {
  const SafetensorsFile file = SafetensorsFile::from_bytes("base.safetensors", valid_file());
  ASSERT_EQ(file.tensors().size(), 2u);
  EXPECT_EQ(file.tensors()[0].name, "weight");  // in the order of their data
  EXPECT_EQ(file.tensors()[1].name, "bias");
  EXPECT_EQ(file.metadata_value("format"), "pt");
  const std::vector<float> all = ramp(9, -1.0f, 0.25f);
  EXPECT_EQ(file.read_f32("weight", std::vector<std::int64_t>{2, 3}),
            std::vector<float>(all.begin(), all.begin() + 6));
  EXPECT_EQ(file.read_f32("bias", std::vector<std::int64_t>{3}),
            std::vector<float>(all.begin() + 6, all.end()));
}

// ---- round trips -------------------------------------------------------------------------------

TEST(SafetensorsRoundTrip, NamesDtypesShapesValuesAndMetadataSurvive) {
  const std::vector<float> weights = ramp(12, -3.0f, 0.5f);
  const std::vector<double> reference = {0.0,
                                         -0.0,
                                         1.0 / 3.0,
                                         -2.5e-300,
                                         std::numeric_limits<double>::denorm_min(),
                                         std::numeric_limits<double>::max(),
                                         std::numeric_limits<double>::lowest(),
                                         123456.789};
  const std::vector<std::int64_t> indices = {0, -1, 42, std::numeric_limits<std::int64_t>::min(),
                                             std::numeric_limits<std::int64_t>::max()};
  SafetensorsWriter writer;
  writer.add_f32("encoder.weight", {3, 4}, weights);
  writer.add_f64("reference_output", {2, 2, 2}, reference);
  writer.add_i64("joint_indices", {5}, indices);
  writer.set_metadata("format", "pt");
  writer.set_metadata("note", "quotes \" backslash \\ newline \n unicode \xc3\xa9");

  const SafetensorsFile file = SafetensorsFile::from_bytes("trip.safetensors", writer.serialize());
  ASSERT_EQ(file.tensors().size(), 3u);
  // The writer's order is the file's order.
  EXPECT_EQ(file.tensors()[0].name, "encoder.weight");
  EXPECT_EQ(file.tensors()[1].name, "reference_output");
  EXPECT_EQ(file.tensors()[2].name, "joint_indices");
  EXPECT_EQ(file.tensors()[0].dtype, DType::kF32);
  EXPECT_EQ(file.tensors()[1].dtype, DType::kF64);
  EXPECT_EQ(file.tensors()[2].dtype, DType::kI64);
  EXPECT_EQ(file.shape_of("encoder.weight"), (std::vector<std::int64_t>{3, 4}));
  EXPECT_EQ(file.shape_of("reference_output"), (std::vector<std::int64_t>{2, 2, 2}));
  EXPECT_EQ(file.shape_of("joint_indices"), (std::vector<std::int64_t>{5}));

  EXPECT_EQ(file.read_f32("encoder.weight", std::vector<std::int64_t>{3, 4}), weights);
  const std::vector<double> reference_read =
      file.read_f64("reference_output", std::vector<std::int64_t>{2, 2, 2});
  ASSERT_EQ(reference_read.size(), reference.size());
  // Bit for bit, so that -0.0 and the denormal are checked too.
  EXPECT_EQ(std::memcmp(reference_read.data(), reference.data(), 8 * reference.size()), 0);
  const TensorInfo& index_tensor =
      file.require("joint_indices", DType::kI64, std::vector<std::int64_t>{5});
  std::vector<std::int64_t> indices_read(index_tensor.numel());
  const auto index_bytes = file.bytes(index_tensor);
  ASSERT_EQ(index_bytes.size(), 8 * indices.size());
  std::memcpy(indices_read.data(), index_bytes.data(), index_bytes.size());
  EXPECT_EQ(indices_read, indices);

  EXPECT_EQ(file.metadata(),
            (std::map<std::string, std::string>{
                {"format", "pt"}, {"note", "quotes \" backslash \\ newline \n unicode \xc3\xa9"}}));
}

TEST(SafetensorsRoundTrip, EveryDtypeKeepsItsBytes) {
  const DType all[] = {DType::kBool, DType::kU8,   DType::kI8,  DType::kI16, DType::kU16,
                       DType::kF16,  DType::kBF16, DType::kI32, DType::kU32, DType::kF32,
                       DType::kF64,  DType::kI64,  DType::kU64};
  SafetensorsWriter writer;
  std::vector<std::vector<std::byte>> payloads;
  for (const DType dtype : all) {
    ASSERT_GT(dtype_size(dtype), 0u) << dtype_name(dtype);
    std::vector<std::byte> payload(3 * dtype_size(dtype));
    for (std::size_t i = 0; i < payload.size(); ++i) {
      payload[i] = static_cast<std::byte>(payload.size() * 16 + i);
    }
    writer.add("t_" + std::string(dtype_name(dtype)), dtype, {3}, payload);
    payloads.push_back(payload);
  }
  const SafetensorsFile file =
      SafetensorsFile::from_bytes("dtypes.safetensors", writer.serialize());
  ASSERT_EQ(file.tensors().size(), std::size(all));
  for (std::size_t i = 0; i < std::size(all); ++i) {
    const std::string name = "t_" + std::string(dtype_name(all[i]));
    const TensorInfo& t = file.require(name, all[i], std::vector<std::int64_t>{3});
    const auto stored = file.bytes(t);
    EXPECT_TRUE(std::equal(stored.begin(), stored.end(), payloads[i].begin(), payloads[i].end()))
        << name;
  }
}

TEST(SafetensorsRoundTrip, ZeroSizeTensorsAnywhereInTheFile) {
  const std::vector<float> middle = ramp(4, 1.0f, 1.0f);
  SafetensorsWriter writer;
  writer.add_f32("empty_first", {0}, {});
  writer.add_f32("empty_matrix", {3, 0}, {});
  writer.add_f32("middle", {2, 2}, middle);
  writer.add_f64("empty_last", {0, 5}, {});
  const SafetensorsFile file = SafetensorsFile::from_bytes("empty.safetensors", writer.serialize());
  ASSERT_EQ(file.tensors().size(), 4u);
  EXPECT_TRUE(file.read_f32("empty_first", std::vector<std::int64_t>{0}).empty());
  EXPECT_TRUE(file.read_f32("empty_matrix", std::vector<std::int64_t>{3, 0}).empty());
  EXPECT_EQ(file.read_f32("middle", std::vector<std::int64_t>{2, 2}), middle);
  EXPECT_TRUE(file.read_f64("empty_last", std::vector<std::int64_t>{0, 5}).empty());
  EXPECT_EQ(file.require("empty_matrix", DType::kF32, std::vector<std::int64_t>{3, 0}).numel(), 0u);
  std::vector<float> nothing;
  file.copy_f32("empty_first", std::vector<std::int64_t>{0}, nothing);
}

TEST(SafetensorsRoundTrip, FileWithNoTensorsAtAll) {
  SafetensorsWriter writer;
  writer.set_metadata("only", "metadata");
  const SafetensorsFile file = SafetensorsFile::from_bytes("none.safetensors", writer.serialize());
  EXPECT_TRUE(file.tensors().empty());
  EXPECT_EQ(file.metadata_value("only"), "metadata");
  const SafetensorsFile bare =
      SafetensorsFile::from_bytes("bare.safetensors", SafetensorsWriter().serialize());
  EXPECT_TRUE(bare.tensors().empty());
  EXPECT_TRUE(bare.metadata().empty());
}

TEST(SafetensorsRoundTrip, RankZeroTensorHoldsOneElement) {
  const float scale = 0.125f;
  const double temperature = 36.6;
  SafetensorsWriter writer;
  writer.add_f32("scale", {}, std::span<const float>(&scale, 1));
  writer.add_f64("temperature", {}, std::span<const double>(&temperature, 1));
  const SafetensorsFile file =
      SafetensorsFile::from_bytes("scalar.safetensors", writer.serialize());
  EXPECT_TRUE(file.shape_of("scale").empty());
  EXPECT_EQ(file.require("scale", DType::kF32, {}).numel(), 1u);
  EXPECT_EQ(file.read_f32("scale", {}), std::vector<float>{scale});
  EXPECT_EQ(file.read_f64("temperature", {}), std::vector<double>{temperature});
  // A scalar is not a one-element vector.
  EXPECT_CONTAINS(error_message([&] { file.read_f32("scale", std::vector<std::int64_t>{1}); }),
                  "expected shape [1], found []");
}

TEST(SafetensorsRoundTrip, DataSectionIsEightByteAlignedForEveryHeaderLength) {
  // Names of 1..24 characters move the JSON's length through every remainder modulo 8.
  for (std::size_t name_length = 1; name_length <= 24; ++name_length) {
    const std::string name(name_length, 'n');
    const std::vector<double> values = {1.5, -2.5};
    SafetensorsWriter writer;
    writer.add_f64(name, {2}, values);
    const std::vector<std::byte> bytes = writer.serialize();

    std::uint64_t length_field = 0;
    for (int i = 7; i >= 0; --i) {  // the length field is little-endian, whatever the host
      length_field = (length_field << 8) | std::to_integer<std::uint64_t>(bytes[i]);
    }
    const SafetensorsHeader header = parse_safetensors_header("aligned.safetensors", bytes);
    EXPECT_EQ(header.data_offset, 8 + length_field) << name_length;
    EXPECT_EQ(header.data_offset % 8, 0u) << name_length;
    EXPECT_EQ(bytes.size(), header.data_offset + 16) << name_length;
    // The padding is fewer than 8 spaces after the JSON's closing brace (JSON ignores them).
    const std::string header_text(reinterpret_cast<const char*>(bytes.data()) + 8, length_field);
    const std::size_t closing_brace = header_text.rfind('}');
    ASSERT_NE(closing_brace, std::string::npos);
    EXPECT_LT(header_text.size() - closing_brace - 1, 8u) << name_length;
    EXPECT_EQ(header_text.find_first_not_of(' ', closing_brace + 1), std::string::npos);
    const SafetensorsFile file = SafetensorsFile::from_bytes("aligned.safetensors", bytes);
    EXPECT_EQ(file.read_f64(name, std::vector<std::int64_t>{2}), values);
  }
}

TEST(SafetensorsRoundTrip, ParserListsTensorsInDataOrderNotNameOrder) {
  SafetensorsWriter writer;
  const std::vector<float> two = {1.0f, 2.0f};
  writer.add_f32("zeta", {2}, two);
  writer.add_f32("alpha", {2}, two);
  writer.add_f32("mu", {2}, two);
  const SafetensorsHeader header = parse_safetensors_header("order", writer.serialize());
  ASSERT_EQ(header.tensors.size(), 3u);
  EXPECT_EQ(header.tensors[0].name, "zeta");
  EXPECT_EQ(header.tensors[1].name, "alpha");
  EXPECT_EQ(header.tensors[2].name, "mu");
  for (std::size_t i = 0; i < header.tensors.size(); ++i) {
    EXPECT_EQ(header.tensors[i].begin, 8 * i);
    EXPECT_EQ(header.tensors[i].end, 8 * i + 8);
  }
}

TEST(SafetensorsWriter, RejectsInconsistentTensors) {
  SafetensorsWriter writer;
  const std::vector<float> five(5, 1.0f);
  EXPECT_CONTAINS(error_message([&] {
                    writer.add_f32("w", {2, 3}, five);
                  }),
                  "tensor 'w' shape [2, 3] needs 24 bytes, given 20");
  EXPECT_CONTAINS(error_message([&] {
                    writer.add_f32("neg", {-1, -5}, five);
                  }),
                  "tensor 'neg' has a negative dimension");
  writer.add_f32("w", {5}, five);
  EXPECT_CONTAINS(error_message([&] { writer.add_f32("w", {5}, five); }), "'w' used twice");
  EXPECT_CONTAINS(error_message([&] { writer.add_f32("__metadata__", {5}, five); }),
                  "'__metadata__' used twice or reserved");
  // 2^62 × 4 × 4 bytes wraps to 0 in 64 bits: without a checked product this "matches" no data
  // and the writer would produce a file that every reader rejects.
  EXPECT_CONTAINS(error_message([&] {
                    writer.add_f32("huge", {std::int64_t{1} << 62, 4}, std::span<float>());
                  }),
                  "overflows");
}

// ---- write: through a temporary file and a rename ----------------------------------------------

SafetensorsWriter small_writer(float first_value) {
  SafetensorsWriter writer;
  writer.add_f32("values", {3}, ramp(3, first_value, 1.0f));
  writer.set_metadata("version", std::to_string(first_value));
  return writer;
}

std::vector<fs::path> directory_entries(const fs::path& directory) {
  std::vector<fs::path> entries;
  for (const auto& entry : fs::directory_iterator(directory)) {
    entries.push_back(entry.path().filename());
  }
  std::sort(entries.begin(), entries.end());
  return entries;
}

TEST(SafetensorsWrite, WritesAFileThatReadsBackAndLeavesNoTemporaryFile) {
  ScratchDir scratch;
  const fs::path path = scratch.path() / "weights.safetensors";
  small_writer(7.0f).write(path);
  EXPECT_EQ(directory_entries(scratch.path()), std::vector<fs::path>{"weights.safetensors"});
  const SafetensorsFile file = SafetensorsFile::read(path);
  EXPECT_EQ(file.source(), path.string());
  EXPECT_EQ(file.read_f32("values", std::vector<std::int64_t>{3}), ramp(3, 7.0f, 1.0f));
  EXPECT_EQ(file.metadata_value("version"), std::to_string(7.0f));
  // Byte for byte what serialize() gives.
  std::ifstream in(path, std::ios::binary);
  const std::vector<char> on_disk((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
  const std::vector<std::byte> serialized = small_writer(7.0f).serialize();
  ASSERT_EQ(on_disk.size(), serialized.size());
  EXPECT_EQ(std::memcmp(on_disk.data(), serialized.data(), serialized.size()), 0);
}

TEST(SafetensorsWrite, ReplacesAnExistingFileByRenameNotInPlace) {
  ScratchDir scratch;
  const fs::path path = scratch.path() / "weights.safetensors";
  const fs::path old_link = scratch.path() / "old.safetensors";
  small_writer(1.0f).write(path);
  // A second name for the old file's inode. Rewriting in place would change what it reads;
  // writing a new file and renaming it over `path` leaves the old inode, and so this link, intact.
  fs::create_hard_link(path, old_link);
  small_writer(2.0f).write(path);
  EXPECT_EQ(SafetensorsFile::read(path).read_f32("values", std::vector<std::int64_t>{3}),
            ramp(3, 2.0f, 1.0f));
  EXPECT_EQ(SafetensorsFile::read(old_link).read_f32("values", std::vector<std::int64_t>{3}),
            ramp(3, 1.0f, 1.0f));
  EXPECT_EQ(directory_entries(scratch.path()),
            (std::vector<fs::path>{"old.safetensors", "weights.safetensors"}));
}

TEST(SafetensorsWrite, FailsNamingThePathWhenTheDirectoryDoesNotExist) {
  ScratchDir scratch;
  const fs::path path = scratch.path() / "no-such-dir" / "weights.safetensors";
  const std::string message = error_message([&] { small_writer(1.0f).write(path); });
  EXPECT_CONTAINS(message, path.string());
  EXPECT_CONTAINS(message, "cannot create");
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(directory_entries(scratch.path()).empty());
}

TEST(SafetensorsWrite, FailsNamingThePathWhenTheParentIsAFile) {
  ScratchDir scratch;
  const fs::path not_a_directory = scratch.path() / "plain-file";
  std::ofstream(not_a_directory) << "not a directory";
  const fs::path path = not_a_directory / "weights.safetensors";
  const std::string message = error_message([&] { small_writer(1.0f).write(path); });
  EXPECT_CONTAINS(message, path.string());
  EXPECT_EQ(directory_entries(scratch.path()), std::vector<fs::path>{"plain-file"});
}

TEST(SafetensorsWrite, FailsNamingThePathInAReadOnlyDirectory) {
  ScratchDir scratch;
  const fs::path read_only = scratch.path() / "read-only";
  fs::create_directory(read_only);
  fs::permissions(read_only, fs::perms::owner_read | fs::perms::owner_exec);
  if (::access(read_only.c_str(), W_OK) == 0) {
    fs::permissions(read_only, fs::perms::owner_all);
    GTEST_SKIP() << "running with privileges that ignore directory permissions (root?)";
  }
  const fs::path path = read_only / "weights.safetensors";
  const std::string message = error_message([&] { small_writer(1.0f).write(path); });
  fs::permissions(read_only, fs::perms::owner_all);  // so that ScratchDir can remove it
  EXPECT_CONTAINS(message, path.string());
  EXPECT_TRUE(directory_entries(read_only).empty());
}

TEST(SafetensorsWrite, FailedRenameLeavesNeitherFileNorTemporary) {
  // The final name is taken by a non-empty directory: the temporary file is written, the rename
  // fails, and the temporary must be cleaned up.
  ScratchDir scratch;
  const fs::path path = scratch.path() / "weights.safetensors";
  fs::create_directories(path / "occupied");
  const std::string message = error_message([&] { small_writer(1.0f).write(path); });
  EXPECT_CONTAINS(message, path.string());
  EXPECT_CONTAINS(message, "cannot move the finished file into place");
  EXPECT_TRUE(fs::is_directory(path / "occupied"));
  EXPECT_EQ(directory_entries(scratch.path()), std::vector<fs::path>{"weights.safetensors"});
}

// ---- read --------------------------------------------------------------------------------------

TEST(SafetensorsRead, NonexistentPathNamesThePath) {
  ScratchDir scratch;
  const fs::path path = scratch.path() / "missing.safetensors";
  const std::string message = error_message([&] { SafetensorsFile::read(path); });
  EXPECT_CONTAINS(message, path.string());
  EXPECT_CONTAINS(message, "cannot open");
}

TEST(SafetensorsRead, DirectoryNamesThePath) {
  ScratchDir scratch;
  EXPECT_CONTAINS(error_message([&] { SafetensorsFile::read(scratch.path()); }),
                  scratch.path().string());
}

TEST(SafetensorsRead, CorruptFileOnDiskNamesThePath) {
  ScratchDir scratch;
  const fs::path path = scratch.path() / "truncated.safetensors";
  // The valid file with its last 4 bytes lost.
  const std::vector<std::byte> bytes = file_with_header(kValidHeader, with_data(32));
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  const std::string message = error_message([&] { SafetensorsFile::read(path); });
  EXPECT_CONTAINS(message, path.string() + ": tensor 'bias'");
  EXPECT_CONTAINS(message, "beyond the data section of 32 bytes");
}

// ---- corruption table: each file must be rejected at load --------------------------------------

struct Corruption {
  std::string name;  // the test's name; the file is called "<name>.safetensors" in the error
  std::vector<std::byte> file;
  std::string expected;  // a phrase the error message must contain
};

std::vector<Corruption> corruption_table() {
  const std::string header(kValidHeader);
  return {
      // -- not a safetensors file at all --
      {"empty_file", {}, "file is 0 bytes, too short for a safetensors header (at least 8)"},
      {"shorter_than_length_field", bytes_of("\x10\0\0\0\0"sv), "file is 5 bytes, too short"},
      {"png_image", bytes_of("\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0\0\x10\0\0\0\x10\x08\x06\0\0\0"sv),
       "header length 727905341920923785 bytes exceeds the limit of 100000000"},
      {"zip_archive", bytes_of("PK\x03\x04\x14\0\0\0\x08\0weights.json"sv),
       "header length 85966670672 bytes exceeds the limit"},
      {"plain_text", bytes_of("These are not the tensors you are looking for.\n"),
       "exceeds the limit of 100000000 (not a safetensors file?)"},
      {"json_without_length_field", bytes_of(kValidHeader), "exceeds the limit"},
      // -- the length field --
      {"header_length_beyond_file", assemble(header.size() + 100, header, valid_data()),
       "header length " + std::to_string(header.size() + 100) + " runs past the end of the file (" +
           std::to_string(header.size() + 36) + " bytes follow the length field)"},
      {"truncated_inside_header", assemble(header.size(), header.substr(0, 20), {}),
       "runs past the end of the file (20 bytes follow the length field)"},
      {"header_length_zero", assemble(0, header, valid_data()),
       "header length is 0 bytes; not a safetensors file"},
      {"header_length_one", assemble(1, header, valid_data()), "header length is 1 bytes"},
      {"header_length_absurd", assemble(std::uint64_t{1} << 62, header, valid_data()),
       "header length 4611686018427387904 bytes exceeds the limit"},
      {"header_length_all_ones", assemble(~std::uint64_t{0}, header, valid_data()),
       "header length 18446744073709551615 bytes exceeds the limit"},
      // -- the JSON --
      {"json_missing_bracket", file_with_header(edited_header("[2,3]", "[2,3")),
       "header is not valid JSON"},
      {"json_trailing_comma", file_with_header(edited_header("[24,36]}}", "[24,36]},}")),
       "header is not valid JSON"},
      {"json_cut_short", file_with_header(header.substr(0, header.size() - 1)),
       "header is not valid JSON"},
      {"json_invalid_utf8", file_with_header(edited_header("\"bias\"", "\"bi\xff\xfe\"")),
       "header is not valid JSON"},
      {"json_nul_byte", file_with_header(edited_header("\"pt\"", "\"p\0t\""sv)),
       "header is not valid JSON"},
      {"json_array_not_object",
       file_with_header(R"([{"dtype":"F32","shape":[9],"data_offsets":[0,36]}])"),
       "header does not start with '{'"},
      {"header_starts_with_space", file_with_header(" " + header),
       "header does not start with '{'"},
      {"header_is_a_string", file_with_header(R"("weights")"), "does not start with '{'"},
      {"json_nested_too_deep_in_shape", file_with_header(edited_header("[3]", "[[3]]")),
       "header JSON nests deeper than 3 levels"},
      {"json_nested_too_deep_in_metadata",
       file_with_header(edited_header(R"("pt")", R"({"a":{"b":"c"}})")),
       "header JSON nests deeper than 3 levels"},
      {"json_nested_100000_levels", file_with_header("{\"a\":" + std::string(100000, '[')),
       "header JSON nests deeper than 3 levels"},
      // -- tensor entries --
      {"entry_not_an_object",
       file_with_header(edited_header(
           R"("bias":{"dtype":"F32","shape":[3],"data_offsets":[24,36]})", R"("bias":[24,36])")),
       "tensor 'bias': expected an object with dtype, shape and data_offsets, found array"},
      {"unknown_field", file_with_header(edited_header("[24,36]}", R"([24,36],"offset":24})")),
       "tensor 'bias': unknown field 'offset'"},
      {"missing_dtype",
       file_with_header(edited_header(R"({"dtype":"F32","shape":[3])", R"({"shape":[3])")),
       "tensor 'bias': missing field 'dtype'"},
      {"duplicate_field",
       file_with_header(edited_header(R"({"dtype":"F32","shape":[3])",
                                      R"({"dtype":"F32","dtype":"I32","shape":[3])")),
       "tensor 'bias': field 'dtype' appears twice"},
      {"unknown_dtype",
       file_with_header(edited_header(R"("F32","shape":[3])", R"("F33","shape":[3])")),
       "tensor 'bias': unknown dtype 'F33'"},
      {"lowercase_dtype",
       file_with_header(edited_header(R"("F32","shape":[3])", R"("f32","shape":[3])")),
       "tensor 'bias': unknown dtype 'f32'"},
      {"dtype_not_a_string",
       file_with_header(edited_header(R"("F32","shape":[3])", R"(32,"shape":[3])")),
       "tensor 'bias': dtype: expected a string, found number"},
      {"shape_not_an_array", file_with_header(edited_header("[2,3]", "6")),
       "tensor 'weight': shape: expected an array, found number"},
      {"shape_a_string", file_with_header(edited_header("[2,3]", R"("2x3")")),
       "tensor 'weight': shape: expected an array, found string"},
      {"shape_negative_dimension", file_with_header(edited_header("[2,3]", "[-2,-3]")),
       "tensor 'weight': shape: expected a non-negative integer, found -2"},
      {"shape_fractional_dimension", file_with_header(edited_header("[2,3]", "[1.5,4]")),
       "tensor 'weight': shape: expected a non-negative integer, found 1.5"},
      {"shape_dimension_a_string", file_with_header(edited_header("[2,3]", R"([2,"3"])")),
       "tensor 'weight': shape: expected a non-negative integer, found string"},
      {"shape_dimension_beyond_int64",
       file_with_header(edited_header("[3]", "[9223372036854775808]")),
       "tensor 'bias': shape dimension 9223372036854775808 is too large"},
      {"shape_dimension_beyond_uint64",
       file_with_header(edited_header("[3]", "[18446744073709551616]")),
       "tensor 'bias': shape: expected a non-negative integer, found 1.8446744073709552e+19"},
      {"shape_too_many_dimensions",
       file_with_header(edited_header("[3]", "[3,1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,1]")),
       "tensor 'bias': shape has 17 dimensions, more than 16"},
      {"byte_count_overflows", file_with_header(edited_header("[2,3]", "[4294967296,4294967296]")),
       "tensor 'weight': shape [4294967296, 4294967296] of F32 overflows 64-bit byte count"},
      {"byte_count_wraps_to_the_right_length",
       file_with_header(edited_header("[2,3]", "[4611686018427387910]")),
       "tensor 'weight': shape [4611686018427387910] of F32 overflows 64-bit byte count"},
      {"shape_disagrees_with_data_length", file_with_header(edited_header("[2,3]", "[2,2]")),
       "tensor 'weight': shape [2, 2] of F32 needs 16 bytes, data_offsets [0, 24] hold 24"},
      {"dtype_disagrees_with_data_length",
       file_with_header(edited_header(R"("F32","shape":[2,3])", R"("F64","shape":[2,3])")),
       "tensor 'weight': shape [2, 3] of F64 needs 48 bytes, data_offsets [0, 24] hold 24"},
      // -- data_offsets --
      {"data_offsets_one_number", file_with_header(edited_header("[0,24]", "[0]")),
       "tensor 'weight': data_offsets: expected [begin, end], found [0]"},
      {"data_offsets_three_numbers", file_with_header(edited_header("[0,24]", "[0,12,24]")),
       "tensor 'weight': data_offsets: expected [begin, end], found [0,12,24]"},
      {"data_offsets_not_an_array", file_with_header(edited_header("[0,24]", R"("0:24")")),
       "tensor 'weight': data_offsets: expected [begin, end], found \"0:24\""},
      {"data_offsets_negative", file_with_header(edited_header("[0,24]", "[-24,0]")),
       "tensor 'weight': data_offsets: expected a non-negative integer, found -24"},
      {"data_offsets_end_before_begin", file_with_header(edited_header("[0,24]", "[24,0]")),
       "tensor 'weight': data_offsets [24, 0] end before they begin"},
      {"data_offsets_beyond_data", file_with_header(edited_header("[24,36]", "[36,48]")),
       "tensor 'bias': data_offsets [36, 48] reach beyond the data section of 36 bytes"},
      {"data_offsets_far_beyond_data",
       file_with_header(edited_header(
           R"("shape":[3],"data_offsets":[24,36])",
           R"("shape":[0],"data_offsets":[18446744073709551615,18446744073709551615])")),
       "reach beyond the data section of 36 bytes"},
      {"data_section_truncated", file_with_header(header, with_data(32)),
       "tensor 'bias': data_offsets [24, 36] reach beyond the data section of 32 bytes"},
      {"data_offsets_overlap", file_with_header(edited_header("[24,36]", "[20,32]")),
       "tensor 'bias': data_offsets [20, 32] overlap tensor 'weight' [0, 24]"},
      {"data_offsets_shared",
       file_with_header(edited_header(R"("shape":[3],"data_offsets":[24,36])",
                                      R"("shape":[6],"data_offsets":[0,24])"),
                        with_data(24)),
       "data_offsets [0, 24] overlap tensor"},
      {"zero_size_tensor_inside_another",
       file_with_header(edited_header(R"("shape":[3],"data_offsets":[24,36])",
                                      R"("shape":[0],"data_offsets":[8,8])"),
                        with_data(24)),
       "tensor 'bias': data_offsets [8, 8] overlap tensor 'weight' [0, 24]"},
      {"gap_between_tensors", file_with_header(edited_header("[24,36]", "[28,40]"), with_data(40)),
       "tensor 'bias': data_offsets begin at 28 but the previous tensor 'weight' ends at 24 (a gap "
       "in the data section)"},
      {"gap_before_first_tensor",
       file_with_header(edited_header({{"[0,24]", "[4,28]"}, {"[24,36]", "[28,40]"}}),
                        with_data(40)),
       "tensor 'weight': data_offsets begin at 4 but the data section starts at 0 (a gap in the "
       "data section)"},
      {"trailing_bytes", file_with_header(header, with_data(44)),
       "the data section has 8 trailing bytes that belong to no tensor"},
      {"duplicate_tensor_name",
       file_with_header(edited_header(
           R"("bias":{)", R"("bias":{"dtype":"F32","shape":[0],"data_offsets":[0,0]},"bias":{)")),
       "tensor 'bias' appears twice in the header"},
      // -- __metadata__ --
      {"metadata_not_an_object", file_with_header(edited_header(R"({"format":"pt"})", R"("pt")")),
       "__metadata__: expected an object of strings, found string"},
      {"metadata_value_a_number", file_with_header(edited_header(R"("pt")", "1")),
       "__metadata__.format: expected a string, found number"},
      {"metadata_value_an_object", file_with_header(edited_header(R"("pt")", R"({"name":"pt"})")),
       "__metadata__.format: expected a string, found object"},
      {"metadata_duplicate_key",
       file_with_header(edited_header(R"("format":"pt")", R"("format":"pt","format":"np")")),
       "__metadata__: key 'format' appears twice"},
  };
}

// gtest prints a failing case's parameter; the name says which it is.
void PrintTo(const Corruption& c, std::ostream* out) {
  *out << c.name;
}

class SafetensorsCorruption : public ::testing::TestWithParam<Corruption> {};

TEST_P(SafetensorsCorruption, IsRejectedWithAMessageNamingFileAndFault) {
  const Corruption& c = GetParam();
  const std::string source = c.name + ".safetensors";
  const std::string message = error_message([&] { SafetensorsFile::from_bytes(source, c.file); });
  EXPECT_EQ(message.rfind(source + ": ", 0), 0u) << "message: " << message;
  EXPECT_CONTAINS(message, c.expected);
}

INSTANTIATE_TEST_SUITE_P(Table, SafetensorsCorruption, ::testing::ValuesIn(corruption_table()),
                         [](const ::testing::TestParamInfo<Corruption>& param) {
                           return param.param.name;
                         });

TEST(SafetensorsCorruptionTable, CaseNamesAreUniqueAndEveryCaseDiffersFromTheValidFile) {
  const std::vector<Corruption> cases = corruption_table();
  EXPECT_GE(cases.size(), 50u);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    EXPECT_NE(cases[i].file, valid_file()) << cases[i].name;
    for (std::size_t j = i + 1; j < cases.size(); ++j) {
      EXPECT_NE(cases[i].name, cases[j].name);
    }
  }
}

// ---- at use: names, dtypes, shapes and values checked when a tensor is taken -------------------

SafetensorsFile valid_loaded_file() {
  return SafetensorsFile::from_bytes("model.safetensors", valid_file());
}

TEST(SafetensorsUse, MissingTensorListsThePresentOnes) {
  const SafetensorsFile file = valid_loaded_file();
  const std::string message =
      error_message([&] { file.require("gamma", DType::kF32, std::vector<std::int64_t>{3}); });
  EXPECT_CONTAINS(message, "model.safetensors: tensor 'gamma': missing");
  EXPECT_CONTAINS(message, "the file holds 2 tensors: weight, bias");
  EXPECT_CONTAINS(error_message([&] { file.shape_of("beta"); }), "tensor 'beta': missing");
  EXPECT_CONTAINS(error_message([&] {
                    file.read_f32("Weight", std::vector<std::int64_t>{2, 3});
                  }),
                  "tensor 'Weight': missing");
  EXPECT_FALSE(file.contains("gamma"));
  EXPECT_TRUE(file.contains("bias"));
}

TEST(SafetensorsUse, MissingTensorInABigFileListsTheFirstEight) {
  SafetensorsWriter writer;
  const std::vector<float> one = {1.0f};
  for (int i = 0; i < 10; ++i) {
    writer.add_f32("layer" + std::to_string(i), {1}, one);
  }
  const SafetensorsFile file = SafetensorsFile::from_bytes("big.safetensors", writer.serialize());
  const std::string message = error_message([&] { file.shape_of("layer10"); });
  EXPECT_CONTAINS(message,
                  "holds 10 tensors: layer0, layer1, layer2, layer3, layer4, layer5, "
                  "layer6, layer7, ...)");
  EXPECT_EQ(message.find("layer8"), std::string::npos) << message;
}

TEST(SafetensorsUse, WrongDtypeNamesExpectedAndFound) {
  const SafetensorsFile file = valid_loaded_file();
  EXPECT_CONTAINS(error_message([&] {
                    file.read_f64("weight", std::vector<std::int64_t>{2, 3});
                  }),
                  "model.safetensors: tensor 'weight': expected dtype F64, found F32");
  EXPECT_CONTAINS(
      error_message([&] { file.require("bias", DType::kI64, std::vector<std::int64_t>{3}); }),
      "model.safetensors: tensor 'bias': expected dtype I64, found F32");
  SafetensorsWriter writer;
  const std::vector<double> values = {1.0, 2.0};
  writer.add_f64("reference", {2}, values);
  const SafetensorsFile f64_file =
      SafetensorsFile::from_bytes("ref.safetensors", writer.serialize());
  EXPECT_CONTAINS(
      error_message([&] { f64_file.read_f32("reference", std::vector<std::int64_t>{2}); }),
      "ref.safetensors: tensor 'reference': expected dtype F32, found F64");
}

TEST(SafetensorsUse, WrongShapeNamesExpectedAndFound) {
  const SafetensorsFile file = valid_loaded_file();
  EXPECT_CONTAINS(error_message([&] {
                    file.read_f32("weight", std::vector<std::int64_t>{3, 2});
                  }),
                  "model.safetensors: tensor 'weight': expected shape [3, 2], found [2, 3]");
  EXPECT_CONTAINS(error_message([&] { file.read_f32("weight", std::vector<std::int64_t>{6}); }),
                  "tensor 'weight': expected shape [6], found [2, 3]");
  EXPECT_CONTAINS(error_message([&] {
                    file.require("bias", DType::kF32, std::vector<std::int64_t>{3, 1});
                  }),
                  "tensor 'bias': expected shape [3, 1], found [3]");
  std::vector<float> too_small(5);
  EXPECT_CONTAINS(error_message([&] {
                    file.copy_f32("weight", std::vector<std::int64_t>{2, 3}, too_small);
                  }),
                  "tensor 'weight': destination holds 5 floats, tensor has 6");
}

TEST(SafetensorsUse, NonFiniteValuesAreRejectedNamingTheElement) {
  struct Case {
    float bad_value;
    std::string expected;
  };
  const Case cases[] = {{std::numeric_limits<float>::quiet_NaN(), "element 4 is NaN"},
                        {-std::numeric_limits<float>::quiet_NaN(), "element 4 is NaN"},
                        {std::numeric_limits<float>::infinity(), "element 4 is +Inf"},
                        {-std::numeric_limits<float>::infinity(), "element 4 is -Inf"}};
  for (const Case& c : cases) {
    std::vector<float> values = ramp(6, 0.0f, 1.0f);
    values[4] = c.bad_value;
    SafetensorsWriter writer;
    writer.add_f32("weight", {2, 3}, values);
    const SafetensorsFile file = SafetensorsFile::from_bytes("nan.safetensors", writer.serialize());
    const std::string message = error_message([&] {
      file.read_f32("weight", std::vector<std::int64_t>{2, 3});
    });
    EXPECT_CONTAINS(message, "nan.safetensors: tensor 'weight': " + c.expected);
    EXPECT_CONTAINS(message, "values must be finite");
    std::vector<float> out(6);
    EXPECT_CONTAINS(error_message([&] {
                      file.copy_f32("weight", std::vector<std::int64_t>{2, 3}, out);
                    }),
                    c.expected);
  }
}

TEST(SafetensorsUse, NonFiniteDoublesAreRejectedNamingTheElement) {
  struct Case {
    double bad_value;
    std::string expected;
  };
  const Case cases[] = {{std::numeric_limits<double>::quiet_NaN(), "element 0 is NaN"},
                        {std::numeric_limits<double>::infinity(), "element 0 is +Inf"},
                        {-std::numeric_limits<double>::infinity(), "element 0 is -Inf"}};
  for (const Case& c : cases) {
    const std::vector<double> values = {c.bad_value, 1.0};
    SafetensorsWriter writer;
    writer.add_f64("reference", {2}, values);
    const SafetensorsFile file = SafetensorsFile::from_bytes("ref.safetensors", writer.serialize());
    EXPECT_CONTAINS(
        error_message([&] { file.read_f64("reference", std::vector<std::int64_t>{2}); }),
        "ref.safetensors: tensor 'reference': " + c.expected);
  }
}

TEST(SafetensorsUse, NonFiniteValuesAreFineInTensorsNobodyReads) {
  // Only values that are read are checked; loading the file itself never looks at them.
  std::vector<float> values = {std::numeric_limits<float>::infinity()};
  SafetensorsWriter writer;
  writer.add_f32("unused", {1}, values);
  writer.add_f32("used", {1}, std::vector<float>{2.0f});
  const SafetensorsFile file = SafetensorsFile::from_bytes("mixed.safetensors", writer.serialize());
  EXPECT_EQ(file.read_f32("used", std::vector<std::int64_t>{1}), std::vector<float>{2.0f});
}

TEST(SafetensorsUse, MissingMetadataKeyNamesFileAndKey) {
  const SafetensorsFile file = valid_loaded_file();
  EXPECT_EQ(file.metadata_value("format"), "pt");
  EXPECT_CONTAINS(error_message([&] { file.metadata_value("version"); }),
                  "model.safetensors: __metadata__ has no 'version' entry");
}

TEST(SafetensorsUse, BytesOfATensorAreExactlyItsData) {
  const SafetensorsFile file = valid_loaded_file();
  const std::vector<std::byte> data = valid_data();
  const auto bias = file.bytes(*file.find("bias"));
  ASSERT_EQ(bias.size(), 12u);
  EXPECT_TRUE(std::equal(bias.begin(), bias.end(), data.begin() + 24));
  EXPECT_EQ(file.find("gamma"), nullptr);
}

TEST(SafetensorsDtype, NamesAndSizes) {
  EXPECT_EQ(dtype_name(DType::kF32), "F32");
  EXPECT_EQ(dtype_name(DType::kBF16), "BF16");
  EXPECT_EQ(dtype_size(DType::kBool), 1u);
  EXPECT_EQ(dtype_size(DType::kF16), 2u);
  EXPECT_EQ(dtype_size(DType::kU32), 4u);
  EXPECT_EQ(dtype_size(DType::kI64), 8u);
  EXPECT_EQ(shape_string(std::vector<std::int64_t>{64, 30, 11}), "[64, 30, 11]");
  EXPECT_EQ(shape_string({}), "[]");
}

}  // namespace
}  // namespace deixis
