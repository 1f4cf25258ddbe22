// The ffmpeg video writer: frames in, an H.264 file with that size and frame count out; a missing
// ffmpeg, odd sizes and wrong frames are clear errors.

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>

#include "core/error.h"
#include "render/video_writer.h"
#include "test_support.h"

namespace deixis::render {
namespace {

std::string command_output(const std::string& command) {
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  std::string out;
  char buffer[256];
  while (pipe && fgets(buffer, sizeof buffer, pipe.get()) != nullptr) {
    out += buffer;
  }
  return out;
}

Image frame(int width, int height, int i) {
  Image image{width, height,
              std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height * 3)};
  for (std::size_t k = 0; k < image.rgb.size(); ++k) {
    image.rgb[k] = static_cast<std::uint8_t>((k / 3 + static_cast<std::size_t>(i) * 4) % 256);
  }
  return image;
}

TEST(VideoWriterTest, WritesAnMp4WithTheFramesGiven) {
  deixis::testing::ScratchDir dir;
  const auto path = dir.path() / "clip.mp4";
  VideoOptions options;
  options.width = 64;
  options.height = 48;
  {
    VideoWriter video(path, options);
    for (int i = 0; i < 12; ++i) {
      video.write(frame(64, 48, i));
    }
    EXPECT_EQ(video.frames_written(), 12);
    video.finish();
  }
  ASSERT_TRUE(std::filesystem::exists(path));
  const std::string probe = command_output(
      "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
      "stream=codec_name,width,height,nb_read_frames -of csv=p=0 '" +
      path.string() + "'");
  EXPECT_EQ(probe, "h264,64,48,12\n");
}

TEST(VideoWriterTest, MissingFfmpegIsAClearError) {
  deixis::testing::ScratchDir dir;
  VideoOptions options;
  options.ffmpeg = "deixis-no-such-ffmpeg";
  try {
    VideoWriter video(dir.path() / "clip.mp4", options);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("cannot run 'deixis-no-such-ffmpeg'"), std::string::npos) << message;
    EXPECT_NE(message.find("install Debian's ffmpeg"), std::string::npos) << message;
  }
}

TEST(VideoWriterTest, OddSizesWrongFramesAndMissingDirectoriesAreErrors) {
  deixis::testing::ScratchDir dir;
  VideoOptions odd;
  odd.width = 65;
  odd.height = 48;
  EXPECT_THROW(VideoWriter(dir.path() / "odd.mp4", odd), Error);
  VideoOptions options;
  options.width = 64;
  options.height = 48;
  EXPECT_THROW(VideoWriter(dir.path() / "missing" / "clip.mp4", options), Error);
  VideoWriter video(dir.path() / "clip.mp4", options);
  EXPECT_THROW(video.write(frame(32, 48, 0)), Error);
  video.write(frame(64, 48, 0));
  video.finish();
}

TEST(VideoWriterTest, FfmpegFailingIsReportedNotFatal) {
  deixis::testing::ScratchDir dir;
  VideoOptions options;
  options.width = 64;
  options.height = 48;
  // ffmpeg cannot pick a muxer for an unknown extension and exits at once; writing then finds
  // the pipe closed, which must be an error, not SIGPIPE.
  VideoWriter video(dir.path() / "clip.not-a-format", options);
  try {
    for (int i = 0; i < 200; ++i) {
      video.write(frame(64, 48, i));
    }
    FAIL() << "ffmpeg kept reading 200 frames it cannot write";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("ffmpeg stopped reading"), std::string::npos) << e.what();
  }
  try {
    video.finish();
    FAIL() << "expected ffmpeg's failure from finish()";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("ffmpeg exited with status"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace deixis::render
