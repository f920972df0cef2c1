// Analytical derivatives of the dynamics:
//   rnea_derivatives                  dtau/dq and dtau/dqd of inverse dynamics (dtau/dqdd is M), fixed base;
//   forward_dynamics_derivatives      dqdd/dq = -M^-1 dtau/dq, dqdd/dqd = -M^-1 dtau/dqd, dqdd/dtau = M^-1;
//   floating_rnea_derivatives         the floating form's joint torques and base wrench (floating_rnea)
//                                     with respect to q, qd and the base velocity.
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
//   B_i psi = dI_i/dt psi + psi x* (I_i v_i)    dI_i/dt = v_i x* I_i - I_i v_i x, the inertia's rate as it moves
// and over the subtree of i the composites F_i = sum f_k (tau_i = S_i . F_i), Ic_i = sum I_k, Bc_i = sum B_k.
// Then, for j = i or an ancestor of i (the matrices are zero between joints on different branches):
//   dtau_i/dq_j  = S_i . (Ic_i S''_j + Bc_i S'_j)      dtau_j/dq_i  = S_j . (S_i x* F_i + Ic_i S''_i + Bc_i S'_i)
//   dtau_i/dqd_j = S_i . (2 Ic_i S'_j + Bc_i S_j)      dtau_j/dqd_i = S_j . (2 Ic_i S'_i + Bc_i S_i)
// (the second column for j a proper ancestor of i). A spatial inertia is ten numbers (mass, first moment,
// rotational inertia about the origin: detail/body_inertia.hpp), and so is its rate (whose mass is 0); the
// rate term psi x* h is linear in the momentum h, so Bc_i is the summed rate and the summed momentum: no
// 6 x 6 matrix is formed. Two passes, like rnea; each entry is two dot products along the ancestor walks,
// so the cost is O(n) per-link work plus O(n depth) dot products.
//
// The floating form runs the same passes with the base moving (see floating_rnea_derivatives).
// Forward dynamics is M qdd = tau - h(q, qd), so dqdd/dx = -M^-1 dtau/dx at the qdd it gives: the
// derivatives of rnea at that qdd go through the tree-sparse L^T D L factorisation (ldlt.hpp) that
// forward dynamics leaves in data.
#pragma once

#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/algorithm/ldlt.hpp"
#include "humandyn/data.hpp"
#include "humandyn/detail/body_inertia.hpp"
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
  template <class T>
  using Links = typename Data<Model>::template Links<T>;
  using JointMatrix = typename Data<Model>::MassMatrix;  // nj x nj

  explicit DerivativeData(const Model& model) {
    const Eigen::Index n = model.size();
    if constexpr (nj == Eigen::Dynamic) body.resize(std::size_t(n));
    for (int i = 0; i < n; ++i) body[std::size_t(i)] = detail::link_inertia(model.joint(i));
    for (auto* m : {&dtau_dq, &dtau_dqd, &dqdd_dq, &dqdd_dqd, &dqdd_dtau}) m->setZero(n, n);
    tau.setZero(n);
    if constexpr (nj == Eigen::Dynamic) {
      const auto k = std::size_t(n);
      R.assign(k, Mat3<S>::Identity());
      p.assign(k, Vec3<S>::Zero());
      for (auto* x : {&axis, &axis_dot, &axis_ddot, &v, &a, &F, &hc}) x->assign(k, SpatialVector<S>::Zero());
      for (auto* x : {&Ic, &Ic_dot}) x->assign(k, detail::BodyInertia<S>{});
    }
  }

  // results
  JointMatrix dtau_dq;              ///< dtau/dq (N m / rad, nj x nj): entry (i, j) = dtau_i / dq_j
  JointMatrix dtau_dqd;             ///< dtau/dqd (N m s / rad, nj x nj)
  typename Model::JointVector tau;  ///< the torques rnea gives at the same state (N m, nj)
  JointMatrix dqdd_dq;              ///< dqdd/dq (1/s^2, nj x nj), from forward_dynamics_derivatives
  JointMatrix dqdd_dqd;             ///< dqdd/dqd (1/s, nj x nj)
  JointMatrix dqdd_dtau;            ///< dqdd/dtau = M^-1 (1 / (kg m^2), nj x nj), symmetric

  // each link's inertia about its origin in its frame, from the model
  Links<detail::BodyInertia<S>> body{};
  // the passes' workspace, per link, in the base frame
  Links<Mat3<S>> R{};                      // orientation of link i's frame
  Links<Vec3<S>> p{};                      // origin of link i's frame (m)
  Links<SpatialVector<S>> axis{};          // S_i, joint i's motion subspace
  Links<SpatialVector<S>> axis_dot{};      // S'_i = v_lambda x S_i
  Links<SpatialVector<S>> axis_ddot{};     // S''_i = a_lambda x S_i + v_lambda x S'_i
  Links<SpatialVector<S>> v{};             // velocity of link i
  Links<SpatialVector<S>> a{};             // spatial acceleration of link i, gravity included as -g
  Links<SpatialVector<S>> F{};             // f_i, then summed over i's subtree
  Links<SpatialVector<S>> hc{};            // momentum I_i v_i, then summed over i's subtree
  Links<detail::BodyInertia<S>> Ic{};      // I_i, then summed over i's subtree
  Links<detail::BodyInertia<S>> Ic_dot{};  // dI_i/dt, then summed over i's subtree
};

namespace detail {

// I x for the spatial inertia I = [[J, [h]x], [-[h]x, m 1]] kept as its ten numbers
template <class S>
HUMANDYN_ALWAYS_INLINE SpatialVector<S> times(const BodyInertia<S>& B, const SpatialVector<S>& x) noexcept {
  const Vec3<S> w = x.template head<3>(), u = x.template tail<3>();
  const Vec3<S> Jw(B.xx * w.x() + B.xy * w.y() + B.xz * w.z(), B.xy * w.x() + B.yy * w.y() + B.yz * w.z(),
                   B.xz * w.x() + B.yz * w.y() + B.zz * w.z());
  return spatial<S>(Jw + B.h.cross(u), B.m * u - B.h.cross(w));
}

// dI/dt = v x* I - I v x of a body moving with velocity v = (w; u): again a spatial inertia, of mass 0,
// first moment w x h + m u and rotational part [w]x J - J [w]x - (h u^T + u h^T) + 2 (u . h) 1.
template <class S>
HUMANDYN_ALWAYS_INLINE BodyInertia<S> inertia_rate(const BodyInertia<S>& B, const SpatialVector<S>& v) noexcept {
  const Vec3<S> w = v.template head<3>(), u = v.template tail<3>();
  // the columns of A = [w]x J; the rotational part of the rate is A + A^T, less the shift terms
  const Vec3<S> a0 = w.cross(Vec3<S>(B.xx, B.xy, B.xz)), a1 = w.cross(Vec3<S>(B.xy, B.yy, B.yz)),
                a2 = w.cross(Vec3<S>(B.xz, B.yz, B.zz));
  const S uh = S(2) * u.dot(B.h);
  BodyInertia<S> R;
  R.h = w.cross(B.h) + B.m * u;
  R.xx = S(2) * a0.x() - S(2) * u.x() * B.h.x() + uh;
  R.yy = S(2) * a1.y() - S(2) * u.y() * B.h.y() + uh;
  R.zz = S(2) * a2.z() - S(2) * u.z() * B.h.z() + uh;
  R.xy = a1.x() + a0.y() - (u.x() * B.h.y() + u.y() * B.h.x());
  R.xz = a2.x() + a0.z() - (u.x() * B.h.z() + u.z() * B.h.x());
  R.yz = a2.y() + a1.z() - (u.y() * B.h.z() + u.z() * B.h.y());
  return R;
}

// The forward step of joint i: link i's pose, axis, motion and own inertia terms, in the base frame.
template <Twist T, class Model, class Mounted, class Massless>
HUMANDYN_NOINLINE HUMANDYN_FLATTEN inline void derivatives_forward_step(
    const Model& model, DerivativeData<Model>& dd, int i, typename Model::scalar_type q, typename Model::scalar_type qd,
    typename Model::scalar_type qdd, const SpatialVector<typename Model::scalar_type>& v_base,
    const SpatialVector<typename Model::scalar_type>& a_base, Mounted mounted, Massless massless) noexcept {
  using S = typename Model::scalar_type;
  const auto& j = model.joint(i);
  const auto k = std::size_t(i);

  // joint i's DH base frame b_i: the parent link's frame (or the base's), through the mount
  Mat3<S> Rb = Mat3<S>::Identity();
  Vec3<S> pb = Vec3<S>::Zero();
  SpatialVector<S> v_parent = v_base, a_parent = a_base;
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
    dd.hc[k].setZero();
    dd.Ic[k] = BodyInertia<S>{};
    dd.Ic_dot[k] = BodyInertia<S>{};
    return;
  }
  // the link's inertia about the base origin, its rate, its momentum and the force its motion demands
  const BodyInertia<S> I = shifted(rotated(dd.body[k], dd.R[k]), dd.p[k]);
  const SpatialVector<S> h = times(I, vi);
  dd.Ic[k] = I;
  dd.Ic_dot[k] = inertia_rate(I, vi);
  dd.hc[k] = h;
  dd.F[k] = times(I, ai) + cross_force(vi, h);
}

// For joint k once the inward pass has summed its subtree: the row vectors r1 = Ic_k S_k and
// r2 = Bc_k^T S_k = Ic_dot_k S_k - S_k x* hc_k, and dF/dq_k and dF/dqd_k, the derivatives of the force
// the subtree needs (the same for every force that sums it), with Bc psi = Ic_dot psi + psi x* hc.
template <class Model>
struct SubtreeDerivatives {
  using S = typename Model::scalar_type;
  SpatialVector<S> r1, r2, dF_dq, dF_dqd;

  HUMANDYN_ALWAYS_INLINE SubtreeDerivatives(const DerivativeData<Model>& dd, std::size_t k) noexcept {
    const SpatialVector<S>& Sk = dd.axis[k];
    const SpatialVector<S> Ic_dot_S = times(dd.Ic_dot[k], Sk), S_x_hc = cross_force(Sk, dd.hc[k]);
    r1 = times(dd.Ic[k], Sk);
    r2 = Ic_dot_S - S_x_hc;
    dF_dq = cross_force(Sk, dd.F[k]) + times(dd.Ic[k], dd.axis_ddot[k]) + times(dd.Ic_dot[k], dd.axis_dot[k]) +
            cross_force(dd.axis_dot[k], dd.hc[k]);
    dF_dqd = S(2) * times(dd.Ic[k], dd.axis_dot[k]) + Ic_dot_S + S_x_hc;
  }
};

// The backward step of joint i, its subtree's composites complete: row i and column i of both
// matrices over i's ancestors, then the composites joined to the parent's.
template <class Model>
HUMANDYN_NOINLINE HUMANDYN_FLATTEN inline void derivatives_backward_step(const Model& model, DerivativeData<Model>& dd,
                                                                         int i) noexcept {
  using S = typename Model::scalar_type;
  const auto k = std::size_t(i);
  const SpatialVector<S>& Si = dd.axis[k];
  dd.tau[i] = Si.dot(dd.F[k]);

  // row i over j = i and its ancestors, column i over the ancestors
  const SubtreeDerivatives<Model> d(dd, k);
  const SpatialVector<S>&r1 = d.r1, &r2 = d.r2, &dF_dq = d.dF_dq, &dF_dqd = d.dF_dqd;
  dd.dtau_dq(i, i) = r1.dot(dd.axis_ddot[k]) + r2.dot(dd.axis_dot[k]);
  dd.dtau_dqd(i, i) = S(2) * r1.dot(dd.axis_dot[k]) + r2.dot(Si);
  for (int j = parent_of(model, i); j >= 0; j = parent_of(model, j)) {
    const auto jk = std::size_t(j);
    dd.dtau_dq(i, j) = r1.dot(dd.axis_ddot[jk]) + r2.dot(dd.axis_dot[jk]);
    dd.dtau_dqd(i, j) = S(2) * r1.dot(dd.axis_dot[jk]) + r2.dot(dd.axis[jk]);
    dd.dtau_dq(j, i) = dd.axis[jk].dot(dF_dq);
    dd.dtau_dqd(j, i) = dd.axis[jk].dot(dF_dqd);
  }

  const int parent = parent_of(model, i);
  if (parent < 0) return;
  const auto pk = std::size_t(parent);
  dd.F[pk] += dd.F[k];
  dd.hc[pk] += dd.hc[k];
  dd.Ic[pk] += dd.Ic[k];
  dd.Ic_dot[pk] += dd.Ic_dot[k];
}

// Both passes with the base moving at v_base with spatial acceleration a_base (gravity included), base frame.
template <class Model, class Q, class QD, class QDD>
inline void derivative_passes(const Model& model, DerivativeData<Model>& dd,
                              const SpatialVector<typename Model::scalar_type>& v_base,
                              const SpatialVector<typename Model::scalar_type>& a_base, const Eigen::MatrixBase<Q>& q,
                              const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<QDD>& qdd) noexcept {
  using S = typename Model::scalar_type;
  eigen_assert(q.size() == model.size() && qd.size() == model.size() && qdd.size() == model.size());
  for_each_joint(model, [&](auto i, auto T, auto mounted, auto massless) {
    derivatives_forward_step<decltype(T)::value>(model, dd, int(i), S(q[int(i)]), S(qd[int(i)]), S(qdd[int(i)]), v_base,
                                                 a_base, mounted, massless);
  });
  for_each_joint_reverse(model, [&](auto i, auto, auto, auto) { derivatives_backward_step(model, dd, int(i)); });
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
inline const typename DerivativeData<Model>::JointMatrix& rnea_derivatives(const Model& model,
                                                                           DerivativeData<Model>& dd,
                                                                           const Eigen::MatrixBase<Q>& q,
                                                                           const Eigen::MatrixBase<QD>& qd,
                                                                           const Eigen::MatrixBase<QDD>& qdd) noexcept {
  using S = typename Model::scalar_type;
  const SpatialVector<S> a_base =
      detail::spatial<S>(Vec3<S>::Zero(), -(model.base_pose().R.transpose() * model.gravity()));
  detail::derivative_passes(model, dd, SpatialVector<S>::Zero(), a_base, q, qd, qdd);
  return dd.dtau_dq;
}

/// The mass matrix M(q) = dtau/dqdd at the angles of the last rnea_derivatives call, from the subtree
/// inertias that call left in dd: M_ij = S_j . Ic_i S_i for j = i or an ancestor of i (Featherstone 2008,
/// §6.2, in the base frame), zero between joints on different branches. Cheaper than crba when the
/// derivatives are wanted anyway (a backward-Euler Jacobian, integrators.hpp).
/// \param M  receives the mass matrix (kg m^2, nj x nj), both triangles
template <class Model, class Out>
inline void derivatives_mass_matrix(const Model& model, const DerivativeData<Model>& dd,
                                    Eigen::MatrixBase<Out>& M) noexcept {
  using S = typename Model::scalar_type;
  eigen_assert(M.rows() == model.size() && M.cols() == model.size());
  M.setZero();
  detail::for_each_joint(model, [&](auto i, auto, auto, auto) {
    const auto k = std::size_t(i);
    const SpatialVector<S> r1 = detail::times(dd.Ic[k], dd.axis[k]);
    M(int(i), int(i)) = r1.dot(dd.axis[k]);
    detail::for_each_ancestor_inline(
        model, i, [&](auto j) { M(int(i), int(j)) = M(int(j), int(i)) = r1.dot(dd.axis[std::size_t(int(j))]); });
  });
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
  solve_mass_matrix(model, data, dd.dqdd_dq);
  dd.dqdd_dqd = -dd.dtau_dqd;
  solve_mass_matrix(model, data, dd.dqdd_dqd);
  dd.dqdd_dtau.setIdentity();
  solve_mass_matrix(model, data, dd.dqdd_dtau);
  return dd.dqdd_dq;
}

/// The workspace and results of floating_rnea_derivatives: the joints' (DerivativeData's dtau_dq,
/// dtau_dqd, tau) and the base's. The base velocity v_b is (angular; linear) in the base frame, as for
/// floating_rnea; the base wrench is (moment about the base origin; force) in the base frame.
template <class Model>
struct FloatingDerivativeData : DerivativeData<Model> {
  using S = typename Model::scalar_type;
  static constexpr int nj = Model::nj;

  explicit FloatingDerivativeData(const Model& model) : DerivativeData<Model>(model) {
    base_body = detail::origin_form(model.description().base_body);
    dtau_dvb.setZero(model.size(), 6);
    dwrench_dq.setZero(6, model.size());
    dwrench_dqd.setZero(6, model.size());
  }

  Eigen::Matrix<S, nj, 6> dtau_dvb;     ///< dtau/dv_b (N m s, N s; nj x 6)
  Eigen::Matrix<S, 6, nj> dwrench_dq;   ///< d(base wrench)/dq (N m / rad, N / rad; 6 x nj)
  Eigen::Matrix<S, 6, nj> dwrench_dqd;  ///< d(base wrench)/dqd (6 x nj)
  SpatialMatrix<S> dwrench_dvb;         ///< d(base wrench)/dv_b (6 x 6)
  SpatialVector<S> base_wrench;         ///< the base wrench floating_rnea gives at the same state
  detail::BodyInertia<S> base_body;     ///< the base body's inertia about the base origin, from the model
};

/// The partial derivatives of floating-base inverse dynamics (floating_rnea, Terms::Full, no external
/// wrenches) at the state (X, v_b, q, qd) and accelerations (a_b, qdd), the base pose X and acceleration
/// a_b held: the joint torques' fdd.dtau_dq, fdd.dtau_dqd (nj x nj) and fdd.dtau_dvb (nj x 6), and the
/// base wrench's fdd.dwrench_dq, fdd.dwrench_dqd (6 x nj) and fdd.dwrench_dvb (6 x 6); also the torques
/// (fdd.tau) and the base wrench (fdd.base_wrench) themselves. The base is a 6-DOF joint on the world:
/// its axes are the base frame's, their rate is 0 with respect to the world, and v_b enters each link's
/// velocity: dtau_i/dv_b = (Bc_i^T S_i - v_b x* Ic_i S_i)^T, d(wrench)/dv_b = Ic_0 [v_b]x + Bc_0 over
/// the whole body with the base body.
/// \param X    base pose in the world
/// \param v_b  base velocity (rad/s; m/s), base frame
/// \param a_b  base acceleration (rad/s^2; m/s^2), base frame (the derivative of v_b's coordinates)
/// \param q, qd, qdd  joint angles (rad), velocities (rad/s), accelerations (rad/s^2), nj each
template <class Model, class Q, class QD, class QDD>
inline void floating_rnea_derivatives(const Model& model, FloatingDerivativeData<Model>& fdd,
                                      const Pose<typename Model::scalar_type>& X,
                                      const SpatialVector<typename Model::scalar_type>& v_b,
                                      const SpatialVector<typename Model::scalar_type>& a_b,
                                      const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                                      const Eigen::MatrixBase<QDD>& qdd) noexcept {
  using S = typename Model::scalar_type;
  using detail::cross_force;
  using detail::times;
  SpatialVector<S> a0 = a_b;
  a0.template tail<3>() -= X.R.transpose() * model.gravity();
  detail::derivative_passes(model, fdd, v_b, a0, q, qd, qdd);

  // the base body, then each subtree hanging from the base: what the base carries
  const SpatialVector<S> hb = times(fdd.base_body, v_b);
  fdd.base_wrench = times(fdd.base_body, a0) + cross_force(v_b, hb);
  detail::BodyInertia<S> Ic = fdd.base_body, Ic_dot = detail::inertia_rate(fdd.base_body, v_b);
  SpatialVector<S> hc = hb;
  detail::for_each_joint(model, [&](auto i, auto, auto, auto) {
    const auto k = std::size_t(i);
    const detail::SubtreeDerivatives<Model> d(fdd, k);
    fdd.dtau_dvb.row(int(i)) = (d.r2 - cross_force(v_b, d.r1)).transpose();
    fdd.dwrench_dq.col(int(i)) = d.dF_dq;
    fdd.dwrench_dqd.col(int(i)) = d.dF_dqd;
    if (detail::parent_of(model, i) >= 0) return;
    fdd.base_wrench += fdd.F[k];
    Ic += fdd.Ic[k];
    Ic_dot += fdd.Ic_dot[k];
    hc += fdd.hc[k];
  });
  for (int c = 0; c < 6; ++c) {
    const SpatialVector<S> e = SpatialVector<S>::Unit(c);
    fdd.dwrench_dvb.col(c) = times(Ic, detail::cross_motion(v_b, e)) + times(Ic_dot, e) + cross_force(e, hc);
  }
}

}  // namespace humandyn
