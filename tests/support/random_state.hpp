// Reproducible random joint states and KDL solver wrappers, shared by the core's test suites.
#pragma once

#include "humandyn/model.hpp"
#include "support/kdl_tree.hpp"

#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include <Eigen/Core>

#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace humandyn::testing {

// One joint state: angles, velocities, accelerations; Vector is Eigen::VectorXd or a fixed-size vector.
template <class Vector>
struct BasicJointState {
  Vector q, qd, qdd;
};
using JointState = BasicJointState<Eigen::VectorXd>;
template <int N>
using FixedJointState = BasicJointState<Eigen::Matrix<double, N, 1>>;

// n states drawn uniformly with |q| <= q_max, |qd| <= qd_max, |qdd| <= qdd_max, from a fixed seed
// (q, qd, qdd of the first state, then the next: the same draws for either Vector).
template <class Vector = Eigen::VectorXd>
std::vector<BasicJointState<Vector>> random_states(int joints, int n, unsigned seed,
                                                   double q_max = 3.14159265358979323846, double qd_max = 10.0,
                                                   double qdd_max = 50.0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto draw = [&](double scale) {
    Vector v;
    v.resize(joints);
    for (int i = 0; i < joints; ++i) v[i] = scale * u(rng);
    return v;
  };
  std::vector<BasicJointState<Vector>> states;
  states.reserve(std::size_t(n));
  for (int k = 0; k < n; ++k) {
    BasicJointState<Vector> s;
    s.q = draw(q_max);
    s.qd = draw(qd_max);
    s.qdd = draw(qdd_max);
    states.push_back(std::move(s));
  }
  return states;
}

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
