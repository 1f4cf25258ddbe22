#pragma once
// safetensors: the one file format Deixis uses for weights and datasets
// (https://huggingface.co/docs/safetensors). Layout: an 8-byte little-endian header length N, N
// bytes of JSON, then the data section. Every field is validated before use (as ggml does): the
// header length against the file, the JSON's shape, dtypes, shapes, numel × size without overflow,
// offsets that tile the data section exactly (in range, ordered, no overlap, no gap), no duplicate
// names; and at use, the expected names, dtypes and shapes and finite values. Each error names the
// file, the tensor, and what was expected and found.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace deixis {

enum class DType { kBool, kU8, kI8, kI16, kU16, kF16, kBF16, kI32, kU32, kF32, kF64, kI64, kU64 };

std::string_view dtype_name(DType dtype);  // "F32", ...
std::size_t dtype_size(DType dtype);       // bytes per element

struct TensorInfo {
  std::string name;
  DType dtype = DType::kF32;
  std::vector<std::int64_t> shape;
  std::uint64_t begin = 0;  // byte offsets into the data section
  std::uint64_t end = 0;
  std::uint64_t numel() const;
};

struct SafetensorsHeader {
  std::vector<TensorInfo> tensors;  // in file order of their data
  std::map<std::string, std::string> metadata;
  std::uint64_t data_offset = 0;  // where the data section starts in the file (8 + N)
};

// The largest header we accept; the format's own reference implementation uses the same bound.
inline constexpr std::uint64_t kMaxSafetensorsHeaderBytes = 100'000'000;

// Parses and validates the header of a whole file held in memory. `source` names the file in error
// messages. Throws deixis::Error. This is the function the fuzz target drives.
SafetensorsHeader parse_safetensors_header(std::string_view source,
                                           std::span<const std::byte> file);

// Shape written the way PyTorch prints it: [64, 30, 11].
std::string shape_string(std::span<const std::int64_t> shape);

// A validated safetensors file, read whole into memory.
class SafetensorsFile {
 public:
  static SafetensorsFile read(const std::filesystem::path& path);
  static SafetensorsFile from_bytes(std::string source, std::vector<std::byte> bytes);

  const std::string& source() const { return source_; }
  const std::vector<TensorInfo>& tensors() const { return header_.tensors; }
  const std::map<std::string, std::string>& metadata() const { return header_.metadata; }

  // nullptr when absent.
  const TensorInfo* find(std::string_view name) const;
  bool contains(std::string_view name) const { return find(name) != nullptr; }

  // The tensor's metadata entry, or an error naming the file and the key.
  const std::string& metadata_value(std::string_view key) const;

  // The tensor, checked to exist with this dtype and shape. Errors name file, tensor, expected
  // and found.
  const TensorInfo& require(std::string_view name, DType dtype,
                            std::span<const std::int64_t> shape) const;

  // The raw bytes of a tensor (not necessarily aligned for its dtype).
  std::span<const std::byte> bytes(const TensorInfo& tensor) const;

  // Copies an F32 tensor of exactly this shape into `out` (numel floats); rejects NaN and ±Inf,
  // naming the first bad element's index.
  void copy_f32(std::string_view name, std::span<const std::int64_t> shape,
                std::span<float> out) const;
  std::vector<float> read_f32(std::string_view name, std::span<const std::int64_t> shape) const;
  // F64 tensors (reference outputs of the fixtures) are read as double.
  std::vector<double> read_f64(std::string_view name, std::span<const std::int64_t> shape) const;
  // The stored shape of a tensor that must exist (any dtype).
  const std::vector<std::int64_t>& shape_of(std::string_view name) const;

 private:
  SafetensorsFile(std::string source, std::vector<std::byte> bytes, SafetensorsHeader header);
  const TensorInfo& require_present(std::string_view name) const;

  std::string source_;
  std::vector<std::byte> bytes_;
  SafetensorsHeader header_;
};

// Builds a safetensors file. Tensors are written in the order added; the header is padded with
// spaces to a multiple of 8 bytes so that the data section is aligned. `write` goes through a
// temporary file and a rename, so a crash never leaves a half-written file under the final name.
class SafetensorsWriter {
 public:
  void add(std::string name, DType dtype, std::vector<std::int64_t> shape,
           std::span<const std::byte> data);
  void add_f32(std::string name, std::vector<std::int64_t> shape, std::span<const float> values);
  void add_f64(std::string name, std::vector<std::int64_t> shape, std::span<const double> values);
  void add_i64(std::string name, std::vector<std::int64_t> shape,
               std::span<const std::int64_t> values);
  void set_metadata(std::string key, std::string value);

  std::vector<std::byte> serialize() const;
  void write(const std::filesystem::path& path) const;

 private:
  struct Entry {
    std::string name;
    DType dtype;
    std::vector<std::int64_t> shape;
    std::vector<std::byte> data;
  };
  std::vector<Entry> entries_;
  std::map<std::string, std::string> metadata_;
};

}  // namespace deixis
