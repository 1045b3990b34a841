// Speed of the execution stage: physics steps per second of the servo loop on the test arm
// (PLATFORM.md measured ~140k-220k bare PD steps/s on this kind of machine).

#include <benchmark/benchmark.h>

#include <cmath>

#include "support/test_arm.hpp"
#include "blendbench/sim/simulator.hpp"

namespace blendbench {
namespace {

// One second of a smooth joint reference at 1 kHz, starting at rest.
JointReference one_second(const JointVector& q0) {
  JointReference reference;
  reference.dt = 0.001;
  for (int k = 0; k <= 1000; ++k) {
    const double t = k * reference.dt;
    const double w = 2 * M_PI;
    reference.q.push_back(q0 + JointVector::Constant(0.2 * (1 - std::cos(w * t))));
    reference.qd.push_back(JointVector::Constant(0.2 * w * std::sin(w * t)));
    reference.qdd.push_back(JointVector::Constant(0.2 * w * w * std::cos(w * t)));
  }
  return reference;
}

void run_servo(benchmark::State& state, bool feedforward, double rate_hz) {
  const Simulator sim = Simulator::from_xml_string(test::kTestArmXml);
  const JointVector q0 = test::test_arm_bent_pose();
  ServoConfig servo = default_servo(sim, q0, rate_hz);
  servo.feedforward = feedforward;
  JointReference reference = one_second(q0);
  if (rate_hz < 1000) {
    // keep every (1000 / rate)-th sample so dt matches the servo period
    const auto keep = static_cast<std::size_t>(std::lround(1000 / rate_hz));
    JointReference thinned;
    thinned.dt = reference.dt * static_cast<double>(keep);
    for (std::size_t k = 0; k < reference.q.size(); k += keep) {
      thinned.q.push_back(reference.q[k]);
      thinned.qd.push_back(reference.qd[k]);
      thinned.qdd.push_back(reference.qdd[k]);
    }
    reference = thinned;
  }
  RunOptions options;
  options.settle_time = 0;
  std::int64_t steps = 0;
  for (auto _ : state) {
    const Trace trace = sim.run(reference, servo, options);
    if (trace.diverged) state.SkipWithError(trace.warning.c_str());
    benchmark::DoNotOptimize(trace.samples.data());
    steps += 1000;
  }
  state.SetItemsProcessed(steps);  // physics steps (1 ms each)
}

void BM_ServoLoop1kHz(benchmark::State& state) { run_servo(state, false, 1000); }
void BM_ServoLoop1kHzFeedforward(benchmark::State& state) { run_servo(state, true, 1000); }
void BM_ServoLoop250Hz(benchmark::State& state) { run_servo(state, false, 250); }

// The floor under the loop: mj_step with a PD torque written straight into ctrl, no trace.
void BM_BareMjStepPd(benchmark::State& state) {
  const Simulator sim = Simulator::from_xml_string(test::kTestArmXml);
  const mjModel& m = sim.model();
  mjData* d = mj_makeData(&m);
  const JointVector q0 = test::test_arm_bent_pose();
  for (int i = 0; i < 6; ++i) d->qpos[i] = q0[i];
  const ServoConfig servo = default_servo(sim, q0);
  for (auto _ : state) {
    for (int i = 0; i < 6; ++i)
      d->ctrl[i] = servo.kp[i] * (q0[i] + 0.1 - d->qpos[i]) - servo.kd[i] * d->qvel[i] + d->qfrc_bias[i];
    mj_step(&m, d);
  }
  state.SetItemsProcessed(state.iterations());
  mj_deleteData(d);
}

BENCHMARK(BM_ServoLoop1kHz)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ServoLoop1kHzFeedforward)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ServoLoop250Hz)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BareMjStepPd);

}  // namespace
}  // namespace blendbench

BENCHMARK_MAIN();
