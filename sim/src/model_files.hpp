#pragma once
// Private to sim/src: the files of an MJCF model read and checked by this program before MuJoCo
// sees any of them, so that MuJoCo loads the model from memory (its virtual file system) and
// opens no file itself. Issue 42 found a model that hung on an <include>, mesh, height field or
// texture that was a FIFO, an OBJ mesh whose face index MuJoCo read out of bounds (SIGSEGV), a
// mesh path that was a folder (a library's message, exit 1) and a model of 10^5 geoms that ran
// for minutes. The rules:
//   - every file (the model, each <include>, each file an asset names) is read through
//     core/input_file.hpp: regular files only, never blocking, at most kMaxModelFileBytes each
//     and kMaxModelBytes together;
//   - each XML file is read by expat (no recursion, entity amplification limited): well-formed,
//     at most kMaxModelDepth levels and, over the model with its includes, kMaxModelElements
//     elements; includes at most kMaxIncludeDepth deep;
//   - an OBJ mesh's faces index only vertices, texture coordinates and normals the file has;
//   - files are found as MuJoCo 2.2.2 finds them (measured on Debian's build): an include's file
//     relative to the main model's folder (at any depth), a mesh's, skin's and height field's in
//     <compiler meshdir>, a texture's in <compiler texturedir> (the last <compiler> in document
//     order wins; strippath keeps the file's name alone), an absolute name as it is.
// MuJoCo 2.2.2's virtual file system keeps a file's name without its folder, so two different
// files of one name (meshes/visual/link1.stl, meshes/collision/link1.stl) cannot both be given:
// such a model is refused, naming both.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace blendbench::sim_detail {

// The largest file of a model (a mesh), the largest model with all its files, in bytes.
inline constexpr std::uintmax_t kMaxModelFileBytes = std::uintmax_t{64} << 20;
inline constexpr std::uintmax_t kMaxModelBytes = std::uintmax_t{256} << 20;
// Elements of the model with its includes. The shipped arms have about 120, the most detailed
// robot models of MuJoCo Menagerie a few hundred; at 2000 compiling takes 0.05 s and a physics
// step about 0.3 ms with every geom colliding (measured on this machine; 10^5 geoms took minutes).
inline constexpr std::size_t kMaxModelElements = 2000;
// Nesting of elements within one file (a body per joint: an arm nests about 12) and of includes.
inline constexpr int kMaxModelDepth = 64;
inline constexpr int kMaxIncludeDepth = 8;

struct ModelFiles {
  std::string main;  // the name of the model file in `files`
  std::vector<std::pair<std::string, std::string>> files;  // name (without folder, as MuJoCo looks it up), content
};

// Reads the model `path` and every file it names. Throws InputError naming the file that is
// refused (the model file, line and column of the element naming another file, and field "mjcf").
ModelFiles read_model_files(const std::string& path);

// The same for model text (tests, the model built from a URDF): it may name no other file.
ModelFiles model_text_files(const std::string& text, const std::string& name);

// Checks an OBJ mesh's text: every face's vertex, texture-coordinate and normal index refers to
// one the file has. Throws InputError(file, line, 0, "", message) for one that does not.
void check_obj(const std::string& text, const std::string& file);

}  // namespace blendbench::sim_detail
