// Pinocchio's rnea, computeGeneralizedGravity, aba, crba, computeRNEADerivatives and computeABADerivatives on the same
// human and the same states, as Pinocchio's CMake package gives them to a C++ program: compiled in its library
// (libpinocchio_default, instantiated for double). The model is built through Pinocchio's C++ API from the same
// description: each joint a revolute about z (JointModelRZ) placed at its parent link frame * mount * Rz(theta), each
// link's body appended at Tz(d) Tx(a) Rx(alpha) from its joint frame. Before the benchmarks are registered, Pinocchio's
// torques are checked against humandyn's on the pool: a model that disagrees is never timed.
#include "bench_common.hpp"

#include "humandyn/floating.hpp"
#include "support/pinocchio_model.hpp"

#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace humandyn::bench {

namespace {

using V = humandyn::testing::pin::Vector;  // Pinocchio's compiled algorithms take their vectors as this

const pinocchio::Model& pin_model() {
  static const pinocchio::Model m = humandyn::testing::pinocchio_model(bench_description());
  return m;
}

// The floating form, with Pinocchio's free flyer, and the base states of the pool as its configurations
// (Pinocchio: position, quaternion (x, y, z, w); velocities and accelerations (linear; angular)).
const pinocchio::Model& pin_floating_model() {
  static const pinocchio::Model m = humandyn::testing::pinocchio_model(floating_description(bench_description()), true);
  return m;
}

struct FreeFlyerPool {
  std::vector<Eigen::VectorXd> q, v, a;
};

const FreeFlyerPool& free_flyer_pool() {
  static const FreeFlyerPool pool = [] {
    FreeFlyerPool p;
    const auto& s = random_pool();
    const auto& base = base_pool();
    const auto swap = [](const SpatialVector<double>& x) {
      SpatialVector<double> y;
      y << x.tail<3>(), x.head<3>();
      return y;
    };
    for (std::size_t k = 0; k < base.size(); ++k) {
      const Eigen::Quaterniond r(base[k].X.R);
      Eigen::VectorXd q(7 + s.q[k].size()), v(6 + s.q[k].size()), a(6 + s.q[k].size());
      q << base[k].X.p, r.coeffs(), s.q[k];
      v << swap(base[k].v), s.qd[k];
      a << swap(base[k].a), s.qdd[k];
      p.q.push_back(q);
      p.v.push_back(v);
      p.a.push_back(a);
    }
    return p;
  }();
  return pool;
}

// Pinocchio against humandyn on the whole pool: the largest torque difference (N m).
double largest_difference() {
  const auto& model = bench_model<HumanModel<double>>();
  Data<HumanModel<double>> data(model);
  pinocchio::Data pd(pin_model());
  const auto& s = random_pool();
  double worst = 0;
  for (int i = 0; i < s.size(); ++i) {
    const auto k = std::size_t(i);
    const Eigen::VectorXd ours = rnea(model, data, s.q[k], s.qd[k], s.qdd[k]);
    const Eigen::VectorXd theirs = pinocchio::rnea(pin_model(), pd, V(s.q[k]), V(s.qd[k]), V(s.qdd[k]));
    worst = std::max(worst, (ours - theirs).cwiseAbs().maxCoeff());
  }
  // the floating form: joint torques against Pinocchio's free flyer
  const auto& fm = floating_bench_model();
  FloatingData<FloatingHumanModel<double>> fd(fm);
  pinocchio::Data pf(pin_floating_model());
  const auto& ff = free_flyer_pool();
  const auto& base = base_pool();
  for (std::size_t k = 0; k < ff.q.size(); ++k) {
    const Eigen::VectorXd ours = floating_rnea(fm, fd, base[k].X, base[k].v, base[k].a, s.q[k], s.qd[k], s.qdd[k]);
    const Eigen::VectorXd theirs = pinocchio::rnea(pin_floating_model(), pf, V(ff.q[k]), V(ff.v[k]), V(ff.a[k]));
    worst = std::max(worst, (ours - theirs.tail(ours.size())).cwiseAbs().maxCoeff());
  }
  return worst;
}

void pin_rnea(benchmark::State& st) {
  pinocchio::Data data(pin_model());
  const auto& pool = random_pool();
  over_pool(st, [&](std::size_t i) {
    benchmark::DoNotOptimize(pinocchio::rnea(pin_model(), data, V(pool.q[i]), V(pool.qd[i]), V(pool.qdd[i])));
  });
}

void pin_gravity(benchmark::State& st) {
  pinocchio::Data data(pin_model());
  const auto& pool = random_pool();
  over_pool(st, [&](std::size_t i) {
    benchmark::DoNotOptimize(pinocchio::computeGeneralizedGravity(pin_model(), data, V(pool.q[i])));
  });
}

// Pinocchio's torques of the pool's accelerations: the forward dynamics benchmarks' inputs.
const std::vector<Eigen::VectorXd>& pin_tau_pool() {
  static const std::vector<Eigen::VectorXd> tau = [] {
    pinocchio::Data data(pin_model());
    const auto& pool = random_pool();
    std::vector<Eigen::VectorXd> out;
    for (std::size_t k = 0; k < pool.q.size(); ++k)
      out.push_back(pinocchio::rnea(pin_model(), data, V(pool.q[k]), V(pool.qd[k]), V(pool.qdd[k])));
    return out;
  }();
  return tau;
}

void pin_aba(benchmark::State& st) {
  pinocchio::Data data(pin_model());
  const auto& pool = random_pool();
  const auto& tau = pin_tau_pool();
  over_pool(st, [&](std::size_t i) {
    benchmark::DoNotOptimize(pinocchio::aba(pin_model(), data, V(pool.q[i]), V(pool.qd[i]), V(tau[i])));
  });
}

void pin_rnea_derivatives(benchmark::State& st) {
  pinocchio::Data data(pin_model());
  const auto& pool = random_pool();
  over_pool(st, [&](std::size_t i) {
    pinocchio::computeRNEADerivatives(pin_model(), data, V(pool.q[i]), V(pool.qd[i]), V(pool.qdd[i]));
    benchmark::DoNotOptimize(data.dtau_dq.data());
  });
}

void pin_aba_derivatives(benchmark::State& st) {
  pinocchio::Data data(pin_model());
  const auto& pool = random_pool();
  const auto& tau = pin_tau_pool();
  over_pool(st, [&](std::size_t i) {
    pinocchio::computeABADerivatives(pin_model(), data, V(pool.q[i]), V(pool.qd[i]), V(tau[i]));
    benchmark::DoNotOptimize(data.ddq_dq.data());
  });
}

void pin_crba(benchmark::State& st) {
  pinocchio::Data data(pin_model());
  const auto& pool = random_pool();
  over_pool(st, [&](std::size_t i) { benchmark::DoNotOptimize(pinocchio::crba(pin_model(), data, V(pool.q[i]))); });
}

void pin_rnea_free_flyer(benchmark::State& st) {
  pinocchio::Data data(pin_floating_model());
  const auto& pool = free_flyer_pool();
  over_pool(st, [&](std::size_t i) {
    benchmark::DoNotOptimize(pinocchio::rnea(pin_floating_model(), data, V(pool.q[i]), V(pool.v[i]), V(pool.a[i])));
  });
}

void pin_aba_free_flyer(benchmark::State& st) {
  pinocchio::Data data(pin_floating_model());
  const auto& pool = free_flyer_pool();
  // the joint torques the floating benchmarks use (the pool's accelerations), no wrench on the base
  std::vector<Eigen::VectorXd> tau;
  for (std::size_t k = 0; k < pool.q.size(); ++k) {
    Eigen::VectorXd t = Eigen::VectorXd::Zero(pool.v[k].size());
    t.tail(t.size() - 6) = pool.a[k].tail(t.size() - 6);
    tau.push_back(t);
  }
  over_pool(st, [&](std::size_t i) {
    benchmark::DoNotOptimize(pinocchio::aba(pin_floating_model(), data, V(pool.q[i]), V(pool.v[i]), V(tau[i])));
  });
}

}  // namespace

void register_pinocchio_benchmarks() {
  const double diff = largest_difference();
  if (!(diff <= 1e-9)) {
    std::fprintf(stderr, "Pinocchio's model disagrees with humandyn by %.3g N m: its benchmarks are skipped\n", diff);
    return;
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.1e", diff);
  benchmark::AddCustomContext("pinocchio_vs_humandyn_max_torque_difference_Nm", text);
  benchmark::RegisterBenchmark("pinocchio/rnea", pin_rnea);
  benchmark::RegisterBenchmark("pinocchio/computeGeneralizedGravity", pin_gravity);
  benchmark::RegisterBenchmark("pinocchio/aba", pin_aba);
  benchmark::RegisterBenchmark("pinocchio/crba", pin_crba);
  benchmark::RegisterBenchmark("pinocchio/rnea/free_flyer", pin_rnea_free_flyer);
  benchmark::RegisterBenchmark("pinocchio/aba/free_flyer", pin_aba_free_flyer);
  benchmark::RegisterBenchmark("pinocchio/computeRNEADerivatives", pin_rnea_derivatives);
  benchmark::RegisterBenchmark("pinocchio/computeABADerivatives", pin_aba_derivatives);
}

}  // namespace humandyn::bench
