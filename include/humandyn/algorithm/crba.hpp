// The joint-space equation of motion M(q) qdd + h(q, qd) = tau, in two parts:
//   crba               M(q) by the composite-rigid-body algorithm (Featherstone, RBDA §6.2);
//   nonlinear_effects  h(q, qd) = C(q, qd) qd + g(q) by Newton-Euler with qdd = 0, without M.
//
// The composite-rigid-body algorithm runs in world axes about the world origin, where the inertias of a
// subtree simply add up:
//   each link's motion subspace S_i (axis z_i through the point o_i: (z_i; o_i x z_i)) and inertia;
//   tips inwards, the composite inertia Ic_i of the subtree link i carries, summed at the branch points;
//   M_ii = S_i . Ic_i S_i, and M_ki = M_ik = S_k . Ic_i S_i for each ancestor k of i.
// Joints on different branches never meet in that last walk: their entries of M stay exactly zero.
#pragma once

#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/data.hpp"
#include "humandyn/detail/joint_loop.hpp"
#include "humandyn/detail/spatial.hpp"
#include "humandyn/detail/tree.hpp"

#include <Eigen/Core>

namespace humandyn {

namespace detail {

// With trig_ready, the cosines and sines of theta_i + q_i are taken from data.cos_q, data.sin_q (left
// there by rnea for the same q) instead of being computed again.
template <bool trig_ready, class Model, class Q>
inline const typename Data<Model>::MassMatrix& crba_impl(const Model& model, Data<Model>& data,
                                                         const Eigen::MatrixBase<Q>& q) noexcept {
  using S = typename Model::scalar_type;
  eigen_assert(q.size() == model.size());
  const Pose<S>& base = model.base_pose();

  // base outwards: each link frame in the world, the joint's motion subspace (its axis is z of the DH
  // base frame b, through b's origin) and the link's inertia, in world axes about the world origin
  for_each_joint(model, [&](auto i, auto T, auto mounted, auto massless) {
    const auto k = std::size_t(i);
    const auto& j = model.joint(int(i));
    Pose<S> b = j.parent < 0 ? base : data.oMi[std::size_t(j.parent)];
    if (mounted) b = b * Pose<S>{j.mount_R, j.mount_p};
    const Vec3<S> z = b.R.col(2);
    data.S_o[k] = spatial<S>(z, b.p.cross(z));

    // link frame: R = R_b Rz(theta + q) Rx(alpha), p = p_b + R_b (a c, a s, d)
    S c, s;
    if constexpr (trig_ready) {
      c = data.cos_q[k];
      s = data.sin_q[k];
    } else {
      const S th = j.theta + S(q[int(i)]);
      c = std::cos(th);
      s = std::sin(th);
    }
    const Vec3<S> x = c * b.R.col(0) + s * b.R.col(1), y = c * b.R.col(1) - s * b.R.col(0);
    Pose<S>& X = data.oMi[k];
    X.R = rotate_columns_x<decltype(T)::value>(x, y, z, j.ca, j.sa);
    X.p = b.p + j.a * x + j.d * z;

    if (massless) {
      data.Ic_mass[k] = S(0);
      data.Ic_h[k].setZero();
      data.Ic_I[k].setZero();
    } else {
      const Vec3<S> com = X.p + X.R * j.com;
      data.Ic_mass[k] = j.mass;
      data.Ic_h[k] = j.mass * com;
      data.Ic_I[k] = X.R * j.inertia * X.R.transpose() +
                     j.mass * (com.squaredNorm() * Mat3<S>::Identity() - com * com.transpose());
    }
  });

  // composite inertias, tips inwards: each subtree's inertia joins its parent's
  for_each_joint_reverse(model, [&](auto i, auto, auto, auto) {
    const int parent = parent_of(model, i);
    if (parent < 0) return;
    const auto k = std::size_t(i), p = std::size_t(parent);
    data.Ic_mass[p] += data.Ic_mass[k];
    data.Ic_h[p] += data.Ic_h[k];
    data.Ic_I[p] += data.Ic_I[k];
  });

  // F_i = Ic_i S_i (moment about the world origin; force); M_ki = S_k . F_i down the ancestors of i
  for_each_joint(model, [&](auto i, auto, auto, auto) {
    const auto k = std::size_t(i);
    const Vec3<S> z = data.S_o[k].template head<3>(), sv = data.S_o[k].template tail<3>();
    const Vec3<S>& h = data.Ic_h[k];
    const SpatialVector<S> F = spatial<S>(data.Ic_I[k] * z + h.cross(sv), data.Ic_mass[k] * sv - h.cross(z));
    data.M(int(i), int(i)) = data.S_o[k].dot(F);
    for_each_ancestor(model, i, [&](auto a) {
      const S m = data.S_o[std::size_t(a)].dot(F);
      data.M(int(i), int(a)) = m;
      data.M(int(a), int(i)) = m;
    });
  });
  return data.M;
}

}  // namespace detail

// The joint-space mass matrix M(q) (kg m^2), symmetric positive semidefinite (definite when every
// joint moves some inertia), into data.M; also leaves the link frames in data.oMi.
template <class Model, class Q>
inline const typename Data<Model>::MassMatrix& crba(const Model& model, Data<Model>& data,
                                                    const Eigen::MatrixBase<Q>& q) noexcept {
  return detail::crba_impl<false>(model, data, q);
}

// The bias torques h = C(q, qd) qd + g(q) (N m), the torques that give qdd = 0: rnea(q, qd, 0), into data.h.
// Terms::NoCoriolis (and Terms::GravityOnly) drop the velocity products: h = g(q).
template <Terms terms = Terms::Full, class Model, class Q, class QD>
inline const typename Model::JointVector& nonlinear_effects(const Model& model, Data<Model>& data,
                                                            const Eigen::MatrixBase<Q>& q,
                                                            const Eigen::MatrixBase<QD>& qd) noexcept {
  using JointVector = typename Model::JointVector;
  if constexpr (terms == Terms::Full) data.h = rnea<Terms::Full>(model, data, q, qd, JointVector::Zero(model.size()));
  else data.h = gravity_torques(model, data, q);
  return data.h;
}

// As above, with external wrenches fext[i] on the links: h = C qd + g - J^T fext.
template <Terms terms = Terms::Full, class Model, class Q, class QD>
inline const typename Model::JointVector& nonlinear_effects(const Model& model, Data<Model>& data,
                                                            const Eigen::MatrixBase<Q>& q,
                                                            const Eigen::MatrixBase<QD>& qd,
                                                            const LinkWrenches<Model>& fext) noexcept {
  using JointVector = typename Model::JointVector;
  constexpr Terms used = terms == Terms::Full ? Terms::Full : Terms::GravityOnly;
  data.h = rnea<used>(model, data, q, qd, JointVector::Zero(model.size()), fext);
  return data.h;
}

}  // namespace humandyn
