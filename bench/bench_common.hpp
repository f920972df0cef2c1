// What the micro-benchmarks share: the model they run on (--model default|female|paper, read before
// Google Benchmark's own flags), and the pool of random states (|q| <= 1, |qd| <= 2, |qdd| <= 5; the same
// pool, from the same seed, for every library), cycled through one state per iteration.
#pragma once

#include "humandyn/builders.hpp"
#include "humandyn/floating.hpp"
#include "humandyn/model.hpp"
#include "support/motions.hpp"

#include <Eigen/Geometry>

#include <cstddef>
#include <string>
#include <vector>

namespace humandyn::bench {

// The model description chosen on the command line (default: de Leva's reference male).
const ModelDescription<double>& bench_description();

// Sets the model from its name; false for an unknown name.
bool select_model(const std::string& name);

inline constexpr int pool_size = 1000;

// The random pool in double.
inline const StateSet& random_pool() {
  static const StateSet pool = random_states(int(bench_description().joints.size()), pool_size);
  return pool;
}

// A model of type Model (any scalar, any shape) built from bench_description(), once.
template <class Model>
const Model& bench_model() {
  static const Model model(bench_description().template cast<typename Model::scalar_type>());
  return model;
}

// The random pool in a model's own vector type.
template <class Vector>
struct TypedPool {
  std::vector<Vector> q, qd, qdd;
};

template <class Vector>
const TypedPool<Vector>& typed_pool() {
  static const TypedPool<Vector> pool = [] {
    using S = typename Vector::Scalar;
    TypedPool<Vector> p;
    for (int i = 0; i < random_pool().size(); ++i) {
      p.q.push_back(random_pool().q[std::size_t(i)].cast<S>());
      p.qd.push_back(random_pool().qd[std::size_t(i)].cast<S>());
      p.qdd.push_back(random_pool().qdd[std::size_t(i)].cast<S>());
    }
    return p;
  }();
  return pool;
}

// The floating form of the chosen model (a free base at the pelvis), and a base state per pool state.
using FD = FloatingHumanModel<double>;

inline const FD& floating_bench_model() {
  static const FD model(floating_description(bench_description()));
  return model;
}

// A base state per pool state: pose turned about a pool-drawn axis, velocity and acceleration from the pool.
struct BaseSample {
  Pose<double> X;
  SpatialVector<double> v, a;
};

inline const std::vector<BaseSample>& base_pool() {
  static const std::vector<BaseSample> pool = [] {
    std::vector<BaseSample> out;
    const auto& p = random_pool();
    for (int i = 0; i < p.size(); ++i) {
      const auto k = std::size_t(i);
      BaseSample b;
      const Vec3<double> axis = Vec3<double>(p.q[k].segment<3>(6)) + Vec3<double>(0, 0, 2);
      b.X = Pose<double>{Eigen::AngleAxisd(p.q[k][9], axis.normalized()).toRotationMatrix(), p.q[k].segment<3>(10)};
      b.v = p.qd[k].head<6>();
      b.a = p.qdd[k].head<6>();
      out.push_back(b);
    }
    return out;
  }();
  return pool;
}

// The next index into the pool.
inline std::size_t next_state(std::size_t i) { return i + 1 == std::size_t(pool_size) ? 0 : i + 1; }

// A benchmark's loop: call(i) once per iteration of `st`, on pool state i, cycling through the pool.
template <class BenchmarkState, class Call>
inline void over_pool(BenchmarkState& st, Call&& call) {
  std::size_t i = 0;
  for ([[maybe_unused]] auto _ : st) {
    call(i);
    i = next_state(i);
  }
}

}  // namespace humandyn::bench
