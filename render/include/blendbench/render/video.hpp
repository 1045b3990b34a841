#pragma once
// Video output: raw RGB frames piped into an ffmpeg child process that encodes H.264 (libx264,
// yuv420p, -preset superfast) in an MP4 container. A writer thread feeds the pipe, so rendering
// the next frame overlaps with ffmpeg reading and encoding this one. The video is written to a
// temporary file next to the target and renamed onto it by finish(), so a crash or an error
// never leaves a half-written video under the target name.

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
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

  // Appends one frame: width*height*3 bytes of RGB, rows top-down (OffscreenRenderer::read).
  // The frame is copied into a queue of kQueuedFrames buffers (reused, so no allocation per
  // frame once it is full) and the call returns; it waits only while the queue is full. Throws
  // std::invalid_argument for a wrong size, std::runtime_error with ffmpeg's message when ffmpeg
  // has exited (the writer is then aborted).
  void write(const std::vector<std::uint8_t>& rgb);

  // Sends the queued frames, closes ffmpeg's input, waits for it, checks its exit status and
  // renames the temporary file onto the target. Throws std::runtime_error (with ffmpeg's
  // message) when ffmpeg failed, no frame was written or the rename failed; the temporary file
  // is removed in every case.
  void finish();

  [[nodiscard]] int frames() const { return frames_; }

  // Frames that may wait for the pipe: enough to ride out ffmpeg's uneven reading, few enough
  // to keep memory small (four 1920x1080 frames are 25 MB).
  static constexpr std::size_t kQueuedFrames = 4;

 private:
  // The writer thread: sends queued frames to the pipe until closed or the pipe fails.
  void feed();
  // Stops the writer thread (after the queue is sent, unless ffmpeg is gone).
  void stop_feeding();
  // Throws the writer thread's failure, after cleaning up; called when it has failed.
  [[noreturn]] void fail_from_feeder();
  // Kills and reaps ffmpeg if it runs, stops the thread, closes the pipe and removes the
  // temporary file.
  void abort() noexcept;
  // ffmpeg's stderr so far (its last lines).
  [[nodiscard]] std::string ffmpeg_message() const;

  std::string path_, temp_path_;
  int width_, height_;
  int pipe_fd_ = -1;  // ffmpeg's stdin
  int log_fd_ = -1;   // ffmpeg's stderr, an unlinked temporary file
  int pid_ = -1;
  int frames_ = 0;

  // the queue between write() and the writer thread
  std::thread feeder_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::vector<std::uint8_t>> queued_;
  std::vector<std::vector<std::uint8_t>> spare_;
  bool closing_ = false;
  bool failed_ = false;
  std::string failure_;  // why the pipe failed (errno text)
};

}  // namespace blendbench
