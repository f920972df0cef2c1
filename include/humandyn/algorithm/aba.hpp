// Forward dynamics by the articulated-body algorithm (Featherstone, RBDA Table 7.1), over the tree of
// DH chains in link frames (detail/spatial.hpp): O(n), no mass matrix.
//   pass 1, base outwards: link velocities v_i, velocity-product accelerations c_i = v_i x S_i qd_i,
//     rigid-body inertias I_i and bias forces p_i = v_i x* I_i v_i - f_ext_i;
//   pass 2, tips inwards: U_i = IA_i S_i, D_i = S_i . U_i, u_i = tau_i - S_i . pA_i; what link i passes to
//     its parent is the articulated inertia IA_i - U_i U_i^T / D_i and the bias pA_i + Ia_i c_i + U_i u_i / D_i;
//     at a branch point the children's contributions add up;
//   pass 3, base outwards: a'_i = i_X_p a_p + c_i, qdd_i = (u_i - U_i . a'_i) / D_i, a_i = a'_i + S_i qdd_i,
//     with gravity entered as the base's acceleration -g.
// A floating base (RBDA Table 9.6) moves at v_0 and is one more body: pass 2 ends at it with IA_0 and
// pA_0, its acceleration is a_0 = -IA_0^-1 pA_0, and pass 3 starts from there. Gravity is then left out
// of every pass (the algorithm runs in a frame falling with the body, where joint accelerations are the
// same) and added to the base's acceleration at the end.
#pragma once

#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/data.hpp"
#include "humandyn/detail/joint_loop.hpp"
#include "humandyn/detail/spatial.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace humandyn {

/// A floating base for the articulated-body algorithm: its pose and velocity in, its articulated
/// inertia and bias force as work space, its acceleration out (spatial, angular; linear, base frame:
/// the time derivative of the velocity's base-frame coordinates).
template <class S>
struct ArticulatedBase {
  Pose<S> pose;                                    ///< base frame in the world
  SpatialVector<S> v = SpatialVector<S>::Zero();   ///< base velocity (rad/s; m/s), base frame
  SpatialMatrix<S> IA = SpatialMatrix<S>::Zero();  ///< articulated inertia of the whole body at the base
  SpatialVector<S> pA = SpatialVector<S>::Zero();  ///< its bias force
  SpatialVector<S> a = SpatialVector<S>::Zero();   ///< the base's acceleration (rad/s^2; m/s^2), gravity included
};

namespace detail {

template <Terms terms, bool with_external, bool floating = false, class Model, class Q, class QD, class Tau>
inline const typename Model::JointVector& aba_impl(
    const Model& model, Data<Model>& data, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
    const Eigen::MatrixBase<Tau>& tau, const LinkWrenches<Model>* fext,
    ArticulatedBase<typename Model::scalar_type>* base = nullptr) noexcept {
  using S = typename Model::scalar_type;
  static_assert(terms != Terms::GravityOnly, "forward dynamics needs the inertial terms: use Full or NoCoriolis");
  eigen_assert(q.size() == model.size() && qd.size() == model.size() && tau.size() == model.size());

  // pass 1: link velocities, velocity-product accelerations, link inertias and bias forces (and the
  // floating base's own)
  if constexpr (floating) {
    base->IA = spatial_inertia(model.description().base_body);
    base->pA.setZero();
    if constexpr (terms == Terms::Full) base->pA = cross_force(base->v, SpatialVector<S>(base->IA * base->v));
  }
  joint_cos_sin(model, q, data.cos_q, data.sin_q);
  for_each_joint(model, [&](auto i, auto T, auto mounted, auto massless) {
    constexpr Twist twist = decltype(T)::value;
    const auto k = std::size_t(i);
    const auto& j = model.joint(int(i));
    const S c = data.cos_q[k], s = data.sin_q[k];

    SpatialVector<S> v = SpatialVector<S>::Zero();
    if constexpr (terms == Terms::Full) {
      const SpatialVector<S> vJ = motion_subspace<twist>(j) * S(qd[int(i)]);
      if (j.parent >= 0)
        v = motion_to_child<twist>(j, mounted, c, s, data.v[std::size_t(j.parent)]);
      else if constexpr (floating)
        v = motion_to_child<twist>(j, mounted, c, s, base->v);
      v += vJ;
      data.v[k] = v;
      data.c[k] = cross_motion(v, vJ);
    }

    if (massless) {
      data.IA[k].setZero();
      data.pA[k].setZero();
    } else {
      data.IA[k] = link_spatial_inertia(j);
      if constexpr (terms == Terms::Full) {
        // I v = (I_o w + h x v, m v - h x w) with h = m com, I_o the rotational inertia about the origin
        const Vec3<S> w = v.template head<3>(), vo = v.template tail<3>(), h = j.h;
        const Vec3<S> n = j.inertia_origin * w + h.cross(vo);
        const Vec3<S> f = j.mass * vo - h.cross(w);
        data.pA[k] = cross_force(v, spatial<S>(n, f));
      } else {
        data.pA[k].setZero();
      }
    }
    if constexpr (with_external) {
      data.pA[k].template head<3>() -= (*fext)[k].moment;
      data.pA[k].template tail<3>() -= (*fext)[k].force;
    }
  });

  // pass 2: articulated inertias and bias forces, tips inwards, summed at the branch points
  for_each_joint_reverse(model, [&](auto i, auto T, auto mounted, auto) {
    constexpr Twist twist = decltype(T)::value;
    const auto k = std::size_t(i);
    const auto& j = model.joint(int(i));
    const SpatialVector<S> Si = motion_subspace<twist>(j);
    const SpatialVector<S> U = inertia_times_subspace<twist>(data.IA[k], j.ca, j.sa, Vec3<S>(Si.template tail<3>()));
    const S D_inv = S(1) / Si.dot(U);
    const S u = S(tau[int(i)]) - Si.dot(data.pA[k]);
    data.U[k] = U;
    data.D_inv[int(i)] = D_inv;
    data.u[int(i)] = u;
    if (j.parent >= 0 || floating) {
      const S c = data.cos_q[k], s = data.sin_q[k];
      SpatialMatrix<S>& Ia = data.IA[k];  // becomes what the parent sees: IA - U U^T / D
      const SpatialVector<S> UD = D_inv * U;
      for (int col = 0; col < 6; ++col) Ia.col(col) -= UD * U[col];
      SpatialVector<S> pa = data.pA[k] + U * (D_inv * u);
      if constexpr (terms == Terms::Full) pa.noalias() += Ia * data.c[k];
      if constexpr (floating) {
        if (j.parent < 0) {
          add_inertia_to_parent<twist>(j, mounted, c, s, Ia, base->IA);
          base->pA += force_to_parent<twist>(j, mounted, c, s, pa);
          return;
        }
      }
      const auto p = std::size_t(j.parent);
      add_inertia_to_parent<twist>(j, mounted, c, s, Ia, data.IA[p]);
      data.pA[p] += force_to_parent<twist>(j, mounted, c, s, pa);
    }
  });

  // pass 3: accelerations, base outwards; a fixed base accelerates at -g, a floating one at
  // -IA_0^-1 pA_0 in the frame falling with the body (gravity added to it at the end)
  SpatialVector<S> a_base;
  if constexpr (floating) {
    a_base = -base->IA.llt().solve(base->pA);
    base->a = a_base;
    base->a.template tail<3>() += base->pose.R.transpose() * model.gravity();
  } else {
    a_base = spatial<S>(Vec3<S>::Zero(), Vec3<S>(-(model.base_pose().R.transpose() * model.gravity())));
  }
  for_each_joint(model, [&](auto i, auto T, auto mounted, auto) {
    constexpr Twist twist = decltype(T)::value;
    const auto k = std::size_t(i);
    const auto& j = model.joint(int(i));
    const SpatialVector<S>& a_parent = j.parent >= 0 ? data.a[std::size_t(j.parent)] : a_base;
    SpatialVector<S> a = motion_to_child<twist>(j, mounted, data.cos_q[k], data.sin_q[k], a_parent);
    if constexpr (terms == Terms::Full) a += data.c[k];
    const S qdd = (data.u[int(i)] - data.U[k].dot(a)) * data.D_inv[int(i)];
    data.qdd[int(i)] = qdd;
    data.a[k] = a + motion_subspace<twist>(j) * qdd;
  });
  return data.qdd;
}

}  // namespace detail

/// Forward dynamics by the articulated-body algorithm (Featherstone 2008, §7.3, Table 7.1), O(nj), in
/// link frames: the joint accelerations that the torques tau produce at (q, qd) under gravity.
/// \tparam terms  Terms::Full or Terms::NoCoriolis (drops the velocity products, as if qd were zero);
///                GravityOnly does not compile
/// \param model  the model
/// \param data   workspace made from `model`; receives qdd and v, c, a, IA, pA, U, u, D_inv, cos_q, sin_q
/// \param q      joint angles (rad), nj
/// \param qd     joint velocities (rad/s), nj
/// \param tau    joint torques (N m), nj
/// \return data.qdd, joint accelerations (rad/s^2), nj. Meaningless (not NaN-checked) where the mass
///         matrix is singular (forward_dynamics.hpp). No allocation.
template <Terms terms = Terms::Full, class Model, class Q, class QD, class Tau>
inline const typename Model::JointVector& aba(const Model& model, Data<Model>& data, const Eigen::MatrixBase<Q>& q,
                                              const Eigen::MatrixBase<QD>& qd,
                                              const Eigen::MatrixBase<Tau>& tau) noexcept
    requires(terms != Terms::GravityOnly) {
  return detail::aba_impl<terms, false>(model, data, q, qd, tau, nullptr);
}

/// As above, with external wrenches on the links.
/// \param fext  per link: force (N) and moment (N m) about its origin, in its frame (as for rnea)
/// \return data.qdd (rad/s^2), nj
template <Terms terms = Terms::Full, class Model, class Q, class QD, class Tau>
inline const typename Model::JointVector& aba(const Model& model, Data<Model>& data, const Eigen::MatrixBase<Q>& q,
                                              const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<Tau>& tau,
                                              const LinkWrenches<Model>& fext) noexcept
    requires(terms != Terms::GravityOnly) {
  return detail::aba_impl<terms, true>(model, data, q, qd, tau, &fext);
}

/// Floating-base forward dynamics by the articulated-body algorithm (RBDA Table 9.6): joint
/// accelerations (rad/s^2, data.qdd, returned) and the base's acceleration (base.a) at the base's pose
/// and velocity (base.pose, base.v), angles q and rates qd, under joint torques tau (N m) and gravity,
/// with no wrench on the base. The model's base body is the floating base.
template <Terms terms = Terms::Full, class Model, class Q, class QD, class Tau>
inline const typename Model::JointVector& aba(const Model& model, Data<Model>& data,
                                              ArticulatedBase<typename Model::scalar_type>& base,
                                              const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                                              const Eigen::MatrixBase<Tau>& tau,
                                              const LinkWrenches<Model>* fext = nullptr) noexcept
    requires(terms != Terms::GravityOnly) {
  if (fext) return detail::aba_impl<terms, true, true>(model, data, q, qd, tau, fext, &base);
  return detail::aba_impl<terms, false, true>(model, data, q, qd, tau, nullptr, &base);
}

}  // namespace humandyn
