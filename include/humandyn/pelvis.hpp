// The seed body with a pelvis: a mass matrix that can be inverted.
//
// As built, the seed body's pelvis link (joint 4's link) is massless, and the right hip pitch, the waist
// pitch and the left hip pitch (joints 4, 5 and 13) turn about one line. Turning the pelvis one way and
// both of its children back the other way moves no mass: M (e4 - e5 - e13) = 0. Inverse dynamics does
// not mind, but forward dynamics is undefined in that direction, and a spring on it (a servo) has an
// infinite frequency, beyond any explicit step. An implicit servo still works, since M + h Kd + h^2 Kp
// is positive definite.
//
// with_pelvis() gives link 4 a lower trunk: 8.2 kg (de Leva's male lower trunk, 11.2 % of 73 kg), its
// centre 4 cm above the hip axis, the moments of a 0.25 x 0.2 x 0.12 m block; PelvisShape is the seed's
// shape except that link 4 may carry mass.
#pragma once

#include "humandyn/model.hpp"
#include "humandyn/shape.hpp"

#include <Eigen/Core>

namespace humandyn {

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

// `d` (the seed topology, link 4 massless) with a pelvis on link 4; ModelError otherwise.
inline ModelDescription<double> with_pelvis(ModelDescription<double> d) {
  if (d.joints.size() != 16 || d.joints[3].parent != 2)
    throw ModelError("model '" + d.name + "': a pelvis goes on the seed body's link 4");
  if (d.joints[3].body.mass > 0) return d;  // the de Leva builders already give the pelvis its lower trunk
  auto& b = d.joints[3].body;
  b.mass = 8.2;
  // link 4's frame: x up the body, z along the hip axis at the home pose
  b.com = Eigen::Vector3d(0.04, 0.0, 0.0);
  const double m = b.mass, lx = 0.2, ly = 0.12, lz = 0.25;
  b.inertia = Eigen::Vector3d(m * (ly * ly + lz * lz) / 12, m * (lx * lx + lz * lz) / 12, m * (lx * lx + ly * ly) / 12)
                  .asDiagonal();
  d.name += ", with a pelvis";
  return d;
}

}  // namespace humandyn
