#include "blendbench/io/plausibility.hpp"

#include <cmath>
#include <mutex>
#include <variant>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"
#include "blendbench/core/units.hpp"
#include "blendbench/io/urdf_chain.hpp"
#include "blendbench/robot/ik.hpp"

namespace blendbench {
namespace {

std::string mm_s(double velocity) { return format_value(velocity / kMm, 4) + " mm/s"; }

}  // namespace

std::optional<LoadWarning> unit_warning(const Program& program, bool units_metres, const SourceRef& units_where) {
  if (!units_metres) return std::nullopt;
  double total = 0;
  for (const Move& move : program.moves) total += std::visit([](const auto& g) { return length(g); }, move.geometry);
  if (!(total > kLongPathMetres)) return std::nullopt;
  return LoadWarning{units_where, "units",
                     "the program is " + format_value(total, 4) + " m long with 'units: m' (over " +
                         format_value(kLongPathMetres) + " m); if its numbers are millimetres, say 'units: mm'"};
}

std::optional<LoadWarning> gcode_feed_warning(const GcodeResult& parsed, double defaults_velocity) {
  if (parsed.first_feed_where.line == 0) return std::nullopt;
  if (std::abs(parsed.first_feed - defaults_velocity) <= 1e-9 * defaults_velocity) return std::nullopt;
  return LoadWarning{parsed.first_feed_where, "F",
                     "the program's F words set the feed (" + mm_s(parsed.first_feed) + " from here on) and override defaults.velocity (" +
                         mm_s(defaults_velocity) + ", which applies only to moves before the first F word)"};
}

double tcp_speed_bound(const KinematicChain& chain, const JointVector& q) {
  const Mat6 j = jacobian(chain, q);
  double bound = 0;
  for (std::size_t i = 0; i < chain.joints.size(); ++i) {
    bound += chain.joints[i].velocity_limit * j.block<3, 1>(0, static_cast<Eigen::Index>(i)).norm();
  }
  return bound;
}

std::optional<LoadWarning> feed_speed_warning(const Scenario& scenario) {
  KinematicChain chain;
  try {
    // urdfdom's log handler is global (urdf_chain.hpp): one load at a time
    static std::mutex urdf_mutex;
    const std::lock_guard<std::mutex> lock(urdf_mutex);
    chain = load_urdf_chain(scenario.robot.urdf, scenario.robot.base_link, scenario.robot.tip_link);
  } catch (const InputError&) {
    return std::nullopt;  // a URDF this chain loader refuses (e.g. one with estimated limits): the runner's model decides
  }
  chain.tcp = chain.tcp * scenario.robot.tool;
  Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
  start.linear() = scenario.robot.tool_rotation;
  start.translation() = scenario.start;
  IkSolver::Result solved;
  try {
    solved = IkSolver(chain).solve(start, scenario.robot.q_seed);
  } catch (const InputError&) {
    return std::nullopt;
  }
  if (!solved.outcome.ok()) return std::nullopt;
  const double bound = tcp_speed_bound(chain, solved.q);
  const Move* first = nullptr;
  std::size_t count = 0;
  for (const Move& move : scenario.program.moves) {
    if (!(move.limits.velocity > bound)) continue;
    if (!first) first = &move;
    ++count;
  }
  if (!first) return std::nullopt;
  return LoadWarning{first->where, "velocity",
                     mm_s(first->limits.velocity) + " is beyond the arm: its joint speed limits allow at most " + mm_s(bound) +
                         " at the start pose (" + std::to_string(count) + " of " + std::to_string(scenario.program.moves.size()) +
                         " moves ask for more); if it is meant in mm/min, divide by 60"};
}

std::string to_string(const LoadWarning& warning) {
  return InputError(warning.where.file, warning.where.line, warning.where.column, warning.field, warning.message).what();
}

}  // namespace blendbench
