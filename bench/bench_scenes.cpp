// Scenes (scene.hpp): time per call of every named scene's inverse dynamics, and of the locked scenes'
// forward dynamics, beside the full model's, in one binary with one set of
// flags, on one pool of random
// states (|q| <= 1, |qd| <= 2, |qdd| <= 5, cycled one per iteration). Each scene runs the states
// constrained to it (locked joints at their lock angles and still); its counters say how far its
// outputs are from the full model's on the unconstrained states (what the scene gives up) and on the
// constrained ones (zero up to rounding where it claims exactness).
//
//   humandyn_bench_scenes [--benchmark_min_time=0.5] [--benchmark_repetitions=5]
#include "humandyn/builders.hpp"
#include "humandyn/poses.hpp"
#include "humandyn/scene.hpp"
#include "support/random_states.hpp"

#include <benchmark/benchmark.h>

#include <string>
#include <vector>

namespace {

using namespace humandyn;
using Vec16 = Eigen::Matrix<double, 16, 1>;

constexpr int kPool = 1000;

struct Pool {
  std::vector<Vec16> q, qd, qdd;
};

const Pool& full_pool() {
  static const Pool pool = [] {
    Pool p;
    for (const auto& s : support::random_states<Vec16>(16, kPool, 2024, 1.0, 2.0, 5.0)) {
      p.q.push_back(s.q);
      p.qd.push_back(s.qd);
      p.qdd.push_back(s.qdd);
    }
    return p;
  }();
  return pool;
}

const ModelDescription<double>& description() {
  static const ModelDescription<double> d = human_description(default_parameters());
  return d;
}

// the lock angles: seated (poses.hpp: hips and knees bent by 90 degrees, thighs forward)
const Eigen::VectorXd& lock_angles() {
  static const Eigen::VectorXd q = poses::angles(HumanModel<double>(description()), poses::seated);
  return q;
}

// A scene's pool: the full pool constrained to the scene, in the scene's joints.
template <class SceneT>
struct ScenePool {
  std::vector<typename SceneT::template vector<double>> q, qd, qdd;
  std::vector<Vec16> q_full, qd_full, qdd_full;
  ScenePool() {
    const Pool& p = full_pool();
    for (int k = 0; k < kPool; ++k) {
      Vec16 q_k = p.q[std::size_t(k)], qd_k = p.qd[std::size_t(k)], qdd_k = p.qdd[std::size_t(k)];
      SceneT::constrain(lock_angles(), q_k, qd_k, qdd_k);
      q_full.push_back(q_k);
      qd_full.push_back(qd_k);
      qdd_full.push_back(qdd_k);
      q.push_back(SceneT::reduce(q_k));
      qd.push_back(SceneT::reduce(qd_k));
      qdd.push_back(SceneT::reduce(qdd_k));
    }
  }
};

// Largest |tau_scene - tau_full| over the scene's outputs (N m), on the pool as it is (`constrained`
// false) or constrained to the scene.
template <class SceneT>
double error_against_full(bool constrained) {
  const HumanModel<double> full(description());
  Data<HumanModel<double>> full_data(full);
  const auto model = SceneT::template model<double>(description(), lock_angles());
  Data<std::decay_t<decltype(model)>> data(model);
  const Pool& p = full_pool();
  double e = 0;
  for (int k = 0; k < kPool; ++k) {
    Vec16 q = p.q[std::size_t(k)], qd = p.qd[std::size_t(k)], qdd = p.qdd[std::size_t(k)];
    const Vec16 expected = rnea(full, full_data, q, qd, qdd);
    if (constrained) SceneT::constrain(lock_angles(), q, qd, qdd);
    const Vec16 tau_full = rnea(full, full_data, q, qd, qdd);
    const Vec16 got =
        SceneT::expand(scene_rnea<SceneT>(model, data, SceneT::reduce(q), SceneT::reduce(qd), SceneT::reduce(qdd)));
    for (int i = 0; i < 16; ++i)
      if (SceneT::outputs(i)) e = std::max(e, std::abs(got[i] - (constrained ? tau_full[i] : expected[i])));
  }
  return e;
}

template <class SceneT>
void scene_inverse_dynamics(benchmark::State& st) {
  const auto model = SceneT::template model<double>(description(), lock_angles());
  Data<std::decay_t<decltype(model)>> data(model);
  const ScenePool<SceneT> pool;
  std::size_t i = 0;
  for ([[maybe_unused]] auto _ : st) {
    benchmark::DoNotOptimize(scene_rnea<SceneT>(model, data, pool.q[i], pool.qd[i], pool.qdd[i]).data());
    benchmark::ClobberMemory();
    i = (i + 1) % kPool;
  }
  st.counters["joints"] = SceneT::nj;
  st.counters["fwd_steps"] = SceneT::forward_steps;
  st.counters["bwd_steps"] = SceneT::backward_steps;
  st.counters["err_free_Nm"] = error_against_full<SceneT>(false);
  st.counters["err_held_Nm"] = error_against_full<SceneT>(true);
}

template <class NamedScene>
void scene_forward_dynamics_bench(benchmark::State& st) {
  using SceneT = BasicScene<SeedShape, NamedScene::spec>;
  static const ModelDescription<double> body = human_description(default_parameters());
  const auto model = SceneT::template model<double>(body, lock_angles());
  Data<std::decay_t<decltype(model)>> data(model);
  const ScenePool<SceneT> pool;
  std::vector<typename SceneT::template vector<double>> tau;
  for (int k = 0; k < kPool; ++k)
    tau.push_back(
        scene_rnea<SceneT>(model, data, pool.q[std::size_t(k)], pool.qd[std::size_t(k)], pool.qdd[std::size_t(k)]));
  std::size_t i = 0;
  for ([[maybe_unused]] auto _ : st) {
    benchmark::DoNotOptimize(scene_forward_dynamics<SceneT>(model, data, pool.q[i], pool.qd[i], tau[i]).data());
    benchmark::ClobberMemory();
    i = (i + 1) % kPool;
  }
  st.counters["joints"] = SceneT::nj;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  for_each_named_scene([](auto scene) {
    using SceneT = decltype(scene);
    benchmark::RegisterBenchmark(("scene_rnea/" + std::string(SceneT::name)).c_str(), scene_inverse_dynamics<SceneT>);
  });
  // forward dynamics: the scenes with every torque as output and full or locked joints
  for_each_named_scene([](auto scene) {
    using SceneT = decltype(scene);
    if constexpr (SceneT::terms == Terms::Full && !SceneT::prunes_outputs)
      benchmark::RegisterBenchmark(("scene_aba/" + std::string(SceneT::name)).c_str(),
                                   scene_forward_dynamics_bench<SceneT>);
  });
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
