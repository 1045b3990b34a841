#include "blendbench/sim/execution.hpp"

#include <chrono>

namespace blendbench {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Arc-length tolerance for "the reference is at this point of the path" (m).
constexpr double kOnPath = 1e-9;

}  // namespace

std::vector<CornerTiming> corner_timings(const std::vector<CornerPlacement>& placements, const Timing& timing) {
  std::vector<CornerTiming> out;
  for (const CornerPlacement& p : placements) {
    CornerTiming c;
    c.index = p.index;
    c.t_start = c.t_end = timing.cycle_time;
    for (const TimedSample& s : timing.samples) {
      if (s.s >= p.s_start - kOnPath) {
        c.t_start = s.t;
        break;
      }
    }
    for (const TimedSample& s : timing.samples) {
      if (s.s <= p.s_end + kOnPath) c.t_end = s.t;
    }
    out.push_back(c);
  }
  return out;
}

Execution execute(const Simulator& sim, const IkSolver& ik, const Program& program, const Path& path,
                  const Timing& timing, const ExecutionOptions& options) {
  Execution out;
  // the reference: the tool pose of every sample, mapped to the joints
  auto start = Clock::now();
  std::vector<Eigen::Isometry3d> poses;
  poses.reserve(timing.samples.size());
  for (const TimedSample& s : timing.samples) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    // the path's orientation where the program sets one, else the fixed tool orientation
    pose.linear() = path.oriented() ? path.orientation(s.s).toRotationMatrix() : options.tool_rotation;
    pose.translation() = path.point(s.s);
    poses.push_back(pose);
  }
  out.joints = map_to_joints(ik, poses, timing.dt, options.q0, options.mapping);
  out.ik_seconds = seconds_since(start);
  if (!out.joints.outcome.ok()) return out;
  out.singularities = scan_singularities(ik, out.joints.joints.q, timing.dt);
  Execution ran = execute_mapped(sim, program, path, timing, out.joints.joints, options);
  ran.joints = std::move(out.joints);
  ran.singularities = std::move(out.singularities);
  ran.ik_seconds = out.ik_seconds;
  return ran;
}

Execution execute_mapped(const Simulator& sim, const Program& program, const Path& path, const Timing& timing,
                         const JointTrajectory& joints, const ExecutionOptions& options) {
  Execution out;
  // the run
  const auto start = Clock::now();
  out.trace = sim.run(joints, options.servo, options.run);
  out.simulation_seconds = seconds_since(start);
  out.corners = corner_timings(corner_placements(path, program), timing);
  if (out.trace.diverged) return out;

  // metrics and health
  MetricsOptions metrics = options.metrics;
  const Primitive& last = program.moves.back().geometry;
  metrics.end_point = point(last, length(last));
  metrics.corners = out.corners;
  // the reference's place on the path at each sample (the trace runs on past the reference's end)
  metrics.reference_s.reserve(out.trace.samples.size());
  for (std::size_t k = 0; k < out.trace.samples.size(); ++k) {
    metrics.reference_s.push_back(timing.samples.empty() ? 0.0 : timing.samples[std::min(k, timing.samples.size() - 1)].s);
  }
  out.metrics = compute_metrics(out.trace, program, path, metrics);
  out.health = check_health(out.trace, joints, sim.limits());
  return out;
}

}  // namespace blendbench
