// A whole-body motion of the floating form whose velocities and accelerations are exact derivatives: the
// pelvis turning about the vertical and travelling forward with a small sway and bob, every joint on its own
// sine (0.5-0.875 Hz). The motion pipeline's closed loops run on it (test_contact, test_motion_cli), with
// the seed body's landmarks of closed_loop_body.
#pragma once

#include "humandyn/motion/filter.hpp"
#include "humandyn/motion/fit.hpp"

#include <Eigen/Geometry>

#include <cmath>

namespace humandyn::testing {

// The default body with a foot 0.19 m long (the toe at the sole's level), the head 0.24 m above the neck and
// the lower back 0.1 m above the mid-hip point: the body the closed loops' clips are made with.
inline motion::ClipBody closed_loop_body() {
  motion::ClipBody b;
  b.parameters = default_parameters();
  b.foot_length = 0.19;
  b.toe_drop = b.parameters.a16;
  b.head_length = 0.24;
  b.lower_back_length = 0.1;
  return b;
}

template <class Model>
motion::FloatingFrame turning_walk(const Model& model, double t) {
  motion::FloatingFrame f;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const double w0 = 2 * M_PI * 0.4, th = 0.3 * std::sin(w0 * t), thd = 0.3 * w0 * std::cos(w0 * t),
               thdd = -0.3 * w0 * w0 * std::sin(w0 * t);
  f.base.R = Eigen::AngleAxisd(th, up).toRotationMatrix() * model.base_pose().R;
  const double w1 = 2 * M_PI * 0.5;
  f.base.p = model.base_pose().p + Eigen::Vector3d(0.8 * t, 0.05 * std::sin(w1 * t), 0.02 * std::cos(w1 * t));
  const Eigen::Vector3d pd(0.8, 0.05 * w1 * std::cos(w1 * t), -0.02 * w1 * std::sin(w1 * t));
  const Eigen::Vector3d pdd(0, -0.05 * w1 * w1 * std::sin(w1 * t), -0.02 * w1 * w1 * std::cos(w1 * t));
  const Eigen::Vector3d wb = f.base.R.transpose() * up * thd, vb = f.base.R.transpose() * pd;
  f.v_b << wb, vb;
  f.a_b << f.base.R.transpose() * up * thdd, f.base.R.transpose() * pdd - wb.cross(vb);
  for (int i = 0; i < 16; ++i) {
    const double w = 2 * M_PI * (0.5 + 0.025 * i), a = 0.4, c = 0.3 + 0.02 * i;
    f.q[i] = c + a * std::sin(w * t + i), f.qd[i] = a * w * std::cos(w * t + i),
    f.qdd[i] = -a * w * w * std::sin(w * t + i);
  }
  return f;
}

}  // namespace humandyn::testing
