#pragma once
// Writing results: every file is written atomically (a temporary file in the same directory,
// then rename), so a crash or a full disk never leaves a half-written result behind.

#include <filesystem>
#include <string>
#include <string_view>

#include "blendbench/core/format.hpp"

namespace blendbench {

// Writes `content` to `path` atomically; creates missing parent directories. Throws
// std::runtime_error naming the path and the system error when it cannot.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

// A temporary path next to `path` for writers that produce the file themselves (ffmpeg); the
// caller renames it to `path` when complete and removes it on failure.
std::filesystem::path temporary_path_for(const std::filesystem::path& path);

// Fixed-point text with `decimals` digits after the point (progress lines, tables); a
// non-finite value as "nan", "inf" or "-inf".
std::string format_fixed(double value, int decimals);

}  // namespace blendbench
