#pragma once
// Frames into a video file through Debian's ffmpeg: spawns `ffmpeg -f rawvideo -pix_fmt rgb24
// -s WxH -r FPS -i - ... <path>` and writes each Image to its standard input. H.264 (libx264,
// yuv420p) for .mp4, so the size must be even. ffmpeg's own messages go to our standard error.

#include <sys/types.h>
#include <filesystem>
#include <string>

#include "render/image.h"

namespace deixis::render {

struct VideoOptions {
  int width = 1280;
  int height = 720;
  int frames_per_second = 30;
  int crf = 20;                   // libx264 quality: lower is better and bigger
  std::string ffmpeg = "ffmpeg";  // looked up on PATH
};

class VideoWriter {
 public:
  // Starts ffmpeg. Throws deixis::Error when ffmpeg is not installed, the size is odd or not
  // positive, or the output directory does not exist.
  VideoWriter(const std::filesystem::path& path, const VideoOptions& options);
  // Finishes the file if finish() was not called; errors are then only logged to stderr.
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // Throws deixis::Error when the frame's size differs from the video's or ffmpeg has exited.
  void write(const Image& frame);
  // Closes ffmpeg's input and waits for it; throws deixis::Error if it failed.
  void finish();

  int frames_written() const { return frames_; }

 private:
  std::filesystem::path path_;
  VideoOptions options_;
  pid_t child_ = -1;
  int pipe_ = -1;  // ffmpeg's standard input
  int frames_ = 0;
};

}  // namespace deixis::render
