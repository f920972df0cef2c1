// Error against run time: every way of computing a dynamics quantity (a "variant": an algorithm, its
// terms, its scalar type, its shape, or another library) is timed and compared with a reference computed
// in long double with the full model, on the same states.
//
// A variant is one line in a table (see bench_variants in cmd_bench.cpp): a name, the problem it solves and
// two functions, one evaluating a single state in double (for the error figures) and one timing the call
// over a pool of states (with the call inlined in the loop).
#pragma once

#include "bench/timing.hpp"
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/data.hpp"
#include "humandyn/model.hpp"
#include "support/motions.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace humandyn::bench {

using VectorLD = Eigen::Matrix<long double, Eigen::Dynamic, 1>;

// What a variant computes from (q, qd, x): inverse dynamics takes x = qdd and gives tau (N m), forward
// dynamics takes x = tau and gives qdd (rad/s^2).
enum class Problem { InverseDynamics, ForwardDynamics };

inline const char* problem_name(Problem p) {
  return p == Problem::InverseDynamics ? "inverse dynamics" : "forward dynamics";
}
inline const char* problem_unit(Problem p) { return p == Problem::InverseDynamics ? "N m" : "rad/s^2"; }

// The inputs of one problem over a set of states, and the reference outputs in long double.
struct Workload {
  std::string name;  // the state set: "random", "motions"
  Problem problem = Problem::InverseDynamics;
  std::vector<Eigen::VectorXd> q, qd, x;
  std::vector<VectorLD> reference;
  int size() const { return int(q.size()); }
};

// How far results are from the reference: the largest and root-mean-square absolute error over every
// joint of every state, and the largest relative error of a state, |result - reference|_inf /
// max(|reference|_inf, 1e-3 * the largest |reference|_inf of the set) (normwise, so a joint whose
// reference is near zero does not divide by zero, nor a state at rest whose reference is all but zero).
struct ErrorStats {
  double max_abs = 0, rms_abs = 0, max_rel = 0;
  int states = 0;
};

inline ErrorStats error_stats(const std::vector<VectorLD>& reference, const std::vector<Eigen::VectorXd>& result) {
  ErrorStats e;
  long double sum_sq = 0;
  long count = 0;
  const std::size_t n = std::min(reference.size(), result.size());
  long double set_scale = 0;
  for (std::size_t s = 0; s < n; ++s) set_scale = std::max(set_scale, reference[s].cwiseAbs().maxCoeff());
  for (std::size_t s = 0; s < n; ++s) {
    const VectorLD diff = result[s].cast<long double>() - reference[s];
    const long double worst = diff.cwiseAbs().maxCoeff();
    const long double scale = std::max(reference[s].cwiseAbs().maxCoeff(), 1e-3L * set_scale);
    e.max_abs = std::max(e.max_abs, double(worst));
    e.max_rel = std::max(e.max_rel, double(scale > 0 ? worst / scale : worst));
    sum_sq += diff.squaredNorm();
    count += diff.size();
  }
  e.rms_abs = count > 0 ? double(std::sqrt(sum_sq / count)) : 0.0;
  e.states = int(n);
  // not the same states, or a result that is not a number (which the largest differences above pass over)
  if (reference.size() != result.size() ||
      std::any_of(result.begin(), result.end(), [](const Eigen::VectorXd& r) { return !r.allFinite(); }))
    e.max_abs = e.max_rel = e.rms_abs = INFINITY;
  return e;
}

struct Variant {
  std::string name;  // e.g. "ID full double static"
  Problem problem = Problem::InverseDynamics;
  std::string scalar;  // "double", "float", "long double"
  std::string engine;  // "humandyn", "KDL", ...
  // Evaluates one state; inputs and output in double.
  std::function<void(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& x,
                     Eigen::VectorXd& out)>
      evaluate;
  // Mean nanoseconds per call over the workload's states (see ns_per_call), run for about `seconds`.
  std::function<double(const Workload&, double seconds)> time;
};

// The variant's outputs on every state of the workload, in order.
inline std::vector<Eigen::VectorXd> evaluate_all(const Variant& v, const Workload& w) {
  std::vector<Eigen::VectorXd> out(std::size_t(w.size()));
  for (int s = 0; s < w.size(); ++s)
    v.evaluate(w.q[std::size_t(s)], w.qd[std::size_t(s)], w.x[std::size_t(s)], out[std::size_t(s)]);
  return out;
}

// The variant's error on the workload.
inline ErrorStats measure_error(const Variant& v, const Workload& w) {
  return error_stats(w.reference, evaluate_all(v, w));
}

// The workload's states in a model's own vector type, packed for the timing loop.
template <class Vector>
std::vector<Vector> cast_all(const std::vector<Eigen::VectorXd>& xs) {
  std::vector<Vector> out;
  out.reserve(xs.size());
  for (const auto& x : xs) out.push_back(x.cast<typename Vector::Scalar>());
  return out;
}

// A variant from a humandyn per-call function `call(model, data, q, qd, x) -> const JointVector&`,
// run on `model` (any scalar, any shape).
template <class Model, class Call>
Variant humandyn_variant(std::string name, Problem problem, std::string scalar, std::shared_ptr<const Model> model,
                         Call call) {
  using S = typename Model::scalar_type;
  using V = typename Model::JointVector;
  auto data = std::make_shared<Data<Model>>(*model);
  Variant v;
  v.name = std::move(name);
  v.problem = problem;
  v.scalar = std::move(scalar);
  v.engine = "humandyn";
  v.evaluate = [model, data, call](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& x,
                                   Eigen::VectorXd& out) {
    // NOLINTNEXTLINE(performance-unnecessary-copy-initialization): a float cast must be evaluated once
    const V qs = q.cast<S>(), qds = qd.cast<S>(), xs = x.cast<S>();
    out = call(*model, *data, qs, qds, xs).template cast<double>();
  };
  v.time = [model, data, call](const Workload& w, double seconds) {
    const auto q = cast_all<V>(w.q), qd = cast_all<V>(w.qd), x = cast_all<V>(w.x);
    return ns_per_call(w.size(), seconds, [&](int i) {
      const auto& r = call(*model, *data, q[std::size_t(i)], qd[std::size_t(i)], x[std::size_t(i)]);
      do_not_optimize(r);
    });
  };
  return v;
}

// Inverse dynamics with the given terms, as a variant.
template <Terms terms, class Model>
Variant rnea_variant(std::string name, std::string scalar, std::shared_ptr<const Model> model) {
  return humandyn_variant(
      std::move(name), Problem::InverseDynamics, std::move(scalar), std::move(model),
      [](const Model& m, Data<Model>& d, const auto& q, const auto& qd,
         const auto& qdd) -> const typename Model::JointVector& { return rnea<terms>(m, d, q, qd, qdd); });
}

// The inverse dynamics workload of a state set: inputs (q, qd, qdd) and the full long double torques.
inline Workload inverse_dynamics_workload(const ModelDescription<double>& description, const StateSet& states) {
  Workload w;
  w.name = states.name;
  w.problem = Problem::InverseDynamics;
  w.q = states.q;
  w.qd = states.qd;
  w.x = states.qdd;
  const AnyModel<long double> model(description.cast<long double>());
  Data<AnyModel<long double>> data(model);
  for (int s = 0; s < w.size(); ++s) {
    const VectorLD q = w.q[std::size_t(s)].cast<long double>(), qd = w.qd[std::size_t(s)].cast<long double>(),
                   qdd = w.x[std::size_t(s)].cast<long double>();
    w.reference.push_back(rnea<Terms::Full>(model, data, q, qd, qdd));
  }
  return w;
}

// Forward dynamics with the given method and terms, as a variant (x = tau, output qdd).
template <FdMethod method, Terms terms, class Model>
Variant forward_dynamics_variant(std::string name, std::string scalar, std::shared_ptr<const Model> model) {
  return humandyn_variant(std::move(name), Problem::ForwardDynamics, std::move(scalar), std::move(model),
                          [](const Model& m, Data<Model>& d, const auto& q, const auto& qd,
                             const auto& tau) -> const typename Model::JointVector& {
                            return forward_dynamics<method, terms>(m, d, q, qd, tau);
                          });
}

// The forward dynamics workload of a state set: the torques that realise its accelerations (the long
// double inverse dynamics, rounded to double: the inputs every variant reads), and the accelerations
// those torques give in long double (mass matrix and LTDL solve, full model) as the reference.
inline Workload forward_dynamics_workload(const ModelDescription<double>& description, const StateSet& states) {
  const Workload id = inverse_dynamics_workload(description, states);
  Workload w;
  w.name = states.name;
  w.problem = Problem::ForwardDynamics;
  w.q = states.q;
  w.qd = states.qd;
  const AnyModel<long double> model(description.cast<long double>());
  Data<AnyModel<long double>> data(model);
  for (int s = 0; s < id.size(); ++s) {
    const auto k = std::size_t(s);
    w.x.push_back(id.reference[k].cast<double>());
    const VectorLD q = w.q[k].cast<long double>(), qd = w.qd[k].cast<long double>(), tau = w.x[k].cast<long double>();
    w.reference.push_back(forward_dynamics<FdMethod::MassMatrix, Terms::Full>(model, data, q, qd, tau));
  }
  return w;
}

}  // namespace humandyn::bench
