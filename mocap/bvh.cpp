#include "mocap/bvh.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace deixis::mocap {

namespace {

constexpr std::array<std::string_view, 6> kChannelNames = {"Xposition", "Yposition", "Zposition",
                                                           "Xrotation", "Yrotation", "Zrotation"};

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

// A whitespace tokenizer that knows the line of every token.
class Cursor {
 public:
  Cursor(std::string_view text, const std::string& source) : text_(text), source_(source) {}

  [[noreturn]] void fail(std::size_t line, const std::string& reason) const {
    throw Error(source_ + ":" + std::to_string(line) + ": " + reason);
  }
  [[noreturn]] void fail(const std::string& reason) const { fail(line_, reason); }

  // The next token, or an empty view at the end of the text.
  std::string_view next() {
    skip_space();
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) {
      ++pos_;
    }
    token_line_ = line_;
    return text_.substr(start, pos_ - start);
  }
  std::string_view expect(const char* what) {
    const std::string_view t = next();
    if (t.empty()) {
      fail("the file ends where " + std::string(what) + " should be");
    }
    return t;
  }
  double number(const char* what) {
    const std::string_view t = expect(what);
    double v = 0;
    if (!parse_number(t, v)) {
      fail(token_line_, std::string(what) + ": '" + clip(t) + "' is not a finite number");
    }
    return v;
  }
  // The rest of the current line (for the motion section, which is line by line).
  std::string_view line_rest() {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') {
      ++pos_;
    }
    const std::string_view rest = text_.substr(start, pos_ - start);
    if (pos_ < text_.size()) {
      ++pos_;
      ++line_;
    }
    return rest;
  }
  bool at_end() const { return pos_ >= text_.size(); }
  std::size_t line() const { return line_; }
  std::size_t token_line() const { return token_line_; }
  std::size_t remaining() const { return text_.size() - pos_; }

  static bool parse_number(std::string_view t, double& v) {
    if (!t.empty() && t.front() == '+') {
      t.remove_prefix(1);
    }
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    return ec == std::errc() && end == t.data() + t.size() && std::isfinite(v);
  }
  static std::string clip(std::string_view t) {
    std::string s(t.substr(0, 40));
    for (char& c : s) {
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) {
        c = '?';
      }
    }
    return s;
  }

 private:
  void skip_space() {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') {
        ++line_;
      }
      ++pos_;
    }
  }
  std::string_view text_;
  const std::string& source_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
  std::size_t token_line_ = 1;
};

void check_lines(std::string_view text, const std::string& source, const BvhLimits& limits) {
  std::size_t line = 1;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= text.size(); ++i) {
    if (i == text.size() || text[i] == '\n') {
      if (i - start > limits.max_line_bytes) {
        throw Error(source + ":" + std::to_string(line) + ": the line is " +
                    std::to_string(i - start) + " bytes long (at most " +
                    std::to_string(limits.max_line_bytes) + ")");
      }
      ++line;
      start = i + 1;
    } else if (text[i] == '\0') {
      throw Error(source + ":" + std::to_string(line) + ": a NUL byte (not a text file)");
    }
  }
}

void parse_channels(Cursor& c, BvhNode& node, std::size_t& channels) {
  const double count = c.number("the channel count");
  if (count != std::floor(count) || count < 0 || count > 6) {
    c.fail(c.token_line(),
           "CHANNELS " + Cursor::clip(std::to_string(count)) + ": a joint has 0 to 6 channels");
  }
  node.channels.clear();
  for (int k = 0; k < static_cast<int>(count); ++k) {
    const std::string_view t = c.expect("a channel name");
    int found = -1;
    for (std::size_t n = 0; n < kChannelNames.size(); ++n) {
      if (iequals(t, kChannelNames[n])) {
        found = static_cast<int>(n);
      }
    }
    if (found < 0) {
      c.fail(c.token_line(), "unknown channel '" + Cursor::clip(t) +
                                 "' (Xposition, Yposition, Zposition, Xrotation, Yrotation, "
                                 "Zrotation)");
    }
    const auto ch = static_cast<Channel>(found);
    if (std::find(node.channels.begin(), node.channels.end(), ch) != node.channels.end()) {
      c.fail(c.token_line(),
             "channel " + std::string(t) + " is listed twice for joint '" + node.name + "'");
    }
    node.channels.push_back(ch);
  }
  node.first_value = static_cast<int>(channels);
  channels += node.channels.size();
}

void parse_hierarchy(Cursor& c, Bvh& b, const BvhLimits& limits) {
  std::string_view t = c.next();
  if (t.size() >= 3 && static_cast<unsigned char>(t[0]) == 0xEF) {
    t.remove_prefix(3);  // a UTF-8 byte order mark
  }
  if (t != "HIERARCHY") {
    c.fail(c.token_line(), "expected HIERARCHY at the start, found '" + Cursor::clip(t) + "'");
  }
  std::vector<int> open;  // the nodes whose '{' is open
  t = c.expect("ROOT");
  while (true) {
    if (open.empty()) {
      if (t == "MOTION") {
        break;
      }
      if (t != "ROOT") {
        c.fail(c.token_line(), "expected ROOT or MOTION, found '" + Cursor::clip(t) + "'");
      }
    }
    if (t == "ROOT" || t == "JOINT" || t == "End") {
      if (t != "ROOT" && open.empty()) {
        c.fail(c.token_line(), Cursor::clip(t) + " outside a joint's braces");
      }
      if (!open.empty() && b.nodes[static_cast<std::size_t>(open.back())].end_site) {
        c.fail(c.token_line(), "an End Site has no children");
      }
      if (b.nodes.size() >= limits.max_nodes) {
        c.fail(c.token_line(),
               "more than " + std::to_string(limits.max_nodes) + " joints and end sites");
      }
      BvhNode node;
      node.parent = open.empty() ? -1 : open.back();
      if (t == "End") {
        if (c.expect("Site") != "Site") {
          c.fail(c.token_line(), "expected 'End Site'");
        }
        node.end_site = true;
        node.name = b.nodes[static_cast<std::size_t>(node.parent)].name + "/End Site";
      } else {
        const std::string_view name = c.expect("a joint name");
        if (name == "{" || name.size() > limits.max_name_bytes) {
          c.fail(c.token_line(), "a joint needs a name of 1 to " +
                                     std::to_string(limits.max_name_bytes) + " bytes");
        }
        node.name = std::string(name);
      }
      if (c.expect("{") != "{") {
        c.fail(c.token_line(), "expected '{' after " + node.name);
      }
      open.push_back(static_cast<int>(b.nodes.size()));
      b.nodes.push_back(std::move(node));
      bool has_offset = false;
      bool has_channels = false;
      // OFFSET and CHANNELS come first, in either order.
      while (true) {
        t = c.expect("'}'");
        BvhNode& n = b.nodes.back();
        if (t == "OFFSET") {
          if (has_offset) {
            c.fail(c.token_line(), n.name + " has a second OFFSET");
          }
          for (int k = 0; k < 3; ++k) {
            n.offset[k] = c.number("OFFSET");
          }
          has_offset = true;
        } else if (t == "CHANNELS") {
          if (n.end_site) {
            c.fail(c.token_line(), "an End Site has no CHANNELS");
          }
          if (has_channels) {
            c.fail(c.token_line(), n.name + " has a second CHANNELS");
          }
          has_channels = true;
          parse_channels(c, n, b.channels);
        } else {
          break;
        }
      }
      if (!has_offset) {
        c.fail(c.token_line(), b.nodes.back().name + " has no OFFSET");
      }
      continue;  // t is the next keyword
    }
    if (t == "}") {
      if (open.empty()) {
        c.fail(c.token_line(), "'}' without an open joint");
      }
      open.pop_back();
      t = c.expect(open.empty() ? "ROOT or MOTION" : "'}'");
      continue;
    }
    c.fail(c.token_line(),
           "unknown keyword '" + Cursor::clip(t) + "' in the hierarchy" +
               (open.empty()
                    ? ""
                    : " (inside " + b.nodes[static_cast<std::size_t>(open.back())].name + ")"));
  }
  if (b.nodes.empty()) {
    c.fail(c.token_line(), "MOTION before any ROOT");
  }
}

void parse_motion(Cursor& c, Bvh& b, const BvhLimits& limits) {
  if (b.channels == 0) {
    c.fail(c.token_line(), "the hierarchy has no channels: there is no motion to read");
  }
  if (c.expect("Frames:") != "Frames:") {
    c.fail(c.token_line(), "expected 'Frames:'");
  }
  const double frames = c.number("Frames:");
  const std::size_t frames_line = c.token_line();
  if (frames != std::floor(frames) || frames < 1 ||
      frames > static_cast<double>(limits.max_frames)) {
    c.fail(frames_line, "Frames: " + std::to_string(frames) + " (1 to " +
                            std::to_string(limits.max_frames) + ")");
  }
  const auto n = static_cast<std::size_t>(frames);
  if (b.channels > 0 && n > limits.max_values / b.channels) {
    c.fail(frames_line, std::to_string(n) + " frames of " + std::to_string(b.channels) +
                            " channels exceed " + std::to_string(limits.max_values) + " values");
  }
  if (c.expect("Frame") != "Frame" || c.expect("Time:") != "Time:") {
    c.fail(c.token_line(), "expected 'Frame Time:'");
  }
  b.frame_time = c.number("Frame Time:");
  if (!(b.frame_time > 0.0 && b.frame_time <= 60.0)) {
    c.fail(c.token_line(),
           "Frame Time: " + std::to_string(b.frame_time) + " s (must be above 0 and at most 60)");
  }
  c.line_rest();
  // Reserve what the bytes left can hold, never what a hostile header claims.
  b.motion.reserve(std::min(n * b.channels, c.remaining() / 2 + b.channels));
  std::size_t read = 0;
  while (read < n) {
    if (c.at_end()) {
      c.fail(c.line(), "truncated motion: the file ends after " + std::to_string(read) + " of " +
                           std::to_string(n) + " frames");
    }
    const std::size_t line = c.line();
    std::string_view rest = c.line_rest();
    std::size_t values = 0;
    const std::size_t before = b.motion.size();
    while (true) {
      while (!rest.empty() && is_space(rest.front())) {
        rest.remove_prefix(1);
      }
      if (rest.empty()) {
        break;
      }
      std::size_t end = 0;
      while (end < rest.size() && !is_space(rest[end])) {
        ++end;
      }
      double v = 0;
      if (!Cursor::parse_number(rest.substr(0, end), v) ||
          std::abs(v) > static_cast<double>(std::numeric_limits<float>::max())) {
        c.fail(line, "frame " + std::to_string(read) + ": '" + Cursor::clip(rest.substr(0, end)) +
                         "' is not a finite number");
      }
      if (values < b.channels) {
        b.motion.push_back(static_cast<float>(v));
      }
      ++values;
      rest.remove_prefix(end);
    }
    if (values == 0) {
      continue;  // blank line
    }
    if (values != b.channels) {
      b.motion.resize(before);
      c.fail(line, "frame " + std::to_string(read) + " has " + std::to_string(values) +
                       " values; the hierarchy's channels need " + std::to_string(b.channels));
    }
    ++read;
  }
  // What follows the declared frames is ignored: exporters write one frame more than they
  // declare (Boxing_Toes.bvh of Debian's assimp-testmodels), and readers stop at the count.
  if (b.channels == 0) {
    b.motion.clear();
  }
}

Eigen::Matrix3d axis_rotation(Channel c, double degrees) {
  const double a = degrees * (M_PI / 180.0);
  const Eigen::Vector3d axis = c == Channel::kXrotation   ? Eigen::Vector3d::UnitX()
                               : c == Channel::kYrotation ? Eigen::Vector3d::UnitY()
                                                          : Eigen::Vector3d::UnitZ();
  return Eigen::AngleAxisd(a, axis).toRotationMatrix();
}

}  // namespace

std::string_view channel_name(Channel c) {
  return kChannelNames[static_cast<std::size_t>(c)];
}

int Bvh::find(std::string_view name) const {
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].name == name) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

Bvh parse_bvh(std::string_view text, const std::string& source, const BvhLimits& limits) {
  if (text.size() > limits.max_file_bytes) {
    throw Error(source + ":1: the file is " + std::to_string(text.size()) + " bytes (at most " +
                std::to_string(limits.max_file_bytes) + ")");
  }
  check_lines(text, source, limits);
  Bvh b;
  b.source = source;
  Cursor c(text, source);
  parse_hierarchy(c, b, limits);
  parse_motion(c, b, limits);
  return b;
}

Bvh read_bvh(const std::filesystem::path& path, const BvhLimits& limits) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) {
    throw Error(path.string() + ": cannot read (" + ec.message() + ")");
  }
  if (size > limits.max_file_bytes) {
    throw Error(path.string() + ":1: the file is " + std::to_string(size) + " bytes (at most " +
                std::to_string(limits.max_file_bytes) + ")");
  }
  std::ifstream in(path, std::ios::binary);
  std::string text(static_cast<std::size_t>(size), '\0');
  if (!in.read(text.data(), static_cast<std::streamsize>(size))) {
    throw Error(path.string() + ": cannot read");
  }
  return parse_bvh(text, path.string(), limits);
}

Bvh slice(const Bvh& bvh, std::size_t first, std::size_t end) {
  Bvh out;
  out.source = bvh.source;
  out.nodes = bvh.nodes;
  out.channels = bvh.channels;
  out.frame_time = bvh.frame_time;
  const auto begin = bvh.motion.begin() + static_cast<std::ptrdiff_t>(first * bvh.channels);
  out.motion.assign(begin, begin + static_cast<std::ptrdiff_t>((end - first) * bvh.channels));
  return out;
}

std::string write_bvh(const Bvh& b) {
  std::ostringstream out;
  char buffer[48];
  auto num = [&](double v) {
    std::snprintf(buffer, sizeof buffer, "%.9g", v);
    return std::string(buffer);
  };
  out << "HIERARCHY\n";
  std::vector<int> open;
  auto close_to = [&](int parent) {
    while (!open.empty() && open.back() != parent) {
      out << std::string(open.size() - 1, '\t') << "}\n";
      open.pop_back();
    }
  };
  for (std::size_t i = 0; i < b.nodes.size(); ++i) {
    const BvhNode& n = b.nodes[i];
    close_to(n.parent);
    const std::string indent(open.size(), '\t');
    out << indent
        << (n.end_site ? std::string("End Site") : (n.parent < 0 ? "ROOT " : "JOINT ") + n.name)
        << '\n'
        << indent << "{\n"
        << indent << "\tOFFSET " << num(n.offset.x()) << ' ' << num(n.offset.y()) << ' '
        << num(n.offset.z()) << '\n';
    if (!n.end_site) {
      out << indent << "\tCHANNELS " << n.channels.size();
      for (const Channel ch : n.channels) {
        out << ' ' << channel_name(ch);
      }
      out << '\n';
    }
    open.push_back(static_cast<int>(i));
  }
  close_to(-1);
  out << "MOTION\nFrames: " << b.frames() << "\nFrame Time: " << num(b.frame_time) << '\n';
  for (std::size_t f = 0; f < b.frames(); ++f) {
    const std::span<const float> row = b.frame(f);
    for (std::size_t k = 0; k < row.size(); ++k) {
      out << (k == 0 ? "" : " ") << num(row[k]);
    }
    out << '\n';
  }
  return out.str();
}

Eigen::Matrix3d channel_rotation(const BvhNode& node, std::span<const float> row) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  for (std::size_t k = 0; k < node.channels.size(); ++k) {
    const Channel ch = node.channels[k];
    if (ch >= Channel::kXrotation) {
      R = R * axis_rotation(
                  ch, static_cast<double>(row[static_cast<std::size_t>(node.first_value) + k]));
    }
  }
  return R;
}

void forward_kinematics(const Bvh& b, std::span<const float> row, double scale,
                        std::span<JointPose> out) {
  for (std::size_t i = 0; i < b.nodes.size(); ++i) {
    const BvhNode& n = b.nodes[i];
    Eigen::Vector3d t = n.offset;
    for (std::size_t k = 0; k < n.channels.size(); ++k) {
      const Channel ch = n.channels[k];
      if (ch <= Channel::kZposition) {
        t[static_cast<int>(ch)] +=
            static_cast<double>(row[static_cast<std::size_t>(n.first_value) + k]);
      }
    }
    t *= scale;
    const Eigen::Matrix3d R = channel_rotation(n, row);
    if (n.parent < 0) {
      out[i] = {R, t};
    } else {
      const JointPose& p = out[static_cast<std::size_t>(n.parent)];
      out[i] = {p.R * R, p.R * t + p.p};
    }
  }
}

LengthUnit parse_length_unit(std::string_view name) {
  for (const LengthUnit u : {LengthUnit::kAuto, LengthUnit::kMetre, LengthUnit::kCentimetre,
                             LengthUnit::kMillimetre, LengthUnit::kInch, LengthUnit::kCmu}) {
    if (name == unit_name(u)) {
      return u;
    }
  }
  throw Error("unknown unit '" + std::string(name) + "' (m, cm, mm, inch, cmu or auto)");
}

std::string_view unit_name(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::kAuto:
      return "auto";
    case LengthUnit::kMetre:
      return "m";
    case LengthUnit::kCentimetre:
      return "cm";
    case LengthUnit::kMillimetre:
      return "mm";
    case LengthUnit::kInch:
      return "inch";
    case LengthUnit::kCmu:
      return "cmu";
  }
  return "?";
}

double metres_per_unit(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::kMetre:
      return 1.0;
    case LengthUnit::kCentimetre:
      return 0.01;
    case LengthUnit::kMillimetre:
      return 0.001;
    case LengthUnit::kInch:
      return 0.0254;
    case LengthUnit::kCmu:
      return 0.0254 / 0.45;
    case LengthUnit::kAuto:
      break;
  }
  throw Error("metres_per_unit: the unit 'auto' must be inferred first (infer_unit)");
}

double rest_height(const Bvh& b) {
  std::vector<JointPose> poses(b.nodes.size());
  const std::vector<float> zeros(b.channels, 0.0f);
  forward_kinematics(b, zeros, 1.0, poses);
  double low = poses.front().p.y();
  double high = low;
  for (const JointPose& p : poses) {
    low = std::min(low, p.p.y());
    high = std::max(high, p.p.y());
  }
  return high - low;
}

LengthUnit infer_unit(const Bvh& b) {
  const double height = rest_height(b);
  LengthUnit best = LengthUnit::kMetre;
  double best_distance = INFINITY;
  for (const LengthUnit u : {LengthUnit::kMetre, LengthUnit::kCentimetre, LengthUnit::kMillimetre,
                             LengthUnit::kInch, LengthUnit::kCmu}) {
    const double d = std::abs(std::log(height * metres_per_unit(u) / 1.70));
    if (d < best_distance) {
      best_distance = d;
      best = u;
    }
  }
  const double metres = height * metres_per_unit(best);
  if (!(metres >= 1.0 && metres <= 2.5)) {
    throw Error(b.source + ": cannot infer the unit: the rest pose is " + std::to_string(height) +
                " units tall, which no unit (m, cm, mm, inch, cmu) makes 1.0-2.5 m; state --unit");
  }
  return best;
}

}  // namespace deixis::mocap
