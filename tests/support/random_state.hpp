// Random joint states (support/random_states.hpp) and KDL solver wrappers, shared by the core's test suites.
#pragma once

#include "humandyn/model.hpp"
#include "support/kdl_tree.hpp"
#include "support/random_states.hpp"

#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include <Eigen/Core>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace humandyn::testing {

using support::BasicJointState;
using support::FixedJointState;
using support::JointState;
using support::random_states;

inline KDL::JntArray to_jnt(const Eigen::VectorXd& v) {
  KDL::JntArray a(unsigned(v.size()));
  a.data = v;
  return a;
}

// KDL's tree inverse dynamics of a description. The tree must outlive the solver (it keeps a
// reference), so both live here.
class KdlTreeDynamics {
 public:
  explicit KdlTreeDynamics(const ModelDescription<double>& d)
      : desc_(d), tree_(kdl_tree(d)), solver_(tree_, kdl_gravity(d)) {}
  KdlTreeDynamics(const KdlTreeDynamics&) = delete;
  KdlTreeDynamics& operator=(const KdlTreeDynamics&) = delete;

  // f_ext: wrench on each named segment, in its tip frame about the tip frame's origin.
  Eigen::VectorXd torques(const JointState& s, const KDL::WrenchMap& f_ext = {}) {
    KDL::JntArray tau(tree_.getNrOfJoints());
    if (solver_.CartToJnt(to_jnt(s.q), to_jnt(s.qd), to_jnt(s.qdd), f_ext, tau) != 0)
      throw std::runtime_error("KDL TreeIdSolver_RNE failed");
    return tau.data;
  }
  const KDL::Tree& tree() const { return tree_; }

 private:
  ModelDescription<double> desc_;
  KDL::Tree tree_;
  KDL::TreeIdSolver_RNE solver_;
};

// KDL's chain inverse dynamics of a single-chain description.
class KdlChainDynamics {
 public:
  explicit KdlChainDynamics(const ModelDescription<double>& d)
      : chain_(kdl_chain(d)), solver_(chain_, kdl_gravity(d)) {}
  KdlChainDynamics(const KdlChainDynamics&) = delete;
  KdlChainDynamics& operator=(const KdlChainDynamics&) = delete;

  // f_ext: one wrench per chain segment (fixed mount segments included), in its tip frame.
  Eigen::VectorXd torques(const JointState& s, KDL::Wrenches f_ext = {}) {
    if (f_ext.empty()) f_ext.assign(chain_.getNrOfSegments(), KDL::Wrench::Zero());
    KDL::JntArray tau(chain_.getNrOfJoints());
    if (solver_.CartToJnt(to_jnt(s.q), to_jnt(s.qd), to_jnt(s.qdd), f_ext, tau) != 0)
      throw std::runtime_error("KDL ChainIdSolver_RNE failed");
    return tau.data;
  }
  const KDL::Chain& chain() const { return chain_; }

 private:
  KDL::Chain chain_;
  KDL::ChainIdSolver_RNE solver_;
};

}  // namespace humandyn::testing
