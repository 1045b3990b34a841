// The files of an MJCF model, read and checked before MuJoCo sees them (model_files.hpp).

#include "model_files.hpp"

#include <expat.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"
#include "blendbench/core/input_file.hpp"

namespace blendbench::sim_detail {
namespace {

namespace fs = std::filesystem;

constexpr const char* kField = "mjcf";

// A file an element of the model names: where, and what.
struct Reference {
  std::string element, attribute, value;
  std::string file;  // the XML file that names it
  int line = 0;
  int column = 0;
};

// What the scan of the model and its includes found so far.
struct Scan {
  fs::path model_dir;  // the main model's folder: includes and relative asset folders start there
  std::string meshdir, texturedir;
  bool strippath = false;
  std::size_t elements = 0;
  std::uintmax_t bytes = 0;
  bool text_only = false;  // a model given as text: it may name no file
  std::vector<Reference> assets;
  std::vector<std::string> sources;  // per entry of out.files: the file it was read from
  ModelFiles out;
};

std::string mib(std::uintmax_t bytes) { return format_value(static_cast<double>(bytes) / (1 << 20), 4) + " MiB"; }

// Adds a file under the name MuJoCo looks it up by (its name without folder); the same file named
// twice is kept once, two different files of one name are refused.
void add_file(Scan& scan, const fs::path& source, std::string content, const Reference* from) {
  const std::string name = source.filename().string();
  for (std::size_t i = 0; i < scan.out.files.size(); ++i) {
    if (scan.out.files[i].first != name) continue;
    if (scan.out.files[i].second == content) return;
    const std::string message = "two different files are named '" + name + "' (" + scan.sources[i] + " and " +
                                source.string() + "): MuJoCo 2.2.2 finds a model's files by name alone; rename one";
    if (from != nullptr) throw InputError(from->file, from->line, from->column, kField, message);
    throw InputError(source.string(), 0, 0, kField, message);
  }
  scan.bytes += content.size();
  if (scan.bytes > kMaxModelBytes) {
    const std::string message = "the model's files together exceed " + mib(kMaxModelBytes);
    if (from != nullptr) throw InputError(from->file, from->line, from->column, kField, message);
    throw InputError(source.string(), 0, 0, kField, message);
  }
  scan.out.files.emplace_back(name, std::move(content));
  scan.sources.push_back(source.string());
}

// Reads a file a reference names, the refusal located at the element that names it.
std::string read_referenced(const fs::path& path, const Reference& ref, const std::string& what) {
  try {
    return read_input_file(path.string(), what, kMaxModelFileBytes);
  } catch (const InputError& e) {
    throw InputError(ref.file, ref.line, ref.column, kField,
                     "<" + ref.element + " " + ref.attribute + "=\"" + printable(ref.value) + "\">: " + e.what());
  }
}

void scan_xml(Scan& scan, const std::string& text, const std::string& file, int include_depth);

// One XML file's walk with expat. A problem is recorded and the parse stopped (no exception may
// cross expat's C frames); scan_xml rethrows it.
struct Walk {
  Scan* scan = nullptr;
  XML_Parser parser = nullptr;
  std::string file;
  int include_depth = 0;
  int depth = 0;
  std::exception_ptr problem;

  [[nodiscard]] Reference here(const char* element, const std::string& attribute, const std::string& value) const {
    return {element, attribute, value, file, static_cast<int>(XML_GetCurrentLineNumber(parser)),
            static_cast<int>(XML_GetCurrentColumnNumber(parser)) + 1};
  }

  void fail(const std::string& message) {
    problem = std::make_exception_ptr(InputError(file, static_cast<int>(XML_GetCurrentLineNumber(parser)),
                                                 static_cast<int>(XML_GetCurrentColumnNumber(parser)) + 1, kField, message));
    XML_StopParser(parser, XML_FALSE);
  }

  void start(const char* element, const char** attributes) {
    const std::string name(element);
    if (++depth > kMaxModelDepth) return fail("elements are nested more than " + std::to_string(kMaxModelDepth) + " deep");
    if (++scan->elements > kMaxModelElements) {
      return fail("the model holds more than " + std::to_string(kMaxModelElements) +
                  " elements (with its includes): no arm needs that many, and MuJoCo's work grows with them");
    }
    for (int i = 0; attributes[i] != nullptr; i += 2) {
      const std::string attribute(attributes[i]);
      const std::string value(attributes[i + 1]);
      if (name == "compiler") {
        if (attribute == "meshdir") scan->meshdir = value;
        if (attribute == "texturedir") scan->texturedir = value;
        if (attribute == "strippath") scan->strippath = value == "true";
      }
      // every attribute that names a file (file, and a cube texture's fileright ... fileback)
      if (attribute.rfind("file", 0) != 0 || value.empty()) continue;
      const Reference ref = here(element, attribute, value);
      if (name != "include") {
        scan->assets.push_back(ref);
        continue;
      }
      // an include: read and walked where it stands (a <compiler> in it counts in document order)
      try {
        if (scan->text_only) throw InputError(ref.file, ref.line, ref.column, kField, "a model given as text includes no file");
        if (include_depth + 1 > kMaxIncludeDepth) {
          throw InputError(ref.file, ref.line, ref.column, kField,
                           "includes are nested more than " + std::to_string(kMaxIncludeDepth) + " deep");
        }
        const fs::path path = fs::path(value).is_absolute() ? fs::path(value) : scan->model_dir / value;
        std::string content = read_referenced(path, ref, "included file");
        scan_xml(*scan, content, path.string(), include_depth + 1);
        add_file(*scan, path, std::move(content), &ref);
      } catch (...) {
        problem = std::current_exception();
        XML_StopParser(parser, XML_FALSE);
        return;
      }
    }
  }
};

void scan_xml(Scan& scan, const std::string& text, const std::string& file, int include_depth) {
  const std::unique_ptr<XML_ParserStruct, void (*)(XML_Parser)> parser(XML_ParserCreate("UTF-8"), XML_ParserFree);
  if (!parser) throw InputError(file, 0, 0, kField, "cannot start the XML parser (out of memory)");
  Walk walk;
  walk.scan = &scan;
  walk.parser = parser.get();
  walk.file = file;
  walk.include_depth = include_depth;
  XML_SetUserData(parser.get(), &walk);
  XML_SetElementHandler(
      parser.get(),
      [](void* data, const XML_Char* element, const XML_Char** attributes) { static_cast<Walk*>(data)->start(element, attributes); },
      [](void* data, const XML_Char*) { --static_cast<Walk*>(data)->depth; });
  // the files are at most kMaxModelFileBytes (64 MiB), within expat's int length
  const XML_Status status = XML_Parse(parser.get(), text.data(), static_cast<int>(text.size()), XML_TRUE);
  if (walk.problem) std::rethrow_exception(walk.problem);
  if (status != XML_STATUS_OK) {
    throw InputError(file, static_cast<int>(XML_GetCurrentLineNumber(parser.get())),
                     static_cast<int>(XML_GetCurrentColumnNumber(parser.get())) + 1, kField,
                     std::string("not well-formed XML: ") + XML_ErrorString(XML_GetErrorCode(parser.get())));
  }
}

// The folder MuJoCo looks for an element's file in, relative to the model's folder unless absolute.
std::string asset_dir(const Scan& scan, const std::string& element) {
  if (element == "mesh" || element == "skin" || element == "hfield") return scan.meshdir;
  if (element == "texture") return scan.texturedir;
  return {};
}

// Whether a file name ends in `extension` (any case).
bool has_extension(const std::string& name, const std::string& extension) {
  if (name.size() < extension.size()) return false;
  return std::equal(extension.rbegin(), extension.rend(), name.rbegin(),
                    [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b)); });
}

// Reads and checks every asset file the model names.
void read_assets(Scan& scan) {
  for (const Reference& ref : scan.assets) {
    const fs::path named = scan.strippath ? fs::path(ref.value).filename() : fs::path(ref.value);
    const fs::path dir = asset_dir(scan, ref.element);
    const fs::path path = named.is_absolute() ? named : dir.is_absolute() ? dir / named : scan.model_dir / dir / named;
    std::string content = read_referenced(path, ref, ref.element + " file");
    if (ref.element == "mesh" && has_extension(path.string(), ".obj")) {
      try {
        check_obj(content, path.string());
      } catch (const InputError& e) {
        throw InputError(ref.file, ref.line, ref.column, kField, "<mesh file=\"" + printable(ref.value) + "\">: " + e.what());
      }
    }
    add_file(scan, path, std::move(content), &ref);
  }
}

// An OBJ index: a whole number within int's range (tinyobjloader's type), else nullopt.
std::optional<long> obj_index(std::string_view text) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  long value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value > 2147483647L || value < -2147483647L) {
    return std::nullopt;
  }
  return value;
}

}  // namespace

void check_obj(const std::string& text, const std::string& file) {
  // counts of vertices, texture coordinates and normals so far; the largest positive index of
  // each (tinyobjloader resolves those after reading the whole file) and where it was used
  std::array<long, 3> count{};
  std::array<long, 3> largest{};
  std::array<int, 3> largest_line{};
  const char* const kinds[] = {"vertex", "texture coordinate", "normal"};
  // the first face corner without a normal: MuJoCo 2.2.2 copies a normal for every corner by its
  // index once the file has any `vn`, and a corner without one (index -1) reads before the array
  // (found by fuzz_mjcf under AddressSanitizer)
  int corner_without_normal_line = 0;
  std::string corner_without_normal;
  long faces = 0;
  int line_number = 0;
  std::size_t at = 0;
  while (at < text.size()) {
    ++line_number;
    // a line ends at \n, \r\n or a lone \r, as tinyobjloader reads the file
    const std::size_t end = std::min(text.find_first_of("\r\n", at), text.size());
    std::string_view line(text.data() + at, end - at);
    at = end + 1;
    if (end < text.size() && text[end] == '\r' && at < text.size() && text[at] == '\n') ++at;
    // the line's words, between spaces and tabs
    std::vector<std::string_view> words;
    for (std::size_t i = 0; i < line.size();) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      const std::size_t start = i;
      while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
      if (i > start) words.push_back(line.substr(start, i - start));
    }
    if (words.empty()) continue;
    // a keyword counts only followed by a space or a tab: tinyobjloader reads a line "v" alone
    // as nothing (counting it made four such lines pass as four points: fuzz_mjcf, AddressSanitizer)
    const bool separated = words[0].data() + words[0].size() < line.data() + line.size();
    if (!separated) continue;
    if (words[0] == "v") ++count[0];
    if (words[0] == "vt") ++count[1];
    if (words[0] == "vn") ++count[2];
    if (words[0] != "f") continue;
    // tinyobjloader keeps a face of three corners or more, and drops the others
    if (words.size() >= 4) ++faces;
    for (std::size_t w = 1; w < words.size(); ++w) {
      // v, v/vt, v//vn or v/vt/vn
      std::string_view corner = words[w];
      // without a normal: fewer than two slashes, or nothing after the second ("1//" too)
      const std::size_t second_slash =
          corner.find('/') == std::string_view::npos ? std::string_view::npos : corner.find('/', corner.find('/') + 1);
      if (corner_without_normal_line == 0 && (second_slash == std::string_view::npos || second_slash + 1 == corner.size())) {
        corner_without_normal_line = line_number;
        corner_without_normal = std::string(corner);
      }
      for (std::size_t k = 0; k < 3 && !corner.empty(); ++k) {
        const std::size_t slash = corner.find('/');
        const std::string_view part = corner.substr(0, slash);
        corner = slash == std::string_view::npos ? std::string_view() : corner.substr(slash + 1);
        if (part.empty() && k > 0) continue;
        const auto fail = [&](const std::string& why) {
          throw InputError(file, line_number, 0, "",
                           "face " + std::string(words[w]) + ": the " + kinds[k] + " index " + why);
        };
        const std::optional<long> index = obj_index(part);
        if (!index) {
          // appended apart: "'" + printable(...) draws GCC 12's -Wrestrict false positive
          std::string why = printable(part);
          why += " is not a whole number";
          fail(why);
        }
        if (*index == 0) fail("is 0 (OBJ counts from 1)");
        if (*index < 0 && count[k] + *index < 0) {
          fail(std::to_string(*index) + " reaches before the first (" + std::to_string(count[k]) + " so far)");
        }
        if (*index > largest[k]) {
          largest[k] = *index;
          largest_line[k] = line_number;
        }
      }
    }
  }
  for (std::size_t k = 0; k < 3; ++k) {
    if (largest[k] > count[k]) {
      throw InputError(file, largest_line[k], 0, "",
                       "a face uses " + std::string(kinds[k]) + " " + std::to_string(largest[k]) + ", but the file has " +
                           std::to_string(count[k]));
    }
  }
  // without faces MuJoCo 2.2.2 builds the mesh as the convex hull of its vertices, and with fewer
  // than four it dereferences a null pointer (fuzz_mjcf, AddressSanitizer); its own check for an
  // inline <mesh vertex=...> ("at least 4 vertices required") is not made for a file
  if (faces == 0 && count[0] < 4) {
    throw InputError(file, 0, 0, "",
                     "has " + std::to_string(count[0]) +
                         (count[0] == 1 ? " vertex" : " vertices") +
                         " and no faces: a mesh given by its points alone needs at least 4 (MuJoCo builds their convex "
                         "hull)");
  }
  // and then copies a texture coordinate and a normal for every vertex once the file has any:
  // fewer than the vertices read past their array (fuzz_mjcf, AddressSanitizer)
  for (std::size_t k = 1; k < 3 && faces == 0; ++k) {
    if (count[k] > 0 && count[k] < count[0]) {
      throw InputError(file, 0, 0, "",
                       "has " + std::to_string(count[0]) + " vertices and " + std::to_string(count[k]) + " " + kinds[k] +
                           "s but no faces: without faces every vertex needs its own " + kinds[k] + " (or none)");
    }
  }
  if (count[2] > 0 && corner_without_normal_line != 0) {
    throw InputError(file, corner_without_normal_line, 0, "",
                     "face " + printable(corner_without_normal) +
                         ": has no normal, but the file has normals (vn); with normals every face corner needs "
                         "one (v//vn or v/vt/vn)");
  }
}

ModelFiles read_model_files(const std::string& path) {
  Scan scan;
  scan.model_dir = fs::path(path).parent_path();
  const std::string text = [&] {
    try {
      return read_input_file(path, "MJCF file", kMaxModelFileBytes);
    } catch (const InputError& e) {
      throw InputError(path, 0, 0, kField, e.detail());
    }
  }();
  scan.out.main = fs::path(path).filename().string();
  // the model file first, under its own name
  add_file(scan, path, text, nullptr);
  scan_xml(scan, text, path, 0);
  read_assets(scan);
  return std::move(scan.out);
}

ModelFiles model_text_files(const std::string& text, const std::string& name) {
  Scan scan;
  scan.text_only = true;
  scan.out.main = name;
  add_file(scan, name, text, nullptr);
  scan_xml(scan, text, name, 0);
  if (!scan.assets.empty()) {
    const Reference& ref = scan.assets.front();
    throw InputError(name, ref.line, ref.column, kField, "a model given as text names no file (<" + ref.element + " " + ref.attribute + ">)");
  }
  return std::move(scan.out);
}

}  // namespace blendbench::sim_detail
