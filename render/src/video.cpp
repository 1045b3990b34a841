#include "blendbench/render/video.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "blendbench/core/format.hpp"

extern char** environ;

namespace blendbench {
namespace {

// How much of ffmpeg's stderr goes into an error message (its tail).
constexpr std::size_t kMessageBytes = 2000;
// libx264's speed preset: measured on rendered frames (flat shading, text) at 1280x720 on two
// cores, superfast costs about half of veryfast's CPU time for files of similar size, and leaves
// the cores to the renderer (bench_render).
constexpr const char* kPreset = "superfast";

std::string system_error(const std::string& what) { return what + ": " + std::strerror(errno); }

// Waits for the child, retrying on EINTR; returns its wait status, or -1.
int reap(int pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return status;
}

// Writes all bytes to a pipe with SIGPIPE blocked on this thread, so a dead reader shows up as
// EPIPE instead of killing the process; a SIGPIPE raised here is consumed. Returns false on error
// (errno set).
bool write_all(int fd, const std::uint8_t* data, std::size_t size) {
  sigset_t pipe_set, old_set, pending;
  sigemptyset(&pipe_set);
  sigaddset(&pipe_set, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_set, &old_set);
  sigpending(&pending);
  const bool was_pending = sigismember(&pending, SIGPIPE) == 1;

  bool ok = true;
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      ok = false;
      break;
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }

  // consume our own SIGPIPE before unblocking
  const int saved_errno = errno;
  if (!ok && errno == EPIPE && !was_pending) {
    const timespec zero{0, 0};
    while (sigtimedwait(&pipe_set, nullptr, &zero) < 0 && errno == EINTR) {
    }
  }
  pthread_sigmask(SIG_SETMASK, &old_set, nullptr);
  errno = saved_errno;
  return ok;
}

// The mode a newly created file gets in this process, 0666 less the umask, as for the run's other
// outputs (opened with 0666). mkostemp creates its file 0600 and ffmpeg keeps the mode of the
// file it overwrites, so without this the video alone would be private. The umask is read from
// /proc/self/status (umask() cannot read it without setting it, which races with other threads
// creating files); 022 when the line is missing.
mode_t new_file_mode() {
  mode_t mask = 022;
  if (FILE* status = std::fopen("/proc/self/status", "re")) {
    char line[256];
    while (std::fgets(line, sizeof line, status) != nullptr) {
      unsigned value = 0;
      if (std::sscanf(line, "Umask: %o", &value) == 1) {
        mask = static_cast<mode_t>(value);
        break;
      }
    }
    std::fclose(status);
  }
  return static_cast<mode_t>(0666 & ~mask);
}

}  // namespace

VideoWriter::VideoWriter(std::string path, int width, int height, double fps)
    : path_(std::move(path)), width_(width), height_(height) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("video size must be positive");
  if (!(fps > 0) || !std::isfinite(fps)) throw std::invalid_argument("video frame rate must be positive");

  // the temporary video next to the target (same file system, so the rename is atomic)
  const auto slash = path_.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "" : path_.substr(0, slash + 1);
  const std::string name = slash == std::string::npos ? path_ : path_.substr(slash + 1);
  std::string temp = dir + "." + name + ".partial-XXXXXX";
  const int temp_fd = mkostemp(temp.data(), O_CLOEXEC);
  if (temp_fd < 0) throw std::runtime_error(system_error("cannot create a temporary file next to " + path_));
  (void)::fchmod(temp_fd, new_file_mode());  // best effort: the video is still written if it fails
  ::close(temp_fd);
  temp_path_ = temp;

  // ffmpeg's stderr goes to an unlinked temporary file, read back for error messages
  const char* tmpdir = std::getenv("TMPDIR");
  std::string log = std::string(tmpdir != nullptr && tmpdir[0] != '\0' ? tmpdir : "/tmp") + "/blendbench-ffmpeg-XXXXXX";
  log_fd_ = mkostemp(log.data(), O_CLOEXEC);
  if (log_fd_ < 0) {
    const std::string message = system_error("cannot create a temporary file for ffmpeg's messages");
    abort();
    throw std::runtime_error(message);
  }
  ::unlink(log.c_str());

  // the pipe; both ends close-on-exec so no other child inherits the write end
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) {
    const std::string message = system_error("cannot create a pipe to ffmpeg");
    abort();
    throw std::runtime_error(message);
  }
  pipe_fd_ = fds[1];

  // ffmpeg: raw RGB on stdin -> H.264 in MP4; odd sizes padded to even for yuv420p
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  std::vector<std::string> args = {"ffmpeg", "-nostdin", "-y", "-hide_banner", "-loglevel", "error",
                                   "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", size, "-framerate",
                                   format_value(fps), "-i", "pipe:0", "-an"};
  if (width % 2 != 0 || height % 2 != 0) args.insert(args.end(), {"-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2"});
  args.insert(args.end(), {"-c:v", "libx264", "-preset", kPreset, "-pix_fmt", "yuv420p", "-movflags",
                           "+faststart", "-f", "mp4", temp_path_});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[0], STDIN_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, log_fd_, STDERR_FILENO);
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, "ffmpeg", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[0]);
  if (rc != 0) {
    abort();
    throw std::runtime_error(std::string("cannot start ffmpeg: ") + std::strerror(rc));
  }
  pid_ = pid;
}

VideoWriter::~VideoWriter() {
  if (pid_ >= 0 || !temp_path_.empty() || feeder_.joinable()) abort();
  if (log_fd_ >= 0) ::close(log_fd_);
}

void VideoWriter::feed() {
  std::unique_lock lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return !queued_.empty() || closing_; });
    if (queued_.empty()) return;
    std::vector<std::uint8_t> frame = std::move(queued_.front());
    queued_.pop_front();
    // the pipe is written without the lock, so write() can queue the next frame meanwhile
    lock.unlock();
    const bool ok = write_all(pipe_fd_, frame.data(), frame.size());
    const std::string cause = ok ? std::string() : system_error("writing to ffmpeg");
    lock.lock();
    spare_.push_back(std::move(frame));
    if (!ok) {
      failed_ = true;
      failure_ = cause;
      queued_.clear();
      changed_.notify_all();
      return;
    }
    changed_.notify_all();
  }
}

void VideoWriter::stop_feeding() {
  {
    const std::lock_guard lock(mutex_);
    closing_ = true;
  }
  changed_.notify_all();
  if (feeder_.joinable()) feeder_.join();
}

void VideoWriter::fail_from_feeder() {
  stop_feeding();
  // ffmpeg is gone or broken: collect what it said, then clean up
  ::close(pipe_fd_);
  pipe_fd_ = -1;
  reap(pid_);
  pid_ = -1;
  const std::string message = ffmpeg_message();
  const std::string cause = failure_;
  abort();
  throw std::runtime_error("ffmpeg stopped while writing " + path_ + " (" + cause + ")" +
                           (message.empty() ? "" : ": " + message));
}

void VideoWriter::write(const std::vector<std::uint8_t>& rgb) {
  const std::size_t expected = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) * 3;
  if (rgb.size() != expected)
    throw std::invalid_argument("video frame has " + std::to_string(rgb.size()) + " bytes, expected " +
                                std::to_string(expected));
  if (pid_ < 0) throw std::runtime_error("video writer for " + path_ + " is closed");
  if (!feeder_.joinable()) feeder_ = std::thread([this] { feed(); });

  // a spare buffer (or a new one while the queue fills), filled and queued
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return queued_.size() < kQueuedFrames || failed_; });
  if (failed_) {
    lock.unlock();
    fail_from_feeder();
  }
  std::vector<std::uint8_t> frame;
  if (!spare_.empty()) {
    frame = std::move(spare_.back());
    spare_.pop_back();
  }
  frame.assign(rgb.begin(), rgb.end());
  queued_.push_back(std::move(frame));
  lock.unlock();
  changed_.notify_all();
  ++frames_;
}

void VideoWriter::finish() {
  if (pid_ < 0) throw std::runtime_error("video writer for " + path_ + " is closed");
  if (frames_ == 0) {
    abort();
    throw std::runtime_error("no frame was written to " + path_);
  }

  // the queued frames go out, then end of input: ffmpeg finalises the file and exits
  stop_feeding();
  if (failed_) fail_from_feeder();
  ::close(pipe_fd_);
  pipe_fd_ = -1;
  const int status = reap(pid_);
  pid_ = -1;
  if (status < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string how = status < 0                ? "could not be waited for"
                            : WIFSIGNALED(status)     ? "was killed by signal " + std::to_string(WTERMSIG(status))
                                                      : "exited with status " + std::to_string(WEXITSTATUS(status));
    const std::string message = ffmpeg_message();
    abort();
    throw std::runtime_error("ffmpeg " + how + " writing " + path_ + (message.empty() ? "" : ": " + message));
  }

  // publish the finished video under its name
  if (std::rename(temp_path_.c_str(), path_.c_str()) != 0) {
    const std::string message = system_error("cannot rename " + temp_path_ + " to " + path_);
    abort();
    throw std::runtime_error(message);
  }
  temp_path_.clear();
}

void VideoWriter::abort() noexcept {
  // a dead ffmpeg makes a blocked pipe write fail, so the writer thread can be joined
  if (pid_ >= 0) ::kill(pid_, SIGKILL);
  {
    const std::lock_guard lock(mutex_);
    closing_ = true;
    queued_.clear();
  }
  changed_.notify_all();
  if (feeder_.joinable()) feeder_.join();
  if (pipe_fd_ >= 0) {
    ::close(pipe_fd_);
    pipe_fd_ = -1;
  }
  if (pid_ >= 0) {
    reap(pid_);
    pid_ = -1;
  }
  if (!temp_path_.empty()) {
    ::unlink(temp_path_.c_str());
    temp_path_.clear();
  }
}

std::string VideoWriter::ffmpeg_message() const {
  if (log_fd_ < 0) return {};
  const off_t end = ::lseek(log_fd_, 0, SEEK_END);
  if (end <= 0) return {};
  const off_t start = end > static_cast<off_t>(kMessageBytes) ? end - static_cast<off_t>(kMessageBytes) : 0;
  std::string text(static_cast<std::size_t>(end - start), '\0');
  const ssize_t n = ::pread(log_fd_, text.data(), text.size(), start);
  text.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  for (char& c : text)
    if (c == '\n') c = ' ';
  return text;
}

}  // namespace blendbench
