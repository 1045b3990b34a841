#pragma once
// Writing results: every file is written atomically (a temporary file in the same directory,
// then rename), so a crash or a full disk never leaves a half-written result behind.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "blendbench/core/format.hpp"

namespace blendbench {

// Writes `content` to `path` atomically; creates missing parent directories. The temporary file
// (`path` + ".tmp.<pid>", created exclusively, never through a symbolic link) is registered for
// removal on the way out (run_folder.hpp) while it exists; temporaries of the same file left by a
// process that no longer runs (killed by SIGKILL) are removed first. Throws std::runtime_error
// naming the path and the system error when it cannot, and when `path` exists but is not a
// regular file (a symbolic link, a FIFO, a directory, a device is never replaced).
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

// Writes several files as one output (`plan`'s CSV and summary): each is first written whole to
// its temporary beside it (write_file_atomic's rules), and only then are they renamed over their
// names, so a stop or a failure while writing never leaves a new file beside an old one. Throws
// std::runtime_error as write_file_atomic; the temporaries are removed.
void write_files_atomic(const std::vector<std::pair<std::filesystem::path, std::string>>& files);

// The lock of a command's output files, as (option, path) pairs, held while the object lives: an
// exclusive flock on `.<file>.lock` beside each (removed at the end), so two commands writing the
// same file cannot mix their outputs; the second is refused at once with InputError naming the
// option. Empty paths are skipped.
class OutputFilesLock {
 public:
  explicit OutputFilesLock(const std::vector<std::pair<std::string, std::filesystem::path>>& outputs);
  ~OutputFilesLock();
  OutputFilesLock(const OutputFilesLock&) = delete;
  OutputFilesLock& operator=(const OutputFilesLock&) = delete;

 private:
  struct Held {
    int fd;
    std::filesystem::path path;
    std::uint64_t cleanup;
  };
  std::vector<Held> held_;
};

// A folder this program manages (a sweep's folder and everything below it), held open: every file
// and folder below it is reached from the folder's descriptor one name at a time and never
// through a symbolic link, so a link planted inside (at points/<hash>/log.txt, or points/ itself)
// sends no write and no read outside it. The folder itself may be reached through links in the
// path the user named. Copies share the descriptor.
class OutputDir {
 public:
  // Opens `path`, creating it and its parents when `create`. Throws std::runtime_error naming it.
  OutputDir(const std::filesystem::path& path, bool create);

  // The sub-folder `name` (one name, no '/'), created when missing. Throws std::runtime_error when
  // it exists and is not a folder (a symbolic link, a file).
  [[nodiscard]] OutputDir sub(const std::string& name) const;
  // The sub-folder `name` when it exists (nullopt when not); throws as sub() for a non-folder.
  [[nodiscard]] std::optional<OutputDir> find(const std::string& name) const;

  // Writes the file `name` atomically (write_file_atomic's rules, in this folder).
  void write(const std::string& name, std::string_view content) const;
  // The regular file `name`, nullopt when absent (core/input_file.hpp read_input_file_at: a
  // symbolic link, FIFO or device is an InputError naming it). `what` names it in messages.
  [[nodiscard]] std::optional<std::string> read(const std::string& name, const std::string& what) const;
  // A new empty file `name` for a child process's output, whatever was there removed first (a
  // link or a hard link there is replaced, never written through); returns its descriptor
  // (close-on-exec; the caller closes it). Throws std::runtime_error.
  [[nodiscard]] int create_fresh(const std::string& name) const;
  // Removes the file `name` (nothing when absent). Throws std::runtime_error when it cannot.
  void remove(const std::string& name) const;

  // Takes an advisory lock (flock) on the file `name` (created when missing, never through a
  // link), shared or exclusive, without waiting; held until the returned descriptor is closed
  // (the caller owns it). Returns -1 when another process holds a conflicting lock; an exclusive
  // holder writes its pid into the file for the message of the next. Throws std::runtime_error.
  [[nodiscard]] int try_lock(const std::string& name, bool shared) const;
  // The pid an exclusive holder of the lock file `name` wrote, or "" (for messages).
  [[nodiscard]] std::string lock_holder(const std::string& name) const;

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  [[nodiscard]] int fd() const { return *fd_; }

 private:
  OutputDir(std::shared_ptr<const int> fd, std::filesystem::path path) : fd_(std::move(fd)), path_(std::move(path)) {}
  std::shared_ptr<const int> fd_;  // closed with the last copy
  std::filesystem::path path_;     // for messages
};

// Checks the output files a command was given, as (option, path) pairs, before any work: each
// must be absent or a regular file (not a symbolic link, FIFO, directory or device), and no two
// may name the same file, however spelled (relative or absolute, "..", a symbolic link in the
// folder path, a hard link). Throws InputError naming the option(s) otherwise. Empty paths are
// skipped (an option not given).
void check_output_files(const std::vector<std::pair<std::string, std::filesystem::path>>& outputs);

// A temporary path next to `path` for writers that produce the file themselves (ffmpeg); the
// caller renames it to `path` when complete and removes it on failure.
std::filesystem::path temporary_path_for(const std::filesystem::path& path);

// Fixed-point text with `decimals` digits after the point (progress lines, tables); a
// non-finite value as "nan", "inf" or "-inf".
std::string format_fixed(double value, int decimals);

}  // namespace blendbench
