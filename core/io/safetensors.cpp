#include "core/io/safetensors.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "core/error.h"
#include "core/io/atomic_file.h"

static_assert(std::endian::native == std::endian::little,
              "safetensors is little-endian; Deixis reads it by memcpy");

namespace deixis {
namespace {

using json = nlohmann::json;

constexpr std::size_t kMaxRank = 16;  // far above any tensor we store; bounds work per header
constexpr int kMaxJsonDepth = 3;      // header { tensor { shape [ ... ] } }

struct DTypeEntry {
  DType dtype;
  std::string_view name;
  std::size_t size;
};
constexpr std::array<DTypeEntry, 13> kDTypes = {{{DType::kBool, "BOOL", 1},
                                                 {DType::kU8, "U8", 1},
                                                 {DType::kI8, "I8", 1},
                                                 {DType::kI16, "I16", 2},
                                                 {DType::kU16, "U16", 2},
                                                 {DType::kF16, "F16", 2},
                                                 {DType::kBF16, "BF16", 2},
                                                 {DType::kI32, "I32", 4},
                                                 {DType::kU32, "U32", 4},
                                                 {DType::kF32, "F32", 4},
                                                 {DType::kF64, "F64", 8},
                                                 {DType::kI64, "I64", 8},
                                                 {DType::kU64, "U64", 8}}};

[[noreturn]] void fail(std::string_view source, const std::string& what) {
  throw Error(std::string(source) + ": " + what);
}

[[noreturn]] void fail_tensor(std::string_view source, std::string_view tensor,
                              const std::string& what) {
  throw Error(std::string(source) + ": tensor '" + std::string(tensor) + "': " + what);
}

// Thrown from inside the JSON parser's callback to stop early; turned into an Error by the caller.
struct HeaderRejected {
  std::string what;
};

std::string json_type(const json& j) {
  return j.type_name();
}

bool parse_dtype(std::string_view text, DType& out) {
  for (const auto& entry : kDTypes) {
    if (entry.name == text) {
      out = entry.dtype;
      return true;
    }
  }
  return false;
}

std::uint64_t read_unsigned(std::string_view source, std::string_view tensor, const json& j,
                            std::string_view field) {
  if (!j.is_number_unsigned() && !(j.is_number_integer() && j.get<std::int64_t>() >= 0)) {
    fail_tensor(source, tensor,
                std::string(field) + ": expected a non-negative integer, found " +
                    (j.is_number() ? j.dump() : json_type(j)));
  }
  return j.get<std::uint64_t>();
}

TensorInfo parse_tensor_entry(std::string_view source, const std::string& name, const json& j) {
  if (!j.is_object()) {
    fail_tensor(source, name,
                "expected an object with dtype, shape and data_offsets, found " + json_type(j));
  }
  for (const auto& [key, value] : j.items()) {
    if (key != "dtype" && key != "shape" && key != "data_offsets") {
      fail_tensor(source, name, "unknown field '" + key + "'");
    }
  }
  for (const char* key : {"dtype", "shape", "data_offsets"}) {
    if (!j.contains(key)) {
      fail_tensor(source, name, std::string("missing field '") + key + "'");
    }
  }
  TensorInfo info;
  info.name = name;
  const json& dtype = j["dtype"];
  if (!dtype.is_string()) {
    fail_tensor(source, name, "dtype: expected a string, found " + json_type(dtype));
  }
  if (!parse_dtype(dtype.get<std::string>(), info.dtype)) {
    fail_tensor(source, name, "unknown dtype '" + dtype.get<std::string>() + "'");
  }
  const json& shape = j["shape"];
  if (!shape.is_array()) {
    fail_tensor(source, name, "shape: expected an array, found " + json_type(shape));
  }
  if (shape.size() > kMaxRank) {
    fail_tensor(source, name,
                "shape has " + std::to_string(shape.size()) + " dimensions, more than " +
                    std::to_string(kMaxRank));
  }
  for (const json& dim : shape) {
    const std::uint64_t d = read_unsigned(source, name, dim, "shape");
    if (d > static_cast<std::uint64_t>(INT64_MAX)) {
      fail_tensor(source, name, "shape dimension " + std::to_string(d) + " is too large");
    }
    info.shape.push_back(static_cast<std::int64_t>(d));
  }
  const json& offsets = j["data_offsets"];
  if (!offsets.is_array() || offsets.size() != 2) {
    fail_tensor(source, name, "data_offsets: expected [begin, end], found " + offsets.dump());
  }
  info.begin = read_unsigned(source, name, offsets[0], "data_offsets");
  info.end = read_unsigned(source, name, offsets[1], "data_offsets");
  if (info.begin > info.end) {
    fail_tensor(source, name,
                "data_offsets [" + std::to_string(info.begin) + ", " + std::to_string(info.end) +
                    "] end before they begin");
  }
  // numel × element size, with every multiplication checked for overflow.
  std::uint64_t bytes = dtype_size(info.dtype);
  for (const std::int64_t d : info.shape) {
    if (__builtin_mul_overflow(bytes, static_cast<std::uint64_t>(d), &bytes)) {
      fail_tensor(source, name,
                  "shape " + shape_string(info.shape) + " of " +
                      std::string(dtype_name(info.dtype)) + " overflows 64-bit byte count");
    }
  }
  if (info.end - info.begin != bytes) {
    fail_tensor(source, name,
                "shape " + shape_string(info.shape) + " of " + std::string(dtype_name(info.dtype)) +
                    " needs " + std::to_string(bytes) + " bytes, data_offsets [" +
                    std::to_string(info.begin) + ", " + std::to_string(info.end) + "] hold " +
                    std::to_string(info.end - info.begin));
  }
  return info;
}

std::map<std::string, std::string> parse_metadata(std::string_view source, const json& j) {
  if (!j.is_object()) {
    fail(source, "__metadata__: expected an object of strings, found " + json_type(j));
  }
  std::map<std::string, std::string> metadata;
  for (const auto& [key, value] : j.items()) {
    if (!value.is_string()) {
      fail(source, "__metadata__." + key + ": expected a string, found " + json_type(value));
    }
    metadata.emplace(key, value.get<std::string>());
  }
  return metadata;
}

// The data section must be tiled exactly: tensors sorted by offset, each starting where the
// previous ended, the last ending at the end of the file.
void check_tiling(std::string_view source, std::vector<TensorInfo>& tensors,
                  std::uint64_t data_size) {
  std::stable_sort(tensors.begin(), tensors.end(), [](const TensorInfo& a, const TensorInfo& b) {
    return a.begin != b.begin ? a.begin < b.begin : a.end < b.end;
  });
  std::uint64_t expected_begin = 0;
  const TensorInfo* previous = nullptr;
  for (const TensorInfo& t : tensors) {
    if (t.end > data_size) {
      fail_tensor(source, t.name,
                  "data_offsets [" + std::to_string(t.begin) + ", " + std::to_string(t.end) +
                      "] reach beyond the data section of " + std::to_string(data_size) + " bytes");
    }
    if (t.begin < expected_begin) {
      fail_tensor(source, t.name,
                  "data_offsets [" + std::to_string(t.begin) + ", " + std::to_string(t.end) +
                      "] overlap tensor '" + previous->name + "' [" +
                      std::to_string(previous->begin) + ", " + std::to_string(previous->end) + "]");
    }
    if (t.begin > expected_begin) {
      fail_tensor(source, t.name,
                  "data_offsets begin at " + std::to_string(t.begin) + " but " +
                      (previous ? "the previous tensor '" + previous->name + "' ends at "
                                : std::string("the data section starts at ")) +
                      std::to_string(expected_begin) + " (a gap in the data section)");
    }
    expected_begin = t.end;
    previous = &t;
  }
  if (expected_begin != data_size) {
    fail(source, "the data section has " + std::to_string(data_size - expected_begin) +
                     " trailing bytes that belong to no tensor (file truncated or corrupt?)");
  }
}

}  // namespace

std::string_view dtype_name(DType dtype) {
  for (const auto& entry : kDTypes) {
    if (entry.dtype == dtype) {
      return entry.name;
    }
  }
  return "?";
}

std::size_t dtype_size(DType dtype) {
  for (const auto& entry : kDTypes) {
    if (entry.dtype == dtype) {
      return entry.size;
    }
  }
  return 0;
}

std::uint64_t TensorInfo::numel() const {
  std::uint64_t n = 1;
  for (const std::int64_t d : shape) {
    n *= static_cast<std::uint64_t>(d);
  }
  return n;
}

std::string shape_string(std::span<const std::int64_t> shape) {
  std::string s = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    s += (i ? ", " : "") + std::to_string(shape[i]);
  }
  return s + "]";
}

SafetensorsHeader parse_safetensors_header(std::string_view source,
                                           std::span<const std::byte> file) {
  if (file.size() < 8) {
    fail(source, "file is " + std::to_string(file.size()) +
                     " bytes, too short for a safetensors header (at least 8)");
  }
  std::uint64_t header_size = 0;
  std::memcpy(&header_size, file.data(), 8);
  if (header_size < 2) {
    fail(source,
         "header length is " + std::to_string(header_size) + " bytes; not a safetensors file");
  }
  if (header_size > kMaxSafetensorsHeaderBytes) {
    fail(source, "header length " + std::to_string(header_size) + " bytes exceeds the limit of " +
                     std::to_string(kMaxSafetensorsHeaderBytes) + " (not a safetensors file?)");
  }
  if (header_size > file.size() - 8) {
    fail(source, "header length " + std::to_string(header_size) +
                     " runs past the end of the file (" + std::to_string(file.size() - 8) +
                     " bytes follow the length field)");
  }
  const char* text = reinterpret_cast<const char*>(file.data() + 8);
  if (text[0] != '{') {
    fail(source, "header does not start with '{'; not a safetensors file");
  }

  // nlohmann keeps the last of duplicate keys silently; a header that says two things about one
  // tensor (or one metadata key) is ambiguous, so duplicates are rejected at both levels.
  std::set<std::string> top_level_keys;
  std::string entry_name;            // the top-level key whose object is being parsed
  std::set<std::string> entry_keys;  // the keys seen so far inside that object
  const json::parser_callback_t callback = [&](int depth, json::parse_event_t event, json& parsed) {
    if (depth > kMaxJsonDepth) {
      throw HeaderRejected{"header JSON nests deeper than " + std::to_string(kMaxJsonDepth) +
                           " levels"};
    }
    if (event == json::parse_event_t::key && depth == 1) {
      entry_name = parsed.get<std::string>();
      entry_keys.clear();
      if (!top_level_keys.insert(entry_name).second) {
        throw HeaderRejected{"tensor '" + entry_name + "' appears twice in the header"};
      }
    }
    if (event == json::parse_event_t::key && depth == 2) {
      const std::string key = parsed.get<std::string>();
      if (!entry_keys.insert(key).second) {
        throw HeaderRejected{entry_name == "__metadata__"
                                 ? "__metadata__: key '" + key + "' appears twice"
                                 : "tensor '" + entry_name + "': field '" + key +
                                       "' appears twice"};
      }
    }
    return true;
  };
  json header;
  try {
    header = json::parse(text, text + header_size, callback);
  } catch (const HeaderRejected& rejected) {
    fail(source, rejected.what);
  } catch (const json::exception& e) {
    fail(source, std::string("header is not valid JSON: ") + e.what());
  }
  if (!header.is_object()) {
    fail(source, "header JSON is " + json_type(header) + ", expected an object");
  }

  SafetensorsHeader result;
  result.data_offset = 8 + header_size;
  for (const auto& [key, value] : header.items()) {
    if (key == "__metadata__") {
      result.metadata = parse_metadata(source, value);
    } else {
      result.tensors.push_back(parse_tensor_entry(source, key, value));
    }
  }
  check_tiling(source, result.tensors, file.size() - result.data_offset);
  return result;
}

// ---- SafetensorsFile ---------------------------------------------------------------------------

SafetensorsFile::SafetensorsFile(std::string source, std::vector<std::byte> bytes,
                                 SafetensorsHeader header)
    : source_(std::move(source)), bytes_(std::move(bytes)), header_(std::move(header)) {}

SafetensorsFile SafetensorsFile::read(const std::filesystem::path& path) {
  const std::string source = path.string();
  // Only regular files: a directory opens as a stream too, and on ext4 its end "offset" is
  // 2^63 - 1, which would be allocated as the file's size.
  std::error_code status_error;
  const std::filesystem::file_status status = std::filesystem::status(path, status_error);
  if (status_error) {
    fail(source, "cannot open: " + status_error.message());
  }
  if (!std::filesystem::is_regular_file(status)) {
    fail(source, "cannot open: not a regular file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    fail(source, std::string("cannot open: ") + std::strerror(errno));
  }
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) {
    fail(source, "cannot determine the file size");
  }
  in.seekg(0, std::ios::beg);
  std::vector<std::byte> bytes(static_cast<std::size_t>(size));
  if (!in.read(reinterpret_cast<char*>(bytes.data()), size)) {
    fail(source, "read failed after " + std::to_string(in.gcount()) + " of " +
                     std::to_string(size) + " bytes");
  }
  return from_bytes(source, std::move(bytes));
}

SafetensorsFile SafetensorsFile::from_bytes(std::string source, std::vector<std::byte> bytes) {
  SafetensorsHeader header = parse_safetensors_header(source, bytes);
  return SafetensorsFile(std::move(source), std::move(bytes), std::move(header));
}

const TensorInfo* SafetensorsFile::find(std::string_view name) const {
  for (const TensorInfo& t : header_.tensors) {
    if (t.name == name) {
      return &t;
    }
  }
  return nullptr;
}

const std::string& SafetensorsFile::metadata_value(std::string_view key) const {
  const auto it = header_.metadata.find(std::string(key));
  if (it == header_.metadata.end()) {
    fail(source_, "__metadata__ has no '" + std::string(key) + "' entry");
  }
  return it->second;
}

const TensorInfo& SafetensorsFile::require_present(std::string_view name) const {
  if (const TensorInfo* t = find(name)) {
    return *t;
  }
  std::string present;
  for (std::size_t i = 0; i < header_.tensors.size() && i < 8; ++i) {
    present += (i ? ", " : "") + header_.tensors[i].name;
  }
  if (header_.tensors.size() > 8) {
    present += ", ...";
  }
  fail_tensor(source_, name,
              "missing (the file holds " + std::to_string(header_.tensors.size()) +
                  " tensors: " + present + ")");
}

const std::vector<std::int64_t>& SafetensorsFile::shape_of(std::string_view name) const {
  return require_present(name).shape;
}

const TensorInfo& SafetensorsFile::require(std::string_view name, DType dtype,
                                           std::span<const std::int64_t> shape) const {
  const TensorInfo& t = require_present(name);
  if (t.dtype != dtype) {
    fail_tensor(source_, name,
                "expected dtype " + std::string(dtype_name(dtype)) + ", found " +
                    std::string(dtype_name(t.dtype)));
  }
  if (!std::equal(t.shape.begin(), t.shape.end(), shape.begin(), shape.end())) {
    fail_tensor(source_, name,
                "expected shape " + shape_string(shape) + ", found " + shape_string(t.shape));
  }
  return t;
}

std::span<const std::byte> SafetensorsFile::bytes(const TensorInfo& tensor) const {
  return std::span<const std::byte>(bytes_).subspan(header_.data_offset + tensor.begin,
                                                    tensor.end - tensor.begin);
}

namespace {

template <typename T>
void check_finite(std::string_view source, std::string_view name, std::span<const T> values) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      const char* found = std::isnan(values[i]) ? "NaN" : (values[i] > 0 ? "+Inf" : "-Inf");
      fail_tensor(source, name,
                  "element " + std::to_string(i) + " is " + found + "; values must be finite");
    }
  }
}

}  // namespace

void SafetensorsFile::copy_f32(std::string_view name, std::span<const std::int64_t> shape,
                               std::span<float> out) const {
  const TensorInfo& t = require(name, DType::kF32, shape);
  if (out.size() != t.numel()) {
    fail_tensor(source_, name,
                "destination holds " + std::to_string(out.size()) + " floats, tensor has " +
                    std::to_string(t.numel()));
  }
  const auto data = bytes(t);
  if (!data.empty()) {  // a zero-size tensor's destination may be null, which memcpy forbids
    std::memcpy(out.data(), data.data(), data.size());
  }
  check_finite<float>(source_, name, out);
}

std::vector<float> SafetensorsFile::read_f32(std::string_view name,
                                             std::span<const std::int64_t> shape) const {
  std::vector<float> values(require(name, DType::kF32, shape).numel());
  copy_f32(name, shape, values);
  return values;
}

std::vector<double> SafetensorsFile::read_f64(std::string_view name,
                                              std::span<const std::int64_t> shape) const {
  const TensorInfo& t = require(name, DType::kF64, shape);
  std::vector<double> values(t.numel());
  const auto data = bytes(t);
  if (!data.empty()) {  // as in copy_f32: an empty vector's data() may be null
    std::memcpy(values.data(), data.data(), data.size());
  }
  check_finite<double>(source_, name, values);
  return values;
}

// ---- SafetensorsWriter -------------------------------------------------------------------------

void SafetensorsWriter::add(std::string name, DType dtype, std::vector<std::int64_t> shape,
                            std::span<const std::byte> data) {
  // The same checks, in the same order, as the reader's: the writer never makes a file that
  // parse_safetensors_header rejects (an unchecked product could wrap to match the data's size).
  if (shape.size() > kMaxRank) {
    throw Error("safetensors writer: tensor '" + name + "' has more than " +
                std::to_string(kMaxRank) + " dimensions");
  }
  std::uint64_t byte_count = dtype_size(dtype);
  for (const std::int64_t d : shape) {
    if (d < 0) {
      throw Error("safetensors writer: tensor '" + name + "' has a negative dimension");
    }
    if (__builtin_mul_overflow(byte_count, static_cast<std::uint64_t>(d), &byte_count)) {
      throw Error("safetensors writer: tensor '" + name + "' shape " + shape_string(shape) +
                  " overflows 64-bit byte count");
    }
  }
  if (byte_count != data.size()) {
    throw Error("safetensors writer: tensor '" + name + "' shape " + shape_string(shape) +
                " needs " + std::to_string(byte_count) + " bytes, given " +
                std::to_string(data.size()));
  }
  if (name == "__metadata__" || std::any_of(entries_.begin(), entries_.end(),
                                            [&](const Entry& e) { return e.name == name; })) {
    throw Error("safetensors writer: tensor name '" + name + "' used twice or reserved");
  }
  entries_.push_back({std::move(name), dtype, std::move(shape), {data.begin(), data.end()}});
}

void SafetensorsWriter::add_f32(std::string name, std::vector<std::int64_t> shape,
                                std::span<const float> values) {
  add(std::move(name), DType::kF32, std::move(shape), std::as_bytes(values));
}

void SafetensorsWriter::add_f64(std::string name, std::vector<std::int64_t> shape,
                                std::span<const double> values) {
  add(std::move(name), DType::kF64, std::move(shape), std::as_bytes(values));
}

void SafetensorsWriter::add_i64(std::string name, std::vector<std::int64_t> shape,
                                std::span<const std::int64_t> values) {
  add(std::move(name), DType::kI64, std::move(shape), std::as_bytes(values));
}

void SafetensorsWriter::set_metadata(std::string key, std::string value) {
  metadata_[std::move(key)] = std::move(value);
}

std::vector<std::byte> SafetensorsWriter::serialize() const {
  json header = json::object();
  if (!metadata_.empty()) {
    header["__metadata__"] = metadata_;
  }
  std::uint64_t offset = 0;
  for (const Entry& e : entries_) {
    header[e.name] = {{"dtype", dtype_name(e.dtype)},
                      {"shape", e.shape},
                      {"data_offsets", {offset, offset + e.data.size()}}};
    offset += e.data.size();
  }
  std::string text = header.dump();
  text.append((8 - text.size() % 8) % 8, ' ');  // align the data section to 8 bytes
  const std::uint64_t header_size = text.size();

  std::vector<std::byte> out;
  out.reserve(8 + header_size + offset);
  for (int i = 0; i < 8; ++i) {
    out.push_back(static_cast<std::byte>((header_size >> (8 * i)) & 0xff));
  }
  for (const char c : text) {
    out.push_back(static_cast<std::byte>(c));
  }
  for (const Entry& e : entries_) {
    out.insert(out.end(), e.data.begin(), e.data.end());
  }
  return out;
}

void SafetensorsWriter::write(const std::filesystem::path& path) const {
  write_file_atomically(path, serialize());
}

}  // namespace deixis
