#pragma once
// The output folder of a run (`blendbench run --out DIR`, and each paper folder of `reproduce`),
// handled as a whole: the one lock-and-stage rule for an output folder.
//
// - Lock: a run holds an exclusive flock on the lock file `.<name>.lock` beside DIR (a sibling,
//   so it outlives the swap below); a second run into DIR fails at once with InputError (field
//   "--out", exit 2: the folder asked for is in use), naming the pid that holds it.
// - Staging: the run writes into a fresh sibling `.<name>.staging-<pid>`. Staging folders of
//   earlier runs that were killed (SIGKILL, power loss) are removed first: under the lock no
//   other run can own them, and only names of exactly that form (digits after "staging-") are
//   removed, so `foo` never touches the staging folder of an output named `foo.staging-1`.
// - Names of the machinery (`.X.lock`, `.X.staging-N`, `.X.staging-old-N`) are refused as DIR,
//   so no output can take one.
// - Nesting: DIR inside a run folder (a folder above it holds summary.json or results.json: the
//   next run there replaces it, DIR with it), inside a staging folder, or inside the folder of a
//   run that is running (its lock held) is refused; the checks are made under the lock, so two
//   runs starting together cannot both pass.
// - Commit: the staging folder takes DIR's place in one rename (renameat2 RENAME_EXCHANGE when
//   DIR exists; the previous run, then under the staging name, is deleted afterwards), made in
//   the folder the run started in, held open. So summary.json and the variant folders always come
//   from one run, no folder of an earlier run survives, and a run that ends before its commit (an
//   error, a kill) leaves the previous run intact. Before the rename the commit checks that the
//   folder above DIR is still the one the run started in (not swapped for a link) and that every
//   entry the caller requires (summary.json, the variant folders it names) is in the staging
//   folder; when not, nothing is published and the staging folder is kept, its path in the error.
// - Without a commit (an exception, an interrupt) the destructor removes the staging folder.
//
// Refused with InputError (field "--out"), before anything is written: an existing DIR that is
// not a directory (a file, a symlink, a FIFO, a device), and a directory that is neither empty
// nor a folder of this kind (no marker file, summary.json for a run): the swap would delete
// what it holds.
//
// Also here: the program's stop-signal handlers and a registry of paths to remove on the way
// out, used by write_file_atomic and RunFolder and emptied by main's exit paths and by
// std::terminate.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace blendbench {

class RunFolder {
 public:
  // Takes the lock for `out` and creates the staging folder (and `out`'s parent when missing).
  // `marker` is the file that makes an existing folder one of this kind (replaceable); `flag`
  // names the option in refusals. Throws InputError (field `flag`) as described above,
  // std::runtime_error when the file system refuses (the system's message and the path).
  explicit RunFolder(const std::filesystem::path& out, const std::string& marker = "summary.json",
                     const std::string& flag = "--out");
  ~RunFolder();  // removes the staging folder unless committed or kept; releases and removes the lock
  RunFolder(const RunFolder&) = delete;
  RunFolder& operator=(const RunFolder&) = delete;

  // Where the run writes (an empty folder, a sibling of target()).
  [[nodiscard]] const std::filesystem::path& staging() const { return staging_; }
  // The folder the run is for (`out` made absolute).
  [[nodiscard]] const std::filesystem::path& target() const { return target_; }
  // Whether target() held a run (the marker file) when the lock was taken.
  [[nodiscard]] bool had_previous_run() const { return had_previous_; }

  // Publishes the staging folder as target(), replacing what it held as a whole (see above);
  // `required` are entries (names, or relative paths) the staging folder must hold. Throws
  // std::runtime_error when a check or a rename fails (the previous run is then intact, and after
  // a failed check the staging folder is kept).
  void commit(const std::vector<std::string>& required = {}) { commit_to(target_, required); }
  // The same at `where`, a sibling of target() (e.g. a run interrupted while target() holds a
  // previous one); `where` must be absent, empty or a folder of this kind, else std::runtime_error.
  void commit_to(const std::filesystem::path& where, const std::vector<std::string>& required = {});

 private:
  // The constructor's steps once the lock is held: checks, stale staging folders, the staging folder.
  void prepare(const std::filesystem::path& out, const std::string& name);
  // Refuses (InputError) a target inside a run folder, a staging folder or a running run's folder.
  void check_not_nested(const std::filesystem::path& out) const;
  // Throws (keeping the staging folder) unless the folder above the target is the one the run
  // started in and the staging folder holds `required`.
  void check_before_publishing(const std::vector<std::string>& required);
  // Removes the staging folder unless committed or kept; releases and removes the lock; unless
  // committed, removes the folders above the target it created when they are empty. Idempotent.
  void release() noexcept;

  std::filesystem::path target_, staging_, lock_path_;
  std::filesystem::path parent_;      // the folder above the target, resolved (no link in it)
  std::string marker_, flag_, lock_name_, staging_name_;
  std::vector<std::filesystem::path> created_;  // folders above target_ this run created, deepest first
  int parent_fd_ = -1;   // the folder above the target, held open: renames happen in it
  int staging_fd_ = -1;  // the staging folder, held open: the commit checks it is still the one at its name
  int lock_fd_ = -1;
  bool had_previous_ = false;
  bool committed_ = false;
  bool kept_ = false;  // a failed check before publishing: the staging folder stays for the user
  std::uint64_t staging_cleanup_ = 0, lock_cleanup_ = 0;
};

// How long a stop request may take to unwind before the program ends anyway (issue 42: an open
// blocked on a FIFO outlived `timeout` by 1,019 s). A run unwinds in well under a second (the
// simulation checks for a request at every step); the rest is headroom for an encoder or a plot
// script to end after the SIGTERM forwarded to it.
inline constexpr std::chrono::seconds kStopGrace{5};

// Installs handlers for SIGINT, SIGTERM and SIGPIPE that only record the signal
// (core/interrupt.hpp, request_stop) and wake a watchdog thread, which forwards SIGTERM to the
// child processes (report/process.hpp) and, when the program has not ended kStopGrace later or a
// second signal comes, kills them, removes the registered paths and exits with 128 + the first
// signal. SIGXFSZ is ignored (a write past a file-size limit fails with an error instead). Also
// a std::terminate handler that removes the registered paths before aborting. Call once, early
// in main.
void install_stop_handlers();

// Registers `path` (a file or a folder) to be removed by remove_registered_paths; returns a
// handle for unregister_cleanup. Thread-safe.
std::uint64_t register_cleanup(const std::filesystem::path& path);
// Forgets a registration (the path was published or removed by its owner); 0 is ignored.
void unregister_cleanup(std::uint64_t handle) noexcept;
// Removes every registered path (recursively) and forgets them; for exit paths that skip
// destructors. Never throws.
void remove_registered_paths() noexcept;

}  // namespace blendbench
