#include "avatar/gltf_limits.h"

#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "core/error.h"
#include "core/io/json_guard.h"

namespace deixis::avatar::gltf {

namespace {

std::uint32_t u32_at(std::span<const std::uint8_t> bytes, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, bytes.data() + at, 4);  // GLB is little-endian, as every target Deixis runs on
  return v;
}

constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"

// A URI as it may appear in a message: control characters escaped, long ones cut.
std::string printable(std::string_view uri) {
  std::string out;
  for (const char c : uri.substr(0, 120)) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7F) {
      static const char* kHex = "0123456789abcdef";
      out += std::string("\\x") + kHex[u >> 4] + kHex[u & 15];
    } else {
      out += c;
    }
  }
  return uri.size() > 120 ? out + "..." : out;
}

// tinygltf percent-decodes external URIs before it opens them, so they are checked decoded too.
std::string percent_decoded(std::string_view uri) {
  std::string out;
  const auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') {
      return c - '0';
    }
    if (c >= 'a' && c <= 'f') {
      return c - 'a' + 10;
    }
    if (c >= 'A' && c <= 'F') {
      return c - 'A' + 10;
    }
    return -1;
  };
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
      out += static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
      i += 2;
    } else if (uri[i] == '+') {
      out += ' ';  // dlib::urldecode, which tinygltf uses, reads '+' as a space
    } else {
      out += uri[i];
    }
  }
  return out;
}

// "" when `path` is relative and never climbs above its starting folder.
std::string relative_path_problem(std::string_view path) {
  if (path.find('\0') != std::string_view::npos) {
    return "contains a NUL byte";
  }
  if (!path.empty() && (path.front() == '/' || path.front() == '\\')) {
    return "is an absolute path";
  }
  const std::size_t colon = path.find(':');
  if (colon != std::string_view::npos && path.find_first_of("/\\") > colon) {
    return "has a scheme or drive other than data:";
  }
  long depth = 0;
  std::size_t start = 0;
  while (start <= path.size()) {
    const std::size_t end = std::min(path.find_first_of("/\\", start), path.size());
    const std::string_view segment = path.substr(start, end - start);
    if (segment == "..") {
      if (--depth < 0) {
        return "leaves the file's folder";
      }
    } else if (!segment.empty() && segment != ".") {
      ++depth;
    }
    start = end + 1;
  }
  return "";
}

// Walks the JSON without building it: counts values and checks the URIs of buffers and images.
class GltfJsonCheck : public nlohmann::json_sax<nlohmann::json> {
 public:
  GltfJsonCheck(const std::string& source, bool has_folder, const std::string& kind)
      : source_(source), kind_(kind), has_folder_(has_folder) {}

  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t& s) override {
    if (is_uri()) {
      const std::string problem = uri_problem(s, has_folder_);
      if (!problem.empty()) {
        throw Error(source_ + ": " + open_[0].key + "[" + std::to_string(open_[1].index) +
                    "].uri '" + printable(s) + "' " + problem);
      }
    }
    return value();
  }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override {
    count();
    open_.push_back({true, {}, 0});
    return true;
  }
  bool key(string_t& k) override {
    open_.back().key = k;
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override {
    count();
    open_.push_back({false, {}, 0});
    return true;
  }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t, const std::string&, const nlohmann::json::exception& e) override {
    throw Error(source_ + ": not a readable " + kind_ + ": invalid JSON: " + e.what());
  }

 private:
  struct Frame {
    bool object = false;
    std::string key;
    std::size_t index = 0;  // arrays: elements so far
  };

  // {"buffers": [{"uri": ...}]} and the same for images.
  bool is_uri() const {
    return open_.size() == 3 && open_[0].object &&
           (open_[0].key == "buffers" || open_[0].key == "images") && !open_[1].object &&
           open_[2].object && open_[2].key == "uri";
  }
  void count() {
    if (++values_ > kMaxJsonValues) {
      throw Error(source_ + ": the glTF JSON has more than " + std::to_string(kMaxJsonValues) +
                  " values (numbers, strings, arrays and objects); an avatar needs far fewer");
    }
  }
  bool value() {
    count();
    element_done();
    return true;
  }
  bool close() {
    open_.pop_back();
    element_done();
    return true;
  }
  void element_done() {
    if (!open_.empty() && !open_.back().object) {
      ++open_.back().index;
    }
  }

  const std::string& source_;
  const std::string& kind_;
  bool has_folder_;
  std::vector<Frame> open_;
  std::uint64_t values_ = 0;
};

// How many indices a primitive's bake reads or makes: strips and fans become triangle lists.
std::uint64_t baked_indices(int mode, std::uint64_t n) {
  if (mode == TINYGLTF_MODE_TRIANGLE_STRIP || mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    return n >= 3 ? 3 * (n - 2) : 0;
  }
  return n;
}

std::uint64_t accessor_count(const tinygltf::Model& model, int accessor) {
  if (accessor < 0 || static_cast<std::size_t>(accessor) >= model.accessors.size()) {
    return 0;  // the bake names the missing accessor
  }
  return model.accessors[accessor].count;
}

// total += n, or an error naming the cap once total would pass it (no overflow on any n).
void add_within(std::uint64_t& total, std::uint64_t n, std::uint64_t cap, const std::string& what,
                const std::string& source) {
  if (n > cap || total > cap - n) {
    throw Error(source + ": the mesh has more than " + std::to_string(cap) + " " + what +
                " once every node that uses a mesh is counted (at most " + std::to_string(cap) +
                " for an avatar)");
  }
  total += n;
}

}  // namespace

std::string_view gltf_json(std::span<const std::uint8_t> bytes, bool binary,
                           const std::string& source) {
  if (!binary) {
    if (bytes.size() > kMaxJsonBytes) {
      throw Error(source + ": " + std::to_string(bytes.size()) + " bytes of glTF JSON (at most " +
                  std::to_string(kMaxJsonBytes >> 20) + " MiB)");
    }
    return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
  }
  const auto where = [&](const std::string& what) {
    return Error(source + ": not a readable glTF binary (.glb): " + what);
  };
  if (bytes.size() < 20) {
    throw where("header cut short (" + std::to_string(bytes.size()) + " bytes)");
  }
  if (u32_at(bytes, 4) != 2) {
    throw where("version " + std::to_string(u32_at(bytes, 4)) + " (only glTF 2 is read)");
  }
  const std::uint64_t length = u32_at(bytes, 8);
  if (length > bytes.size() || length < 20) {
    throw where("the header says " + std::to_string(length) + " bytes, the file has " +
                std::to_string(bytes.size()));
  }
  const std::uint64_t json_length = u32_at(bytes, 12);
  if (u32_at(bytes, 16) != kChunkJson) {
    throw where("first chunk is not JSON");
  }
  if (json_length > length - 20) {
    throw where("JSON chunk of " + std::to_string(json_length) + " bytes runs past the end (" +
                std::to_string(length) + " bytes)");
  }
  if (json_length > kMaxJsonBytes) {
    throw where("JSON chunk of " + std::to_string(json_length) + " bytes (at most " +
                std::to_string(kMaxJsonBytes >> 20) + " MiB)");
  }
  const std::uint64_t rest = length - 20 - json_length;
  if (rest != 0) {
    if (rest < 8) {
      throw where("second chunk header cut short (" + std::to_string(rest) + " bytes)");
    }
    const std::uint64_t bin_length = u32_at(bytes, 20 + json_length);
    if (u32_at(bytes, 24 + json_length) != kChunkBin) {
      throw where("second chunk is not BIN");
    }
    if (bin_length > rest - 8) {
      throw where("BIN chunk of " + std::to_string(bin_length) + " bytes runs past the end (" +
                  std::to_string(rest - 8) + " bytes left)");
    }
  }
  return {reinterpret_cast<const char*>(bytes.data()) + 20, static_cast<std::size_t>(json_length)};
}

std::string uri_problem(std::string_view uri, bool has_folder) {
  if (uri.empty()) {
    return "";  // a .glb's buffer 0: the BIN chunk (tinygltf refuses it in a .gltf)
  }
  if (uri.starts_with("data:")) {
    return tinygltf::IsDataURI(std::string(uri))
               ? ""
               : "is a data: URI of a kind not read (base64 octet-stream or image only)";
  }
  if (!has_folder) {
    return "is an external file, and bytes loaded from memory have no folder to read it from";
  }
  for (const std::string& form : {std::string(uri), percent_decoded(uri)}) {
    if (std::string problem = relative_path_problem(form); !problem.empty()) {
      return problem + " (only data: URIs and relative paths inside the file's folder are read)";
    }
  }
  return "";
}

void check_gltf_json(std::string_view json, const std::string& source, bool has_folder,
                     const std::string& kind) {
  if (const auto problem = json_depth_problem(json, kMaxJsonDepth)) {
    throw Error(source + ": glTF JSON " + *problem);
  }
  GltfJsonCheck check(source, has_folder, kind);
  nlohmann::json::sax_parse(json, &check);
}

tinygltf::FsCallbacks ConfinedFiles::callbacks() {
  return {&ConfinedFiles::exists, &ConfinedFiles::expand, &ConfinedFiles::read,
          &ConfinedFiles::write, this};
}

bool ConfinedFiles::inside(const std::string& path) const {
  const std::filesystem::path p = std::filesystem::path(path).lexically_normal();
  const std::filesystem::path rel = p.lexically_relative(folder_.lexically_normal());
  return !folder_.empty() && !rel.empty() && !rel.is_absolute() && *rel.begin() != "..";
}

bool ConfinedFiles::exists(const std::string& path, void* self) {
  std::error_code ec;
  return static_cast<ConfinedFiles*>(self)->inside(path) &&
         std::filesystem::is_regular_file(path, ec);
}

std::string ConfinedFiles::expand(const std::string& path, void*) {
  return path;  // no ~ or $VARIABLE expansion: a file names bytes, never the environment
}

bool ConfinedFiles::read(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                         void* self) {
  auto& files = *static_cast<ConfinedFiles*>(self);
  std::error_code ec;
  if (!files.inside(path) || !std::filesystem::is_regular_file(path, ec)) {
    *err += "'" + path + "' is not a file inside " + files.folder_.string() + "\n";
    return false;
  }
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || size > kMaxExternalBytes - files.read_bytes_) {
    *err += "'" + path + "' would take the external files past " +
            std::to_string(kMaxExternalBytes >> 20) + " MiB\n";
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  out->resize(static_cast<std::size_t>(size));
  if (!in.read(reinterpret_cast<char*>(out->data()), static_cast<std::streamsize>(size))) {
    *err += "cannot read '" + path + "'\n";
    return false;
  }
  files.read_bytes_ += size;
  return true;
}

bool ConfinedFiles::write(std::string* err, const std::string&, const std::vector<unsigned char>&,
                          void*) {
  *err += "the avatar loader writes no files\n";
  return false;
}

void check_mesh_budget(const tinygltf::Model& model, const std::vector<int>& nodes,
                       const std::string& source) {
  std::uint64_t mesh_nodes = 0;
  std::uint64_t vertices = 0;
  std::uint64_t indices = 0;
  for (const int node : nodes) {
    const int mesh = model.nodes[node].mesh;
    if (mesh < 0 || static_cast<std::size_t>(mesh) >= model.meshes.size()) {
      continue;  // the bake names a missing mesh
    }
    add_within(mesh_nodes, 1, kMaxMeshNodes, "nodes placing a mesh", source);
    // As the bake does: primitives of one node with the same attributes (and normals) share
    // their vertices; every other primitive and every other node bakes its own.
    std::set<std::map<std::string, int>> shared;
    for (const tinygltf::Primitive& p : model.meshes[mesh].primitives) {
      const auto position = p.attributes.find("POSITION");
      const std::uint64_t n =
          position == p.attributes.end() ? 0 : accessor_count(model, position->second);
      const bool reused = p.attributes.contains("NORMAL") && !shared.insert(p.attributes).second;
      add_within(vertices, reused ? 0 : n, kMaxVertices, "vertices", source);
      add_within(indices,
                 baked_indices(p.mode, p.indices >= 0 ? accessor_count(model, p.indices) : n),
                 kMaxIndices, "indices (triangle strips and fans as lists)", source);
    }
  }
}

}  // namespace deixis::avatar::gltf
