// Models and states for the forward-dynamics suites.
//
// Table 1's body (the paper model) has a singular mass matrix: the right hip pitch, the waist pitch and
// the left hip pitch (joints 4, 5, 13) turn about one line, and the pelvis link between them is
// massless, so M (e4 - e5 - e13) = 0 and forward dynamics is undefined in that direction. The de Leva
// builders put the lower trunk on that link; the suites also run a body with a pelvis block of their
// own (8.2 kg on link 4), on a shape that lets link 4 carry mass.
#pragma once

#include "humandyn/builders.hpp"
#include "humandyn/model.hpp"
#include "humandyn/shape.hpp"

#include <Eigen/Core>

#include <random>
#include <vector>

namespace humandyn::testing {

// SeedShape with a massive pelvis link (joint 4's link): everything else compile-time as in the seed.
struct PelvisShape {
  static constexpr int nj = 16;
  static constexpr bool is_static = true;
  static constexpr ShapeSpec<16> spec = [] {
    ShapeSpec<16> s = SeedShape::spec;
    s.massless[3] = false;
    return s;
  }();
  static constexpr int num_chains = SeedShape::num_chains;
  static constexpr auto chains = SeedShape::chains;
};

// The seed human of `p` with a pelvis on link 4: 8.2 kg (de Leva's male lower trunk is 11.2 % of
// 73 kg), its centre 4 cm above the hip axis, moments of a 0.25 x 0.2 x 0.12 m block.
inline ModelDescription<double> with_pelvis(ModelDescription<double> d) {
  auto& b = d.joints[3].body;
  b.mass = 8.2;
  // link 4's frame: z along the hip axis (to the left), x along the body (up) at the home pose
  b.com = Eigen::Vector3d(0.04, 0.0, 0.0);
  const double m = b.mass, lx = 0.2, ly = 0.12, lz = 0.25;
  b.inertia = Eigen::Vector3d(m * (ly * ly + lz * lz) / 12, m * (lx * lx + lz * lz) / 12, m * (lx * lx + ly * ly) / 12)
                  .asDiagonal();
  return d;
}

inline ModelDescription<double> pelvis_description() { return with_pelvis(human_description(default_parameters())); }

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
