// KDL with a moving base, entered by hand: six massless virtual joints (translations along the
// world x, y, z, then rotations about z, y', x'') carry the base frame and its body, and the model
// hangs from them. Their accelerations move the base; their torques are the wrench that holds it (force
// along the world axes, moment about the base origin along the three rotation axes).
#pragma once

#include "humandyn/algorithm/rnea.hpp"
#include "support/kdl_tree.hpp"
#include "support/random_state.hpp"

#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include <Eigen/Geometry>

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace humandyn::testing {

// The base's six virtual joint values: position (m) and z-y-x rotation angles (rad).
struct BaseJoints {
  Eigen::Matrix<double, 6, 1> q, qd, qdd;
};

// The three rotation axes in the world: z, then y turned by the first angle, then x turned by both.
inline std::array<Vec3<double>, 3> rotation_axes(const BaseJoints& b) {
  const Mat3<double> Rz = Eigen::AngleAxisd(b.q[3], Vec3<double>::UnitZ()).toRotationMatrix();
  const Mat3<double> Ry = Eigen::AngleAxisd(b.q[4], Vec3<double>::UnitY()).toRotationMatrix();
  return {Vec3<double>::UnitZ(), Rz * Vec3<double>::UnitY(), Rz * Ry * Vec3<double>::UnitX()};
}

// The base frame's motion in the world from the virtual joints, by hand: the translations run along
// the world axes, the rotations about rotation_axes; R0 is the base frame's rotation at zero angles.
inline BaseMotion<double> base_motion_of(const BaseJoints& b, const Mat3<double>& R0) {
  const auto [e1, e2, e3] = rotation_axes(b);
  BaseMotion<double> m;
  m.pose.R = Eigen::AngleAxisd(b.q[3], Vec3<double>::UnitZ()).toRotationMatrix() *
             Eigen::AngleAxisd(b.q[4], Vec3<double>::UnitY()).toRotationMatrix() *
             Eigen::AngleAxisd(b.q[5], Vec3<double>::UnitX()).toRotationMatrix() * R0;
  m.pose.p = b.q.head<3>();
  m.w = b.qd[3] * e1 + b.qd[4] * e2 + b.qd[5] * e3;
  // each axis turns with the rotations before it: d(e_k)/dt = w_before_k x e_k
  m.wd = b.qdd[3] * e1 + b.qdd[4] * e2 + b.qdd[5] * e3 + (b.qd[3] * e1).cross(b.qd[4] * e2) +
         (b.qd[3] * e1 + b.qd[4] * e2).cross(b.qd[5] * e3);
  m.a = b.qdd.head<3>();
  return m;
}

// The model hung from six virtual joints in KDL; the fixed segment between them carries the base
// frame's home rotation and the base body (the stance foot).
class KdlOnMovingBase {
 public:
  explicit KdlOnMovingBase(const ModelDescription<double>& d) : tree_(build(d)), solver_(tree_, gravity(d)) {}

  // KDL's torques: the six virtual joints first, then the model's joints.
  Eigen::VectorXd torques(const BaseJoints& b, const JointState& s) {
    const auto n = Eigen::Index(s.q.size());
    Eigen::VectorXd q(6 + n), qd(6 + n), qdd(6 + n);
    q << b.q, s.q;
    qd << b.qd, s.qd;
    qdd << b.qdd, s.qdd;
    KDL::JntArray tau(tree_.getNrOfJoints());
    if (solver_.CartToJnt(to_jnt(q), to_jnt(qd), to_jnt(qdd), KDL::WrenchMap{}, tau) != 0)
      throw std::runtime_error("KDL TreeIdSolver_RNE failed");
    return tau.data;
  }

 private:
  static KDL::Vector gravity(const ModelDescription<double>& d) { return to_kdl(d.gravity); }
  static KDL::Tree build(const ModelDescription<double>& d) {
    KDL::Tree tree("root");
    const KDL::Joint::JointType types[6] = {KDL::Joint::TransX, KDL::Joint::TransY, KDL::Joint::TransZ,
                                            KDL::Joint::RotZ,   KDL::Joint::RotY,   KDL::Joint::RotX};
    std::string parent = "root";
    for (int k = 0; k < 6; ++k) {
      const std::string name = "virtual_" + std::to_string(k);
      tree.addSegment(KDL::Segment(name, KDL::Joint(name, types[k])), parent);
      parent = name;
    }
    Pose<double> home;
    home.R = d.base_pose.R;
    tree.addSegment(
        KDL::Segment("base", KDL::Joint("base_fixed", KDL::Joint::Fixed), to_kdl(home), to_kdl(d.base_body)), parent);
    return kdl_tree(d, tree, "base");
  }
  KDL::Tree tree_;
  KDL::TreeIdSolver_RNE solver_;
};

// n random base states: positions and angles within 1 (m, rad), rates 3, accelerations 10.
inline std::vector<BaseJoints> random_base_joints(int n, unsigned seed) {
  const auto s = random_states(6, n, seed, 1.0, 3.0, 10.0);
  std::vector<BaseJoints> out;
  for (const auto& x : s) out.push_back({x.q, x.qd, x.qdd});
  return out;
}

}  // namespace humandyn::testing
