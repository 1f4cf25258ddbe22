// The BVH reader (mocap/bvh.h): each rotation channel order composes left to right (known joint
// positions to 1e-6 m), position channels on a non-root joint, the writer round trip, units, the
// corruption table (each bad file is an error naming its line and reason), and the Debian
// recordings (assimp-testmodels).

#include "mocap/bvh.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "core/error.h"

namespace deixis::mocap {
namespace {

const std::filesystem::path kDebian = "/usr/share/assimp/models/BVH";

// root (positions) -> a (rotations in `order`) -> b at (0, 0, 1) -> end site.
std::string chain(const std::string& order, const std::string& values) {
  return "HIERARCHY\nROOT r\n{\n OFFSET 0 0 0\n CHANNELS 3 Xposition Yposition Zposition\n"
         " JOINT a\n {\n  OFFSET 1 0 0\n  CHANNELS 3 " +
         order +
         "\n  JOINT b\n  {\n   OFFSET 0 0 1\n   CHANNELS 0\n   End Site\n   {\n    OFFSET 0 0 "
         "1\n   }\n  }\n }\n}\nMOTION\nFrames: 1\nFrame Time: 0.0333333\n" +
         values + "\n";
}

Eigen::Vector3d position_of(const Bvh& b, const std::string& name) {
  std::vector<JointPose> poses(b.nodes.size());
  forward_kinematics(b, b.frame(0), 1.0, poses);
  return poses[static_cast<std::size_t>(b.find(name))].p;
}

TEST(Bvh, RotationChannelsComposeLeftToRight) {
  // X 90 then Y 90: Rx·Ry·(0,0,1) = Rx·(1,0,0) = (1,0,0); the other order gives (0,-1,0).
  const Bvh xy = parse_bvh(chain("Xrotation Yrotation Zrotation", "0 0 0 90 90 0"), "xy");
  EXPECT_LT((position_of(xy, "b") - Eigen::Vector3d(2, 0, 0)).norm(), 1e-6);
  const Bvh yx = parse_bvh(chain("Yrotation Xrotation Zrotation", "0 0 0 90 90 0"), "yx");
  EXPECT_LT((position_of(yx, "b") - Eigen::Vector3d(1, -1, 0)).norm(), 1e-6);
  // Z 90 alone: (0,0,1) stays.
  const Bvh z = parse_bvh(chain("Zrotation Xrotation Yrotation", "0 0 0 90 0 0"), "z");
  EXPECT_LT((position_of(z, "b") - Eigen::Vector3d(1, 0, 1)).norm(), 1e-6);
}

TEST(Bvh, EveryChannelOrderGivesTheProductInListedOrder) {
  const char* axes[3] = {"X", "Y", "Z"};
  const double angle[3] = {20, -35, 50};  // the value given to X, Y, Z
  int perm[3] = {0, 1, 2};
  int orders = 0;
  do {
    std::string order;
    std::string values = "0.5 -0.25 2";
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    for (const int k : perm) {
      order.append(axes[k]).append("rotation ");
      values.append(" ").append(std::to_string(angle[k]));
      R = R * Eigen::AngleAxisd(angle[k] * M_PI / 180, Eigen::Vector3d::Unit(k)).toRotationMatrix();
    }
    const Bvh b = parse_bvh(chain(order, values), order);
    const Eigen::Vector3d expected =
        Eigen::Vector3d(0.5, -0.25, 2) + Eigen::Vector3d(1, 0, 0) + R * Eigen::Vector3d(0, 0, 1);
    EXPECT_LT((position_of(b, "b") - expected).norm(), 1e-6) << order;
    ++orders;
  } while (std::next_permutation(perm, perm + 3));
  EXPECT_EQ(orders, 6);
}

TEST(Bvh, PositionChannelsOnANonRootJointAddToItsOffset) {
  const std::string text =
      "HIERARCHY\nROOT r\n{\n OFFSET 0 1 0\n CHANNELS 1 Yrotation\n JOINT a\n {\n"
      "  OFFSET 1 0 0\n  CHANNELS 4 Zposition Xrotation Xposition Yposition\n  End Site\n  {\n"
      "   OFFSET 0 1 0\n  }\n }\n}\nMOTION\nFrames: 2\nFrame Time: 0.01\n"
      "90 0.25 0 0 0\n90 0.25 90 0.5 -0.5\n";
  const Bvh b = parse_bvh(text, "pos");
  ASSERT_EQ(b.channels, 5u);
  std::vector<JointPose> poses(b.nodes.size());
  forward_kinematics(b, b.frame(0), 1.0, poses);
  // Ry(90) maps (1, 0, 0.25) to (0.25, 0, -1).
  EXPECT_LT((poses[1].p - Eigen::Vector3d(0.25, 1, -1)).norm(), 1e-6);
  forward_kinematics(b, b.frame(1), 1.0, poses);
  // a at offset + (0.5, -0.5, 0.25) = (1.5, -0.5, 0.25) → Ry(90): (0.25, -0.5, -1.5) + (0, 1, 0).
  EXPECT_LT((poses[1].p - Eigen::Vector3d(0.25, 0.5, -1.5)).norm(), 1e-6);
  // The end site: Ry(90)·Rx(90)·(0,1,0) = Ry(90)·(0,0,1) = (1,0,0).
  EXPECT_LT((poses[2].p - Eigen::Vector3d(1.25, 0.5, -1.5)).norm(), 1e-6);
  // Scaling scales offsets and positions alike.
  forward_kinematics(b, b.frame(1), 0.01, poses);
  EXPECT_LT((poses[2].p - 0.01 * Eigen::Vector3d(1.25, 0.5, -1.5)).norm(), 1e-9);
}

TEST(Bvh, TheWriterRoundTrips) {
  const Bvh b = parse_bvh(chain("Zrotation Yrotation Xrotation", "1 2 3 10 20 30"), "a");
  const Bvh again = parse_bvh(write_bvh(b), "b");
  ASSERT_EQ(again.nodes.size(), b.nodes.size());
  EXPECT_EQ(again.motion, b.motion);
  EXPECT_EQ(again.frame_time, b.frame_time);
  for (std::size_t i = 0; i < b.nodes.size(); ++i) {
    EXPECT_EQ(again.nodes[i].name, b.nodes[i].name);
    EXPECT_EQ(again.nodes[i].parent, b.nodes[i].parent);
    EXPECT_EQ(again.nodes[i].channels, b.nodes[i].channels);
    EXPECT_EQ(again.nodes[i].offset, b.nodes[i].offset);
  }
}

struct Corruption {
  const char* what;
  std::string text;
  int line;
  const char* reason;
};

TEST(Bvh, EachCorruptionIsAnErrorNamingItsLine) {
  const std::string good = chain("Zrotation Yrotation Xrotation", "0 0 0 0 0 0");
  auto replace = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    const std::size_t at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return t.replace(at, from.size(), to);
  };
  // Line numbers of `good`: 1 HIERARCHY, 5 CHANNELS of r, 9 CHANNELS of a, 22 Frames:,
  // 23 Frame Time:, 24 the frame.
  const std::vector<Corruption> table = {
      {"truncated motion", replace("Frames: 1", "Frames: 3"), 25, "truncated motion"},
      {"too many values", replace("0 0 0 0 0 0\n", "0 0 0 0 0 0 0\n"), 24, "has 7 values"},
      {"too few values", replace("0 0 0 0 0 0\n", "0 0 0 0 0\n"), 24, "has 5 values"},
      {"not a number", replace("0 0 0 0 0 0\n", "0 0 x 0 0 0\n"), 24, "'x' is not a finite"},
      {"NaN", replace("0 0 0 0 0 0\n", "0 0 nan 0 0 0\n"), 24, "not a finite number"},
      {"inf", replace("0 0 0 0 0 0\n", "0 0 0 inf 0 0\n"), 24, "not a finite number"},
      {"huge", replace("0 0 0 0 0 0\n", "0 0 0 1e300 0 0\n"), 24, "not a finite number"},
      {"absurd frames", replace("Frames: 1", "Frames: 100000000"), 22, "Frames:"},
      {"frame time 0", replace("Frame Time: 0.0333333", "Frame Time: 0"), 23, "Frame Time:"},
      {"negative frame time", replace("Frame Time: 0.0333333", "Frame Time: -1"), 23,
       "Frame Time:"},
      {"unknown keyword", replace("OFFSET 1 0 0", "OFFSET 1 0 0\n  ROTATE 1"), 9,
       "unknown keyword 'ROTATE'"},
      {"unknown channel", replace("Zrotation Yrotation", "Wrotation Yrotation"), 9,
       "unknown channel 'Wrotation'"},
      {"repeated channel", replace("Zrotation Yrotation", "Yrotation Yrotation"), 9,
       "listed twice"},
      {"seven channels", replace("CHANNELS 3 Xposition", "CHANNELS 7 Xposition"), 5,
       "0 to 6 channels"},
      {"missing brace", replace(" JOINT a\n {", " JOINT a\n"), 8, "expected '{'"},
      {"no HIERARCHY", replace("HIERARCHY", "HIERARCHX"), 1, "expected HIERARCHY"},
      {"end site channels",
       replace("    OFFSET 0 0 1\n", "    OFFSET 0 0 1\n CHANNELS 1 Xrotation\n"), 17,
       "End Site has no CHANNELS"},
      {"second channels", replace("  OFFSET 1 0 0\n", "  OFFSET 1 0 0\n  CHANNELS 1 Xrotation\n"),
       10, "second CHANNELS"},
      {"second offset", replace("  OFFSET 1 0 0\n", "  OFFSET 1 0 0\n  OFFSET 1 0 0\n"), 9,
       "second OFFSET"},
      {"no offset", replace("  OFFSET 1 0 0\n", ""), 9, "has no OFFSET"},
      {"ends in the hierarchy", good.substr(0, good.find(" JOINT b")), 10, "the file ends"},
  };
  for (const Corruption& c : table) {
    try {
      parse_bvh(c.text, "bad.bvh");
      ADD_FAILURE() << c.what << ": parsed";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("bad.bvh:" + std::to_string(c.line) + ": ", 0), 0u) << c.what << ": " << m;
      EXPECT_NE(m.find(c.reason), std::string::npos) << c.what << ": " << m;
    }
  }
}

TEST(Bvh, LimitsAreEnforced) {
  const std::string good = chain("Zrotation Yrotation Xrotation", "0 0 0 0 0 0");
  BvhLimits small;
  small.max_nodes = 3;
  EXPECT_THROW(parse_bvh(good, "n", small), Error);
  small = {};
  small.max_line_bytes = 10;
  EXPECT_THROW(parse_bvh(good, "l", small), Error);
  small = {};
  small.max_file_bytes = 100;
  EXPECT_THROW(parse_bvh(good, "f", small), Error);
  small = {};
  small.max_values = 5;
  EXPECT_THROW(parse_bvh(good, "v", small), Error);
}

TEST(Bvh, UnitsParseAndAutoPicksTheOneThatMakesAnAdult) {
  EXPECT_EQ(parse_length_unit("cm"), LengthUnit::kCentimetre);
  EXPECT_EQ(parse_length_unit("inch"), LengthUnit::kInch);
  EXPECT_THROW(parse_length_unit("feet"), Error);
  EXPECT_NEAR(metres_per_unit(LengthUnit::kCmu), 0.056444, 1e-6);
  // A 1.75-unit-tall pole in m, cm, inch.
  auto pole = [](double height) {
    return parse_bvh(
        "HIERARCHY\nROOT r\n{\n OFFSET 0 0 0\n CHANNELS 1 Yposition\n End Site\n {\n  OFFSET 0 " +
            std::to_string(height) + " 0\n }\n}\nMOTION\nFrames: 1\nFrame Time: 1\n0\n",
        "pole");
  };
  EXPECT_EQ(infer_unit(pole(1.75)), LengthUnit::kMetre);
  EXPECT_EQ(infer_unit(pole(175)), LengthUnit::kCentimetre);
  EXPECT_EQ(infer_unit(pole(68)), LengthUnit::kInch);
  EXPECT_EQ(infer_unit(pole(30)), LengthUnit::kCmu);
  EXPECT_THROW(infer_unit(pole(8)), Error);
}

TEST(Bvh, TheDebianRecordingsLoad) {
  if (!std::filesystem::exists(kDebian / "01_01.bvh")) {
    GTEST_SKIP() << "no " << kDebian << " (Debian's assimp-testmodels; tools/install-deps)";
  }
  const Bvh a = read_bvh(kDebian / "01_01.bvh");
  EXPECT_EQ(a.frames(), 2752u);
  EXPECT_EQ(a.channels, 96u);
  EXPECT_NEAR(a.frame_time, 1.0 / 120, 1e-6);
  EXPECT_EQ(infer_unit(a), LengthUnit::kCmu);
  EXPECT_EQ(infer_unit(read_bvh(kDebian / "01_03.bvh")), LengthUnit::kCmu);
  const Bvh boxing = read_bvh(kDebian / "Boxing_Toes.bvh");
  EXPECT_EQ(boxing.frames(), 3069u);
  EXPECT_EQ(infer_unit(boxing), LengthUnit::kCentimetre);
  // A truncated copy names the line where it ends.
  std::string text = write_bvh(a);
  text.resize(text.size() / 2);
  text.resize(text.rfind('\n') + 1);
  try {
    parse_bvh(text, "half.bvh");
    ADD_FAILURE() << "parsed";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("truncated motion"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace deixis::mocap
