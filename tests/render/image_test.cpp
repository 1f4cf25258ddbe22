// Screenshots: PNG files round-trip size and pixels; bad paths and images are clear errors.

#include <gtest/gtest.h>

#include <array>
#include <fstream>
#include <string>

#include "core/error.h"
#include "render/image.h"
#include "test_support.h"

namespace deixis::render {
namespace {

Image gradient(int width, int height) {
  Image image{width, height,
              std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height * 3)};
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      std::uint8_t* p = &image.rgb[(static_cast<std::size_t>(y) * width + x) * 3];
      p[0] = static_cast<std::uint8_t>(x * 5);
      p[1] = static_cast<std::uint8_t>(y * 7);
      p[2] = static_cast<std::uint8_t>((x + y) % 2 == 0 ? 255 : 0);
    }
  }
  return image;
}

// Width and height as the file's IHDR chunk states them (bytes 16–23, big-endian), read without
// the PNG decoder the library uses.
std::array<std::uint32_t, 2> png_header_size(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<unsigned char, 24> head{};
  in.read(reinterpret_cast<char*>(head.data()), head.size());
  const auto be32 = [&](int at) {
    return std::uint32_t{head[at]} << 24 | std::uint32_t{head[at + 1]} << 16 |
           std::uint32_t{head[at + 2]} << 8 | std::uint32_t{head[at + 3]};
  };
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(head.data()) + 12, 4), "IHDR");
  return {be32(16), be32(20)};
}

TEST(ImageTest, PngRoundTripsSizeAndPixels) {
  deixis::testing::ScratchDir dir;
  const Image image = gradient(37, 23);  // odd sizes: no row padding may slip in
  const auto path = dir.path() / "shot.png";
  write_png(image, path);
  EXPECT_EQ(png_header_size(path), (std::array<std::uint32_t, 2>{37, 23}));
  const Image read = read_png(path);
  EXPECT_EQ(read.width, 37);
  EXPECT_EQ(read.height, 23);
  EXPECT_EQ(read.rgb, image.rgb);
}

TEST(ImageTest, ReadingAMissingOrBrokenPngIsAnError) {
  deixis::testing::ScratchDir dir;
  EXPECT_THROW(read_png(dir.path() / "absent.png"), Error);
  std::ofstream(dir.path() / "broken.png") << "not a png";
  try {
    read_png(dir.path() / "broken.png");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("broken.png"), std::string::npos) << e.what();
  }
}

TEST(ImageTest, MissingDirectoryIsAnErrorNamingThePath) {
  deixis::testing::ScratchDir dir;
  const auto path = dir.path() / "no-such-dir" / "shot.png";
  try {
    write_png(gradient(4, 4), path);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find("does not exist"), std::string::npos) << message;
  }
}

TEST(ImageTest, UnwritableFileAndBadImagesAreErrors) {
  deixis::testing::ScratchDir dir;
  // A directory where the file should be: fopen fails.
  std::filesystem::create_directory(dir.path() / "taken.png");
  EXPECT_THROW(write_png(gradient(4, 4), dir.path() / "taken.png"), Error);
  EXPECT_THROW(write_png(Image{}, dir.path() / "empty.png"), Error);
  Image short_image = gradient(4, 4);
  short_image.rgb.pop_back();
  EXPECT_THROW(write_png(short_image, dir.path() / "short.png"), Error);
}

}  // namespace
}  // namespace deixis::render
