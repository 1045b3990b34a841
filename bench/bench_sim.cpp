// Speed of the execution stage on the elastic UR5e-like model (models/ur5e_like.xml, 8 kHz
// physics): physics steps per second of the whole servo loop (Simulator::run: the cascade,
// inverse-dynamics feed-forward, encoder delay and quantisation, trace recording) against a
// bare mj_step loop on the same model in the same run. The target is a ratio of at least 0.8 at
// the default rates (the "items_per_second" of BM_ServoLoopDefault over BM_BareMjStep).

#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>

#include "blendbench/sim/simulator.hpp"
#include "support/source_tree.hpp"

namespace blendbench {
namespace {

JointVector ready() {
  JointVector q;
  q << std::numbers::pi, -std::numbers::pi / 2, std::numbers::pi / 2, -std::numbers::pi / 2, -std::numbers::pi / 2, 0;
  return q;
}

const Simulator& arm() {
  static const Simulator sim(blendbench::test::source_path("models/ur5e_like.xml"));
  return sim;
}

// One second of a smooth joint reference at the servo rate, starting at rest.
JointTrajectory one_second(const JointVector& q0, double rate_hz) {
  JointTrajectory reference;
  reference.dt = 1 / rate_hz;
  const auto n = static_cast<int>(std::lround(rate_hz));
  for (int k = 0; k <= n; ++k) {
    const double t = k * reference.dt;
    const double w = 2 * std::numbers::pi;
    reference.q.push_back(q0 + JointVector::Constant(0.1 * (1 - std::cos(w * t))));
    reference.qd.push_back(JointVector::Constant(0.1 * w * std::sin(w * t)));
    reference.qdd.push_back(JointVector::Constant(0.1 * w * w * std::cos(w * t)));
  }
  return reference;
}

// The servo loop at a drive rate (Hz) under the default 500 Hz setpoints.
void run_servo(benchmark::State& state, double rate_hz, bool feedforward) {
  const Simulator& sim = arm();
  ServoTuning tuning;
  tuning.rate_hz = rate_hz;
  ServoConfig servo = tune_servo(sim, ready(), tuning);
  if (!feedforward) servo = with_controller(servo, Controller::kPd);
  const JointTrajectory reference = one_second(ready(), servo.setpoint_rate_hz);
  RunOptions options;
  options.settle_time = 0;
  const auto steps = static_cast<std::int64_t>(std::lround(1 / sim.timestep()));
  for (auto _ : state) {
    const Trace trace = sim.run(reference, servo, options);
    if (trace.diverged) state.SkipWithError(trace.warning.c_str());
    benchmark::DoNotOptimize(trace.samples.data());
  }
  state.SetItemsProcessed(state.iterations() * steps);  // physics steps
}

// the default: 2 kHz drive; the plain PD at the same rates; the fastest drive, 8 kHz
void BM_ServoLoopDefault(benchmark::State& state) { run_servo(state, 2000, true); }
void BM_ServoLoopDefaultPd(benchmark::State& state) { run_servo(state, 2000, false); }
void BM_ServoLoop8kHz(benchmark::State& state) { run_servo(state, 8000, true); }

// The floor under the loop: mj_step on the same model with a PD torque on the motor hinges
// written straight into ctrl, no trace.
void BM_BareMjStep(benchmark::State& state) {
  const Simulator& sim = arm();
  const mjModel& m = sim.model();
  mjData* d = mj_makeData(&m);
  const JointVector q0 = ready();
  for (int i = 0; i < 6; ++i) d->qpos[2 * i] = q0[i];  // motor hinge 2i, gear hinge 2i + 1
  const ServoConfig servo = tune_servo(sim, q0);
  for (auto _ : state) {
    for (int i = 0; i < 6; ++i) {
      d->ctrl[i] = servo.kv[i] * (servo.kp[i] * (q0[i] + 0.01 - d->qpos[2 * i]) - d->qvel[2 * i]);
    }
    mj_step(&m, d);
  }
  state.SetItemsProcessed(state.iterations());
  mj_deleteData(d);
}

BENCHMARK(BM_BareMjStep);
BENCHMARK(BM_ServoLoopDefault)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ServoLoopDefaultPd)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ServoLoop8kHz)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace blendbench

BENCHMARK_MAIN();
