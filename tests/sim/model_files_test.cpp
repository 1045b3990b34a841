// The files of an MJCF model read by this program before MuJoCo sees them (sim/src/model_files):
// found where MuJoCo 2.2.2 finds them (the reference: MuJoCo loading the same safe model from
// disk compiles the same model), and every file issue 42 found hostile refused at the element
// naming it, at once: FIFOs, folders, out-of-range OBJ faces, too many elements, names MuJoCo's
// virtual file system would confuse.

#include "model_files.hpp"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>

#include "blendbench/sim/simulator.hpp"
#include "support/input_error.hpp"
#include "support/scratch.hpp"
#include "support/test_arm.hpp"

namespace blendbench::sim_detail {
namespace {

namespace fs = std::filesystem;

// A tetrahedron (four faces over four vertices) as OBJ text, with `extra` lines appended; every
// corner has a normal, as MuJoCo requires of a file with normals.
std::string tetrahedron(const std::string& extra = "") {
  return "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0 0 0.1\nvt 0 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 1/1/1 2/1/1 4/1/1\nf 1//1 3//1 4//1\n"
         "f -4//-1 -3//-1 -1//-1\n" +
         extra;
}

// The test arm with `before_worldbody` just before its <worldbody> and `in_worldbody` just inside.
std::string arm_with(const std::string& before_worldbody, const std::string& in_worldbody) {
  std::string xml = test::kTestArmXml;
  xml.replace(xml.find("<worldbody>"), 11, before_worldbody + "<worldbody>" + in_worldbody);
  return xml;
}

// The line of the test arm's <worldbody>, where arm_with inserts.
int worldbody_line() {
  const std::string xml = test::kTestArmXml;
  return 1 + static_cast<int>(std::count(xml.begin(), xml.begin() + static_cast<std::ptrdiff_t>(xml.find("<worldbody>")), '\n'));
}

TEST(ModelFiles, FilesAreFoundWhereMujocoFindsThemAndCompileToTheSameModel) {
  const test::ScratchDir dir("model_files");
  fs::create_directories(dir / "arm" / "meshes");
  fs::create_directories(dir / "arm" / "parts");
  fs::create_directories(dir / "arm" / "textures");
  (void)dir.write("arm/meshes/tet.obj", tetrahedron());
  (void)dir.write("arm/parts/floor.xml", "<mujoco><worldbody><geom name='ground' type='plane' size='1 1 0.1'/></worldbody></mujoco>");
  // an include inside an include is found relative to the main model's folder
  (void)dir.write("arm/parts/scene.xml", "<mujoco><include file='parts/floor.xml'/></mujoco>");
  const std::string xml = arm_with("<compiler meshdir='meshes'/><asset><mesh name='tet' file='tet.obj'/></asset>"
                                   "<include file='parts/scene.xml'/>",
                                   "<geom type='mesh' mesh='tet' pos='1 1 0'/>");
  const std::string path = dir.write("arm/arm.xml", xml);
  const ModelFiles files = read_model_files(path);
  EXPECT_EQ(files.main, "arm.xml");
  ASSERT_EQ(files.files.size(), 4u);
  // the reference: MuJoCo reading the same files from disk itself
  char error[1000] = "";
  mjModel* reference = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
  ASSERT_NE(reference, nullptr) << error;
  const Simulator sim(path);
  const mjModel& m = sim.model();
  EXPECT_EQ(m.ngeom, reference->ngeom);
  EXPECT_EQ(m.nmesh, 1);
  EXPECT_EQ(m.nmeshvert, reference->nmeshvert);
  EXPECT_EQ(m.nmeshface, reference->nmeshface);
  EXPECT_GE(mj_name2id(&m, mjOBJ_GEOM, "ground"), 0);
  mj_deleteModel(reference);
}

TEST(ModelFiles, FifosAndFoldersAreRefusedAtTheElementThatNamesThem) {
  const test::ScratchDir dir("model_files_fifo");
  ASSERT_EQ(::mkfifo((dir / "pipe.obj").c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo((dir / "pipe.xml").c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo((dir / "pipe.png").c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo((dir / "pipe.bin").c_str(), 0600), 0);
  fs::create_directories(dir / "folder.obj");
  struct Case {
    std::string before, message;
  };
  const Case cases[] = {
      {"<include file='pipe.xml'/>", "<include file=\"pipe.xml\">: " + (dir / "pipe.xml").string() +
                                         ": the included file is a FIFO (named pipe), not a regular file"},
      {"<asset><mesh name='m' file='pipe.obj'/></asset>", "the mesh file is a FIFO (named pipe)"},
      {"<asset><texture name='t' type='2d' file='pipe.png'/></asset>", "the texture file is a FIFO (named pipe)"},
      {"<asset><texture name='t' type='cube' fileright='pipe.png'/></asset>", "the texture file is a FIFO (named pipe)"},
      {"<asset><hfield name='h' file='pipe.bin' size='1 1 1 1'/></asset>", "the hfield file is a FIFO (named pipe)"},
      {"<asset><mesh name='m' file='folder.obj'/></asset>", "the mesh file is a folder, not a regular file"},
      {"<asset><mesh name='m' file='absent.obj'/></asset>", "No such file"},
  };
  for (const Case& c : cases) {
    const std::string path = dir.write("arm.xml", arm_with(c.before, ""));
    const auto start = std::chrono::steady_clock::now();
    test::expect_input_error([&] { (void)Simulator(path); }, {.file = path, .line = worldbody_line(), .field = "mjcf", .message = c.message},
                             c.before);
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5)) << c.before;
  }
}

TEST(ModelFiles, ObjFacesMayIndexOnlyWhatTheFileHas) {
  EXPECT_NO_THROW(check_obj(tetrahedron(), "tet.obj"));
  EXPECT_NO_THROW(check_obj("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf +1 2 3\r\n", "crlf.obj"));
  EXPECT_NO_THROW(check_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2 3/1\n", "no_normals.obj"));
  struct Case {
    std::string extra;
    int line;
    std::string message;
  };
  // MuJoCo read these out of bounds (a face index of 400000000 crashed it)
  const Case cases[] = {
      {"f 1 2 400000000\n", 11, "a face uses vertex 400000000, but the file has 4"},
      {"f 1 2 -5\n", 11, "the vertex index -5 reaches before the first (4 so far)"},
      {"f 1/2 2/1 3/1\n", 11, "a face uses texture coordinate 2, but the file has 1"},
      {"f 1//3 2//1 3//1\n", 11, "a face uses normal 3, but the file has 1"},
      {"f 1 0 2\n", 11, "the vertex index is 0"},
      {"f 1 two 3\n", 11, "two is not a whole number"},
      {"f 1 2 99999999999\n", 11, "99999999999 is not a whole number"},
      // MuJoCo 2.2.2 read before its normals for a corner without one (fuzz_mjcf, AddressSanitizer)
      {"f 1//1 2 3//1\n", 11, "face 2: has no normal, but the file has normals (vn)"},
      // an empty normal index is no normal either (fuzz_mjcf, AddressSanitizer)
      {"f 1// 2//1 3//1\n", 11, "face 1//: has no normal, but the file has normals (vn)"},
  };
  for (const Case& c : cases) {
    test::expect_input_error([&] { check_obj(tetrahedron(c.extra), "tet.obj"); },
                             {.file = "tet.obj", .line = c.line, .message = c.message}, c.extra);
  }
  // points without faces: MuJoCo 2.2.2 takes their convex hull and crashed on fewer than four
  // (fuzz_mjcf, AddressSanitizer); four or more are a mesh
  EXPECT_NO_THROW(check_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n", "points.obj"));
  // without faces, MuJoCo copies a texture coordinate and a normal per vertex once there are any
  const std::string cloud = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 1 1 1\n";
  EXPECT_NO_THROW(check_obj(cloud + "vn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\n", "points.obj"));
  test::expect_input_error([&] { check_obj(cloud + "vt 0 0\n", "points.obj"); },
                           {.file = "points.obj", .message = "has 5 vertices and 1 texture coordinates but no faces"});
  test::expect_input_error([&] { check_obj(cloud + "vn 0 0 1\n", "points.obj"); },
                           {.file = "points.obj", .message = "every vertex needs its own normal (or none)"});
  // a lone \r ends a line as \n does; a "v" without a space after it is no vertex
  EXPECT_NO_THROW(check_obj("v 0 0 0\rv 1 0 0\rv 0 1 0\rv 0 0 1\r", "points.obj"));
  test::expect_input_error([&] { check_obj(tetrahedron("f 1 2 3\rf 1 2 9\n"), "tet.obj"); },
                           {.file = "tet.obj", .line = 12, .message = "a face uses vertex 9, but the file has 4"});
  for (const std::string& points : {std::string("v 0 0 0\n"), std::string("v 1\nv 1 0 0\nv 0 1 0\n"),
                                    std::string("v\nv\nv \nv"), std::string("v \nf \no "),
                                    std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"), std::string("v 0 0 0 v 1 0 0 v 0 1 0 v 0 0 1\n")}) {
    test::expect_input_error([&] { check_obj(points, "points.obj"); },
                             {.file = "points.obj", .message = "and no faces: a mesh given by its points alone needs at least 4"},
                             points);
  }
  // through a model: refused at the <mesh> naming the file
  const test::ScratchDir dir("model_files_obj");
  (void)dir.write("bad.obj", tetrahedron("f 1 2 400000000\n"));
  const std::string path = dir.write("arm.xml", arm_with("<asset><mesh name='m' file='bad.obj'/></asset>", "<geom type='mesh' mesh='m'/>"));
  test::expect_input_error([&] { (void)Simulator(path); },
                           {.file = path, .line = worldbody_line(), .field = "mjcf", .message = "a face uses vertex 400000000"});
}

TEST(ModelFiles, TheModelsSizeIsBoundedBeforeMujocoCompilesIt) {
  // 10^5 geoms ran for minutes; refused at the first element past the bound
  std::string geoms;
  for (std::size_t i = 0; i < kMaxModelElements; ++i) geoms += "<geom size='0.01'/>";
  test::expect_input_error([&] { (void)Simulator::from_xml_string(arm_with("", geoms)); },
                           {.file = "<string>", .field = "mjcf", .message = "the model holds more than 2000 elements"});
  std::string deep;
  for (int i = 0; i < 100; ++i) deep += "<body>";
  for (int i = 0; i < 100; ++i) deep += "</body>";
  test::expect_input_error([&] { (void)Simulator::from_xml_string(arm_with("", deep)); },
                           {.message = "elements are nested more than 64 deep"});
  // an include of itself: bounded by the include depth
  const test::ScratchDir dir("model_files_loop");
  const std::string self = dir.write("loop.xml", "<mujoco><include file='loop.xml'/></mujoco>");
  test::expect_input_error([&] { (void)read_model_files(self); }, {.message = "includes are nested more than 8 deep"});
  // a text model includes nothing
  test::expect_input_error([&] { (void)Simulator::from_xml_string(arm_with("<include file='/etc/passwd'/>", "")); },
                           {.message = "a model given as text includes no file"});
}

TEST(ModelFiles, TwoDifferentFilesOfOneNameAreRefusedNamingBoth) {
  // MuJoCo 2.2.2 finds files by name alone: visual/link.obj and collision/link.obj would be one
  const test::ScratchDir dir("model_files_names");
  fs::create_directories(dir / "visual");
  fs::create_directories(dir / "collision");
  (void)dir.write("visual/link.obj", tetrahedron());
  (void)dir.write("collision/link.obj", tetrahedron("v 1 1 1\n"));
  const std::string path = dir.write(
      "arm.xml", arm_with("<asset><mesh name='a' file='visual/link.obj'/><mesh name='b' file='collision/link.obj'/></asset>", ""));
  test::expect_input_error([&] { (void)Simulator(path); },
                           {.file = path, .field = "mjcf", .message = "two different files are named 'link.obj'"});
  // the same file named twice is one file
  const std::string same =
      dir.write("same.xml", arm_with("<asset><mesh name='a' file='visual/link.obj'/><mesh name='b' file='visual/../visual/link.obj'/></asset>", ""));
  EXPECT_NO_THROW((void)Simulator(same));
}

}  // namespace
}  // namespace blendbench::sim_detail
