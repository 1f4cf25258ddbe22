// libFuzzer target for parse_safetensors_header, the code that reads a whole untrusted file
// (weights and datasets may come from anywhere). Every input must either be rejected with a
// deixis::Error that names the file, or parse into a header whose invariants hold; anything else
// (another exception, a sanitizer report, a broken invariant) is a crash.
//
// Built with libFuzzer by the `fuzz` preset (tools/fuzz-smoke runs it), and into
// safetensors_header_replay (replay_main.cpp) by ordinary builds, where CTest replays the committed
// corpus fuzz/corpus/safetensors_header/ under GCC's sanitizers.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "core/io/safetensors.h"

namespace {

constexpr std::string_view kSource = "fuzz-input";

// Invariant violations must stop the fuzzer with the input that caused them, so they trap rather
// than throw (an exception could be swallowed) or assert (compiled out with NDEBUG).
void check(bool holds, const char* invariant) {
  if (!holds) {
    std::fprintf(stderr, "safetensors_header_fuzz: invariant violated: %s\n", invariant);
    __builtin_trap();
  }
}

std::uint64_t byte_count(const deixis::TensorInfo& tensor) {
  std::uint64_t bytes = deixis::dtype_size(tensor.dtype);
  for (const std::int64_t d : tensor.shape) {
    check(d >= 0, "shape dimensions are non-negative");
    check(!__builtin_mul_overflow(bytes, static_cast<std::uint64_t>(d), &bytes),
          "numel * dtype_size fits in 64 bits");
  }
  return bytes;
}

// What a successful parse promises about the file it was given.
void check_header(std::span<const std::byte> file, const deixis::SafetensorsHeader& header) {
  check(file.size() >= 8, "an accepted file holds the 8-byte length field");
  std::uint64_t length_field = 0;
  for (int i = 7; i >= 0; --i) {
    length_field = (length_field << 8) | std::to_integer<std::uint64_t>(file[i]);
  }
  check(length_field <= deixis::kMaxSafetensorsHeaderBytes, "header length within the limit");
  check(header.data_offset == 8 + length_field, "data_offset is 8 + the header length field");
  check(header.data_offset <= file.size(), "the data section starts inside the file");
  const std::uint64_t data_size = file.size() - header.data_offset;

  std::set<std::string_view> names;
  std::uint64_t next_begin = 0;
  for (const deixis::TensorInfo& tensor : header.tensors) {
    check(names.insert(tensor.name).second, "tensor names are unique");
    check(tensor.name != "__metadata__", "__metadata__ is not a tensor");
    check(deixis::dtype_size(tensor.dtype) != 0, "every dtype is a known one");
    check(tensor.begin <= tensor.end, "begin <= end");
    // With end <= data_size, [data_offset + begin, data_offset + end) lies within the input.
    check(tensor.end <= data_size, "every tensor lies within the input");
    check(tensor.begin == next_begin, "tensors tile the data section in order, no gap or overlap");
    check(tensor.end - tensor.begin == byte_count(tensor), "end - begin == numel * dtype_size");
    next_begin = tensor.end;
  }
  check(next_begin == data_size, "the tensors cover the data section to its end");
}

// The accessors of an accepted file work on every tensor it lists: require() finds it as listed,
// bytes() covers exactly its data, and reading values either succeeds or reports a non-finite value
// as a deixis::Error.
void check_file_accessors(std::span<const std::byte> input) {
  const deixis::SafetensorsFile file = deixis::SafetensorsFile::from_bytes(
      std::string(kSource), std::vector<std::byte>(input.begin(), input.end()));
  for (const deixis::TensorInfo& tensor : file.tensors()) {
    const deixis::TensorInfo& found = file.require(tensor.name, tensor.dtype, tensor.shape);
    check(&found == &tensor, "require() finds the tensor listed under its name");
    check(file.bytes(tensor).size() == tensor.end - tensor.begin, "bytes() covers the tensor");
    try {
      if (tensor.dtype == deixis::DType::kF32) {
        check(file.read_f32(tensor.name, tensor.shape).size() == tensor.numel(), "read_f32 size");
      } else if (tensor.dtype == deixis::DType::kF64) {
        check(file.read_f64(tensor.name, tensor.shape).size() == tensor.numel(), "read_f64 size");
      }
    } catch (const deixis::Error&) {
      // NaN or ±Inf in the values: reported, as it should be.
    }
  }
}

// Writing the parsed tensors back out with SafetensorsWriter and parsing the result gives the same
// header: the writer accepts everything the reader does, and the two agree on the format.
void check_rewrite(std::span<const std::byte> file, const deixis::SafetensorsHeader& header) {
  deixis::SafetensorsWriter writer;
  for (const deixis::TensorInfo& tensor : header.tensors) {
    writer.add(tensor.name, tensor.dtype, tensor.shape,
               file.subspan(header.data_offset + tensor.begin, tensor.end - tensor.begin));
  }
  for (const auto& [key, value] : header.metadata) {
    writer.set_metadata(key, value);
  }
  const std::vector<std::byte> rewritten = writer.serialize();
  const deixis::SafetensorsHeader reparsed =
      deixis::parse_safetensors_header("rewritten-fuzz-input", rewritten);
  check(reparsed.data_offset % 8 == 0, "the writer aligns the data section");
  check(reparsed.metadata == header.metadata, "metadata survives a rewrite");
  check(reparsed.tensors.size() == header.tensors.size(), "tensor count survives a rewrite");
  for (std::size_t i = 0; i < header.tensors.size(); ++i) {
    const deixis::TensorInfo& before = header.tensors[i];
    const deixis::TensorInfo& after = reparsed.tensors[i];
    check(after.name == before.name && after.dtype == before.dtype && after.shape == before.shape &&
              after.begin == before.begin && after.end == before.end,
          "every tensor survives a rewrite in place");
  }
  const auto data_before = file.subspan(header.data_offset);
  const auto data_after = std::span<const std::byte>(rewritten).subspan(reparsed.data_offset);
  check(std::equal(data_before.begin(), data_before.end(), data_after.begin(), data_after.end()),
        "the data section survives a rewrite");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // libFuzzer may pass a null pointer with size 0; an empty span is what that means.
  const std::span<const std::byte> input =
      size == 0 ? std::span<const std::byte>()
                : std::span<const std::byte>(reinterpret_cast<const std::byte*>(data), size);
  try {
    deixis::SafetensorsHeader header;
    try {
      header = deixis::parse_safetensors_header(kSource, input);
    } catch (const deixis::Error& rejected) {
      // The expected outcome for most inputs; the message must still name the file.
      check(std::string_view(rejected.what()).starts_with(std::string(kSource) + ": "),
            "a rejection names the file");
      return 0;
    }
    check_header(input, header);
    check_file_accessors(input);
    check_rewrite(input, header);
  } catch (const std::exception& e) {
    // From the accessors or the rewrite of an accepted file, even a deixis::Error is a bug.
    std::fprintf(stderr, "safetensors_header_fuzz: unexpected exception: %s\n", e.what());
    __builtin_trap();
  } catch (...) {
    std::fprintf(stderr, "safetensors_header_fuzz: unexpected exception of unknown type\n");
    __builtin_trap();
  }
  return 0;
}
