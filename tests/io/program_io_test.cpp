#include "blendbench/io/program_io.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/input_error.hpp"

namespace blendbench {
namespace {

namespace fs = std::filesystem;

GcodeOptions options() {
  GcodeOptions opt;
  opt.limits = {0.1, 2.0, 3.0, 50.0};
  return opt;
}

// A program with lines, an arc, a feed, modal changes, an ignored word, a comment, a Unicode
// minus (UTF-8 bytes that must arrive unchanged) and no newline at the end.
const std::string kProgram =
    "%\n"
    "G21 G90 G17 (millimetres)\n"
    "G64 P0.5\n"
    "F6000\n"
    "G1 X10 Y0 Z0 S1000\n"
    "G3 X20 Y10 I0 J10\n"
    "G1 X20 Y30 ; along y\n"
    "G61\n"
    "G1 X\xE2\x88\x92" "5 Y30\n"
    "G64\n"
    "G1 X-5 Y0 Z2\n"
    "M30";

// Each test writes its files into its own directory (ctest runs tests in parallel, each in its
// own process) and removes it afterwards.
class ProgramIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("blendbench_program_io_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `text` byte for byte to dir_/name and returns the path.
  std::string write(const std::string& name, const std::string& text) {
    const fs::path file = dir_ / name;
    std::ofstream out(file, std::ios::binary);
    out << text;
    EXPECT_TRUE(out.good()) << file;
    return file.string();
  }

  fs::path dir_;
};

// Field-by-field equality of two moves (the same text parses to bitwise the same values).
void expect_same_move(const Move& a, const Move& b, std::size_t k) {
  ASSERT_EQ(a.geometry.index(), b.geometry.index()) << "move " << k;
  if (const auto* la = std::get_if<Line>(&a.geometry)) {
    const auto& lb = std::get<Line>(b.geometry);
    EXPECT_EQ(la->p0, lb.p0) << "move " << k;
    EXPECT_EQ(la->p1, lb.p1) << "move " << k;
  } else {
    const auto& aa = std::get<Arc>(a.geometry);
    const auto& ab = std::get<Arc>(b.geometry);
    EXPECT_EQ(aa.center, ab.center) << "move " << k;
    EXPECT_EQ(aa.u, ab.u) << "move " << k;
    EXPECT_EQ(aa.v, ab.v) << "move " << k;
    EXPECT_EQ(aa.radius, ab.radius) << "move " << k;
    EXPECT_EQ(aa.sweep, ab.sweep) << "move " << k;
    EXPECT_EQ(aa.rise, ab.rise) << "move " << k;
  }
  EXPECT_EQ(a.limits.velocity, b.limits.velocity) << "move " << k;
  EXPECT_EQ(a.limits.acceleration, b.limits.acceleration) << "move " << k;
  EXPECT_EQ(a.limits.deceleration, b.limits.deceleration) << "move " << k;
  EXPECT_EQ(a.limits.jerk, b.limits.jerk) << "move " << k;
  EXPECT_EQ(a.buffer, b.buffer) << "move " << k;
  EXPECT_EQ(a.transition.method, b.transition.method) << "move " << k;
  EXPECT_EQ(a.transition.parameter, b.transition.parameter) << "move " << k;
  EXPECT_EQ(a.transition.kappa_max, b.transition.kappa_max) << "move " << k;
  EXPECT_EQ(a.transition.start_distance, b.transition.start_distance) << "move " << k;
  EXPECT_EQ(a.transition.velocity, b.transition.velocity) << "move " << k;
  EXPECT_EQ(a.where.file, b.where.file) << "move " << k;
  EXPECT_EQ(a.where.line, b.where.line) << "move " << k;
  EXPECT_EQ(a.where.column, b.where.column) << "move " << k;
  EXPECT_EQ(a.name, b.name) << "move " << k;
}

// Loading a file gives exactly what parsing its text gives, with moves located in that file.
TEST_F(ProgramIoTest, LoadingAFileEqualsParsingItsText) {
  const std::string path = write("part.ngc", kProgram);
  const GcodeResult direct = parse_gcode(kProgram, path, options());
  const GcodeResult loaded = load_gcode_file(path, options());
  ASSERT_EQ(loaded.program.moves.size(), direct.program.moves.size());
  ASSERT_EQ(loaded.program.moves.size(), 5u);
  for (std::size_t k = 0; k < direct.program.moves.size(); ++k)
    expect_same_move(loaded.program.moves[k], direct.program.moves[k], k);
  EXPECT_EQ(loaded.start, direct.start);
  EXPECT_EQ(loaded.ignored, direct.ignored);
  // the file name is the one the moves carry, and the Unicode minus arrived as a minus
  EXPECT_EQ(loaded.program.moves[0].where.file, path);
  EXPECT_EQ(loaded.program.moves[0].where.line, 5);
  EXPECT_TRUE(std::holds_alternative<Arc>(loaded.program.moves[1].geometry));
  const auto& line4 = std::get<Line>(loaded.program.moves[3].geometry);
  EXPECT_NEAR(line4.p1.x(), -5e-3, 1e-15);
}

// A file longer than any read buffer arrives whole: every move of a long zigzag, the last one
// where the file says.
TEST_F(ProgramIoTest, LongFileArrivesWhole) {
  constexpr int kMoves = 3000;
  std::string text = "G21 G90 F600\n";
  for (int k = 1; k <= kMoves; ++k)
    text += "G1 X" + std::to_string(k) + " Y" + std::to_string(k % 2) + " (move " + std::to_string(k) + ")\n";
  ASSERT_GT(text.size(), 64u * 1024u);
  const std::string path = write("long.ngc", text);
  const GcodeResult direct = parse_gcode(text, path, options());
  const GcodeResult loaded = load_gcode_file(path, options());
  ASSERT_EQ(loaded.program.moves.size(), static_cast<std::size_t>(kMoves));
  for (std::size_t k = 0; k < direct.program.moves.size(); ++k)
    expect_same_move(loaded.program.moves[k], direct.program.moves[k], k);
  const auto& last = std::get<Line>(loaded.program.moves.back().geometry);
  EXPECT_NEAR(last.p1.x(), kMoves * 1e-3, 1e-12);
  EXPECT_EQ(loaded.program.moves.back().where.line, kMoves + 1);
}

// The options reach the parser: a different start and feed give a different program.
TEST_F(ProgramIoTest, OptionsArePassedToTheParser) {
  const std::string path = write("nofeed.nc", "G1 X1 Y2\n");
  GcodeOptions opt = options();
  opt.limits.velocity = 0.0375;
  opt.start = Vec3(0.001, 0, 0);
  const GcodeResult r = load_gcode_file(path, opt);
  ASSERT_EQ(r.program.moves.size(), 1u);
  EXPECT_EQ(r.program.moves[0].limits.velocity, 0.0375);
  EXPECT_EQ(r.start, opt.start);
  EXPECT_EQ(std::get<Line>(r.program.moves[0].geometry).p0, opt.start);
}

// A missing file is an InputError that names it, with no line.
TEST_F(ProgramIoTest, MissingFileThrowsNamingTheFile) {
  const std::string path = (dir_ / "missing.ngc").string();
  test::expect_input_error([&] { load_gcode_file(path, options()); },
                           {.file = path, .line = 0, .message = path + ": cannot open the G-code file: No such file"});
}

// A folder, a FIFO and a device are refused before they are opened for reading: a folder used to
// read as an empty text ("no moves"), a FIFO blocked until a writer came, /dev/zero never ended.
TEST_F(ProgramIoTest, OnlyRegularFilesAreRead) {
  const fs::path folder = dir_ / "folder.ngc";
  fs::create_directories(folder);
  test::expect_input_error([&] { load_gcode_file(folder.string(), options()); },
                           {.file = folder.string(), .line = 0, .message = "the G-code file is a folder, not a regular file"});
  const fs::path fifo = dir_ / "pipe.ngc";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  test::expect_input_error([&] { load_gcode_file(fifo.string(), options()); },
                           {.file = fifo.string(), .message = "the G-code file is a FIFO (named pipe), not a regular file"});
  test::expect_input_error([&] { (void)read_input_file("/dev/zero", "scenario file"); },
                           {.file = "/dev/zero", .message = "the scenario file is a character device, not a regular file"});
}

// The size is checked before a byte is read: the limit itself passes, one byte more does not.
TEST_F(ProgramIoTest, FilesOverTheSizeLimitAreRefusedNamingSizeAndLimit) {
  const std::string text(3u << 20, 'x');
  const std::string path = write("big.ngc", text);
  EXPECT_EQ(read_input_file(path, "G-code file", text.size()), text);
  test::expect_input_error([&] { (void)read_input_file(path, "G-code file", text.size() - 1); },
                           {.file = path, .message = "the G-code file is 3 MiB; the limit is 3 MiB"});
  EXPECT_GT(kMaxInputBytes, std::uintmax_t{20} << 20);
}

// An empty file is readable: the parser's error (no moves) names the file.
TEST_F(ProgramIoTest, EmptyFileIsTheParsersNoMovesError) {
  const std::string path = write("empty.ngc", "");
  test::expect_input_error([&] { load_gcode_file(path, options()); }, {.file = path, .message = "no moves"});
}

// A parse error keeps the file name, line, column and word.
TEST_F(ProgramIoTest, ParseErrorKeepsFileAndLine) {
  const std::string path = write("comp.tap", "G21 G90\nG1 X1 F600\n  G41 D1\nG1 X2\n");
  test::expect_input_error([&] { load_gcode_file(path, options()); },
                           {.file = path, .line = 3, .column = 3, .field = "G41", .message = path + ":3:3: "});
}

TEST(IsGcodeFileTest, EveryExtensionInAnyCase) {
  for (const std::string ext : {"ngc", "nc", "gcode", "tap", "cnc"}) {
    std::string upper = ext, mixed = ext;
    for (char& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    mixed[0] = upper[0];
    for (const std::string& e : {ext, upper, mixed}) {
      EXPECT_TRUE(is_gcode_file("part." + e)) << e;
      EXPECT_TRUE(is_gcode_file("/some/dir.d/Part 7.v2." + e)) << e;
    }
  }
}

TEST(IsGcodeFileTest, OtherNamesAreNot) {
  for (const std::string name :
       {"", "part", "ngc", "part.yaml", "part.YML", "part.txt", "part.g", "part.gc", "part.ncc", "part.ngc.bak",
        "part.ngc~", "part.ngc/", "programs.ngc/scenario.yaml", "part.n gc", "part.tapx"}) {
    EXPECT_FALSE(is_gcode_file(name)) << "'" << name << "'";
  }
}

}  // namespace
}  // namespace blendbench
