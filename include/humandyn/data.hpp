// The workspace of the algorithms: every buffer a per-call function writes, sized once from a model.
// One Data per character (or per thread); the Model it was made from stays const and shared.
#pragma once

#include "humandyn/detail/body_inertia.hpp"
#include "humandyn/model.hpp"

namespace humandyn {

/// An external wrench on a link: force and moment about the link frame's origin, in the link frame,
/// applied by the environment to the link (e.g. the weight of a load held in the hand): force in N,
/// moment in N m.
template <class S>
struct Wrench {
  Vec3<S> force = Vec3<S>::Zero();
  Vec3<S> moment = Vec3<S>::Zero();
};

/// A spatial vector (angular; linear) and a spatial matrix (Featherstone 2008, ch. 2).
template <class S>
using SpatialVector = Eigen::Matrix<S, 6, 1>;
template <class S>
using SpatialMatrix = Eigen::Matrix<S, 6, 6>;

/// The workspace of the algorithms for one model: every buffer a per-call function writes, sized once.
/// Per-link entries are in the link's own frame unless said otherwise; vectors indexed by joint have nj entries.
template <class Model>
struct Data {
  using S = typename Model::scalar_type;
  static constexpr int nj = Model::nj;
  template <class T>
  using Links = PerJoint<T, nj>;
  using JointVector = typename Model::JointVector;
  using MassMatrix = Eigen::Matrix<S, nj, nj>;

  explicit Data(const Model& model) {
    if constexpr (nj == Eigen::Dynamic) {
      const auto n = std::size_t(model.size());
      for (auto* links : {&w, &wd, &acc_origin, &f, &n_o, &com_world, &g_link}) links->assign(n, Vec3<S>::Zero());
      g_origin.assign(n, S(0));
      oMi.assign(n, Pose<S>{});
      cos_q.assign(n, S(1));
      sin_q.assign(n, S(0));
      tau.setZero(model.size());
    } else {
      (void)model;
      tau.setZero();
    }
    size_dynamics(model.size());
  }

  // inverse dynamics (rnea.hpp), each in the link's own frame
  Links<Vec3<S>> w{};           // angular velocity of link i
  Links<Vec3<S>> wd{};          // angular acceleration of link i
  Links<Vec3<S>> acc_origin{};  // linear (classical) acceleration of link i's origin, gravity included as -g
  Links<Vec3<S>> f{};           // force link i receives from its parent
  Links<Vec3<S>> n_o{};         // moment link i receives from its parent, about link i's origin
  Links<S> cos_q{}, sin_q{};    // cos and sin of theta_i + q_i, from each algorithm's first sweep, for its own passes
  typename Model::JointVector tau;  // joint torques (N m)

  // forward kinematics (kinematics.hpp), in the world
  Links<Pose<S>> oMi{};           // pose of link i's frame
  Links<Vec3<S>> com_world{};     // centre of mass of link i
  Vec3<S> com = Vec3<S>::Zero();  // whole-body centre of mass (moving links and base body)

  // mass matrix, bias and forward dynamics (crba.hpp, ldlt.hpp, aba.hpp, forward_dynamics.hpp)
  MassMatrix M;   // joint-space mass matrix (nj x nj), symmetric; zero between joints on different branches
  MassMatrix L;   // factor of M (+ diagonal) = L^T D L: unit lower triangular, L(i, j) != 0 only for j an ancestor of i
  JointVector D;  // the diagonal factor (nj)
  JointVector nle;  // nonlinear effects, the bias C(q, qd) qd + g(q): the torques that give qdd = 0 (nj)
  JointVector qdd;  // joint accelerations from forward dynamics (nj)

  // composite rigid bodies (crba.hpp): the subtree joint i carries, in link i's frame about its origin
  Links<detail::BodyInertia<S>> Ic{};

  // mechanical energy (energy.hpp)
  Links<Vec3<S>> g_link{};  // gravity in link i's frame (m/s^2)
  Links<S> g_origin{};      // g . (origin of link i in the world) (m^2/s^2)

  // articulated bodies (aba.hpp) and link velocities (energy.hpp): spatial (angular; linear) vectors in
  // link i's frame about its origin
  Links<SpatialVector<S>> v{};   // velocity of link i
  Links<SpatialVector<S>> c{};   // velocity-product acceleration v_i x S_i qd_i
  Links<SpatialVector<S>> a{};   // acceleration of link i
  Links<SpatialMatrix<S>> IA{};  // articulated-body inertia of link i; after the inward pass, IA_i - U_i U_i^T / D_i
  Links<SpatialVector<S>> pA{};  // articulated-body bias force of link i
  Links<SpatialVector<S>> U{};   // IA_i S_i
  JointVector u;                 // tau_i - S_i . pA_i (nj)
  JointVector D_inv;             // 1 / (S_i . IA_i S_i) (nj)

 private:
  void size_dynamics(Eigen::Index n) {
    M.setZero(n, n);
    L.setZero(n, n);
    for (auto* x : {&D, &nle, &qdd, &u, &D_inv}) x->setZero(n);
    if constexpr (nj == Eigen::Dynamic) {
      const auto k = std::size_t(n);
      for (auto* x : {&v, &c, &a, &pA, &U}) x->assign(k, SpatialVector<S>::Zero());
      Ic.assign(k, detail::BodyInertia<S>{});
      IA.assign(k, SpatialMatrix<S>::Zero());
    } else {
      for (auto* x : {&v, &c, &a, &pA, &U})
        for (auto& e : *x) e.setZero();
      Ic.fill(detail::BodyInertia<S>{});
      for (auto& e : IA) e.setZero();
    }
  }
};

/// One external wrench per link, indexed like the joints (rnea, nonlinear_effects, aba, forward_dynamics).
template <class Model>
using LinkWrenches = PerJoint<Wrench<typename Model::scalar_type>, Model::nj>;

}  // namespace humandyn
