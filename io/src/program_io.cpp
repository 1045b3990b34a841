#include "blendbench/io/program_io.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>
#include <system_error>
#include <vector>

#include "blendbench/core/format.hpp"

namespace blendbench {
namespace {

// A file descriptor closed on every way out.
struct Descriptor {
  int fd = -1;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

// What kind of file a stat mode names, for a refusal.
std::string kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

[[noreturn]] void refuse(const std::string& path, const std::string& message) { throw InputError(path, 0, 0, "", message); }

std::string mib(std::uintmax_t bytes) { return format_value(static_cast<double>(bytes) / (1 << 20), 4) + " MiB"; }

}  // namespace

std::string read_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes) {
  const auto fail = [&](const std::string& message) { refuse(path, message); };
  // the kind and size first, from the path: a FIFO or a device is never opened (opening a FIFO
  // blocks until a writer comes; /dev/zero never ends)
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    fail("cannot open the " + what + ": " + std::strerror(errno));
  }
  if (!S_ISREG(st.st_mode)) fail("the " + what + " is " + kind_of(st.st_mode) + ", not a regular file");
  if (static_cast<std::uintmax_t>(st.st_size) > max_bytes) {
    fail("the " + what + " is " + mib(static_cast<std::uintmax_t>(st.st_size)) + "; the limit is " + mib(max_bytes));
  }
  // O_NONBLOCK: should the path have become a FIFO since, the open does not wait for a writer
  Descriptor in{::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK)};
  if (in.fd < 0) fail("cannot open the " + what + ": " + std::strerror(errno));
  struct stat opened {};
  if (::fstat(in.fd, &opened) != 0 || !S_ISREG(opened.st_mode)) fail("the " + what + " is not a regular file");
  // read at most max_bytes + 1: a file that grew past the limit since stat is refused as well
  std::string text;
  text.reserve(static_cast<std::size_t>(std::min<std::uintmax_t>(static_cast<std::uintmax_t>(opened.st_size), max_bytes)));
  std::array<char, 1 << 16> buffer;
  while (true) {
    const ssize_t n = ::read(in.fd, buffer.data(), buffer.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail("cannot read the " + what + ": " + std::strerror(errno));
    if (n == 0) break;
    text.append(buffer.data(), static_cast<std::size_t>(n));
    if (text.size() > max_bytes) fail("the " + what + " is larger than the limit of " + mib(max_bytes));
  }
  return text;
}

GcodeResult load_gcode_file(const std::string& path, const GcodeOptions& options) {
  const std::string text = read_input_file(path, "G-code file");
  if (options.find_subroutine) return parse_gcode(text, path, options);
  // subroutine files: <name>.ngc in the program's folder, then in each subroutine folder (as
  // LinuxCNC looks in PROGRAM_PREFIX, then SUBROUTINE_PATH); all the files read share the bound
  // of one input file
  GcodeOptions with_files = options;
  std::vector<std::string> folders;
  const std::string own = std::filesystem::path(path).parent_path().string();
  folders.push_back(own.empty() ? "." : own);
  folders.insert(folders.end(), options.subroutine_path.begin(), options.subroutine_path.end());
  std::string searched;
  for (const std::string& folder : folders) searched += (searched.empty() ? "" : ", ") + folder;
  auto budget = std::make_shared<std::uintmax_t>(kMaxInputBytes - std::min<std::uintmax_t>(text.size(), kMaxInputBytes));
  with_files.find_subroutine = [folders, searched, budget](const std::string& name) {
    GcodeSubroutineLookup out;
    out.searched = searched;
    for (const std::string& folder : folders) {
      const std::string candidate = (std::filesystem::path(folder) / (name + ".ngc")).string();
      std::error_code ec;
      if (!std::filesystem::exists(candidate, ec)) continue;
      std::string sub = read_input_file(candidate, "subroutine file", *budget);
      *budget -= sub.size();
      out.file = GcodeSubroutineFile{candidate, std::move(sub)};
      return out;
    }
    return out;
  };
  return parse_gcode(text, path, with_files);
}

bool is_gcode_file(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".ngc" || ext == ".nc" || ext == ".gcode" || ext == ".tap" || ext == ".cnc";
}

}  // namespace blendbench
