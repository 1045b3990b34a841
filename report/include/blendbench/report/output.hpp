#pragma once
// Writing results: every file is written atomically (a temporary file in the same directory,
// then rename), so a crash or a full disk never leaves a half-written result behind.

#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "blendbench/core/format.hpp"

namespace blendbench {

// Writes `content` to `path` atomically; creates missing parent directories. The temporary file
// (`path` + ".tmp.<pid>", created exclusively, never through a symbolic link) is registered for
// removal on the way out (run_folder.hpp) while it exists. Throws std::runtime_error naming the
// path and the system error when it cannot, and when `path` exists but is not a regular file
// (a symbolic link, a FIFO, a directory, a device is never replaced).
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

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
