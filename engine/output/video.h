// A video encoded by ffmpeg from raw RGBA frames.
//
// ffmpeg is started with an argument vector (no shell: any path works) in a session of its own (a
// Ctrl-C at the terminal reaches aeroflock's process group, and ffmpeg must not stop before the run
// has finished the video). It reads the frames on its stdin and writes the container on its
// stdout, which a thread of ours copies into an AtomicFile: the video is whole or absent, and a
// failure to write it (a full disk) is reported from the write that failed, as for every output.
// MP4 and MOV are written fragmented (a pipe cannot be sought back to finish a plain one's index);
// players and ffprobe read them as usual.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <thread>

#include "io/atomic_file.h"

namespace aeroflock {

class VideoWriter {
 public:
  // `rate`: the frame rate as ffmpeg reads it ("30", "1000000/33333"). The container is the one
  // the extension names (.mp4, .mkv, .mov or .webm). Throws std::runtime_error when the temporary
  // cannot be made or ffmpeg cannot be started.
  VideoWriter(const std::filesystem::path& path, uint32_t width, uint32_t height,
              const std::string& rate);
  // Unfinished: ffmpeg is stopped and the video's temporary removed.
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // One frame of width x height x 4 bytes. Throws std::runtime_error when ffmpeg has stopped
  // taking frames (the reason is then finish()'s).
  void frame(std::span<const uint8_t> rgba);
  // Ends the stream, waits for ffmpeg and puts the video in place. Throws std::runtime_error
  // "cannot write PATH: why" when the file could not be written, or one naming ffmpeg's exit
  // status when ffmpeg failed.
  void finish();

 private:
  void stop();  // closes ffmpeg's stdin, joins the copier, waits for ffmpeg; its status
  std::filesystem::path path_;
  size_t frame_bytes_ = 0;
  AtomicFile file_;
  int to_ffmpeg_ = -1;  // ffmpeg's stdin
  pid_t ffmpeg_ = -1;
  int status_ = 0;      // ffmpeg's wait status once stopped
  std::thread copier_;  // ffmpeg's stdout into file_
};

}  // namespace aeroflock
