// What the micro-benchmarks share: the model they run on (--model default|female|paper, read before
// Google Benchmark's own flags), and the pool of random states (|q| <= 1, |qd| <= 2, |qdd| <= 5; the same
// pool, from the same seed, for every library), cycled through one state per iteration.
#pragma once

#include "support/motions.hpp"
#include "humandyn/builders.hpp"
#include "humandyn/model.hpp"

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

// The next index into the pool.
inline std::size_t next_state(std::size_t i) { return i + 1 == std::size_t(pool_size) ? 0 : i + 1; }

}  // namespace humandyn::bench
