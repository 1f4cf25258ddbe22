#include "avatar/gltf_accessors.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/error.h"

namespace deixis::avatar::gltf {

namespace {

std::string type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return "type " + std::to_string(type);
  }
}

[[noreturn]] void fail(const ReadContext& c, int index, const std::string& message) {
  throw Error(c.what + ": accessors[" + std::to_string(index) + "]: " + message);
}

// The bytes of one validated accessor: where element i's component k starts, and its type.
struct View {
  const std::uint8_t* base = nullptr;
  std::size_t stride = 0;
  std::size_t component_size = 0;
  std::size_t count = 0;
  int component_type = 0;
  bool normalized = false;

  const std::uint8_t* at(std::size_t i, int k) const {
    return base + i * stride + static_cast<std::size_t>(k) * component_size;
  }
};

View checked_view(const ReadContext& c, int index, int type, int components) {
  const tinygltf::Model& m = c.model;
  if (index < 0 || static_cast<std::size_t>(index) >= m.accessors.size()) {
    throw Error(c.what + ": accessor " + std::to_string(index) + " does not exist (the file has " +
                std::to_string(m.accessors.size()) + ")");
  }
  const tinygltf::Accessor& a = m.accessors[index];
  if (a.type != type) {
    fail(c, index, "expected " + type_name(type) + ", found " + type_name(a.type));
  }
  if (a.sparse.isSparse) {
    fail(c, index, "sparse accessors are not supported");
  }
  const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
  if (size <= 0) {
    fail(c, index, "unknown component type " + std::to_string(a.componentType));
  }
  if (a.bufferView < 0 || static_cast<std::size_t>(a.bufferView) >= m.bufferViews.size()) {
    fail(c, index, "buffer view " + std::to_string(a.bufferView) + " does not exist");
  }
  const tinygltf::BufferView& bv = m.bufferViews[a.bufferView];
  if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= m.buffers.size()) {
    fail(c, index, "buffer " + std::to_string(bv.buffer) + " does not exist");
  }
  const std::vector<unsigned char>& data = m.buffers[bv.buffer].data;
  // 64-bit sums of values each below 2^63 cannot overflow in the checks below.
  const std::uint64_t element = static_cast<std::uint64_t>(size) * components;
  const std::uint64_t stride = bv.byteStride == 0 ? element : bv.byteStride;
  if (stride < element) {
    fail(c, index,
         "byte stride " + std::to_string(stride) + " is smaller than an element (" +
             std::to_string(element) + " bytes)");
  }
  if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset) {
    fail(c, index,
         "buffer view " + std::to_string(a.bufferView) + " (offset " +
             std::to_string(bv.byteOffset) + ", length " + std::to_string(bv.byteLength) +
             ") runs past the end of its buffer (" + std::to_string(data.size()) + " bytes)");
  }
  // Bounding count, stride and offset by the view's length (itself below 2^32, the largest GLB)
  // keeps the product below 2^64.
  if (data.size() > 0xffffffffull || a.count > bv.byteLength || a.byteOffset > bv.byteLength ||
      (a.count > 1 && stride > bv.byteLength)) {
    fail(c, index,
         std::to_string(a.count) + " elements (offset " + std::to_string(a.byteOffset) +
             ", stride " + std::to_string(stride) + ") cannot fit in buffer view " +
             std::to_string(a.bufferView) + " of " + std::to_string(bv.byteLength) + " bytes");
  }
  const std::uint64_t needed = a.count == 0 ? 0 : a.byteOffset + (a.count - 1) * stride + element;
  if (needed > bv.byteLength) {
    fail(c, index,
         std::to_string(a.count) + " elements from offset " + std::to_string(a.byteOffset) +
             " need " + std::to_string(needed) + " bytes, but the buffer view has " +
             std::to_string(bv.byteLength));
  }
  View v;
  v.base = data.data() + bv.byteOffset + a.byteOffset;
  v.stride = static_cast<std::size_t>(stride);
  v.component_size = static_cast<std::size_t>(size);
  v.count = a.count;
  v.component_type = a.componentType;
  v.normalized = a.normalized;
  return v;
}

template <typename T>
T load(const std::uint8_t* p) {
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

// glTF 2.0 §3.11: normalised signed values map to max(c / max, −1).
float component_as_float(const View& v, const std::uint8_t* p) {
  switch (v.component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return load<float>(p);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return v.normalized ? load<std::uint8_t>(p) / 255.0f : load<std::uint8_t>(p);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return v.normalized ? load<std::uint16_t>(p) / 65535.0f : load<std::uint16_t>(p);
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return v.normalized ? std::max(load<std::int8_t>(p) / 127.0f, -1.0f) : load<std::int8_t>(p);
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return v.normalized ? std::max(load<std::int16_t>(p) / 32767.0f, -1.0f)
                          : load<std::int16_t>(p);
    default:
      return std::nanf("");
  }
}

}  // namespace

std::vector<float> read_floats(const ReadContext& c, int index, int type, int components) {
  const View v = checked_view(c, index, type, components);
  const int t = v.component_type;
  if (t != TINYGLTF_COMPONENT_TYPE_FLOAT && t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
      t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT && t != TINYGLTF_COMPONENT_TYPE_BYTE &&
      t != TINYGLTF_COMPONENT_TYPE_SHORT) {
    fail(c, index, "component type " + std::to_string(t) + " cannot hold these values");
  }
  std::vector<float> out;
  out.reserve(v.count * static_cast<std::size_t>(components));
  for (std::size_t i = 0; i < v.count; ++i) {
    for (int k = 0; k < components; ++k) {
      const float value = component_as_float(v, v.at(i, k));
      if (!std::isfinite(value)) {
        fail(c, index, "element " + std::to_string(i) + " is not a finite number");
      }
      out.push_back(value);
    }
  }
  return out;
}

std::vector<std::uint32_t> read_uints(const ReadContext& c, int index, int type, int components) {
  const View v = checked_view(c, index, type, components);
  const int t = v.component_type;
  if (t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
    fail(c, index, "expected unsigned integers, found component type " + std::to_string(t));
  }
  std::vector<std::uint32_t> out;
  out.reserve(v.count * static_cast<std::size_t>(components));
  for (std::size_t i = 0; i < v.count; ++i) {
    for (int k = 0; k < components; ++k) {
      const std::uint8_t* p = v.at(i, k);
      out.push_back(t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? load<std::uint8_t>(p)
                    : t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? load<std::uint16_t>(p)
                                                                  : load<std::uint32_t>(p));
    }
  }
  return out;
}

}  // namespace deixis::avatar::gltf
