// Issue 42: the hostile inputs and situations a campaign found, each run against the program as
// a user (or an attacker) meets it, in a scratch folder, with a deadline: every one ends in a
// positioned exit 2 or a correct run, in bounded time, with nothing written or read outside the
// folders named, nothing lost and no child left running.

#include <fcntl.h>
#include <signal.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/files.hpp"
#include "support/program.hpp"
#include "support/scratch.hpp"
#include "support/source_tree.hpp"

namespace blendbench {
namespace {

namespace fs = std::filesystem;
using test::read_file;

// How long any one command may take before the test calls it a hang (a run of the tiny scenario
// takes about 0.1 s, a small sweep about 2 s on this machine).
constexpr double kDeadline = 60;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class Hostile : public ::testing::Test {
 protected:
  struct Result {
    int exit_code = -1;  // -2: killed at the deadline
    std::string output;  // stdout and stderr
  };

  // Runs the program with an argument vector in the scratch folder, killed at `deadline` s.
  Result run(const std::vector<std::string>& args, double deadline = kDeadline) const {
    test::Child child(test::blendbench_binary(), args, dir_.path());
    Result r;
    r.exit_code = child.wait_within(deadline);
    r.output = child.output();
    return r;
  }

  // A file in the scratch folder; returns its path.
  std::string write(const std::string& name, const std::string& text) const { return dir_.write(name, text); }

  // The tiny scenario (tests/data/tiny.yaml) with `from` replaced by `to`, written as `name`.
  std::string tiny_with(const std::string& from, const std::string& to, const std::string& name = "scenario.yaml") const {
    std::string text = read_file(test::source_path("tests/data/tiny.yaml"));
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return write(name, text);
  }

  // A sweep over the tiny scenario: two velocities, both variants.
  std::string small_sweep(const std::string& name = "sweep.yaml") const {
    return write(name, "scenario: " + test::source_path("tests/data/tiny.yaml") +
                           "\naxes:\n  defaults.velocity: [150, 200]\n");
  }

  test::ScratchDir dir_{"hostile"};
};

// --- security -----------------------------------------------------------------------------------

TEST_F(Hostile, AUrdfNameCannotIncludeAFileIntoTheModel) {
  // the robot name closes the model and includes a file that changes gravity: the run uses the
  // URDF's model (the name is escaped), the file is never read
  const std::string evil = write("evil.xml", "<mujoco><option gravity=\"0 0 100\"/></mujoco>");
  std::string urdf = read_file(test::source_path("models/offset_wrist_kinematic.urdf"));
  const std::string name = "&quot;&gt;&lt;include file=&quot;" + evil + "&quot;/&gt;&lt;/mujoco&gt;&lt;mujoco model=&quot;";
  const std::size_t at = urdf.find("<robot name=\"") + 13;
  urdf.replace(at, urdf.find('"', at) - at, name);
  const std::string urdf_file = write("arm.urdf", urdf);
  std::string scenario = read_file(test::source_path("scenarios/urdf_only.yaml"));
  const std::string key = "urdf: models/offset_wrist_kinematic.urdf";
  scenario.replace(scenario.find(key), key.size(), "urdf: " + urdf_file);
  write("urdf_only.yaml", scenario);
  const Result r = run({"run", "urdf_only.yaml", "--no-video", "--no-plots", "--variant", "exact_stop", "--out", "out"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string model = read_file(dir_ / "out" / "robot_from_urdf.xml");
  EXPECT_FALSE(has(model, "<include")) << model.substr(0, 400);
  EXPECT_TRUE(has(model, "&lt;include file=&quot;")) << model.substr(0, 400);
  const nlohmann::json summary = nlohmann::json::parse(read_file(dir_ / "out" / "summary.json"));
  EXPECT_EQ(summary["variants"][0]["status"], "ok");
}

TEST_F(Hostile, LinksPlantedInASweepFolderSendNoWriteOutsideIt) {
  const std::string sweep = small_sweep();
  ASSERT_EQ(run({"sweep", sweep, "--out", "sw", "--no-plots", "--jobs", "1"}).exit_code, 0);
  const test::ScratchDir outside("hostile_outside");
  const std::string victim = outside.write("victim.txt", "keep");
  // a link at a point's log.txt: replaced by the point's log, the file it named untouched
  fs::path point;
  for (const auto& e : fs::directory_iterator(dir_ / "sw" / "points")) point = e.path();
  ASSERT_FALSE(point.empty());
  fs::remove(point / "log.txt");
  fs::create_symlink(victim, point / "log.txt");
  const Result again = run({"sweep", sweep, "--out", "sw", "--no-plots", "--jobs", "1"});
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(read_file(victim), "keep");
  EXPECT_EQ(fs::symlink_status(point / "log.txt").type(), fs::file_type::regular);
  // points/ itself a link to a folder outside: refused, nothing written there
  fs::rename(dir_ / "sw" / "points", dir_ / "points_moved");
  fs::create_directory(outside.path() / "points");
  fs::create_directory_symlink(outside.path() / "points", dir_ / "sw" / "points");
  const Result linked = run({"sweep", sweep, "--out", "sw", "--no-plots", "--jobs", "1"});
  EXPECT_EQ(linked.exit_code, 1) << linked.output;
  EXPECT_TRUE(has(linked.output, "points exists and is a symbolic link, not a folder")) << linked.output;
  EXPECT_TRUE(fs::is_empty(outside.path() / "points"));
}

TEST_F(Hostile, CollectReadsNothingOutsideTheSweepFolder) {
  const std::string sweep = small_sweep();
  ASSERT_EQ(run({"sweep", sweep, "--out", "sw", "--no-plots", "--jobs", "1"}).exit_code, 0);
  const test::ScratchDir outside("hostile_secret");
  // a plan whose point hash climbs out of points/
  const fs::path plan_file = dir_ / "sw" / "sweep.plan.json";
  const std::string plan_text = read_file(plan_file);
  nlohmann::json plan = nlohmann::json::parse(plan_text);
  plan["points"][1]["hash"] = "../../" + outside.path().filename().string() + "/x";
  std::ofstream(plan_file) << plan.dump(2);
  const Result climbing = run({"sweep", "--collect", "sw", "--no-plots"});
  EXPECT_EQ(climbing.exit_code, 2) << climbing.output;
  EXPECT_TRUE(has(climbing.output, "sweep.plan.json: 'points[1].hash': a point's hash must be 16 hexadecimal digits"))
      << climbing.output;
  // a point's summary that is a link to a file outside: not read through
  std::ofstream(plan_file) << plan_text;
  const std::string secret = outside.write("summary.json", read_file(dir_ / "sw" / "points" / plan["points"][0]["hash"].get<std::string>() / "summary.json"));
  const fs::path summary = dir_ / "sw" / "points" / plan["points"][0]["hash"].get<std::string>() / "summary.json";
  fs::remove(summary);
  fs::create_symlink(secret, summary);
  const Result linked = run({"sweep", "--collect", "sw", "--no-plots"});
  EXPECT_EQ(linked.exit_code, 2) << linked.output;
  EXPECT_TRUE(has(linked.output, "summary.json: the point's run summary is a symbolic link: it is not read through"))
      << linked.output;
}

// --- crashes, hangs, exit codes ------------------------------------------------------------------

TEST_F(Hostile, CheckReadsRegularJsonFilesOnlyAndNamesWhatIsWrong) {
  fs::create_directories(dir_ / "run");
  write("base.json", R"({"scenario": "tiny", "variants": {}})");
  struct Case {
    std::string summary;  // empty: a FIFO
    std::vector<std::string> args;
    std::string message;
  };
  const Case cases[] = {
      {"", {"check", "run", "--baseline", "base.json"}, "run/summary.json: the run summary is a FIFO (named pipe), not a regular file"},
      {R"({"scenario": "tiny", "variants": []})", {"check", "run", "--baseline", "fifo.json"},
       "fifo.json: the baseline is a FIFO (named pipe), not a regular file"},
      {R"({"scenario": "tiny", "variants": [1e400]})", {"check", "run", "--baseline", "base.json"},
       "run/summary.json: invalid JSON in the run summary: number overflow parsing '1e400'"},
      {"[]", {"check", "run"}, "run/summary.json: not a run summary"},
      {R"({"scenario": "tiny", "variants": []})", {"check", "run", "--baseline", "array.json"}, "array.json: 'variants': a baseline needs"},
  };
  write("array.json", "[1, 2]");
  ASSERT_EQ(::mkfifo((dir_ / "fifo.json").c_str(), 0600), 0);
  for (const Case& c : cases) {
    fs::remove(dir_ / "run" / "summary.json");
    if (c.summary.empty()) {
      ASSERT_EQ(::mkfifo((dir_ / "run" / "summary.json").c_str(), 0600), 0);
    } else {
      write("run/summary.json", c.summary);
    }
    const Result r = run(c.args, 20);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(has(r.output, c.message)) << "expected '" << c.message << "' in\n" << r.output;
  }
}

TEST_F(Hostile, ValidateOpensTheRobotFilesRunOpens) {
  // an MJCF that names a FIFO as its mesh, a URDF nested 10^5 elements deep: `validate` said ok
  // (it did not open them) and `run` refused or crashed
  ASSERT_EQ(::mkfifo((dir_ / "pipe.obj").c_str(), 0600), 0);
  std::string mjcf = read_file(test::source_path("models/ur5e_like_rigid.xml"));
  mjcf.replace(mjcf.find("<asset>"), 7, "<asset><mesh name='m' file='pipe.obj'/>");
  write("arm.xml", mjcf);
  const std::string robot = "robot: {urdf: " + test::source_path("models/ur5e_like.urdf") + ", mjcf: arm.xml, model: rigid}";
  tiny_with("units: mm", "units: mm\n" + robot, "fifo_mesh.yaml");
  std::string deep = "<robot name='x'>";
  for (int i = 0; i < 100000; ++i) deep += "<a>";
  write("deep.urdf", deep);
  tiny_with("units: mm", "units: mm\nrobot: {urdf: deep.urdf, mjcf: " + test::source_path("models/ur5e_like_rigid.xml") +
                             ", model: rigid}", "deep.yaml");
  for (const std::string& command : {std::string("validate"), std::string("run")}) {
    for (const auto& [file, message] : {std::pair<std::string, std::string>{"fifo_mesh.yaml", "the mesh file is a FIFO"},
                                        {"deep.yaml", "deep.urdf:1:"}}) {
      std::vector<std::string> args = {command, file};
      if (command == "run") args.insert(args.end(), {"--no-video", "--no-plots", "--out", "out"});
      const Result r = run(args, 20);
      EXPECT_EQ(r.exit_code, 2) << command << " " << file << "\n" << r.output;
      EXPECT_TRUE(has(r.output, message)) << command << " " << file << "\n" << r.output;
      if (command == "validate") {
        EXPECT_TRUE(has(r.output, "elements are nested more than 64 deep") || file != "deep.yaml") << r.output;
      }
    }
  }
}

TEST_F(Hostile, AModelBuiltFromAUrdfIsBlamedOnTheUrdfNeverOnAStagingFolder) {
  // a URDF whose link weighs 1e308 kg: the message named .out.staging-<pid>/robot_from_urdf.xml,
  // a file deleted before anyone could read it
  std::string urdf = read_file(test::source_path("models/kr6_like.urdf"));
  const std::size_t mass = urdf.find("<mass value=\"", urdf.find("<link name=\"link_2\"")) + 13;
  urdf.replace(mass, urdf.find('"', mass) - mass, "1e308");
  write("heavy.urdf", urdf);
  tiny_with("units: mm", "units: mm\nrobot: {urdf: heavy.urdf, model: rigid}", "heavy.yaml");
  const Result r = run({"run", "heavy.yaml", "--no-video", "--no-plots", "--out", "out"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(has(r.output, "heavy.urdf (the MuJoCo model built from it): 'body.mass'")) << r.output;
  EXPECT_FALSE(has(r.output, "staging")) << r.output;
}

TEST_F(Hostile, EmptyValuesAndLoopingLinksAreBadInputNamingTheOption) {
  const std::string tiny = test::source_path("tests/data/tiny.yaml");
  const std::vector<std::vector<std::string>> empty = {
      {"run", tiny, "--out", "", "--no-video", "--no-plots"},  // wrote to results/runs/tiny silently
      {"run", "", "--no-video", "--no-plots"},
      {"path", tiny, "--csv", ""},
      {"sweep", "--collect", ""},
  };
  for (const auto& args : empty) {
    const Result r = run(args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(has(r.output, "an empty value names nothing")) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir_ / "results"));
  // a loop of symbolic links where a file is named: "filesystem error: Too many levels of
  // symbolic links" (exit 1) before
  fs::create_symlink(dir_ / "loop_b", dir_ / "loop_a");
  fs::create_symlink(dir_ / "loop_a", dir_ / "loop_b");
  fs::create_directories(dir_ / "run");
  write("run/summary.json", R"({"scenario": "tiny", "variants": []})");
  const std::vector<std::vector<std::string>> loops = {
      {"check", "run", "--baseline", "loop_a"},
      {"run", "loop_a", "--no-video", "--no-plots"},
      {"run", tiny, "--out", "loop_a/x", "--no-video", "--no-plots"},
      {"path", tiny, "--csv", "loop_a/x.csv"},
  };
  for (const auto& args : loops) {
    const Result r = run(args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(has(r.output, "Too many levels of symbolic links")) << r.output;
    EXPECT_FALSE(has(r.output, "filesystem error")) << r.output;
  }
}

TEST_F(Hostile, NamesThatAreNotUtf8AreRefusedBeforeAnythingRuns) {
  // a file or folder named with a byte 0xff reached the JSON writer after every variant had run:
  // "[json.exception.type_error.316] invalid UTF-8 byte", exit 1
  const std::string tiny = read_file(test::source_path("tests/data/tiny.yaml"));
  write("t\xff.yaml", tiny);
  write("t.yaml", tiny);
  write("s\xff.yaml", "scenario: t.yaml\naxes:\n  defaults.velocity: [150]\n");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"run", "t\xff.yaml", "--no-video", "--no-plots", "--out", "out"}, "'scenario': 't\\xff.yaml' is not UTF-8 text"},
      {{"run", "t.yaml", "--no-video", "--no-plots", "--out", "r\xff"}, "'--out': 'r\\xff' is not UTF-8 text"},
      {{"sweep", "s\xff.yaml", "--out", "sw", "--no-plots"}, "'s\\xff.yaml' is not UTF-8 text"},
  };
  for (const auto& [args, message] : cases) {
    const Result r = run(args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(has(r.output, message)) << message << "\n" << r.output;
  }
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  EXPECT_FALSE(fs::exists(dir_ / "sw"));
  // a sweep in a folder so named: its points record the scenario's folder in JSON
  fs::create_directories(dir_ / "d\xff");
  write("d\xff/t.yaml", tiny);
  write("d\xff/s.yaml", "scenario: t.yaml\naxes:\n  defaults.velocity: [150]\n");
  test::Child sweep(test::blendbench_binary(), {"sweep", "s.yaml", "--out", "sw", "--no-plots"}, dir_ / "d\xff");
  EXPECT_EQ(sweep.wait_within(kDeadline), 2) << sweep.output();
  EXPECT_TRUE(has(sweep.output(), "s.yaml:1:11: 'scenario': the path '")) << sweep.output();
  EXPECT_TRUE(has(sweep.output(), "d\\xff/t.yaml' is not UTF-8 text")) << sweep.output();
}

TEST_F(Hostile, HostileModelFilesEndInExitTwoAtTheirElementQuickly) {
  // each refused before MuJoCo sees it (a crash, a hang, minutes of work, a library's message
  // or a wrong blame before)
  ASSERT_EQ(::mkfifo((dir_ / "pipe.xml").c_str(), 0600), 0);
  fs::create_directories(dir_ / "meshes.obj");
  write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 400000000\n");
  std::string geoms;
  for (int i = 0; i < 100000; ++i) geoms += "<geom size='0.01'/>";
  const std::string model = read_file(test::source_path("models/ur5e_like_rigid.xml"));
  struct Case {
    std::string from, to, message;
  };
  const Case cases[] = {
      {"<worldbody>", "<include file='pipe.xml'/><worldbody>", "the included file is a FIFO"},
      {"<asset>", "<asset><mesh name='m' file='bad.obj'/>", "a face uses vertex 400000000, but the file has 4"},
      {"<asset>", "<asset><mesh name='m' file='meshes.obj'/>", "the mesh file is a folder"},
      {"<worldbody>", "<worldbody>" + geoms, "the model holds more than 2000 elements"},
      {"timestep=\"0.000125\"", "timestep=\"nan\"", "'option.timestep': the timestep nan s is outside"},
      {"timestep=\"0.000125\"", "timestep=\"1e-290\"", "'option.timestep': the timestep 1e-290 s is outside"},
      // blamed on 'servo.kv' before
      {"mass=\"3.761\"", "mass=\"1e308\"", "'body.mass': body 'shoulder_link' has a mass of 1e+308 kg"},
  };
  for (const Case& c : cases) {
    std::string xml = model;
    xml.replace(xml.find(c.from), c.from.size(), c.to);
    write("arm.xml", xml);
    tiny_with("units: mm", "units: mm\nrobot: {urdf: " + test::source_path("models/ur5e_like.urdf") + ", mjcf: arm.xml, model: rigid}",
              "model.yaml");
    const Result r = run({"run", "model.yaml", "--no-video", "--no-plots", "--out", "out"}, 20);
    EXPECT_EQ(r.exit_code, 2) << c.message << "\n" << r.output.substr(0, 600);
    EXPECT_TRUE(has(r.output, "arm.xml")) << r.output.substr(0, 600);
    EXPECT_TRUE(has(r.output, c.message)) << c.message << "\n" << r.output.substr(0, 600);
  }
}

TEST_F(Hostile, HostileSweepFilesEndInExitTwo) {
  const std::string tiny = test::source_path("tests/data/tiny.yaml");
  std::string base = read_file(tiny);
  write("no_variants.yaml", base.substr(0, base.find("variants:")));
  std::string deep = "a";
  for (int i = 1; i < 20000; ++i) deep += ".a";
  const std::string head = "scenario: " + tiny + "\naxes:\n  defaults.velocity: [150]\n";
  struct Case {
    std::string text, message;
  };
  const Case cases[] = {
      {head + "---\nfoo: 1\n", "a second YAML document"},
      {head + "axes:\n  defaults.velocity: [170]\n", "duplicate key 'axes'"},
      {head + std::string("#\0\n", 3), "control characters are not allowed"},
      {"scenario: " + tiny + "\ndescription: \"\xff\"\naxes:\n  defaults.velocity: [150]\n", "invalid leading UTF-8 octet"},
      {"scenario: " + tiny + "\naxes:\n  ? " + deep + "\n  : [1]\n", "it has more than 64 steps"},
      {"scenario: no_variants.yaml\naxes:\n  defaults.velocity: [150]\n", "'variants': missing required field"},
  };
  for (const Case& c : cases) {
    write("hostile.yaml", c.text);
    const Result r = run({"sweep", "hostile.yaml", "--out", "sw", "--no-plots"}, 20);
    EXPECT_EQ(r.exit_code, 2) << c.message << "\n" << r.output.substr(0, 400);
    EXPECT_TRUE(has(r.output, c.message)) << c.message << "\n" << r.output.substr(0, 400);
  }
  // --collect with a plan that is a link to /dev/zero: refused, not read forever
  fs::create_directories(dir_ / "zero");
  fs::create_symlink("/dev/zero", dir_ / "zero" / "sweep.plan.json");
  const Result zero = run({"sweep", "--collect", "zero", "--no-plots"}, 20);
  EXPECT_EQ(zero.exit_code, 2) << zero.output;
  EXPECT_TRUE(has(zero.output, "sweep.plan.json: the sweep plan is a symbolic link")) << zero.output;
}

// --- wrong numbers -------------------------------------------------------------------------------

TEST_F(Hostile, TinyTransitionsAreRefusedNeverRowsOfNan) {
  const std::string tiny = test::source_path("tests/data/tiny.yaml");
  const std::vector<std::vector<std::string>> cases = {
      {"--method", "clothoid", "--param", "1e-201"},
      {"--method", "biclothoid", "--param", "1e-300"},
      {"--method", "biclothoid", "--start-distance", "1e-200"},
  };
  for (const auto& flags : cases) {
    std::vector<std::string> args = {"path", tiny, "--csv", "path.csv"};
    args.insert(args.end(), flags.begin(), flags.end());
    const Result r = run(args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(has(r.output, "'" + flags[2] + "': is 0 (no transition) or at least 1e-06 mm")) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "path.csv"));
  }
  // in a scenario, refused at the variant's move
  tiny_with("{name: arc, transition: {method: arc, parameter: 5}}", "{name: c, transition: {method: clothoid, parameter: 1e-201}}",
            "tiny_clothoid.yaml");
  const Result r = run({"path", "tiny_clothoid.yaml", "--variant", "c", "--csv", "path.csv"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(has(r.output, "'transition.parameter'")) << r.output;
}

// --- lost or half-written results ----------------------------------------------------------------

TEST_F(Hostile, ARunWithoutACleanVariantNeverReplacesThePreviousRun) {
  // a disk that fills (a file-size limit here) fails every variant: the previous run stays
  const std::string tiny = test::source_path("tests/data/tiny.yaml");
  ASSERT_EQ(run({"run", tiny, "--no-video", "--no-plots", "--out", "out"}).exit_code, 0);
  const std::string before = read_file(dir_ / "out" / "summary.json");
  test::Child full("/bin/sh", {"-c", "ulimit -f 40 && exec \"$0\" \"$@\"", test::blendbench_binary(), "run", tiny, "--no-video",
                               "--no-plots", "--out", "out"},
                   dir_.path());
  EXPECT_EQ(full.wait_within(kDeadline), 1) << full.output();
  EXPECT_TRUE(has(full.output(), "no variant ran clean: out still holds the previous run")) << full.output();
  EXPECT_EQ(read_file(dir_ / "out" / "summary.json"), before);
  EXPECT_TRUE(fs::is_directory(dir_ / "out" / "exact"));
  EXPECT_TRUE(fs::is_regular_file(dir_ / "out.failed" / "summary.json"));
}

TEST_F(Hostile, OutputFoldersCannotNestOrShareTheMachinerysNames) {
  const std::string tiny = test::source_path("tests/data/tiny.yaml");
  ASSERT_EQ(run({"run", tiny, "--no-video", "--no-plots", "--out", "out"}).exit_code, 0);
  // inside a finished run: the next run into `out` would delete it
  Result r = run({"run", tiny, "--no-video", "--no-plots", "--out", "out/inner"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(has(r.output, "is inside the run folder")) << r.output;
  // a name of the machinery
  r = run({"run", tiny, "--no-video", "--no-plots", "--out", ".foo.staging-7"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(has(r.output, "has the name of a run's lock or staging folder")) << r.output;
  // `foo` and `foo.staging-1` share a prefix: a run of foo leaves the other's staging folder alone
  const fs::path others = dir_ / (".foo.staging-1.staging-" + std::to_string(::getpid()));
  fs::create_directories(others / "exact");
  EXPECT_EQ(run({"run", tiny, "--no-video", "--no-plots", "--out", "foo"}).exit_code, 0);
  EXPECT_TRUE(fs::is_directory(others / "exact"));
  // inside the folder of a run that is running (its lock held)
  write("slow.yaml", read_file(tiny).replace(read_file(tiny).find("settle_time_s: 0.3"), 18, "settle_time_s: 60"));
  test::Child slow(test::blendbench_binary(), {"run", "slow.yaml", "--no-video", "--no-plots", "--out", "busy"}, dir_.path());
  ASSERT_TRUE(slow.wait_for_line("[1/2]")) << slow.output();
  r = run({"run", tiny, "--no-video", "--no-plots", "--out", "busy/inner"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(has(r.output, "the output folder of a run that is running")) << r.output;
  slow.signal(SIGTERM);
  EXPECT_EQ(slow.wait_within(kDeadline), 143) << slow.output();
}

TEST_F(Hostile, AFolderAboveTheOutputChangedDuringTheRunPublishesNothing) {
  // the folder above --out moved away and replaced while the run ran: nothing is published that
  // mixes the two, and the run's files are kept where they were written, the message says where
  const std::string tiny = read_file(test::source_path("tests/data/tiny.yaml"));
  write("slow.yaml", std::string(tiny).replace(tiny.find("settle_time_s: 0.3"), 18, "settle_time_s: 3"));
  fs::create_directories(dir_ / "parent");
  test::Child child(test::blendbench_binary(), {"run", "slow.yaml", "--no-video", "--no-plots", "--out", "parent/x"}, dir_.path());
  ASSERT_TRUE(child.wait_for_line("[1/2]")) << child.output();
  fs::rename(dir_ / "parent", dir_ / "moved");
  fs::create_directories(dir_ / "elsewhere");
  fs::create_directory_symlink(dir_ / "elsewhere", dir_ / "parent");
  EXPECT_EQ(child.wait_within(kDeadline), 1) << child.output();
  EXPECT_TRUE(has(child.output(), "not published as")) << child.output();
  EXPECT_TRUE(has(child.output(), "the run's files stay in")) << child.output();
  EXPECT_FALSE(fs::exists(dir_ / "elsewhere" / "x"));
  EXPECT_FALSE(fs::exists(dir_ / "moved" / "x"));
}

TEST_F(Hostile, TwoSweepsIntoOneFolderAtOnceAreRefused) {
  write("slow.yaml", "scenario: " + test::source_path("tests/data/tiny.yaml") +
                         "\naxes:\n  defaults.velocity: [100, 120]\n  simulation.settle_time_s: [20]\n");
  test::Child first(test::blendbench_binary(), {"sweep", "slow.yaml", "--out", "sw", "--no-plots", "--jobs", "1"}, dir_.path());
  ASSERT_TRUE(first.wait_for_line("sweep: slow.yaml")) << first.output();
  const Result second = run({"sweep", small_sweep(), "--out", "sw", "--no-plots"});
  EXPECT_EQ(second.exit_code, 2) << second.output;
  EXPECT_TRUE(has(second.output, "is in use by another sweep (pid " + std::to_string(first.pid()) + ")")) << second.output;
  first.signal(SIGTERM);
  EXPECT_EQ(first.wait_within(kDeadline), 143) << first.output();
}

TEST_F(Hostile, TemporariesOfAKilledCommandAreRemovedByTheNextOne) {
  // a `plan` killed by SIGKILL leaves plan.csv.tmp.<pid>; the next plan into the same place
  // removes it (the pid no longer runs)
  const std::string tiny = test::source_path("tests/data/tiny.yaml");
  test::Child killed(test::blendbench_binary(), {"validate", tiny}, dir_.path());
  const pid_t dead = killed.pid();
  (void)killed.wait();
  write("plan.csv.tmp." + std::to_string(dead), "half");
  write("plan.json.tmp." + std::to_string(dead), "half");
  ASSERT_EQ(run({"plan", tiny, "--csv", "plan.csv", "--summary", "plan.json"}).exit_code, 0);
  for (const auto& e : fs::directory_iterator(dir_.path())) EXPECT_FALSE(has(e.path().filename().string(), ".tmp.")) << e.path();
  // and a command writing the same files at once is refused while the first holds them
  write(".plan.csv.lock", "");
  const int fd = ::open((dir_ / ".plan.csv.lock").c_str(), O_RDWR);
  ASSERT_EQ(::flock(fd, LOCK_EX), 0);
  const Result busy = run({"plan", tiny, "--csv", "plan.csv", "--summary", "plan.json"});
  ::close(fd);
  EXPECT_EQ(busy.exit_code, 2) << busy.output;
  EXPECT_TRUE(has(busy.output, "'--csv': ")) << busy.output;
  EXPECT_TRUE(has(busy.output, "is being written by another command")) << busy.output;
}

TEST_F(Hostile, AReproductionReplacesItsFolderAsAWhole) {
  // killed between two files, `reproduce` left a new results.json beside an old README.md: now a
  // paper's folder is staged and published whole, so an old file never sits beside new ones
  fs::create_directories(dir_ / "papers" / "004");
  write("papers/004/results.json", "old");
  write("papers/004/stale_from_an_old_run.csv", "old");
  const Result r = run({"reproduce", "004", "--out", "papers", "--no-plots"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(read_file(dir_ / "papers" / "004" / "results.json"), "old");
  EXPECT_TRUE(fs::is_regular_file(dir_ / "papers" / "004" / "README.md"));
  EXPECT_FALSE(fs::exists(dir_ / "papers" / "004" / "stale_from_an_old_run.csv"));
  for (const auto& e : fs::directory_iterator(dir_ / "papers")) EXPECT_EQ(e.path().filename(), "004") << e.path();
}

// --- signals and limits -------------------------------------------------------------------------

TEST_F(Hostile, AStopRequestEndsTheProgramHoweverItIsBlocked) {
  // the program blocks in a write to a pipe nobody reads (as an open blocked on a FIFO did, 1,019
  // s after `timeout`'s SIGTERM): the handler's flag is never checked and the call restarts, so
  // the watchdog ends it, kStopGrace (5 s) after the signal, with 128 + SIGTERM
  const std::string tiny = test::source_path("tests/data/tiny.yaml");
  std::vector<std::string> args = {"validate"};
  for (int i = 0; i < 4000; ++i) args.push_back(tiny);  // ~300 kB of output, the pipe holds 64 kB
  test::Child child(test::blendbench_binary(), args, dir_.path());
  // blocked once the pipe is full (its state shows in /proc): about 660 validations of ~100 bytes,
  // some 12 s in the Release build and 40 s in the sanitizer build
  const fs::path wchan = "/proc/" + std::to_string(child.pid()) + "/wchan";
  const auto start = std::chrono::steady_clock::now();
  while (read_file(wchan) != "pipe_write" && read_file(wchan) != "anon_pipe_write" &&
         std::chrono::steady_clock::now() - start < std::chrono::seconds(150)) {
    ::usleep(50000);
  }
  ASSERT_TRUE(has(read_file(wchan), "pipe_write")) << read_file(wchan);
  child.signal(SIGTERM);
  const auto signalled = std::chrono::steady_clock::now();
  const int code = child.wait_exit_within(20);
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
  EXPECT_EQ(code, 143) << child.output().substr(child.output().size() > 400 ? child.output().size() - 400 : 0);
  EXPECT_GT(took, 4.0);
  EXPECT_LT(took, 10.0);
}

TEST_F(Hostile, SweepPointsDieWithTheSweepEvenWhenItIsKilled) {
  // points of 3 s each, two at a time; the sweep is killed (SIGKILL) while they run
  write("slow.yaml", "scenario: " + test::source_path("tests/data/tiny.yaml") +
                         "\naxes:\n  defaults.velocity: [100, 120, 140, 160]\n  simulation.settle_time_s: [3]\n");
  test::Child sweep(test::blendbench_binary(), {"sweep", "slow.yaml", "--out", "sw", "--no-plots", "--jobs", "2"}, dir_.path());
  ASSERT_TRUE(sweep.wait_for_line("sweep: slow.yaml")) << sweep.output();
  // the points' processes, found by their command line
  const auto points = [&] {
    int n = 0;
    for (const auto& e : fs::directory_iterator("/proc")) {
      const std::string cmdline = read_file(e.path() / "cmdline");
      n += has(cmdline, "--run-point") && has(cmdline, (dir_ / "sw").string()) ? 1 : 0;
    }
    return n;
  };
  const auto start = std::chrono::steady_clock::now();
  while (points() < 2 && std::chrono::steady_clock::now() - start < std::chrono::seconds(20)) ::usleep(50000);
  ASSERT_EQ(points(), 2);
  sweep.signal(SIGKILL);
  EXPECT_EQ(sweep.wait_within(20), -1);
  const auto killed = std::chrono::steady_clock::now();
  while (points() > 0 && std::chrono::steady_clock::now() - killed < std::chrono::seconds(10)) ::usleep(50000);
  EXPECT_EQ(points(), 0) << "a point outlived its sweep";
  // no status for a point that did not finish: --resume runs it again
  for (const auto& e : fs::directory_iterator(dir_ / "sw" / "points")) EXPECT_FALSE(fs::exists(e.path() / "status.json"));
}

TEST_F(Hostile, AFileSizeLimitIsAWriteErrorNotAKill) {
  // ulimit -f: SIGXFSZ used to kill the program (its temporary file left behind)
  const std::string tiny = test::source_path("tests/data/tiny.yaml");
  test::Child child("/bin/sh", {"-c", "ulimit -f 16 && exec \"$0\" \"$@\"", test::blendbench_binary(), "plan", tiny, "--csv",
                                "plan.csv", "--summary", "plan.json"},
                    dir_.path());
  EXPECT_EQ(child.wait_within(kDeadline), 1) << child.output();
  EXPECT_TRUE(has(child.output(), "plan.csv: File too large")) << child.output();
  for (const auto& e : fs::directory_iterator(dir_.path())) EXPECT_FALSE(has(e.path().filename().string(), ".tmp.")) << e.path();
  EXPECT_FALSE(fs::exists(dir_ / "plan.csv"));
}

TEST_F(Hostile, OutputLostOnAFullDeviceIsNotSuccess) {
  const std::string tiny = test::source_path("tests/data/tiny.yaml");
  test::Child child("/bin/sh", {"-c", "exec \"$0\" validate \"$1\" > /dev/full", test::blendbench_binary(), tiny}, dir_.path());
  EXPECT_EQ(child.wait_within(kDeadline), 1) << child.output();
  EXPECT_TRUE(has(child.output(), "cannot write to standard output")) << child.output();
}

}  // namespace
}  // namespace blendbench
