#include "render/video_writer.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <vector>

#include "core/error.h"

extern char** environ;

namespace deixis::render {
namespace {

std::vector<std::string> ffmpeg_arguments(const std::filesystem::path& path,
                                          const VideoOptions& o) {
  const std::string size = std::to_string(o.width) + "x" + std::to_string(o.height);
  return {o.ffmpeg,     "-hide_banner",
          "-loglevel",  "error",
          "-nostdin",   "-y",
          "-f",         "rawvideo",
          "-pix_fmt",   "rgb24",
          "-s",         size,
          "-r",         std::to_string(o.frames_per_second),
          "-i",         "pipe:0",
          "-c:v",       "libx264",
          "-preset",    "veryfast",
          "-crf",       std::to_string(o.crf),
          "-pix_fmt",   "yuv420p",
          "-movflags",  "+faststart",
          path.string()};
}

// Writes all of `bytes` to a pipe whose reader may have gone. SIGPIPE is blocked on this thread
// for the call (and a pending one consumed), so a dead ffmpeg becomes EPIPE, not our death;
// no process-wide signal disposition changes.
bool write_all(int fd, const std::uint8_t* bytes, std::size_t size) {
  sigset_t pipe_signal;
  sigset_t previous;
  sigemptyset(&pipe_signal);
  sigaddset(&pipe_signal, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_signal, &previous);
  bool ok = true;
  while (size > 0) {
    const ssize_t n = ::write(fd, bytes, size);
    if (n < 0 && errno == EINTR) {
      continue;
    }
    if (n <= 0) {
      ok = false;
      break;
    }
    bytes += n;
    size -= static_cast<std::size_t>(n);
  }
  if (!ok && errno == EPIPE) {
    const timespec no_wait{0, 0};
    sigtimedwait(&pipe_signal, nullptr, &no_wait);
  }
  pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  return ok;
}

}  // namespace

VideoWriter::VideoWriter(const std::filesystem::path& path, const VideoOptions& options)
    : path_(path), options_(options) {
  const std::string name = path.string();
  if (options.width <= 0 || options.height <= 0 || options.width % 2 != 0 ||
      options.height % 2 != 0 || options.frames_per_second <= 0) {
    throw Error("video '" + name + "': size " + std::to_string(options.width) + " x " +
                std::to_string(options.height) + " at " +
                std::to_string(options.frames_per_second) +
                " fps (H.264 in yuv420p needs a positive, even width and height)");
  }
  const std::filesystem::path directory = path.parent_path();
  if (!directory.empty() && !std::filesystem::is_directory(directory)) {
    throw Error("video '" + name + "': directory '" + directory.string() + "' does not exist");
  }
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) {
    throw Error("video '" + name + "': pipe: " + std::strerror(errno));
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[0], STDIN_FILENO);  // dup2 clears CLOEXEC
  std::vector<std::string> arguments = ffmpeg_arguments(path, options);
  std::vector<char*> argv;
  for (std::string& a : arguments) {
    argv.push_back(a.data());
  }
  argv.push_back(nullptr);
  const int spawned =
      posix_spawnp(&child_, options.ffmpeg.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[0]);
  if (spawned != 0) {
    ::close(fds[1]);
    child_ = -1;
    throw Error("video '" + name + "': cannot run '" + options.ffmpeg +
                "': " + std::strerror(spawned) +
                (spawned == ENOENT ? " (install Debian's ffmpeg: tools/install-deps)" : ""));
  }
  pipe_ = fds[1];
}

VideoWriter::~VideoWriter() {
  if (child_ < 0) {
    return;
  }
  try {
    finish();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
  }
}

void VideoWriter::write(const Image& frame) {
  if (frame.width != options_.width || frame.height != options_.height ||
      frame.rgb.size() != static_cast<std::size_t>(frame.width) * frame.height * 3) {
    throw Error("video '" + path_.string() + "': frame " + std::to_string(frames_) + " is " +
                std::to_string(frame.width) + " x " + std::to_string(frame.height) +
                ", the video " + std::to_string(options_.width) + " x " +
                std::to_string(options_.height));
  }
  if (pipe_ < 0 || !write_all(pipe_, frame.rgb.data(), frame.rgb.size())) {
    throw Error("video '" + path_.string() + "': ffmpeg stopped reading at frame " +
                std::to_string(frames_) + " (its messages are above)");
  }
  ++frames_;
}

void VideoWriter::finish() {
  if (child_ < 0) {
    return;
  }
  if (pipe_ >= 0) {
    ::close(pipe_);
    pipe_ = -1;
  }
  int status = 0;
  pid_t waited = -1;
  do {
    waited = waitpid(child_, &status, 0);
  } while (waited < 0 && errno == EINTR);
  child_ = -1;
  if (waited < 0) {
    throw Error("video '" + path_.string() + "': waiting for ffmpeg: " + std::strerror(errno));
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw Error("video '" + path_.string() + "': ffmpeg " +
                (WIFEXITED(status) ? "exited with status " + std::to_string(WEXITSTATUS(status))
                                   : "was killed by signal " + std::to_string(WTERMSIG(status))) +
                " (its messages are above)");
  }
}

}  // namespace deixis::render
