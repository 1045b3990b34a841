#pragma once
// Video output: raw RGB frames piped into an ffmpeg child process that encodes H.264 (libx264,
// yuv420p, -preset veryfast) in an MP4 container. The video is written to a temporary file next
// to the target and renamed onto it by finish(), so a crash or an error never leaves a
// half-written video under the target name.

#include <cstdint>
#include <string>
#include <vector>

namespace blendbench {

class VideoWriter {
 public:
  // Starts ffmpeg (found on PATH). `path` is the target file; width, height in pixels (> 0; odd
  // sizes are padded to even by one black row/column), fps > 0. Throws std::invalid_argument for
  // bad sizes or rates, std::runtime_error when the temporary file or ffmpeg cannot be created.
  VideoWriter(std::string path, int width, int height, double fps);
  ~VideoWriter();  // without finish(): kills ffmpeg and deletes the temporary file
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  // Appends one frame: width*height*3 bytes of RGB, rows top-down (OffscreenRenderer::render).
  // Throws std::invalid_argument for a wrong size, std::runtime_error with ffmpeg's message when
  // ffmpeg has exited (the writer is then aborted).
  void write(const std::vector<std::uint8_t>& rgb);

  // Closes ffmpeg's input, waits for it, checks its exit status and renames the temporary file
  // onto the target. Throws std::runtime_error (with ffmpeg's message) when ffmpeg failed, no frame
  // was written or the rename failed; the temporary file is removed in every case.
  void finish();

  [[nodiscard]] int frames() const { return frames_; }

 private:
  // Kills and reaps ffmpeg if it runs, closes the pipe and removes the temporary file.
  void abort() noexcept;
  // ffmpeg's stderr so far (its last lines).
  [[nodiscard]] std::string ffmpeg_message() const;

  std::string path_, temp_path_;
  int width_, height_;
  int pipe_fd_ = -1;  // ffmpeg's stdin
  int log_fd_ = -1;   // ffmpeg's stderr, an unlinked temporary file
  int pid_ = -1;
  int frames_ = 0;
};

}  // namespace blendbench
