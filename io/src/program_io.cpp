#include "blendbench/io/program_io.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <memory>
#include <system_error>
#include <vector>

namespace blendbench {

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
