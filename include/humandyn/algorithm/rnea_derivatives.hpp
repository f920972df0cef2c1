// Analytical derivatives of the dynamics of the stance-rooted (fixed-base) body:
//   rnea_derivatives                  dtau/dq and dtau/dqd of inverse dynamics (dtau/dqdd is M);
//   forward_dynamics_derivatives      dqdd/dq = -M^-1 dtau/dq, dqdd/dqd = -M^-1 dtau/dqd, dqdd/dtau = M^-1.
//
// Carpentier and Mansard's recursive derivatives of Newton-Euler ("Analytical derivatives of rigid body
// dynamics algorithms", RSS 2018), in the base frame 0 (the stance foot's frame, where joint 1's DH base
// frame sits), spatial vectors (angular; linear) about its origin. There a quantity carried by the
// subtree of joint j changes with q_j by the spatial cross product with j's axis, which makes every
// column a few products with subtree sums. For joint i with parent link lambda:
//   S_i = (z_i; p_i x z_i)                      axis of joint i (z of its DH base frame b_i, through b_i's origin p_i)
//   v_i = v_lambda + S_i qd_i                   velocity of link i
//   a_i = a_lambda + S_i qdd_i + S'_i qd_i      spatial acceleration, gravity entered as a_0 = (0; -g)
//   S'_i = v_lambda x S_i                       dS_i/dt (S_i is fixed in the parent link)
//   S''_i = a_lambda x S_i + v_lambda x S'_i    d^2 S_i/dt^2
//   f_i = I_i a_i + v_i x* I_i v_i              the force link i's motion demands
//   B_i psi = (v_i x* I_i - I_i v_i x) psi + psi x* (I_i v_i)   (dI_i/dt, plus the momentum's turn)
// and over the subtree of i the composites F_i = sum f_k (tau_i = S_i . F_i), Ic_i = sum I_k, Bc_i = sum B_k.
// Then, for j = i or an ancestor of i (the matrices are zero between joints on different branches):
//   dtau_i/dq_j  = S_i . (Ic_i S''_j + Bc_i S'_j)      dtau_j/dq_i  = S_j . (S_i x* F_i + Ic_i S''_i + Bc_i S'_i)
//   dtau_i/dqd_j = S_i . (2 Ic_i S'_j + Bc_i S_j)      dtau_j/dqd_i = S_j . (2 Ic_i S'_i + Bc_i S_i)
// (the second column for j a proper ancestor of i). Two passes, like rnea; each entry is two dot
// products along the ancestor walks, so the cost is O(n) 6 x 6 work plus O(n depth) dot products.
//
// Forward dynamics is M qdd = tau - h(q, qd), so dqdd/dx = -M^-1 dtau/dx at the qdd it gives: the
// derivatives of rnea at that qdd go through the tree-sparse L^T D L factorisation (ldlt.hpp) that
// forward dynamics leaves in data.
#pragma once

#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/algorithm/ldlt.hpp"
#include "humandyn/data.hpp"
#include "humandyn/detail/dh.hpp"
#include "humandyn/detail/joint_loop.hpp"
#include "humandyn/detail/spatial.hpp"
#include "humandyn/detail/tree.hpp"

#include <Eigen/Core>

namespace humandyn {

/// The workspace and results of rnea_derivatives and forward_dynamics_derivatives, sized once from a
/// model (nj joints). Per-link quantities are in the base frame, about its origin.
template <class Model>
struct DerivativeData {
  using S = typename Model::scalar_type;
  static constexpr int nj = Model::nj;
  template <class T> using Links = PerJoint<T, nj>;
  using JointMatrix = Eigen::Matrix<S, nj, nj>;

  explicit DerivativeData(const Model& model) {
    const Eigen::Index n = model.size();
    for (auto* m : {&dtau_dq, &dtau_dqd, &dqdd_dq, &dqdd_dqd, &dqdd_dtau}) m->setZero(n, n);
    tau.setZero(n);
    if constexpr (nj == Eigen::Dynamic) {
      const auto k = std::size_t(n);
      R.assign(k, Mat3<S>::Identity());
      p.assign(k, Vec3<S>::Zero());
      for (auto* x : {&axis, &axis_dot, &axis_ddot, &v, &a, &F}) x->assign(k, SpatialVector<S>::Zero());
      for (auto* x : {&Ic, &Bc}) x->assign(k, SpatialMatrix<S>::Zero());
    }
  }

  // results
  JointMatrix dtau_dq;    ///< dtau/dq (N m / rad, nj x nj): entry (i, j) = dtau_i / dq_j
  JointMatrix dtau_dqd;   ///< dtau/dqd (N m s / rad, nj x nj)
  typename Model::JointVector tau;  ///< the torques rnea gives at the same state (N m, nj)
  JointMatrix dqdd_dq;    ///< dqdd/dq (1/s^2, nj x nj), from forward_dynamics_derivatives
  JointMatrix dqdd_dqd;   ///< dqdd/dqd (1/s, nj x nj)
  JointMatrix dqdd_dtau;  ///< dqdd/dtau = M^-1 (1 / (kg m^2), nj x nj), symmetric

  // the passes' workspace, per link, in the base frame
  Links<Mat3<S>> R{};                 // orientation of link i's frame
  Links<Vec3<S>> p{};                 // origin of link i's frame (m)
  Links<SpatialVector<S>> axis{};     // S_i, joint i's motion subspace
  Links<SpatialVector<S>> axis_dot{};   // S'_i = v_lambda x S_i
  Links<SpatialVector<S>> axis_ddot{};  // S''_i = a_lambda x S_i + v_lambda x S'_i
  Links<SpatialVector<S>> v{};        // velocity of link i
  Links<SpatialVector<S>> a{};        // spatial acceleration of link i, gravity included as -g
  Links<SpatialVector<S>> F{};        // f_i, then summed over i's subtree
  Links<SpatialMatrix<S>> Ic{};       // I_i, then summed over i's subtree
  Links<SpatialMatrix<S>> Bc{};       // B_i, then summed over i's subtree
};

namespace detail {

// The forward step of joint i: link i's pose, axis, motion and own inertia terms, in the base frame.
template <Twist T, class Model, class Mounted, class Massless>
HUMANDYN_NOINLINE inline void derivatives_forward_step(const Model& model, DerivativeData<Model>& dd, int i,
                                                       typename Model::scalar_type q, typename Model::scalar_type qd,
                                                       typename Model::scalar_type qdd,
                                                       const SpatialVector<typename Model::scalar_type>& a_base,
                                                       Mounted mounted, Massless massless) noexcept {
  using S = typename Model::scalar_type;
  const auto& j = model.joint(i);
  const auto k = std::size_t(i);

  // joint i's DH base frame b_i: the parent link's frame (or the base's), through the mount
  Mat3<S> Rb = Mat3<S>::Identity();
  Vec3<S> pb = Vec3<S>::Zero();
  SpatialVector<S> v_parent = SpatialVector<S>::Zero(), a_parent = a_base;
  if (j.parent >= 0) {
    const auto pk = std::size_t(j.parent);
    Rb = dd.R[pk];
    pb = dd.p[pk];
    v_parent = dd.v[pk];
    a_parent = dd.a[pk];
  }
  if (mounted) {
    pb += Rb * j.mount_p;
    Rb = Rb * j.mount_R;
  }

  // link i's frame: Rz(theta + q), then Tz(d) Tx(a), then Rx(alpha)
  S c, s;
  cos_sin(S(j.theta + q), c, s);
  const Vec3<S> x = c * Rb.col(0) + s * Rb.col(1), y = c * Rb.col(1) - s * Rb.col(0), z = Rb.col(2);
  dd.R[k] = rotate_columns_x<T>(x, y, z, j.ca, j.sa);
  dd.p[k] = pb + j.a * x + j.d * z;

  // the axis and its time derivatives; the link's motion
  const SpatialVector<S> Si = spatial<S>(z, pb.cross(z));
  const SpatialVector<S> Si_dot = cross_motion(v_parent, Si);
  dd.axis[k] = Si;
  dd.axis_dot[k] = Si_dot;
  dd.axis_ddot[k] = cross_motion(a_parent, Si) + cross_motion(v_parent, Si_dot);
  const SpatialVector<S> vi = v_parent + Si * qd;
  const SpatialVector<S> ai = a_parent + Si * qdd + Si_dot * qd;
  dd.v[k] = vi;
  dd.a[k] = ai;

  if (massless) {
    dd.F[k].setZero();
    dd.Ic[k].setZero();
    dd.Bc[k].setZero();
    return;
  }
  // the spatial inertia about the base origin: [[J, [h]x], [[h]x^T, m 1]], h = m c the first moment
  const Mat3<S>& Ri = dd.R[k];
  const Vec3<S> com = Ri * j.com + dd.p[k];
  const Vec3<S> h = j.mass * com;
  const Mat3<S> hx = skew(h);
  SpatialMatrix<S>& I = dd.Ic[k];
  I.template topLeftCorner<3, 3>() = Ri * j.inertia * Ri.transpose() - hx * skew(com);
  I.template topRightCorner<3, 3>() = hx;
  I.template bottomLeftCorner<3, 3>() = -hx;
  I.template bottomRightCorner<3, 3>() = Mat3<S>::Identity() * j.mass;

  // f = I a + v x* I v; B psi = (v x* I) psi + (v x* I)^T psi + psi x* (I v)
  const SpatialVector<S> mom = I * vi;
  dd.F[k] = I * ai + cross_force(vi, mom);
  SpatialMatrix<S> X;
  for (int col = 0; col < 6; ++col) X.col(col) = cross_force<S>(vi, I.col(col));
  SpatialMatrix<S>& B = dd.Bc[k];
  B = X + X.transpose();
  // psi x* mom = -[[ [n]x, [f]x ], [ [f]x, 0 ]] psi for mom = (n; f)
  const Mat3<S> nx = skew<S>(mom.template head<3>()), fx = skew<S>(mom.template tail<3>());
  B.template topLeftCorner<3, 3>() -= nx;
  B.template topRightCorner<3, 3>() -= fx;
  B.template bottomLeftCorner<3, 3>() -= fx;
}

// The backward step of joint i, its subtree's composites complete: row i and column i of both
// matrices over i's ancestors, then the composites joined to the parent's.
template <class Model>
HUMANDYN_NOINLINE inline void derivatives_backward_step(const Model& model, DerivativeData<Model>& dd, int i) noexcept {
  using S = typename Model::scalar_type;
  const auto k = std::size_t(i);
  const SpatialVector<S>& Si = dd.axis[k];
  const SpatialMatrix<S>& Ic = dd.Ic[k];
  const SpatialMatrix<S>& Bc = dd.Bc[k];
  dd.tau[i] = Si.dot(dd.F[k]);

  // row i: dtau_i/dq_j and dtau_i/dqd_j for j = i and its ancestors
  const SpatialVector<S> r1 = Ic * Si;                  // Ic_i S_i (Ic symmetric)
  const SpatialVector<S> r2 = Bc.transpose() * Si;      // Bc_i^T S_i
  const auto row = [&](int jj) {
    const auto jk = std::size_t(jj);
    dd.dtau_dq(i, jj) = r1.dot(dd.axis_ddot[jk]) + r2.dot(dd.axis_dot[jk]);
    dd.dtau_dqd(i, jj) = S(2) * r1.dot(dd.axis_dot[jk]) + r2.dot(dd.axis[jk]);
  };
  row(i);
  // column i: dtau_j/dq_i and dtau_j/dqd_i for the proper ancestors j
  const SpatialVector<S> dF_dq = cross_force(Si, dd.F[k]) + Ic * dd.axis_ddot[k] + Bc * dd.axis_dot[k];
  const SpatialVector<S> dF_dqd = S(2) * (Ic * dd.axis_dot[k]) + Bc * Si;
  for_each_ancestor(model, i, [&](auto jj) {
    row(int(jj));
    const auto& Sj = dd.axis[std::size_t(jj)];
    dd.dtau_dq(int(jj), i) = Sj.dot(dF_dq);
    dd.dtau_dqd(int(jj), i) = Sj.dot(dF_dqd);
  });

  const int parent = parent_of(model, i);
  if (parent < 0) return;
  const auto pk = std::size_t(parent);
  dd.F[pk] += dd.F[k];
  dd.Ic[pk] += Ic;
  dd.Bc[pk] += Bc;
}

}  // namespace detail

/// The partial derivatives of inverse dynamics at (q, qd, qdd), with gravity, the base at rest in its pose:
/// dd.dtau_dq (N m / rad, nj x nj) and dd.dtau_dqd (N m s / rad, nj x nj), entry (i, j) the derivative of
/// tau_i; zero between joints on different branches. dtau/dqdd is the mass matrix (crba). Also leaves the
/// torques rnea(q, qd, qdd) in dd.tau.
/// \param q    joint angles (rad, nj)
/// \param qd   joint velocities (rad/s, nj)
/// \param qdd  joint accelerations (rad/s^2, nj)
/// \return dd.dtau_dq
template <class Model, class Q, class QD, class QDD>
inline const typename DerivativeData<Model>::JointMatrix& rnea_derivatives(const Model& model, DerivativeData<Model>& dd,
                                                                          const Eigen::MatrixBase<Q>& q,
                                                                          const Eigen::MatrixBase<QD>& qd,
                                                                          const Eigen::MatrixBase<QDD>& qdd) noexcept {
  using S = typename Model::scalar_type;
  eigen_assert(q.size() == model.size() && qd.size() == model.size() && qdd.size() == model.size());
  const SpatialVector<S> a_base = detail::spatial<S>(Vec3<S>::Zero(), -(model.base_pose().R.transpose() * model.gravity()));
  detail::for_each_joint(model, [&](auto i, auto T, auto mounted, auto massless) {
    detail::derivatives_forward_step<decltype(T)::value>(model, dd, int(i), S(q[int(i)]), S(qd[int(i)]),
                                                         S(qdd[int(i)]), a_base, mounted, massless);
  });
  detail::for_each_joint_reverse(model, [&](auto i, auto, auto, auto) { detail::derivatives_backward_step(model, dd, int(i)); });
  return dd.dtau_dq;
}

/// The partial derivatives of forward dynamics at (q, qd, tau), with gravity: dd.dqdd_dq (1/s^2, nj x nj),
/// dd.dqdd_dqd (1/s, nj x nj) and dd.dqdd_dtau = M^-1 (1 / (kg m^2), nj x nj). Runs forward dynamics by
/// the mass-matrix method first (data.qdd, data.M, data.L, data.D as forward_dynamics leaves them), then
/// rnea_derivatives at the qdd found (dd.dtau_dq, dd.dtau_dqd, dd.tau = tau), and solves with M's
/// factorisation. M must be regular (see forward_dynamics.hpp).
/// \param q    joint angles (rad, nj)
/// \param qd   joint velocities (rad/s, nj)
/// \param tau  joint torques (N m, nj)
/// \return dd.dqdd_dq
template <class Model, class Q, class QD, class Tau>
inline const typename DerivativeData<Model>::JointMatrix& forward_dynamics_derivatives(
    const Model& model, Data<Model>& data, DerivativeData<Model>& dd, const Eigen::MatrixBase<Q>& q,
    const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<Tau>& tau) noexcept {
  forward_dynamics<FdMethod::MassMatrix, Terms::Full>(model, data, q, qd, tau);
  rnea_derivatives(model, dd, q, qd, data.qdd);
  dd.dqdd_dq = -dd.dtau_dq;
  solve(model, data, dd.dqdd_dq);
  dd.dqdd_dqd = -dd.dtau_dqd;
  solve(model, data, dd.dqdd_dqd);
  dd.dqdd_dtau.setIdentity();
  solve(model, data, dd.dqdd_dtau);
  return dd.dqdd_dq;
}

}  // namespace humandyn
