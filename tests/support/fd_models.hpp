// Models for the forward-dynamics suites: chains cut out of a body. Their random states come from
// support/random_state.hpp.
//
// Table 1's body (the paper model) has a singular mass matrix: the right hip pitch, the waist pitch and
// the left hip pitch (joints 4, 5, 13) turn about one line, and the pelvis link between them is
// massless, so M (e4 - e5 - e13) = 0 and forward dynamics is undefined in that direction. The de Leva
// builders put the lower trunk on that link, so the default model's M is regular.
#pragma once

#include "humandyn/builders.hpp"
#include "humandyn/model.hpp"
#include "humandyn/shape.hpp"

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

}  // namespace humandyn::testing
