// Crowds (crowd.hpp): time per character of inverse dynamics and of the full simulation step (PD servo,
// mass-matrix forward dynamics, semi-implicit Euler), one character at a time against W
// at a time in SIMD lanes — the native lanes of this build's instruction set and a wider fixed-size
// batch — in double and float. Every figure is per character (items processed = characters). Built with
// the flags of the rest (the native lanes are SSE2's); the per-instruction-set kernels are timed by
// `humandyn bench`'s crowd rows (the implicit step there too). Backward Euler, not batched, is timed over
// the crowd character by character, from fresh starts and continuing each character's steps.
#include "humandyn/builders.hpp"
#include "humandyn/crowd.hpp"
#include "humandyn/humandyn.hpp"
#include "support/crowd_states.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <span>
#include <vector>

namespace {

using namespace humandyn;
using humandyn::bench::CrowdStates;

constexpr int nj = SeedShape::nj;
constexpr std::size_t characters = 1024;

enum class Work { ID, Euler };

// The benchmarks' crowd (support/crowd_states.hpp), `characters` strong.
template <class T>
struct Crowd : CrowdStates<T, nj> {
  Crowd() : CrowdStates<T, nj>(characters) {}
};

template <class T, Work work>
void BM_ScalarLoop(benchmark::State& st) {
  const auto model = default_model<T>();
  Crowd<T> crowd;
  Data<HumanModel<T>> data(model);
  StepWorkspace<HumanModel<T>> ws(model);
  std::vector<State<HumanModel<T>>> states(characters, State<HumanModel<T>>(model));
  std::vector<PdServo<HumanModel<T>>> servos(characters, PdServo<HumanModel<T>>(model));
  using V = Eigen::Map<const typename HumanModel<T>::JointVector>;
  for (std::size_t c = 0; c < characters; ++c) character_servo(crowd.servo, c, servos[c]);
  const typename HumanModel<T>::JointVector tau = V(crowd.tau.data());
  for ([[maybe_unused]] auto _ : st)
    for (std::size_t c = 0; c < characters; ++c) {
      const std::size_t k = c * nj;
      if constexpr (work == Work::ID) {
        benchmark::DoNotOptimize(
            rnea(model, data, V(crowd.q.data() + k), V(crowd.qd.data() + k), V(crowd.qdd.data() + k)));
      } else {
        states[c].q = V(crowd.q0.data() + k);
        states[c].qd = V(crowd.qd0.data() + k);
        benchmark::DoNotOptimize(step<Integrator::SemiImplicitEuler>(model, ws, states[c], tau, &servos[c], T(1e-3)));
      }
    }
  st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(characters));
}

template <class B, Work work>
void BM_Lanes(benchmark::State& st) {
  using T = typename detail::lanes<B>::value_type;
  const auto model = default_model<T>();
  const BatchModel<B> batch(model);
  CrowdWorkspace<B> ws(batch);
  Crowd<T> crowd;
  for ([[maybe_unused]] auto _ : st) {
    if constexpr (work == Work::ID) {
      inverse_dynamics_crowd(batch, ws, crowd.q.data(), crowd.qd.data(), crowd.qdd.data(), crowd.out.data(), 0,
                             characters);
    } else {
      st.PauseTiming();
      crowd.q = crowd.q0, crowd.qd = crowd.qd0;
      st.ResumeTiming();
      step_crowd<Integrator::SemiImplicitEuler>(batch, ws, crowd.view(), 0, characters, T(1e-3));
    }
    benchmark::DoNotOptimize(crowd.out.data());
  }
  st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(characters));
}

// Backward Euler over the crowd (step_crowd_backward_euler, the scalar step character by character), a
// simulation continuing from iteration to iteration: every servo tracks its start pose swung by 0.3 rad at
// 1 Hz. Each character starts afresh every step, or continues its last step from its memory.
template <bool with_memory>
void BM_BackwardEuler(benchmark::State& st) {
  using M = HumanModel<double>;
  const auto model = default_model<double>();
  Crowd<double> crowd;
  StepWorkspace<M> ws(model);
  State<M> x(model);
  PdServo<M> servo(model);
  std::vector<BackwardEulerMemory<M>> memory;
  if (with_memory) memory.assign(characters, BackwardEulerMemory<M>(model));
  const double h = 1e-3, omega = 2 * M_PI;
  long steps = 0;
  for ([[maybe_unused]] auto _ : st) {
    st.PauseTiming();
    const double t = double(steps++) * h;
    for (std::size_t k = 0; k < crowd.q_ref.size(); ++k) {
      crowd.q_ref[k] = crowd.q0[k] + 0.3 * std::sin(omega * t);
      crowd.qd_ref[k] = 0.3 * omega * std::cos(omega * t);
    }
    st.ResumeTiming();
    step_crowd_backward_euler(model, ws, x, servo, crowd.view(), std::span(memory), 0, characters, h);
    benchmark::DoNotOptimize(crowd.q.data());
  }
  st.counters["refused"] = double(crowd.refused());
  st.SetItemsProcessed(std::int64_t(st.iterations()) * std::int64_t(characters));
}

BENCHMARK(BM_BackwardEuler<false>)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BackwardEuler<true>)->Unit(benchmark::kMicrosecond);

// The scalar loop, the native lanes and 64 bytes of lanes whatever the instruction set. Clang refuses an
// Eigen matrix of a batch aligned beyond Eigen's static alignment (detail/batch.hpp), so there the 64-byte
// rows are left out unless the instruction set makes them native (AVX-512).
#if defined(__clang__) && EIGEN_MAX_STATIC_ALIGN_BYTES < 64
#define CROWD_ROWS(T, W)                                               \
  BENCHMARK(BM_ScalarLoop<T, Work::W>)->Unit(benchmark::kMicrosecond); \
  BENCHMARK(BM_Lanes<NativeBatch<T>, Work::W>)->Unit(benchmark::kMicrosecond);
#else
#define CROWD_ROWS(T, W)                                                       \
  BENCHMARK(BM_ScalarLoop<T, Work::W>)->Unit(benchmark::kMicrosecond);         \
  BENCHMARK(BM_Lanes<NativeBatch<T>, Work::W>)->Unit(benchmark::kMicrosecond); \
  BENCHMARK(BM_Lanes<FixedBatch<T, 64 / sizeof(T)>, Work::W>)->Unit(benchmark::kMicrosecond);
#endif

CROWD_ROWS(double, ID)
CROWD_ROWS(double, Euler)
CROWD_ROWS(float, ID)
CROWD_ROWS(float, Euler)

}  // namespace

BENCHMARK_MAIN();
