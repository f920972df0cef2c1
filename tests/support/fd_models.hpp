// Models and states for the forward-dynamics suites.
//
// Table 1's body (the paper model) has a singular mass matrix: the right hip pitch, the waist pitch and
// the left hip pitch (joints 4, 5, 13) turn about one line, and the pelvis link between them is
// massless, so M (e4 - e5 - e13) = 0 and forward dynamics is undefined in that direction. The de Leva
// builders put the lower trunk on that link, so the default model's M is regular.
#pragma once

#include "humandyn/builders.hpp"
#include "humandyn/model.hpp"
#include "humandyn/shape.hpp"

#include <Eigen/Core>

#include <random>
#include <vector>

namespace humandyn::testing {

// The joints of `d` listed in `joints` (each the child of the previous one) as a single-chain description.
inline ModelDescription<double> sub_chain(const ModelDescription<double>& d, const std::vector<int>& joints) {
  ModelDescription<double> out = d;
  out.joints.clear();
  for (std::size_t k = 0; k < joints.size(); ++k) {
    auto j = d.joints[std::size_t(joints[k])];
    j.parent = int(k) - 1;
    out.joints.push_back(j);
  }
  return out;
}

// A joint state drawn uniformly: |q| <= q_max, |qd| <= qd_max, |qdd| <= qdd_max.
struct State {
  Eigen::VectorXd q, qd, qdd;
};

inline std::vector<State> draw_states(int joints, int n, unsigned seed, double q_max, double qd_max, double qdd_max) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto draw = [&](double scale) {
    Eigen::VectorXd v(joints);
    for (int i = 0; i < joints; ++i) v[i] = scale * u(rng);
    return v;
  };
  std::vector<State> out;
  for (int k = 0; k < n; ++k) {
    State s;
    s.q = draw(q_max);
    s.qd = draw(qd_max);
    s.qdd = draw(qdd_max);
    out.push_back(s);
  }
  return out;
}

}  // namespace humandyn::testing
