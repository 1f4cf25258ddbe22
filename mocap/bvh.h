#pragma once
// BVH motion capture files as tools write them (docs/bvh.md): HIERARCHY with ROOT / JOINT /
// End Site blocks, OFFSET, CHANNELS in any order per joint (position channels allowed on any
// joint), then MOTION / Frames: / Frame Time: and one line of values per frame.
//
// Conventions (docs/bvh.md#conventions). A joint's local transform is
//   translate(OFFSET + (Xposition, Yposition, Zposition)) · R,
//   R = R_first · R_second · R_third
// where the rotation channels compose left to right in the order the file lists them (intrinsic
// rotations, applied to the child's coordinates), angles in degrees. A joint's world transform is
// its parent's times its local one. Lengths are in the file's unit until scaled (metres_per_unit).
//
// Every file is untrusted: sizes are bounded (BvhLimits) and every error is a deixis::Error
// "<source>:<line>: <reason>".

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace deixis::mocap {

enum class Channel : std::uint8_t {
  kXposition,
  kYposition,
  kZposition,
  kXrotation,
  kYrotation,
  kZrotation
};
std::string_view channel_name(Channel c);

struct BvhNode {
  std::string name;  // the End Site's parent's name + "/End Site" for end sites
  int parent = -1;   // index into Bvh::nodes; parents come before children
  bool end_site = false;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // file units
  std::vector<Channel> channels;                     // at most 6, no repeats
  int first_value = 0;  // where this node's channels start in a frame's row
};

struct BvhLimits {
  std::size_t max_file_bytes = std::size_t{1} << 29;  // 512 MiB
  std::size_t max_line_bytes = std::size_t{1} << 20;
  std::size_t max_nodes = 1024;  // joints and end sites
  std::size_t max_frames = 1'000'000;
  std::size_t max_values = 50'000'000;  // frames x channels (float storage: 200 MB)
  std::size_t max_name_bytes = 256;
};

struct Bvh {
  std::string source;
  std::vector<BvhNode> nodes;
  std::size_t channels = 0;   // values per frame
  double frame_time = 0.0;    // s
  std::vector<float> motion;  // frames x channels

  std::size_t frames() const { return channels == 0 ? motion.size() : motion.size() / channels; }
  std::span<const float> frame(std::size_t i) const {
    return {motion.data() + i * channels, channels};
  }
  // The node of that name (exact), or -1.
  int find(std::string_view name) const;
};

Bvh parse_bvh(std::string_view text, const std::string& source, const BvhLimits& limits = {});
Bvh read_bvh(const std::filesystem::path& path, const BvhLimits& limits = {});
// The file again (every value with 9 significant digits): parse_bvh(write_bvh(b)) gives b.
std::string write_bvh(const Bvh& bvh);
// Frames [first, end) as a recording of their own (a site's `from`/`to`); first < end <= frames.
Bvh slice(const Bvh& bvh, std::size_t first, std::size_t end);

// A node's world transform (double precision; lengths already scaled to metres).
struct JointPose {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
};

// The local rotation of a node's channels from a row (degrees), composed in listed order.
Eigen::Matrix3d channel_rotation(const BvhNode& node, std::span<const float> row);

// Forward kinematics of one row (Bvh::frame(i), or zeros for the rest pose) into `out`
// (nodes.size() entries). Allocates nothing.
void forward_kinematics(const Bvh& bvh, std::span<const float> row, double metres_per_unit,
                        std::span<JointPose> out);

// Lengths: the unit a file's numbers are in.
enum class LengthUnit : std::uint8_t { kAuto, kMetre, kCentimetre, kMillimetre, kInch, kCmu };
// "m", "cm", "mm", "inch", "cmu", "auto"; anything else: deixis::Error.
LengthUnit parse_length_unit(std::string_view name);
std::string_view unit_name(LengthUnit unit);
// Metres per file unit. kCmu: the cgspeed conversion of the CMU database keeps the ASF's lengths,
// whose unit is 1/0.45 inch ("units: length 0.45"): 0.0254 / 0.45 = 0.056444 m.
double metres_per_unit(LengthUnit unit);
// The rest pose's vertical extent (highest minus lowest node, all channels zero), file units.
double rest_height(const Bvh& bvh);
// The unit that makes the rest pose's height closest to 1.70 m (in ratio) among m, cm, mm, inch
// and CMU; deixis::Error naming the height when none gives 1.0-2.5 m.
LengthUnit infer_unit(const Bvh& bvh);

}  // namespace deixis::mocap
