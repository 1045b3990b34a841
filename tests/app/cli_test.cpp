// The blendbench program as a user meets it: exit codes, messages that name file, line and
// field, and the files a run writes (including a video that ffprobe accepts).

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/csv.hpp"
#include "support/program.hpp"
#include "support/property.hpp"

namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

// Runs a shell command, capturing its stdout and stderr.
Result run_shell(const std::string& command) {
  Result r;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) r.output += buffer.data();
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

Result run(const std::string& args) { return run_shell(blendbench::test::blendbench_binary() + " " + args); }

// Runs the program with an argument vector (no shell between) in the working directory `cwd`.
Result run_in(const fs::path& cwd, const std::vector<std::string>& args) {
  blendbench::test::Child child(blendbench::test::blendbench_binary(), args, cwd);
  Result r;
  r.exit_code = child.wait();
  r.output = child.output();
  return r;
}

// Every file below `dir`, as paths relative to it.
std::vector<std::string> files_below(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) out.push_back(fs::relative(e.path(), dir).string());
  std::sort(out.begin(), out.end());
  return out;
}

Result run_probe(const fs::path& video) {
  return run_shell("ffprobe -v error -select_streams v:0 -show_entries stream=codec_name,avg_frame_rate -of compact '" +
                   video.string() + "'");
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("blendbench_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes a scenario file from the tiny one with one text replacement.
  std::string scenario_with(const std::string& from, const std::string& to) {
    std::ifstream in(blendbench::test::source_path("tests/data/tiny.yaml"));
    std::stringstream s;
    s << in.rdbuf();
    std::string text = s.str();
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    const fs::path file = dir_ / "bad.yaml";
    std::ofstream(file) << text;
    return file.string();
  }

  fs::path dir_;
};

// The help states --max-vibration's unit as the command line writes micrometres: µm where the
// locale is UTF-8, um elsewhere (docs/units.md).
TEST_F(Cli, HelpWritesMicrometresAsTheLocaleAllows) {
  const std::string binary = blendbench::test::blendbench_binary();
  const Result utf8 = run_shell("LC_ALL=C.UTF-8 " + binary + " compare --help");
  EXPECT_EQ(utf8.exit_code, 0) << utf8.output;
  EXPECT_NE(utf8.output.find("(\xC2\xB5m, peak to peak)"), std::string::npos) << utf8.output;
  const Result ascii = run_shell("LC_ALL=C " + binary + " compare --help");
  EXPECT_EQ(ascii.exit_code, 0) << ascii.output;
  EXPECT_NE(ascii.output.find("(um, peak to peak)"), std::string::npos) << ascii.output;
  EXPECT_EQ(ascii.output.find("\xC2\xB5"), std::string::npos) << ascii.output;
}

TEST_F(Cli, BadScenarioExitsTwoNamingFileLineAndField) {
  struct Case {
    std::string from, to, expected;
  };
  const Case cases[] = {
      {"units: mm", "units: mm\nspeed: 3", "bad.yaml:4:1: 'speed': unknown key"},
      {"velocity: 200", "velocity: fast", "bad.yaml:5:22: 'defaults.velocity': expected a number"},
      {"jerk: 20000", "jerky: 20000", "bad.yaml:5:47: 'defaults.jerky': unknown key"},
      {"defaults: {velocity: 200, acceleration: 2000, jerk: 20000}", "defaults: {velocity: 200, acceleration: 2000}",
       "bad.yaml:5:11: 'defaults.jerk': missing required field"},
      {"origin: [400, -50, 250]", "origin: [1400, -50, 250]", "bad.yaml:11:7: 'program.moves[0]': the start point"},
      {"units: mm", "units: mm\nservo: {rate_hz: 100}", "bad.yaml:4:18: 'servo.rate_hz': must be in [125, 8000] Hz, got 100"},
      {"units: mm", "units: mm\nservo: {setpoint_rate_hz: 300}", "bad.yaml:4:27: 'servo.setpoint_rate_hz': the servo rate (2000 Hz) must be a whole multiple"},
      {"units: mm", "units: mm\nservo: {controller: pid}", "bad.yaml:4:21: 'servo.controller': unknown value 'pid' (did you mean 'pd'?)"},
      {"units: mm", "units: mm\nservo: {measurement_delay_ticks: -1}", "bad.yaml:4:34: 'servo.measurement_delay_ticks'"},
      {"units: mm", "units: mm\nrobot: {model: flexible}", "bad.yaml:4:16: 'robot.model': unknown value 'flexible' (one of: elastic, rigid)"},
      {"simulation: {settle_tolerance: 0.2, settle_time_s: 0.3}", "simulation: {settle_tolerance: 0.2, settle_time_s: 0.1}",
       "bad.yaml:6:52: 'simulation.settle_time_s': settle_time_s (0.1 s) must be at least the settle window"},
      {"units: mm", "units: mm\nservo: {rate_hz: 3000, setpoint_rate_hz: 500}", "bad.yaml:4:18: 'servo.rate_hz': the servo period"},
  };
  for (const Case& c : cases) {
    const std::string file = scenario_with(c.from, c.to);
    const Result r = run("run " + file + " --no-video --no-plots --out " + (dir_ / "out").string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in:\n" << r.output;
  }
}

// A scenario name is a folder name: quotes, shell syntax and '..' are refused before anything
// is written, so a name can neither run a command nor place the run outside results/runs/.
TEST_F(Cli, ScenarioNamesThatCouldInjectOrEscapeAreRefused) {
  const fs::path work = dir_ / "work";
  fs::create_directories(work / "a" / "b" / "c");
  for (const std::string name : {"\"x'; touch PWNED; echo '\"", "../../../ESCAPED", "\"$(touch PWNED)\"", "\"a b\"", ".hidden"}) {
    const std::string file = scenario_with("name: tiny", "name: " + name);
    const Result r = run_in(work / "a" / "b" / "c", {"run", file, "--no-video"});
    EXPECT_EQ(r.exit_code, 2) << name << "\n" << r.output;
    EXPECT_NE(r.output.find("bad.yaml:2:7: 'name': scenario name"), std::string::npos) << name << "\n" << r.output;
    const std::vector<std::string> expected = {"a", "a/b", "a/b/c"};
    EXPECT_EQ(files_below(work), expected) << name << ": the refused run wrote something";
  }
}

// An output folder is data: a --out full of quotes, ';', '$()' and spaces gets the whole run
// (summary, traces and the plots drawn by a child process), and nothing else happens.
TEST_F(Cli, OutputFolderWithShellSyntaxIsJustAFolder) {
  const fs::path work = dir_ / "work";
  fs::create_directories(work);
  const std::string out = "it's; $(touch PWNED) `touch PWNED2` ' ; touch PWNED3 #";
  const Result r = run_in(work, {"run", blendbench::test::source_path("tests/data/tiny.yaml"), "--no-video", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
  std::vector<std::string> everything = files_below(work);
  EXPECT_EQ(std::count_if(everything.begin(), everything.end(), [](const std::string& f) { return f.find('/') == std::string::npos; }), 1)
      << "only the output folder is created";
  for (const char* file : {"summary.json", "compare_speed.png", "exact/trace.csv", "exact/speed.png", "arc/path.png"}) {
    EXPECT_TRUE(fs::exists(work / out / file)) << file;
  }
  for (const char* file : {"PWNED", "PWNED2", "PWNED3"}) {
    EXPECT_FALSE(fs::exists(work / file)) << file;
    EXPECT_FALSE(fs::exists(fs::path(blendbench::test::source_path("")) / file)) << file;
  }
}

TEST_F(Cli, MissingFilesAndFlagsAreBadInput) {
  EXPECT_EQ(run("run /nonexistent/scenario.yaml --no-video").exit_code, 2);
  EXPECT_EQ(run("frobnicate").exit_code, 2);
  const std::string tiny = blendbench::test::source_path("tests/data/tiny.yaml");
  Result r = run("path " + tiny + " --variant nope --csv " + (dir_ / "p.csv").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("variants: exact, arc"), std::string::npos) << r.output;
  r = run("path " + tiny + " --method spline --param 1 --csv " + (dir_ / "p.csv").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("'--method'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "p.csv")) << "nothing is written on bad input";
}

TEST_F(Cli, BadGcodeNamesLineAndWord) {
  const fs::path file = dir_ / "part.ngc";
  std::ofstream(file) << "G21 G90\nG1 X10 F1000\nG41 D1\nG1 Y10\n";
  const Result r = run("plan " + file.string() + " --csv " + (dir_ / "t.csv").string() + " --summary " +
                       (dir_ / "s.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("part.ngc:3:1: 'G41'"), std::string::npos) << r.output;
}

// `validate FILE...`: one line per file, ok or the positioned refusal, exit 2 when any is bad;
// nothing is run or written. Typos get the closest key; G-code is checked like a scenario.
TEST_F(Cli, ValidateChecksEveryFileWithoutRunningIt) {
  const fs::path work = dir_ / "work";
  fs::create_directories(work);
  const std::string tiny = blendbench::test::source_path("tests/data/tiny.yaml");
  const std::string typo = scenario_with("acceleration: 2000", "acceleraton: 2000");
  const fs::path part = dir_ / "rect.ngc";
  std::ofstream(part) << "G21 G90\nG1 X40 F6000\nG1 Y30\nG64 P0.5\nG1 X0\nM2\n";
  const fs::path bad_part = dir_ / "bad.ngc";
  std::ofstream(bad_part) << "G21 G90\nG1 X40 F6000\nG2 X40 Y0 I-5 P101\n";
  Result r = run_in(work, {"validate", tiny, typo, part.string(), bad_part.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  const std::vector<std::string> lines = [&] {
    std::vector<std::string> out;
    std::stringstream in(r.output);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
  }();
  ASSERT_EQ(lines.size(), 4u) << r.output;
  EXPECT_EQ(lines[0], tiny + ": ok (scenario 'tiny', 2 moves, 2 variants blended, robot loaded)");
  EXPECT_EQ(lines[1], typo + ":5:27: 'defaults.acceleraton': unknown key 'acceleraton' (did you mean 'acceleration'?)");
  EXPECT_EQ(lines[2], part.string() + ": ok (G-code, 3 moves, 2 corners blended, 0 notes)");
  EXPECT_EQ(lines[3].rfind(bad_part.string() + ":3:15: 'P101': the number of turns P of G2/G3 must be an integer from 1 to 100", 0), 0u)
      << lines[3];
  EXPECT_TRUE(files_below(work).empty()) << "validate wrote something";
  // all good: exit 0
  r = run_in(work, {"validate", tiny, part.string()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  // a geometric refusal of one variant's blend shows (a biclothoid of tolerance 0 at a kink)
  const std::string zero = scenario_with("{name: arc, transition: {method: arc, parameter: 5}}",
                                         "{name: bic0, transition: {method: biclothoid, parameter: 0}}");
  r = run_in(work, {"validate", zero});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("'transition.parameter'"), std::string::npos) << r.output;
  // the reference of the format, as committed
  r = run_in(work, {"validate", "--schema"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::ifstream doc(blendbench::test::source_path("docs/scenario_format.md"));
  std::stringstream committed;
  committed << doc.rdbuf();
  EXPECT_EQ(r.output, committed.str());
  EXPECT_EQ(run_in(work, {"validate"}).exit_code, 2);
}

// --subroutine-path names folders searched for the files of subroutines a program calls, after
// the program's own; repeatable, and a folder that does not exist is bad input naming the flag.
TEST_F(Cli, SubroutinePathFlagFindsSubroutineFiles) {
  fs::create_directories(dir_ / "subs");
  fs::create_directories(dir_ / "more");
  const fs::path part = dir_ / "calls.ngc";
  std::ofstream(part) << "G21 F600\no<a> call\no<b> call\nM2\n";
  std::ofstream(dir_ / "subs" / "a.ngc") << "o<a> sub\nG1 X10\no<a> endsub\n";
  std::ofstream(dir_ / "more" / "b.ngc") << "o<b> sub\nG1 Y10\no<b> endsub\n";
  Result r = run_in(dir_, {"validate", "--subroutine-path", (dir_ / "subs").string(), "--subroutine-path",
                           (dir_ / "more").string(), part.string()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(part.string() + ": ok (G-code, 2 moves"), std::string::npos) << r.output;
  r = run_in(dir_, {"path", part.string(), "--subroutine-path", (dir_ / "subs").string(), "--csv", (dir_ / "p.csv").string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("o<b> is not defined in this file, and no file b.ngc was found"), std::string::npos) << r.output;
  r = run_in(dir_, {"path", part.string(), "--subroutine-path", (dir_ / "nope").string(), "--csv", (dir_ / "p.csv").string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("'--subroutine-path'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "p.csv"));
}

// A spacing so small the row count would overflow an integer is refused with the flag.
TEST_F(Cli, PathRefusesASpacingThatWouldWriteTooManyRows) {
  const std::string tiny = blendbench::test::source_path("tests/data/tiny.yaml");
  for (const std::string ds : {"1e-300", "1e-05"}) {
    const Result r = run_in(dir_, {"path", tiny, "--ds", ds, "--csv", (dir_ / "p.csv").string()});
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("'--ds': sampling the 120 mm path every " + ds + " mm would write"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("rows; the limit is 1e+07 (raise --ds)"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "p.csv"));
  }
}

// A 40 x 30 mm rectangle from the origin: three corners of 90 degrees.
constexpr const char* kRectangle = "G21 G90\nG1 X40 F6000\nG1 Y30\nG1 X0\nG1 Y0\nM2\n";

// The scripted contract of `plan` and `path` on a G-code file: the profile's columns and servo
// sampling, no limit exceeded on it, and the same corner reports from both commands.
TEST_F(Cli, PlanAndPathOfAGcodeProgramKeepTheirContract) {
  const fs::path part = dir_ / "rect.ngc";
  std::ofstream(part) << kRectangle;
  constexpr double kFeed = 6000, kAmax = 2000, kJmax = 50000, kDeviation = 0.5;  // mm/min, mm/s^2, mm/s^3, mm
  const std::string options = " --method biclothoid --param " + std::to_string(kDeviation) + " --amax " +
                              std::to_string(kAmax) + " --jmax " + std::to_string(kJmax);
  Result r = run("plan " + part.string() + options + " --csv " + (dir_ / "t.csv").string() + " --summary " +
                 (dir_ / "s.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const blendbench::test::Csv plan_csv = blendbench::test::read_csv(dir_ / "t.csv");
  EXPECT_EQ(plan_csv.header, "t,s,x,y,z,v,a,j,kappa");
  const auto& profile = plan_csv.columns;
  const std::vector<double>& t = profile.at("t");
  ASSERT_GT(t.size(), 100u);
  constexpr double kRel = 1 + 1e-9;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (i > 0) {
      EXPECT_LE(t[i] - t[i - 1], 1e-3 * kRel) << "row " << i;
    }
    EXPECT_LE(std::abs(profile.at("v")[i]), kFeed / 60 * kRel) << "row " << i;
    EXPECT_LE(std::abs(profile.at("a")[i]), kAmax * kRel) << "row " << i;
    EXPECT_LE(std::abs(profile.at("j")[i]), kJmax * kRel) << "row " << i;
  }
  std::ifstream summary_file(dir_ / "s.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_file);
  EXPECT_NEAR(summary["cycle_time_s"].get<double>(), t.back(), 1e-3);
  EXPECT_NEAR(summary["path_length_mm"].get<double>(), profile.at("s").back(), 1e-6);
  const nlohmann::json& corners = summary["corners"];
  ASSERT_EQ(corners.size(), 3u);
  for (const auto& c : corners) {
    for (const char* key : {"index", "method", "case", "length_mm", "deviation_mm", "kappa_max_per_mm",
                            "sharpness_max_per_mm2", "feed_max_mm_per_min"}) {
      EXPECT_TRUE(c.contains(key)) << key;
    }
    EXPECT_EQ(c["method"], "biclothoid");
    EXPECT_LE(c["deviation_mm"].get<double>(), kDeviation * kRel);
    EXPECT_GT(c["deviation_mm"].get<double>(), 0.9 * kDeviation);
  }
  r = run("path " + part.string() + options + " --csv " + (dir_ / "p.csv").string() + " --report " +
          (dir_ / "r.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // the path's corner reports are the plan's, which add what the timing says about each corner
  std::ifstream report_file(dir_ / "r.json");
  nlohmann::json planned = corners;
  for (auto& c : planned) {
    for (const char* key : {"curvature_steps", "curvature_step_per_mm", "curvature_step_velocity_mm_s",
                            "curvature_step_jerk_mm_s3"}) {
      EXPECT_TRUE(c.contains(key)) << key;
      c.erase(key);
    }
  }
  EXPECT_EQ(nlohmann::json::parse(report_file), planned);
  const blendbench::test::Csv path = blendbench::test::read_csv(dir_ / "p.csv");
  EXPECT_EQ(path.header, "s,x,y,z,tx,ty,tz,kappa");
  EXPECT_NEAR(path.columns.at("s").back(), summary["path_length_mm"].get<double>(), 1e-6);
}

// A corner from rest to rest: the velocity planner's span over the whole path has zero velocity
// at both ends, which once reached plan_scurve with a zero peak velocity (an assertion in a build
// with assertions on, as the sanitizer build of the test command is). The plan stops at both ends
// and holds the feed between.
TEST_F(Cli, ACornerFromRestToRestIsPlannedWithAssertionsOn) {
  const fs::path part = dir_ / "corner.ngc";
  std::ofstream(part) << "G21 G90 G64 P1\nG1 F600 X0 Y0\nX10\nY10\nM2\n";
  const Result r = run("plan " + part.string() + " --amax 1000 --jmax 10000 --csv " + (dir_ / "t.csv").string() +
                       " --summary " + (dir_ / "s.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const blendbench::test::Csv profile = blendbench::test::read_csv(dir_ / "t.csv");
  const std::vector<double>& v = profile.columns.at("v");
  ASSERT_GT(v.size(), 10u);
  EXPECT_EQ(v.front(), 0.0);
  EXPECT_EQ(v.back(), 0.0);
  EXPECT_LE(*std::max_element(v.begin(), v.end()), 600.0 / 60 * (1 + 1e-9));
  EXPECT_GT(*std::max_element(v.begin(), v.end()), 0.0);
}

// --start-distance sizes every biclothoid by where it starts; misuse is bad input, naming the flag.
TEST_F(Cli, StartDistanceSizesBiclothoidsAndIsRefusedElsewhere) {
  const fs::path part = dir_ / "rect.ngc";
  std::ofstream(part) << kRectangle;
  const std::string io = " --csv " + (dir_ / "p.csv").string() + " --report " + (dir_ / "r.json").string();
  Result r = run("path " + part.string() + " --method biclothoid --start-distance 2" + io);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream report_file(dir_ / "r.json");
  const nlohmann::json corners = nlohmann::json::parse(report_file);
  ASSERT_EQ(corners.size(), 3u);
  for (const auto& c : corners) {
    EXPECT_NEAR(c["trim_in_mm"].get<double>(), 2.0, 1e-9) << c;
    EXPECT_NEAR(c["trim_out_mm"].get<double>(), 2.0, 1e-9) << c;
  }
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      {"--method arc --start-distance 2", "'--start-distance': sizes only a biclothoid"},
      {"--method biclothoid --param 1 --start-distance 2", "not both"},
      {"--method biclothoid --start-distance 0", "'--start-distance': must be positive"},
      {"--method biclothoid --start-distance -2", "'--start-distance': must be positive"},
      {"--start-distance 2", "'--start-distance': needs --method biclothoid"},
      {"--method biclothoid", "'--param': required with --method biclothoid (mm), or --tolerance, or --start-distance"},
      {"--method arc --param -1", "'--param': must be >= 0"},
      {"--method none --param 1", "'--param': has no meaning with --method none"},
  };
  fs::remove(dir_ / "p.csv");
  for (const Case& c : cases) {
    r = run("path " + part.string() + " " + c.args + io);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in:\n" << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "p.csv")) << c.args;
  }
}

// --tolerance (equal tolerance, issue 44): every corner's parameter solved so that its deviation
// equals it, for every method; each corner reports the tolerance, whether it was reached and the
// G-code line it ends. Misuse is bad input naming the flag (and --param where both are given).
TEST_F(Cli, ToleranceSizesEveryCornerAndNamesItsSourceLine) {
  const fs::path part = dir_ / "rect.ngc";
  std::ofstream(part) << kRectangle;
  const std::string io = " --csv " + (dir_ / "p.csv").string() + " --report " + (dir_ / "r.json").string();
  for (const char* method : {"arc", "bezier", "clothoid", "biclothoid"}) {
    const Result r = run("path " + part.string() + " --method " + method + " --tolerance 0.2" + io);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    std::ifstream report_file(dir_ / "r.json");
    const nlohmann::json corners = nlohmann::json::parse(report_file);
    ASSERT_EQ(corners.size(), 3u);
    for (std::size_t k = 0; k < corners.size(); ++k) {
      const nlohmann::json& c = corners[k];
      EXPECT_EQ(c["tolerance_mm"].get<double>(), 0.2) << c;
      EXPECT_TRUE(c["tolerance_reached"].get<bool>()) << c;
      EXPECT_LE(c["deviation_mm"].get<double>(), 0.2) << c;
      EXPECT_GE(c["deviation_mm"].get<double>(), 0.2 * (1 - 1e-3)) << c;
      // the move ending at corner k is on line k + 2 (line 1 holds G21 G90 only)
      EXPECT_EQ(c["source_file"].get<std::string>(), part.string()) << c;
      EXPECT_EQ(c["source_line"].get<int>(), static_cast<int>(k) + 2) << c;
    }
  }
  // without --method, on the moves the program blends (G64 P: biclothoid), not at its exact stops
  {
    const fs::path blended = dir_ / "blended.ngc";
    std::ofstream(blended) << "G21 G90 G64 P0.05\nG1 X40 F6000\nG1 Y30\nG61\nG1 X0\nG1 Y0\nM2\n";
    const Result r = run("plan " + blended.string() + " --tolerance 0.3 --csv " + (dir_ / "t.csv").string() + " --summary " +
                         (dir_ / "s.json").string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    std::ifstream summary_file(dir_ / "s.json");
    const nlohmann::json corners = nlohmann::json::parse(summary_file)["corners"];
    ASSERT_EQ(corners.size(), 3u);
    EXPECT_EQ(corners[0]["method"], "biclothoid");
    EXPECT_EQ(corners[0]["tolerance_mm"].get<double>(), 0.3);
    EXPECT_TRUE(corners[0]["tolerance_reached"].get<bool>());
    EXPECT_EQ(corners[2]["method"], "none");
    EXPECT_TRUE(corners[2]["tolerance_mm"].is_null());
    EXPECT_TRUE(corners[2]["tolerance_reached"].is_null());
  }
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      {"--method arc --tolerance 0", "'--tolerance': must be > 0"},
      {"--method arc --tolerance -1", "'--tolerance': must be > 0"},
      {"--method arc --tolerance nan", "'--tolerance': must be > 0"},
      {"--method arc --tolerance 0.1 --param 1", "--tolerance and --param exclude each other"},
      {"--tolerance 0.1 --param 1", "--tolerance and --param exclude each other"},
      {"--method biclothoid --tolerance 0.1 --start-distance 1", "--tolerance and --start-distance exclude each other"},
      {"--method none --tolerance 0.1", "'--tolerance': has no meaning with --method none"},
  };
  fs::remove(dir_ / "p.csv");
  for (const Case& c : cases) {
    const Result r = run("path " + part.string() + " " + c.args + io);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in:\n" << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "p.csv")) << c.args;
  }
  const Result bad_run = run("run " + blendbench::test::source_path("tests/data/tiny.yaml") + " --tolerance -0.5 --out " +
                             (dir_ / "never").string());
  EXPECT_EQ(bad_run.exit_code, 2) << bad_run.output;
  EXPECT_NE(bad_run.output.find("'--tolerance': must be > 0"), std::string::npos) << bad_run.output;
  EXPECT_FALSE(fs::exists(dir_ / "never"));
}

// `run --tolerance`: the variants with a transition run at it; summary.json says so per variant
// and per corner, corners.json too, with the YAML line of the move that ends the corner.
TEST_F(Cli, RunAtAToleranceReportsItPerVariantAndCorner) {
  const fs::path out = dir_ / "run";
  const Result r = run("run " + blendbench::test::source_path("tests/data/tiny.yaml") +
                       " --tolerance 0.25 --no-video --no-plots --variant arc --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(out / "summary.json");
  const nlohmann::json v = nlohmann::json::parse(in)["variants"][0];
  EXPECT_EQ(v["tolerance_mm"].get<double>(), 0.25);
  EXPECT_EQ(v["parameter_mm"].get<double>(), 0.0);
  const nlohmann::json& corner = v["plan"]["corners"][0];
  EXPECT_EQ(corner["tolerance_mm"].get<double>(), 0.25);
  EXPECT_TRUE(corner["tolerance_reached"].get<bool>());
  EXPECT_NEAR(v["plan"]["path_deviation_max_mm"].get<double>(), 0.25, 0.25e-3);
  EXPECT_LE(v["plan"]["path_deviation_max_mm"].get<double>(), 0.25);
  // tiny.yaml: the move ending at the corner, `- line: [60, 0, 0]`, is on line 11
  EXPECT_EQ(corner["source_line"].get<int>(), 11);
  EXPECT_NE(corner["source_file"].get<std::string>().find("tiny.yaml"), std::string::npos);
  std::ifstream corners_file(out / "arc" / "corners.json");
  EXPECT_EQ(nlohmann::json::parse(corners_file)[0]["tolerance_reached"], true);
}

TEST_F(Cli, RunWritesSummaryTracesPlotsReportAndAPlayableVideo) {
  const fs::path out = dir_ / "run";
  const Result r = run("run " + blendbench::test::source_path("tests/data/tiny.yaml") + " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("report: " + (out / "report.html").string()), std::string::npos) << r.output;
  std::ifstream in(out / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  ASSERT_EQ(summary["variants"].size(), 2u);
  EXPECT_EQ(summary["robot"]["model"], "elastic");
  // the report names every variant and shows every figure, beside it
  std::ifstream page(out / "report.html");
  std::stringstream html;
  html << page.rdbuf();
  for (const auto& v : summary["variants"]) {
    const std::string name = v["name"];
    EXPECT_EQ(v["status"], "ok") << name;
    for (const char* key : {"cycle_time_s", "tracking_error_max_mm", "tracking_error_rms_mm", "orientation_error_max_deg",
                            "contour_error_programmed_max_mm", "contour_error_planned_max_mm", "jerk_actual_peak_mm_s3",
                            "jerk_commanded_peak_mm_s3", "residual_vibration_final_mm",
                            "residual_vibration_final_frequency_hz", "residual_vibration_corner_max_mm"}) {
      EXPECT_TRUE(v["metrics"][key].is_number()) << name << " " << key;
    }
    EXPECT_TRUE(v["comparison"]["cycle_time_saved_percent"].is_number()) << name;
    EXPECT_EQ(v["health"]["saturated"], false) << name;
    // the page is self-contained (figures inlined) and links each variant's video beside it
    EXPECT_NE(html.str().find("href='" + name + "/video.mp4'"), std::string::npos) << name;
    EXPECT_EQ(html.str().find("src='" + name + "/vibration.png'"), std::string::npos) << name;
    const fs::path vdir = out / name;
    for (const char* file : {"trace.csv", "path.csv", "program.csv", "corners.json", "path.png", "corners.png", "speed.png",
                             "acceleration.png", "curvature.png", "tracking_error.png", "following_error.png",
                             "torques.png", "vibration.png", "joints.png", "video.mp4"}) {
      EXPECT_GT(fs::exists(vdir / file) ? fs::file_size(vdir / file) : 0u, 100u) << vdir / file;
    }
    // corners.json carries what the plot scripts need: the corner point, arc lengths, times
    std::ifstream corners_file(vdir / "corners.json");
    const nlohmann::json corners = nlohmann::json::parse(corners_file);
    ASSERT_EQ(corners.size(), 1u);
    for (const char* key : {"point_mm", "s_programmed_mm", "s_start_mm", "s_end_mm", "t_start_s", "t_end_s"}) {
      EXPECT_TRUE(corners[0].contains(key)) << key;
    }
    EXPECT_NEAR(corners[0]["point_mm"][0].get<double>(), 460.0, 1e-6);
    const Result probe = run_probe(vdir / "video.mp4");
    EXPECT_EQ(probe.exit_code, 0) << probe.output;
    EXPECT_NE(probe.output.find("codec_name=h264"), std::string::npos) << probe.output;
    EXPECT_NE(probe.output.find("avg_frame_rate=24/1"), std::string::npos) << probe.output;
  }
  for (const char* file : {"compare_speed.png", "compare_path.png", "compare_metrics.png", "report.html"}) {
    EXPECT_TRUE(fs::exists(out / file)) << file;
  }
}

// Occurrences of `what` in `text`.
std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// --compare --no-video: compare.mp4 alone, a grid of the two 320x240 variants below the header
// (640x292), its frames at the scenario's rate; with stderr not a terminal, one summary line and
// no progress bar (no carriage return).
TEST_F(Cli, RunCompareWritesOneGridVideoAndOneSummaryLineWhenNotATerminal) {
  const fs::path out = dir_ / "run";
  const Result r = run("run " + blendbench::test::source_path("tests/data/tiny.yaml") + " --compare --no-video --no-plots --out " +
                       out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "compare.mp4"));
  EXPECT_FALSE(fs::exists(out / "exact" / "video.mp4"));
  EXPECT_FALSE(fs::exists(out / "arc" / "video.mp4"));
  const Result probe = run_shell("ffprobe -v error -select_streams v:0 -show_entries stream=width,height,avg_frame_rate,nb_frames -of compact '" +
                                 (out / "compare.mp4").string() + "'");
  EXPECT_EQ(probe.exit_code, 0) << probe.output;
  EXPECT_NE(probe.output.find("width=640|height=292|avg_frame_rate=24/1"), std::string::npos) << probe.output;
  EXPECT_EQ(occurrences(r.output, "comparison: "), 1u) << r.output;
  EXPECT_EQ(occurrences(r.output, " frames 640x292 in "), 1u) << r.output;
  EXPECT_EQ(r.output.find('\r'), std::string::npos) << "a progress bar was drawn into a pipe";
}

// On a terminal (a pseudo-terminal from script(1)) the render draws its bar in place.
TEST_F(Cli, RunDrawsAProgressBarOnATerminal) {
  if (std::system("script --version > /dev/null 2>&1") != 0) GTEST_SKIP() << "script(1) is not installed";
  const fs::path out = dir_ / "run";
  const Result r = run_shell("script -qec \"" + blendbench::test::blendbench_binary() + " run " +
                             blendbench::test::source_path("tests/data/tiny.yaml") + " --variant arc --no-plots --out " +
                             out.string() + "\" /dev/null");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\r[#"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("video arc: frame "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("video arc: "), std::string::npos) << r.output;
}

// --no-plots: no report, and the program says so.
TEST_F(Cli, RunWithoutPlotsSaysThereIsNoReport) {
  const fs::path out = dir_ / "run";
  const Result r = run("run " + blendbench::test::source_path("tests/data/tiny.yaml") + " --no-video --no-plots --out " +
                       out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("no report (--no-plots)"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out / "report.html"));
}

// Plausibility warnings: `validate` prints each under its file (still ok, exit 0), `run` prints
// them on stderr and lists them in summary.json's `warnings`; the summary carries the version
// that `--version` prints.
TEST_F(Cli, WarningsArePrintedAndListedAndTheVersionIsInTheSummary) {
  const fs::path part = dir_ / "part.ngc";
  std::ofstream(part) << "G21 G90\nG1 X60 F6000\nG1 Y60\nM2\n";
  const std::string scenario = scenario_with("program:\n  start: [0, 0, 0]\n  moves:\n    - line: [60, 0, 0]\n    - line: [60, 60, 0]\n",
                                             "program:\n  start: [0, 0, 0]\n  gcode: " + part.string() + "\n");
  Result r = run("validate " + scenario);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("1 warning(s))\n  warning: " + part.string() + ":2:8: 'F': the program's F words set the feed (100 mm/s"),
            std::string::npos)
      << r.output;
  const Result version = run("--version");
  EXPECT_EQ(version.exit_code, 0) << version.output;
  ASSERT_EQ(version.output.rfind("blendbench 0.", 0), 0u) << version.output;
  const fs::path out = dir_ / "warned";
  r = run("run " + scenario + " --no-video --no-plots --variant exact --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("blendbench: warning: " + part.string() + ":2:8: 'F'"), std::string::npos) << r.output;
  std::ifstream in(out / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  ASSERT_EQ(summary.at("warnings").size(), 1u);
  EXPECT_EQ(summary["warnings"][0].at("field"), "F");
  EXPECT_EQ(summary["warnings"][0].at("line"), 2);
  EXPECT_EQ(summary["warnings"][0].at("file"), part.string());
  std::string printed = version.output.substr(std::string("blendbench ").size());
  printed.erase(printed.find_last_not_of('\n') + 1);
  EXPECT_EQ(summary.at("version"), printed);
}

// --smoothing and --smoothing-tolerance on path and plan: a circle written as 400 short lines is
// smoothed into one curve, the summary says so; bad values name the flag (exit 2), as on run.
TEST_F(Cli, SmoothingFlagsSmoothAStreamAndAreCheckedLikeEveryFlag) {
  const fs::path part = dir_ / "circle.ngc";
  {
    std::ofstream out(part);
    out << "G21 G90 G64 P0.05\nG1 X5 Y0 F6000\n";
    char line[64];
    for (int k = 1; k <= 400; ++k) {
      const double a = 2 * M_PI * k / 400;
      std::snprintf(line, sizeof line, "G1 X%.4f Y%.4f\n", 5 * std::cos(a), 5 * std::sin(a));
      out << line;
    }
    out << "M2\n";
  }
  const std::string io = " --csv " + (dir_ / "t.csv").string() + " --summary " + (dir_ / "s.json").string();
  Result r = run("plan " + part.string() + " --smoothing g2_fit --smoothing-tolerance 0.01" + io);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("smoothing g2_fit: streams 1, points 401 -> pieces "), std::string::npos) << r.output;
  std::ifstream summary_file(dir_ / "s.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_file);
  const nlohmann::json& smoothing = summary["smoothing"];
  EXPECT_EQ(smoothing["method"], "g2_fit");
  EXPECT_EQ(smoothing["tolerance_mm"].get<double>(), 0.01);
  EXPECT_EQ(smoothing["runs"], 1);
  EXPECT_EQ(smoothing["points"], 401);
  EXPECT_GT(smoothing["max_distance_mm"].get<double>(), 0);
  EXPECT_LE(smoothing["max_distance_mm"].get<double>(), 0.01);
  EXPECT_GE(smoothing["fit_wall_time_s"].get<double>(), 0);
  EXPECT_EQ(summary["corners"].size(), 1u);  // the lead-in's corner; none inside the stream
  r = run("path " + part.string() + " --smoothing clothoid_points --csv " + (dir_ / "p.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("smoothing clothoid_points: streams 1, points 401"), std::string::npos) << r.output;
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      {"--smoothing spline", "'--smoothing': unknown method 'spline' (none, clothoid_points, g2_fit)"},
      {"--smoothing g2_fit --smoothing-tolerance 0", "'--smoothing-tolerance': must be a positive number of mm"},
      {"--smoothing-tolerance 0.01", "'--smoothing-tolerance': sets g2_fit's tolerance, but the smoothing is none"},
      {"--smoothing clothoid_points --smoothing-tolerance 0.01", "(add --smoothing g2_fit)"},
  };
  fs::remove(dir_ / "s.json");
  for (const Case& c : cases) {
    r = run("plan " + part.string() + " " + c.args + io);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in:\n" << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "s.json")) << c.args;
  }
  r = run("run " + blendbench::test::source_path("tests/data/tiny.yaml") + " --no-video --no-plots --smoothing bad --out " +
          (dir_ / "run").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("'--smoothing': unknown method 'bad'"), std::string::npos) << r.output;
  r = run("run " + blendbench::test::source_path("tests/data/tiny.yaml") + " --no-video --no-plots --smoothing-tolerance 0.01 --out " +
          (dir_ / "run").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("no variant run smooths with g2_fit"), std::string::npos) << r.output;
}

}  // namespace
