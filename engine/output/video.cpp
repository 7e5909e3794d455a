#include "output/video.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <vector>

extern char** environ;

namespace aeroflock {

namespace fs = std::filesystem;

namespace {

// ffmpeg's name of the container a video's extension names, and the options it needs on a pipe.
std::vector<std::string> container_args(const fs::path& video) {
  std::string ext = video.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  const std::vector<std::string> fragmented = {"-movflags",
                                               "+frag_keyframe+empty_moov+default_base_moof"};
  if (ext == ".mkv") return {"-f", "matroska"};
  if (ext == ".webm") return {"-f", "webm"};
  std::vector<std::string> args = fragmented;
  args.insert(args.end(), {"-f", ext == ".mov" ? "mov" : "mp4"});
  return args;
}

// A pipe whose two ends are closed on exec (the child gets its end by dup2, which clears that).
void make_pipe(int fds[2]) {
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw std::runtime_error(std::string("--video: cannot make a pipe to ffmpeg: ") +
                             std::strerror(errno));
}

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

}  // namespace

VideoWriter::VideoWriter(const fs::path& path, uint32_t width, uint32_t height,
                         const std::string& rate)
    : path_(path), frame_bytes_(size_t(width) * height * 4), file_(path) {
  std::vector<std::string> args = {
      "ffmpeg",    "-nostdin",
      "-loglevel", "error",
      "-f",        "rawvideo",
      "-pix_fmt",  "rgba",
      "-s",        std::to_string(width) + "x" + std::to_string(height),
      "-r",        rate,
      "-i",        "pipe:0",
      "-pix_fmt",  "yuv420p"};
  for (std::string& a : container_args(path)) args.push_back(std::move(a));
  args.push_back("pipe:1");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  int in[2], out[2];
  make_pipe(in);
  try {
    make_pipe(out);
  } catch (...) {
    ::close(in[0]), ::close(in[1]);
    throw;
  }
  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attr;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in[0], 0);
  posix_spawn_file_actions_adddup2(&actions, out[1], 1);
  posix_spawnattr_init(&attr);
  // Its own session; SIGPIPE as ffmpeg expects it (aeroflock ignores it, and that is inherited).
  sigset_t defaults;
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGPIPE);
  posix_spawnattr_setsigdefault(&attr, &defaults);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSID | POSIX_SPAWN_SETSIGDEF);
  const int err = ::posix_spawnp(&ffmpeg_, "ffmpeg", &actions, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  ::close(in[0]);
  ::close(out[1]);
  if (err != 0) {
    ::close(in[1]), ::close(out[0]);
    ffmpeg_ = -1;
    throw std::runtime_error(std::string("--video: cannot start ffmpeg: ") + std::strerror(err));
  }
  to_ffmpeg_ = in[1];
  // Copies the container into the file; after a failure (kept by file_) it drains the pipe, so that
  // ffmpeg is never left blocked on a full one.
  copier_ = std::thread([this, from = out[0]] {
    std::vector<char> bytes(size_t(1) << 20);
    for (;;) {
      const ssize_t n = ::read(from, bytes.data(), bytes.size());
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      if (file_.error().empty()) {
        try {
          file_.write(bytes.data(), size_t(n));
        } catch (const std::runtime_error&) {
          // Kept in file_.error(): finish() reports it.
        }
      }
    }
    ::close(from);
  });
}

VideoWriter::~VideoWriter() {
  if (ffmpeg_ > 0) ::kill(ffmpeg_, SIGTERM);
  stop();
}

void VideoWriter::stop() {
  close_fd(to_ffmpeg_);
  if (copier_.joinable()) copier_.join();
  if (ffmpeg_ > 0) {
    while (::waitpid(ffmpeg_, &status_, 0) < 0 && errno == EINTR) {
    }
    ffmpeg_ = -1;
  }
}

void VideoWriter::frame(std::span<const uint8_t> rgba) {
  if (rgba.size() != frame_bytes_)
    throw std::invalid_argument("VideoWriter::frame: pixel count does not match the size");
  const uint8_t* data = rgba.data();
  size_t left = rgba.size();
  while (left > 0) {
    const ssize_t n = to_ffmpeg_ >= 0 ? ::write(to_ffmpeg_, data, left) : -1;
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      // ffmpeg has gone: its reason (or the file's) is finish()'s to tell.
      stop();
      if (!file_.error().empty()) file_.commit();  // throws "cannot write PATH: why"
      throw std::runtime_error("--video: ffmpeg stopped taking frames (" + path_.string() + ")");
    }
    data += n;
    left -= size_t(n);
  }
}

void VideoWriter::finish() {
  stop();
  if (file_.error().empty() && !(WIFEXITED(status_) && WEXITSTATUS(status_) == 0)) {
    const std::string how = WIFEXITED(status_)
                                ? "exit status " + std::to_string(WEXITSTATUS(status_))
                                : "signal " + std::to_string(WTERMSIG(status_));
    throw std::runtime_error("--video: ffmpeg failed writing " + path_.string() + " (" + how + ")");
  }
  file_.commit();  // or throws the failing call's reason
}

}  // namespace aeroflock
