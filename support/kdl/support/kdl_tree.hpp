// A model description as a KDL tree: the independent reference for tests and benchmarks.
// Each joint becomes a KDL segment with a RotZ joint and tip frame Frame::DH(a, alpha, d, theta)
// (standard DH, so the segment's pose is Rz(q) * Rz(theta) Tz(d) Tx(a) Rx(alpha)); a mount becomes a
// fixed segment before it. KDL expresses a segment's inertia in its tip frame, which is the link frame.
#pragma once

#include "humandyn/model.hpp"

#include <kdl/chain.hpp>
#include <kdl/tree.hpp>

#include <stdexcept>
#include <string>

namespace humandyn::testing {

inline KDL::Frame to_kdl(const Pose<double>& X) {
  return KDL::Frame(
      KDL::Rotation(X.R(0, 0), X.R(0, 1), X.R(0, 2), X.R(1, 0), X.R(1, 1), X.R(1, 2), X.R(2, 0), X.R(2, 1), X.R(2, 2)),
      KDL::Vector(X.p.x(), X.p.y(), X.p.z()));
}

inline KDL::RigidBodyInertia to_kdl(const RigidBodyInertia<double>& b) {
  const auto& I = b.inertia;
  return KDL::RigidBodyInertia(b.mass, KDL::Vector(b.com.x(), b.com.y(), b.com.z()),
                               KDL::RotationalInertia(I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)));
}

inline KDL::Vector to_kdl(const Vec3<double>& v) { return KDL::Vector(v.x(), v.y(), v.z()); }

// The segment name of joint i's link in the KDL tree.
inline std::string kdl_segment_name(const ModelDescription<double>& d, int i) {
  return "seg_" + std::to_string(i) + "_" + d.joints[std::size_t(i)].link_name;
}

inline KDL::Segment kdl_segment(const ModelDescription<double>& d, int i) {
  const auto& j = d.joints[std::size_t(i)];
  return KDL::Segment(kdl_segment_name(d, i), KDL::Joint(j.name, KDL::Joint::RotZ),
                      KDL::Frame::DH(j.dh.a, j.dh.alpha, j.dh.d, j.dh.theta), to_kdl(j.body));
}

// The whole model as a KDL tree rooted at "root"; KDL's joint i is the model's joint i. Given a
// tree and one of its segments as `base`, the model is hung from that segment instead (its joints
// then follow the tree's own).
inline KDL::Tree kdl_tree(const ModelDescription<double>& d, KDL::Tree tree = KDL::Tree("root"),
                          const std::string& base = "root") {
  for (int i = 0; i < int(d.joints.size()); ++i) {
    const auto& j = d.joints[std::size_t(i)];
    std::string parent = j.parent < 0 ? base : kdl_segment_name(d, j.parent);
    if (j.mounted) {
      const std::string mount = kdl_segment_name(d, i) + "_mount";
      if (!tree.addSegment(KDL::Segment(mount, KDL::Joint(mount + "_fixed", KDL::Joint::Fixed), to_kdl(j.mount)),
                           parent))
        throw std::runtime_error("KDL refused segment " + mount);
      parent = mount;
    }
    if (!tree.addSegment(kdl_segment(d, i), parent)) throw std::runtime_error("KDL refused joint " + j.name);
  }
  return tree;
}

// The serial chain from the base through the given joints (each the child of the previous one), as a
// KDL chain: for single-chain models and for chains cut out of the tree.
inline KDL::Chain kdl_chain(const ModelDescription<double>& d) {
  KDL::Chain chain;
  for (int i = 0; i < int(d.joints.size()); ++i) {
    const auto& j = d.joints[std::size_t(i)];
    if (j.parent != i - 1) throw std::runtime_error("kdl_chain: joint " + j.name + " does not follow its predecessor");
    if (j.mounted)
      chain.addSegment(KDL::Segment(kdl_segment_name(d, i) + "_mount", KDL::Joint(KDL::Joint::Fixed), to_kdl(j.mount)));
    chain.addSegment(kdl_segment(d, i));
  }
  return chain;
}

// Gravity in the base frame, as KDL's solvers take it.
inline KDL::Vector kdl_gravity(const ModelDescription<double>& d) {
  return to_kdl(Vec3<double>(d.base_pose.R.transpose() * d.gravity));
}

}  // namespace humandyn::testing
