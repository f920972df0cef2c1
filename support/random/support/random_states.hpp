// Reproducible random joint states, the one generator the tests, the benchmarks and `humandyn bench` draw
// from: uniform in |q| <= q_max, |qd| <= qd_max, |qdd| <= qdd_max, from a fixed seed.
#pragma once

#include <Eigen/Core>

#include <random>
#include <vector>

namespace humandyn::support {

// One joint state: angles, velocities, accelerations; Vector is Eigen::VectorXd or a fixed-size vector.
template <class Vector>
struct BasicJointState {
  Vector q, qd, qdd;
};
using JointState = BasicJointState<Eigen::VectorXd>;
template <int N>
using FixedJointState = BasicJointState<Eigen::Matrix<double, N, 1>>;

// n states (q, qd, qdd of the first state, then the next: the same draws for either Vector).
template <class Vector = Eigen::VectorXd>
std::vector<BasicJointState<Vector>> random_states(int joints, int n, unsigned seed,
                                                   double q_max = 3.14159265358979323846, double qd_max = 10.0,
                                                   double qdd_max = 50.0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto draw = [&](double scale) {
    Vector v;
    v.resize(joints);
    for (int i = 0; i < joints; ++i) v[i] = scale * u(rng);
    return v;
  };
  std::vector<BasicJointState<Vector>> states;
  states.reserve(std::size_t(n));
  for (int k = 0; k < n; ++k) {
    BasicJointState<Vector> s;
    s.q = draw(q_max);
    s.qd = draw(qd_max);
    s.qdd = draw(qdd_max);
    states.push_back(std::move(s));
  }
  return states;
}

}  // namespace humandyn::support
