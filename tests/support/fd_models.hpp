// Models for the forward-dynamics suites: chains cut out of a body, a body with general joints. Their random states
// come from support/random_state.hpp.
//
// Table 1's body (the paper model) has a singular mass matrix: the right hip pitch, the waist pitch and
// the left hip pitch (joints 4, 5, 13) turn about one line, and the pelvis link between them is
// massless, so M (e4 - e5 - e13) = 0 and forward dynamics is undefined in that direction. The de Leva
// builders put the lower trunk on that link, so the default model's M is regular.
#pragma once

#include "humandyn/builders.hpp"
#include "humandyn/model.hpp"
#include "humandyn/shape.hpp"

#include <Eigen/Geometry>

#include <utility>
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

// The default body with general joints, as URDF imports make them: five joints mounted (a rotation and a
// shift between the parent link's frame and the joint's DH base frame) and twists other than the seed's
// 0, +-90 and 180 degrees on six more. A runtime-shaped model (AnyModel) takes it.
inline ModelDescription<double> mounted_general_description() {
  ModelDescription<double> d = human_description(default_parameters());
  int k = 0;
  for (const int i : {0, 4, 6, 12, 15}) {
    auto& j = d.joints[std::size_t(i)];
    j.mounted = true;
    j.mount.R = Eigen::AngleAxisd(0.3 + 0.2 * k, Eigen::Vector3d(1, 2 - k, 3).normalized()).toRotationMatrix();
    j.mount.p = Eigen::Vector3d(0.02 * (k + 1), -0.03, 0.05 - 0.01 * k);
    ++k;
  }
  const double pi = 3.14159265358979323846;
  for (const auto& [joint, alpha] : {std::pair{8, pi}, {15, -pi}, {7, 0.7}, {13, -2.1}, {3, 0.4}, {5, 1.2}})
    d.joints[std::size_t(joint)].dh.alpha = alpha;
  return d;
}

}  // namespace humandyn::testing
