#pragma once
// Seed 002's experiment (Makino, clothoidal interpolation, CIRP 1988, section 7) on the elastic
// arm: a 90 degree corner interpolated over 25 x 25 mm between a 40 mm leading and a 30 mm
// following line, run at a constant line speed of 400 mm/s with three curves (its fig. 15):
// A a large circle of radius 25 mm, C a small circle of the clothoid pair's minimum radius, and
// B the clothoid pair. Its figs. 17 and 18 show the pen's path near the corner and the positional
// error pulses of the axes; it concludes that the clothoid "cause[s] less vibration than circular
// arcs", and that the servo decides how visible that is.
//
// The paper's robot was a SCARA; ours is the UR5e-like arm of models/ur5e_like.xml. Units: SI
// (m, s, rad) inside, the report in mm, mrad, um and Hz.

#include <filesystem>
#include <string>
#include <vector>

#include "blendbench/program/path.hpp"
#include "blendbench/program/program.hpp"
#include "blendbench/sim/execution.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench {

// The corner in the arm's workspace and the run around it. The path is one line ending at the
// corner (a run-up of `run_up`, then the paper's leading line) and one leaving it (the paper's
// following line, then `run_out`), so the speed is constant over the paper's part of it: the
// timing law (constant_speed.hpp) ramps up over the first `ramp` and down over the last.
struct Corner002 {
  Vec3 corner = Vec3(0.55, 0.25, 0.10);  // m, base frame; the tool points down
  double heading = 0;                    // rad: direction of the leading line in the base xy plane
  double leading = 0.040, following = 0.030;  // m (the paper's)
  double corner_size = 0.025;            // m: the curves start and end this far from the corner
  double speed = 0.400;                  // m/s (the paper's line speed)
  double run_up = 0.200, run_out = 0.200, ramp = 0.100;  // m
};

// The three curves of the paper's fig. 15.
enum class Curve002 { kLargeCircle, kSmallCircle, kClothoid };

// One curve run: the program, its path and timing, and what the arm did.
struct CurveRun002 {
  Curve002 curve = Curve002::kLargeCircle;
  std::string name;   // "large_circle", "small_circle", "clothoid"
  std::string label;  // for the report
  Program program;
  Path path;
  Timing timing;
  Execution execution;
  // around the corner (from 50 ms before the curve to the end of the vibration window): the
  // drive's following error, peak and RMS (rad) over the joints, and the joint of the peak
  double following_peak = 0, following_rms = 0;
  int following_joint = 0;
};

// The servo settings compared: the tuned default, a slow one (a quarter of the tuned bandwidths)
// and a fast one (8 kHz drive, no measurement delay, an exact encoder).
enum class Servo002 { kDefault, kSlow, kFast };

// Runs one curve at one placement with one servo setting. Throws std::runtime_error when the
// path cannot be planned or reached (the reproduction expects neither).
CurveRun002 run_curve_002(Curve002 curve, const Corner002& corner, Servo002 servo = Servo002::kDefault);

struct Paper002 {
  Corner002 corner;
  std::vector<CurveRun002> runs;  // the three curves, default servo, main placement
  // per servo setting, per curve: following error peak (rad) and residual vibration p2p (m)
  std::vector<std::vector<std::pair<double, double>>> servos;  // [Servo002][Curve002]
  // other placements: (description, per curve residual vibration p2p (m), any limit exceeded)
  struct Placement {
    std::string description;
    std::vector<double> vibration;
    bool clean = true;
  };
  std::vector<Placement> placements;
};

Paper002 reproduce_002();

// README.md of results/papers/002/.
std::string markdown_002(const Paper002& result);

// Writes results.json, README.md and per curve trace_<curve>.csv into `dir`.
void write_002(const Paper002& result, const std::filesystem::path& dir);

}  // namespace blendbench
