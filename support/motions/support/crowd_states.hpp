// The crowd the crowd benchmarks run on (`humandyn bench`'s crowd rows and bench/bench_crowd.cpp): human-sized
// random states (|q| <= 1 rad, |q̇| <= 2 rad/s, |q̈| <= 5 rad/s^2, |τ| <= 5 N m) from a fixed seed, each
// character's servo holding its start pose (kp 50 N m/rad, kd 2 N m s/rad): stable at h = 1 ms.
#pragma once

#include "humandyn/crowd.hpp"

#include <algorithm>
#include <random>
#include <vector>

namespace humandyn::bench {

template <class T, int nj = SeedShape::nj>
struct CrowdStates {
  std::size_t n;
  std::vector<T> q0, qd0, q, qd, qdd, tau, out, kp, kd, q_ref, qd_ref, damping, q_min, q_max, k_lim;
  std::vector<StepStatus> status;
  CrowdServo<T> servo;
  explicit CrowdStates(std::size_t count) : n(count), status(count) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (auto* a : {&q0, &qd0, &qdd, &tau, &out, &kp, &kd, &q_ref, &qd_ref, &damping, &q_min, &q_max, &k_lim})
      a->resize(n * nj);
    for (std::size_t k = 0; k < n * nj; ++k) {
      q0[k] = T(u(rng)), qd0[k] = T(2 * u(rng)), qdd[k] = T(5 * u(rng)), tau[k] = T(5 * u(rng));
      kp[k] = T(50), kd[k] = T(2), q_ref[k] = q0[k], qd_ref[k] = T(0), damping[k] = T(0.1);
      q_min[k] = T(-3), q_max[k] = T(3), k_lim[k] = T(100);
    }
    q = q0, qd = qd0;
    servo = {kp.data(),      kd.data(),    q_ref.data(), qd_ref.data(),
             damping.data(), q_min.data(), q_max.data(), k_lim.data()};
  }
  CrowdStates(const CrowdStates&) = delete;  // the view and the servo point into the vectors
  CrowdStates& operator=(const CrowdStates&) = delete;
  // Back to the start states.
  void restore() {
    q = q0;
    qd = qd0;
  }
  CrowdView<T> view() { return {n, q.data(), qd.data(), tau.data(), &servo, status.data()}; }
  // How many characters the last step refused.
  long refused() const {
    return long(std::count_if(status.begin(), status.end(), [](const StepStatus& s) { return !s.ok(); }));
  }
};

}  // namespace humandyn::bench
