// Subroutines in files of their own (LinuxCNC's "Calling Files"): "o<name> call" of a subroutine
// the program does not define runs o<name> from the file <name>.ngc. Each program is compared
// with the same path written out longhand in one file; the search, the bounds and the refusals
// are checked through parse_gcode with files held in memory and through load_gcode_file with
// files on disk.

#include "blendbench/core/units.hpp"
#include "blendbench/io/gcode.hpp"
#include "blendbench/io/program_io.hpp"
#include "blendbench/io/scenario.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>

#include "support/input_error.hpp"
#include "support/scratch.hpp"

namespace blendbench {
namespace {

constexpr double kSamePath = 1e-12;  // m: two readings of one path (rounding of sums only)

GcodeOptions options() {
  GcodeOptions opt;
  opt.limits = {0.1, 2.0, 3.0, 50.0};
  return opt;
}

// Subroutine files held in memory: name -> text; counts the searches.
struct MemoryFiles {
  std::map<std::string, std::string> files;
  int searches = 0;

  GcodeOptions options() {
    GcodeOptions opt = blendbench::options();
    opt.find_subroutine = [this](const std::string& name) {
      ++searches;
      GcodeSubroutineLookup out;
      out.searched = "memory";
      if (const auto it = files.find(name); it != files.end()) out.file = GcodeSubroutineFile{"subs/" + name + ".ngc", it->second};
      return out;
    };
    return opt;
  }
};

Vec3 end_of(const Move& m) { return point(m.geometry, length(m.geometry)); }

void expect_same_path(const GcodeResult& a, const GcodeResult& b) {
  ASSERT_EQ(a.program.moves.size(), b.program.moves.size());
  for (std::size_t k = 0; k < a.program.moves.size(); ++k) {
    const Move& ma = a.program.moves[k];
    const Move& mb = b.program.moves[k];
    ASSERT_EQ(ma.geometry.index(), mb.geometry.index()) << "move " << k;
    for (const double t : {0.0, 0.5, 1.0}) {
      EXPECT_LE((point(ma.geometry, t * length(ma.geometry)) - point(mb.geometry, t * length(mb.geometry))).norm(), kSamePath)
          << "move " << k << " t=" << t;
    }
    EXPECT_NEAR(ma.limits.velocity, mb.limits.velocity, 1e-15) << "move " << k;
  }
}

TEST(GcodeFiles, ASubroutineInItsOwnFileRunsAsIfWrittenInTheProgram) {
  MemoryFiles subs;
  subs.files["leg"] = "o<leg> sub\nG91 G1 X#1 Y#2\nG90\no<leg> endsub\n";
  const GcodeResult called =
      parse_gcode("G0 X1\nF600\no<leg> call [2] [3]\no<leg> call [-1] [0.5]\nG1 Z4\n", "part.ngc", subs.options());
  const GcodeResult longhand = parse_gcode("G0 X1\nF600\nG1 X3 Y3\nX2 Y3.5\nZ4\n", "part.ngc", options());
  expect_same_path(called, longhand);
  // read once, though called twice; the moves name the file and line they come from
  EXPECT_EQ(subs.searches, 1);
  EXPECT_EQ(called.program.moves[1].where.file, "subs/leg.ngc");
  EXPECT_EQ(called.program.moves[1].where.line, 2);
  EXPECT_EQ(called.program.moves[3].where.file, "part.ngc");
}

TEST(GcodeFiles, ModesSetInAFileCalledFromAFileHoldAfterTheCalls) {
  // as LinuxCNC's trajectory-planner tests call o<default_inch>, which calls o<default_modal_state>
  MemoryFiles subs;
  subs.files["setup_inch"] = "o<setup_inch> sub\no<modal> call\nG20\no<setup_inch> endsub\n";
  subs.files["modal"] = "o<modal> sub\nG17 G40 G49 G54 G90 G94 G97 G98\nG64 P0 Q0\nM5 M9\nS0\nF0\no<modal> endsub\n";
  const GcodeResult r = parse_gcode("o<setup_inch> call\nG0 X1 Y2\nG91 G1 X1 F10\n", "part.ngc", subs.options());
  ASSERT_EQ(r.program.moves.size(), 2u);
  EXPECT_LE((end_of(r.program.moves[0]) - Vec3(25.4, 50.8, 0) * kMm).norm(), kSamePath);
  EXPECT_LE((end_of(r.program.moves[1]) - Vec3(50.8, 50.8, 0) * kMm).norm(), kSamePath);
  EXPECT_NEAR(r.program.moves[1].limits.velocity, 10 * 25.4e-3 / 60, 1e-15);
  EXPECT_EQ(subs.searches, 2);
}

TEST(GcodeFiles, ACallFindsTheCallingFileThenTheProgramThenAFile) {
  MemoryFiles subs;
  // o<step> is defined in the main program and in a file of the same name; the program's wins
  subs.files["step"] = "o<step> sub\nG1 X100\no<step> endsub\n";
  // a file's own helper is called from inside it, without a search
  subs.files["outer"] = "o<outer> sub\no<inner> call\no<outer> endsub\no<inner> sub\nG1 Y7\no<inner> endsub\n";
  const GcodeResult r = parse_gcode("o<step> sub\nG1 X5\no<step> endsub\nF60\no<step> call\no<outer> call\n", "part.ngc",
                                    subs.options());
  ASSERT_EQ(r.program.moves.size(), 2u);
  EXPECT_LE((end_of(r.program.moves[0]) - Vec3(5, 0, 0) * kMm).norm(), kSamePath);
  EXPECT_LE((end_of(r.program.moves[1]) - Vec3(5, 7, 0) * kMm).norm(), kSamePath);
  EXPECT_EQ(subs.searches, 1);
}

TEST(GcodeFiles, AnErrorInASubroutineFileNamesThatFileAndTheCall) {
  MemoryFiles subs;
  subs.files["bad"] = "o<bad> sub\nG1 X1 Q7\no<bad> endsub\n";
  const std::string msg =
      test::expect_input_error([&] { (void)parse_gcode("F60\n\no<bad> call\n", "part.ngc", subs.options()); },
                               {.file = "subs/bad.ngc", .line = 2, .column = 7, .field = "Q7"})
          .detail();
  EXPECT_NE(msg.find("(in o<bad> called from line 3 of part.ngc)"), std::string::npos) << msg;
  // a structure that does not close, found when the file is read
  subs.files["open"] = "o<open> sub\no1 if [1]\no<open> endsub\n";
  const std::string open =
      test::expect_input_error([&] { (void)parse_gcode("o<open> call\n", "part.ngc", subs.options()); },
                               {.file = "subs/open.ngc", .line = 3, .column = 1})
          .detail();
  EXPECT_NE(open.find("(in the subroutine file of o<open>, called from line 1 of part.ngc)"), std::string::npos) << open;
}

TEST(GcodeFiles, CallsThatFindNoSubroutineAreRefusedAtTheCall) {
  MemoryFiles subs;
  subs.files["other"] = "o<elsewhere> sub\no<elsewhere> endsub\n";
  const auto refused = [&](const std::string& program, const std::string& field, const std::string& words,
                           const GcodeOptions& opt) {
    test::expect_input_error([&] { (void)parse_gcode(program, "part.ngc", opt); },
                             {.file = "part.ngc", .line = 2, .column = 1, .field = field, .message = words}, program);
  };
  refused("G0 X1\no<nope> call\n", "o<nope>", "no file nope.ngc was found (searched memory)", subs.options());
  refused("G0 X1\no<other> call\n", "o<other>", "the subroutine file subs/other.ngc does not define o<other>", subs.options());
  refused("G0 X1\no100 call\n", "o100", "only named subroutines, o<name>, are looked up as files", subs.options());
  // a name that could leave the folders searched is never looked up
  refused("G0 X1\no<../x> call\n", "o<../x>", "letters, digits, '-' and '_' only", subs.options());
  refused("G0 X1\no<a.b> call\n", "o<a.b>", "letters, digits, '-' and '_' only", subs.options());
  EXPECT_EQ(subs.searches, 2);
  // no search at all: parse_gcode of text alone
  refused("G0 X1\no<nope> call\n", "o<nope>", "no subroutine files are searched", options());
}

TEST(GcodeFiles, RecursionThroughFilesStopsAtTheCallDepth) {
  MemoryFiles subs;
  subs.files["ping"] = "o<ping> sub\nG91 G1 X1\no<pong> call\no<ping> endsub\n";
  subs.files["pong"] = "o<pong> sub\no<ping> call\no<pong> endsub\n";
  const std::string msg =
      test::expect_input_error([&] { (void)parse_gcode("F60\no<ping> call\n", "part.ngc", subs.options()); },
                               {.message = "nested deeper than"})
          .detail();
  // each file read once, however deep the calls went; the context names the calls between files
  EXPECT_EQ(subs.searches, 2);
  EXPECT_NE(msg.find("o<pong> called from line 3 of subs/ping.ngc"), std::string::npos) << msg.substr(0, 300);
}

TEST(GcodeFiles, LoadGcodeFileSearchesTheProgramsFolderThenThePathInOrder) {
  const test::ScratchDir dir("gcode-files");
  std::filesystem::create_directories(dir / "prog");
  std::filesystem::create_directories(dir / "first");
  std::filesystem::create_directories(dir / "second");
  const std::string program = dir.write("prog/part.ngc", "F60\no<a> call\no<b> call\no<c> call\n");
  (void)dir.write("prog/a.ngc", "o<a> sub\nG1 X1\no<a> endsub\n");
  (void)dir.write("first/a.ngc", "o<a> sub\nG1 X100\no<a> endsub\n");  // hidden by the program's folder
  (void)dir.write("first/b.ngc", "o<b> sub\nG1 Y2\no<b> endsub\n");
  (void)dir.write("second/b.ngc", "o<b> sub\nG1 Y200\no<b> endsub\n");  // hidden by the first folder
  (void)dir.write("second/c.ngc", "o<c> sub\nG1 Z3\no<c> endsub\n");
  GcodeOptions opt = options();
  opt.subroutine_path = {(dir / "first").string(), (dir / "second").string()};
  const GcodeResult r = load_gcode_file(program, opt);
  ASSERT_EQ(r.program.moves.size(), 3u);
  EXPECT_LE((end_of(r.program.moves[2]) - Vec3(1, 2, 3) * kMm).norm(), kSamePath);
  EXPECT_EQ(r.program.moves[0].where.file, (dir / "prog" / "a.ngc").string());
  EXPECT_EQ(r.program.moves[1].where.file, (dir / "first" / "b.ngc").string());
  EXPECT_EQ(r.program.moves[2].where.file, (dir / "second" / "c.ngc").string());

  // not found: the refusal lists the folders searched
  const std::string missing = dir.write("prog/missing.ngc", "G0 X1\no<zzz> call\n");
  const std::string msg = test::expect_input_error([&] { (void)load_gcode_file(missing, opt); },
                                                   {.file = missing, .line = 2, .column = 1, .field = "o<zzz>"})
                              .detail();
  EXPECT_NE(msg.find("no file zzz.ngc was found (searched " + (dir / "prog").string() + ", " + (dir / "first").string() +
                     ", " + (dir / "second").string() + ")"),
            std::string::npos)
      << msg;

  // a name that is not a regular file (a folder) is refused through the safe reading, at the call
  std::filesystem::create_directories(dir / "prog" / "d.ngc");
  const std::string folder = dir.write("prog/folder.ngc", "G0 X1\no<d> call\n");
  test::expect_input_error([&] { (void)load_gcode_file(folder, opt); },
                           {.file = folder, .line = 2, .column = 1, .field = "o<d>", .message = "not a regular file"});
}

// A scenario names its subroutine folders as LinuxCNC's SUBROUTINE_PATH does (':' between
// them), relative to its own folder; a folder that does not exist is refused at the key.
TEST(GcodeFiles, AScenarioNamesSubroutineFoldersRelativeToItself) {
  const test::ScratchDir dir("gcode-files-scenario");
  std::filesystem::create_directories(dir / "cell");
  std::filesystem::create_directories(dir / "subs");
  std::filesystem::create_directories(dir / "more");
  (void)dir.write("cell/part.ngc", "G21 F600\no<a> call\no<b> call\n");
  (void)dir.write("subs/a.ngc", "o<a> sub\nG1 X10\no<a> endsub\n");
  (void)dir.write("more/b.ngc", "o<b> sub\nG1 Y10\no<b> endsub\n");
  const auto scenario = [&](const std::string& program) {
    return dir.write("cell/s.yaml", "name: subs\nunits: mm\nframe: {origin: [400, 0, 300]}\n"
                                    "defaults: {velocity: 100, acceleration: 1000, jerk: 10000}\nprogram:\n" +
                                        program + "variants:\n  - {name: exact, transition: {method: none}}\n");
  };
  const Scenario sc = load_scenario(scenario("  gcode: part.ngc\n  subroutine_path: \"../subs:" + (dir / "more").string() + "\"\n"));
  ASSERT_EQ(sc.program.moves.size(), 2u);
  EXPECT_LE((end_of(sc.program.moves[1]) - Vec3(0.41, 0.01, 0.3)).norm(), 1e-12);
  const std::string missing = scenario("  gcode: part.ngc\n  subroutine_path: \"../subs:../nope\"\n");
  test::expect_input_error([&] { (void)load_scenario(missing); },
                           {.file = missing, .line = 7, .field = "program.subroutine_path", .message = "folder not found: ../nope"});
  const std::string empty = scenario("  gcode: part.ngc\n  subroutine_path: \"../subs::../more\"\n");
  test::expect_input_error([&] { (void)load_scenario(empty); },
                           {.file = empty, .line = 7, .field = "program.subroutine_path", .message = "an empty folder name"});
  const std::string moves = scenario("  moves:\n    - line: [10, 0, 0]\n  subroutine_path: ../subs\n");
  test::expect_input_error([&] { (void)load_scenario(moves); },
                           {.file = moves, .line = 8, .field = "program.subroutine_path", .message = "has no 'gcode'"});
  // without the key, only the program's folder is searched
  const std::string none = scenario("  gcode: part.ngc\n");
  test::expect_input_error([&] { (void)load_scenario(none); },
                           {.file = (dir / "cell" / "part.ngc").string(), .line = 2, .field = "o<a>", .message = "no file a.ngc"});
}

}  // namespace
}  // namespace blendbench
