// KDL's tree solver as a variant and as the per-character work of the real-time loop: the same model
// (support/kdl_tree.hpp builds it; KDL's joint i is the model's joint i), the same states.
// Everything including this header must be compiled with flags compatible with Debian's KDL (no
// -march=native), since Eigen objects cross the library boundary.
#pragma once

#include "bench/variants.hpp"
#include "support/kdl_tree.hpp"

#include <kdl/jntarray.hpp>
#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include <memory>
#include <stdexcept>

namespace humandyn::bench {

// A KDL tree with its inverse dynamics solver (which keeps a reference to the tree: both live here).
struct KdlTreeDynamics {
  explicit KdlTreeDynamics(const ModelDescription<double>& d)
      : tree(testing::kdl_tree(d)),
        solver(tree, testing::kdl_gravity(d)),
        n(tree.getNrOfJoints()),
        q(n),
        qd(n),
        qdd(n),
        tau(n) {}
  KdlTreeDynamics(const KdlTreeDynamics&) = delete;
  KdlTreeDynamics& operator=(const KdlTreeDynamics&) = delete;

  // tau = ID(q, qd, qdd) on KDL's own arrays (what the timing loops call).
  void solve(const KDL::JntArray& jq, const KDL::JntArray& jqd, const KDL::JntArray& jqdd, KDL::JntArray& out) {
    if (solver.CartToJnt(jq, jqd, jqdd, no_wrenches, out) < 0) throw std::runtime_error("KDL TreeIdSolver_RNE failed");
  }

  KDL::Tree tree;
  KDL::TreeIdSolver_RNE solver;
  unsigned n;
  KDL::JntArray q, qd, qdd, tau;
  KDL::WrenchMap no_wrenches;
};

inline KDL::JntArray to_jnt_array(const Eigen::VectorXd& v) {
  KDL::JntArray a(unsigned(v.size()));
  a.data = v;
  return a;
}

// KDL::TreeIdSolver_RNE as an inverse dynamics variant (double).
inline Variant kdl_tree_id_variant(const ModelDescription<double>& description) {
  auto kdl = std::make_shared<KdlTreeDynamics>(description);
  Variant v;
  v.name = "ID full double KDL tree";
  v.problem = Problem::InverseDynamics;
  v.scalar = "double";
  v.engine = "KDL";
  v.evaluate = [kdl](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                     Eigen::VectorXd& out) {
    kdl->q.data = q;
    kdl->qd.data = qd;
    kdl->qdd.data = qdd;
    kdl->solve(kdl->q, kdl->qd, kdl->qdd, kdl->tau);
    out = kdl->tau.data;
  };
  v.time = [kdl](const Workload& w, double seconds) {
    std::vector<KDL::JntArray> q, qd, qdd;
    for (int s = 0; s < w.size(); ++s) {
      q.push_back(to_jnt_array(w.q[std::size_t(s)]));
      qd.push_back(to_jnt_array(w.qd[std::size_t(s)]));
      qdd.push_back(to_jnt_array(w.x[std::size_t(s)]));
    }
    return ns_per_call(w.size(), seconds, [&](int i) {
      kdl->solve(q[std::size_t(i)], qd[std::size_t(i)], qdd[std::size_t(i)], kdl->tau);
      do_not_optimize(kdl->tau);
    });
  };
  return v;
}

}  // namespace humandyn::bench
