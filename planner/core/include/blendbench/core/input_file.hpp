#pragma once
// The one way this program opens an input file (a scenario, G-code, sweep file, URDF, MJCF and
// the files it includes, meshes, a run's summary, a baseline, a sweep's plan and point files).
// The planner never calls it; it lives in core so that every edge that reads a file (io, sim's
// model loader, report, app) shares it. The rules, each one a hang or a crash found by issue 42:
//   - only a regular file is read: a folder, a FIFO, a socket or a device is refused by its kind,
//     from a stat before the open (a FIFO or a device is never opened), and again from fstat on
//     the descriptor after it, which must be the file the stat saw (a swap in between is refused);
//   - the open never blocks (O_NONBLOCK: a FIFO swapped in after the stat does not wait for a
//     writer), and is never a controlling terminal (O_NOCTTY);
//   - at most `max_bytes` are read (a larger file is refused before a byte is read, a file that
//     grows past the limit while read is refused when it does);
//   - every refusal is an InputError naming the file (exit 2), with the system's reason.

#include <cstdint>
#include <optional>
#include <string>

namespace blendbench {

// The largest input file read, in bytes: 64 MiB, twenty times a scenario of 10^5 moves (about
// 3 MB) and far above any robot description or run summary.
inline constexpr std::uintmax_t kMaxInputBytes = std::uintmax_t{64} << 20;

// The whole content of the input file `path`; `what` names it in messages ("scenario file",
// "URDF file"). Throws InputError(path, 0, 0, "", message) as described above, also when the file
// does not exist or cannot be read. Symbolic links in `path` are followed (the user named it).
std::string read_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes = kMaxInputBytes);

// The same for the entry `name` (no '/') of the open folder `dir_fd`, never through a symbolic
// link (the entry itself must not be one): for files inside a folder this program manages, whose
// reads must not leave it. `shown` names the file in messages. Returns nullopt when there is no
// such entry.
std::optional<std::string> read_input_file_at(int dir_fd, const std::string& name, const std::string& shown,
                                              const std::string& what, std::uintmax_t max_bytes = kMaxInputBytes);

}  // namespace blendbench
