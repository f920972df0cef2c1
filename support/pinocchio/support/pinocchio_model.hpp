// A humandyn model description as a Pinocchio model, built through Pinocchio's C++ API: each joint a
// revolute about z (JointModelRZ) placed at its parent link frame * mount * Rz(theta), each link's body
// appended at Tz(d) Tx(a) Rx(alpha) from its joint frame. Fixed base: Pinocchio's universe is the base
// frame (gravity turned into it). Floating base: a free-flyer joint carries the base frame and the base
// body, and the universe is the world.
//
// Linked with Pinocchio's library (libpinocchio_default, its algorithms instantiated for double: the
// humandyn_pinocchio target), a call reaches the compiled algorithm when it passes its vectors as
// pin::Vector (Eigen::Ref<const Eigen::VectorXd>); any other argument type instantiates the algorithm again
// in the calling file, minutes of compile time each.
#pragma once

#include "humandyn/model.hpp"

#include <pinocchio/multibody.hpp>

#include <Eigen/Geometry>

#include <vector>

namespace humandyn::testing {

namespace pin {
using Vector = Eigen::Ref<const Eigen::VectorXd>;  // the argument type of Pinocchio's compiled algorithms
}

inline pinocchio::SE3 to_se3(const Pose<double>& X) { return pinocchio::SE3(X.R, X.p); }

inline pinocchio::Model pinocchio_model(const ModelDescription<double>& d, bool floating = false) {
  const auto rot_z = [](double theta) {
    return pinocchio::SE3(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                          Eigen::Vector3d::Zero());
  };
  const auto dh_link = [](const DHParameters<double>& dh) {  // Tz(d) Tx(a) Rx(alpha)
    return pinocchio::SE3(Eigen::AngleAxisd(dh.alpha, Eigen::Vector3d::UnitX()).toRotationMatrix(),
                          Eigen::Vector3d(dh.a, 0, dh.d));
  };
  pinocchio::Model m;
  pinocchio::JointIndex base = 0;  // the universe, or the free flyer
  if (floating) {
    base = m.addJoint(0, pinocchio::JointModelFreeFlyer(), pinocchio::SE3::Identity(), "base");
    const auto& b = d.base_body;
    m.appendBodyToJoint(base, pinocchio::Inertia(b.mass, b.com, b.inertia), pinocchio::SE3::Identity());
    m.gravity.linear(d.gravity);
  } else {
    m.gravity.linear(d.base_pose.R.transpose() * d.gravity);
  }
  std::vector<pinocchio::SE3> link_in_joint;  // link frame i seen from Pinocchio's joint frame i
  for (std::size_t i = 0; i < d.joints.size(); ++i) {
    const auto& j = d.joints[i];
    pinocchio::SE3 placement = j.parent < 0 ? pinocchio::SE3::Identity() : link_in_joint[std::size_t(j.parent)];
    if (j.mounted) placement = placement * to_se3(j.mount);
    placement = placement * rot_z(j.dh.theta);
    const auto parent = j.parent < 0 ? base : pinocchio::JointIndex(std::size_t(j.parent) + 1 + (floating ? 1 : 0));
    const auto id = m.addJoint(parent, pinocchio::JointModelRZ(), placement, j.name);
    link_in_joint.push_back(dh_link(j.dh));
    m.appendBodyToJoint(id, pinocchio::Inertia(j.body.mass, j.body.com, j.body.inertia), link_in_joint.back());
  }
  return m;
}

}  // namespace humandyn::testing
