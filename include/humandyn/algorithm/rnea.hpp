// Inverse dynamics by the recursive Newton-Euler algorithm over the tree of DH chains, as the seed
// paper does it (Luh, Walker and Paul's form with standard DH, link-frame quantities):
//   forward pass, stance foot outwards: angular velocity w, angular acceleration wd and the linear
//     acceleration vd of each link's origin, with gravity entered as the base's acceleration -g;
//   backward pass, tips inwards: the force f and moment n each link receives from its parent; where
//     a chain starts at a branch point, what it transmits is added to its parent link's (eq. 9, 11).
// The terms are chosen at compile time; the omitted ones are never computed.
#pragma once

#include "humandyn/data.hpp"
#include "humandyn/detail/inline.hpp"
#include "humandyn/detail/joint_loop.hpp"

#include <Eigen/Core>

namespace humandyn {

/// Which terms of the equation of motion an algorithm computes.
enum class Terms {
  Full,         // inertial, velocity-product (Coriolis and centrifugal) and gravity terms
  NoCoriolis,   // the paper's bargain: velocity products dropped, equals Full with qd = 0 (and a base
                // that does not turn: the base's angular velocity is dropped too)
  GravityOnly,  // static torques, equals Full with qd = qdd = 0 and the base at rest in its pose
};

/// The motion of the base frame (the stance foot's frame) in the world, for inverse dynamics on a
/// moving base: a stance foot rolling from heel to toe, or a character on a moving platform.
/// All vectors in world axes. The linear velocity of the base enters no force (Newton–Euler needs the
/// classical acceleration of the origin, `a`), so it is not asked for.
template <class S>
struct BaseMotion {
  Pose<S> pose;                  ///< the base frame in the world (rotation R, origin p; m)
  Vec3<S> w = Vec3<S>::Zero();   ///< angular velocity of the base frame (rad/s)
  Vec3<S> wd = Vec3<S>::Zero();  ///< angular acceleration of the base frame (rad/s^2)
  Vec3<S> a = Vec3<S>::Zero();   ///< acceleration of the base frame's origin (m/s^2), gravity not included

  /// The base at rest in the model's base pose: inverse dynamics then equals the fixed-base one bit for bit.
  template <class Model>
  static BaseMotion at_rest(const Model& model) noexcept {
    BaseMotion b;
    b.pose = model.base_pose();
    return b;
  }
};

namespace detail {

// The base's motion as the forward pass enters it, in the base frame: angular velocity and
// acceleration, and the acceleration of the origin with gravity entered as an upward acceleration,
// vd_0 = R^T (a - g) (Luh, Walker and Paul's device).
template <class S>
struct BaseAcceleration {
  Vec3<S> w = Vec3<S>::Zero(), wd = Vec3<S>::Zero(), vd = Vec3<S>::Zero();
};

template <class Model>
inline BaseAcceleration<typename Model::scalar_type> base_acceleration(const Model& model) noexcept {
  BaseAcceleration<typename Model::scalar_type> b;
  b.vd = -(model.base_pose().R.transpose() * model.gravity());
  return b;
}

// A moving base's, with what `terms` keeps: Terms::GravityOnly keeps the pose alone (no acceleration
// of the origin; the angular terms are dropped by the passes themselves).
template <Terms terms, class Model>
inline BaseAcceleration<typename Model::scalar_type> base_acceleration(
    const Model& model, const BaseMotion<typename Model::scalar_type>& base) noexcept {
  BaseAcceleration<typename Model::scalar_type> b;
  const auto Rt = base.pose.R.transpose();
  b.w = Rt * base.w;
  b.wd = Rt * base.wd;
  if constexpr (terms == Terms::GravityOnly)
    b.vd = -(Rt * model.gravity());
  else
    b.vd = Rt * (base.a - model.gravity());
  return b;
}

// The forward (outward) step of joint i, whose angle theta_i + q_i has cosine c and sine s: the link's
// motion from its parent's, and the force and moment its own motion demands (Newton's and Euler's
// equations), stored as the starting f and n_o. What it takes into account besides gravity is chosen at
// compile time: the velocity products of the joint rates qd and of the base's rotation (`velocity`) and
// the accelerations of the joints and of the base (`acceleration`); the omitted terms are never computed. rnea takes
// both or either, the bias of forward dynamics (crba.hpp) the velocity products alone (qdd = 0).
template <bool velocity, bool acceleration, Twist T, class Model, class Mounted, class Massless>
HUMANDYN_ALWAYS_INLINE void newton_euler_forward_step(const Model& model, Data<Model>& data, int i,
                                                      typename Model::scalar_type c, typename Model::scalar_type s,
                                                      typename Model::scalar_type qd, typename Model::scalar_type qdd,
                                                      const BaseAcceleration<typename Model::scalar_type>& base,
                                                      Mounted mounted, Massless massless) noexcept {
  using S = typename Model::scalar_type;
  constexpr bool angular_acceleration = velocity || acceleration;  // else wd = 0 all along the tree
  const auto& j = model.joint(i);
  const auto k = std::size_t(i);

  // the parent's motion, expressed in this joint's DH base frame (through the mount, if any)
  Vec3<S> w_b = Vec3<S>::Zero(), wd_b = Vec3<S>::Zero(), vd_b;
  if (j.parent < 0) {
    vd_b = base.vd;
    if constexpr (angular_acceleration) wd_b = base.wd;
    if constexpr (velocity) w_b = base.w;
  } else {
    const auto p = std::size_t(j.parent);
    vd_b = data.acc_origin[p];
    if constexpr (angular_acceleration) wd_b = data.wd[p];
    if constexpr (velocity) w_b = data.w[p];
  }
  if (mounted) {
    if constexpr (angular_acceleration) vd_b += wd_b.cross(j.mount_p);
    if constexpr (velocity) vd_b += w_b.cross(w_b.cross(j.mount_p));
    vd_b = j.mount_R.transpose() * vd_b;
    if constexpr (angular_acceleration) wd_b = j.mount_R.transpose() * wd_b;
    if constexpr (velocity) w_b = j.mount_R.transpose() * w_b;
  }

  // link motion: w_i = R^T (w_b + z qd), wd_i = R^T (wd_b + w_b x z qd + z qdd), vd_i = R^T vd_b + wd_i x p* + w_i x
  // (w_i x p*)
  Vec3<S> w = Vec3<S>::Zero(), wd = Vec3<S>::Zero();
  Vec3<S> vd = rot_x_t<T>(rot_z_t(vd_b, c, s), j.ca, j.sa);
  if constexpr (angular_acceleration) {
    Vec3<S> a = wd_b;
    if constexpr (velocity) a += Vec3<S>(w_b.y() * qd, -w_b.x() * qd, 0);
    a = rot_z_t(a, c, s);
    if constexpr (acceleration) a.z() += qdd;
    wd = rot_x_t<T>(a, j.ca, j.sa);
    vd += wd.cross(j.pstar);
  } else {
    (void)qdd;
  }
  if constexpr (velocity) {
    Vec3<S> b = rot_z_t(w_b, c, s);
    b.z() += qd;
    w = rot_x_t<T>(b, j.ca, j.sa);
    vd += w.cross(w.cross(j.pstar));
    data.w[k] = w;
  } else {
    (void)qd;
  }
  if constexpr (angular_acceleration) data.wd[k] = wd;
  data.acc_origin[k] = vd;

  // Newton and Euler for the link: F = m a_c, N = I wd + w x I w; moment about the link origin
  if (massless) {
    data.f[k].setZero();
    data.n_o[k].setZero();
  } else {
    Vec3<S> ac = vd;  // NOLINT(performance-unnecessary-copy-initialization): the terms asked for add to it
    if constexpr (angular_acceleration) ac += wd.cross(j.com);
    if constexpr (velocity) ac += w.cross(w.cross(j.com));
    const Vec3<S> F = j.mass * ac;
    Vec3<S> n = j.com.cross(F);
    if constexpr (angular_acceleration) n += j.inertia * wd;
    if constexpr (velocity) n += w.cross(j.inertia * w);
    data.f[k] = F;
    data.n_o[k] = n;
  }
}

// rnea's forward step of joint i at rate qd and acceleration qdd with the given terms, its cosine and
// sine in data (joint_cos_sin): the Newton-Euler step. Kept out of line: a static shape's sixteen steps
// inlined into one pass run slower; flattened, so that the Eigen products of the step inlined into it
// stay inline too.
template <Terms terms, Twist T, class Model, class Mounted, class Massless>
HUMANDYN_NOINLINE HUMANDYN_FLATTEN inline void rnea_forward_step(
    const Model& model, Data<Model>& data, int i, typename Model::scalar_type qd, typename Model::scalar_type qdd,
    const BaseAcceleration<typename Model::scalar_type>& base, Mounted mounted, Massless massless) noexcept {
  const auto k = std::size_t(i);
  newton_euler_forward_step<terms == Terms::Full, terms != Terms::GravityOnly, T>(
      model, data, i, data.cos_q[k], data.sin_q[k], qd, qdd, base, mounted, massless);
}

// What link i receives through joint i (data.f and data.n_o once its subtree is summed), in the
// joint's DH base frame about that frame's origin, where frame i sits at (a c, a s, d).
template <Twist T, class Model>
inline void wrench_through_joint(const Model& model, const Data<Model>& data, int i,
                                 Vec3<typename Model::scalar_type>& f, Vec3<typename Model::scalar_type>& n) noexcept {
  using S = typename Model::scalar_type;
  const auto& j = model.joint(i);
  const auto k = std::size_t(i);
  const S c = data.cos_q[k], s = data.sin_q[k];
  f = rot_z(rot_x<T>(data.f[k], j.ca, j.sa), c, s);
  const Vec3<S> r(j.a * c, j.a * s, j.d);
  n = rot_z(rot_x<T>(data.n_o[k], j.ca, j.sa), c, s) + r.cross(f);
}

// A wrench in a mounted joint's DH base frame, carried into its parent's frame through the mount.
template <class Joint, class Mounted, class V>
inline void through_mount(const Joint& j, Mounted mounted, V& f, V& n) noexcept {
  if (mounted) {
    f = j.mount_R * f;
    n = j.mount_R * n + j.mount_p.cross(f);
  }
}

// The backward (inward) step of joint i: what link i receives through the joint, moved into the DH
// base frame; the torque is its z moment; it is then added to the parent link's sums.
template <Twist T, class Model, class Mounted>
inline void rnea_backward_step(const Model& model, Data<Model>& data, int i, Mounted mounted) noexcept {
  using S = typename Model::scalar_type;
  const auto& j = model.joint(i);
  Vec3<S> f, n;
  wrench_through_joint<T>(model, data, i, f, n);
  data.tau[i] = n.z();

  // branch summation: the parent link receives the sum of what each child transmits
  if (j.parent >= 0) {
    const auto p = std::size_t(j.parent);
    through_mount(j, mounted, f, n);
    data.f[p] += f;
    data.n_o[p] += n;
  }
}

template <Terms terms, bool with_external, class Model, class Q, class QD, class QDD>
inline const typename Model::JointVector& rnea_impl(const Model& model, Data<Model>& data,
                                                    const BaseAcceleration<typename Model::scalar_type>& base,
                                                    const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                                                    const Eigen::MatrixBase<QDD>& qdd,
                                                    const LinkWrenches<Model>* fext) noexcept {
  using S = typename Model::scalar_type;
  eigen_assert(q.size() == model.size());

  joint_cos_sin(model, q, data.cos_q, data.sin_q);
  for_each_joint(model, [&](auto i, auto T, auto mounted, auto massless) {
    S qdi = 0, qddi = 0;
    if constexpr (terms == Terms::Full) qdi = qd[int(i)];
    if constexpr (terms != Terms::GravityOnly) qddi = qdd[int(i)];
    rnea_forward_step<terms, decltype(T)::value>(model, data, int(i), qdi, qddi, base, mounted, massless);
    if constexpr (with_external) {
      data.f[std::size_t(i)] -= (*fext)[std::size_t(i)].force;
      data.n_o[std::size_t(i)] -= (*fext)[std::size_t(i)].moment;
    }
  });
  for_each_joint_reverse(model, [&](auto i, auto T, auto mounted, auto) {
    rnea_backward_step<decltype(T)::value>(model, data, int(i), mounted);
  });
  return data.tau;
}

}  // namespace detail

/// Inverse dynamics by the recursive Newton-Euler algorithm (Luh, Walker and Paul 1980; Featherstone
/// 2008, §5.3; the seed paper's eqs. 1-11, branch sums eqs. 9 and 11): the joint torques that produce
/// the accelerations qdd at angles q and velocities qd under the model's gravity.
/// \tparam terms  Terms::Full; Terms::NoCoriolis ignores qd; Terms::GravityOnly ignores qd and qdd
/// \param model  the model (link frames as in model.hpp)
/// \param data   workspace made from `model`; receives tau and the link quantities w, wd, vd, f, n_o
/// \param q      joint angles (rad), nj
/// \param qd     joint velocities (rad/s), nj
/// \param qdd    joint accelerations (rad/s^2), nj
/// \return data.tau, joint torques (N m), nj. No allocation; sizes are checked by eigen_assert only.
template <Terms terms = Terms::Full, class Model, class Q, class QD, class QDD>
inline const typename Model::JointVector& rnea(const Model& model, Data<Model>& data, const Eigen::MatrixBase<Q>& q,
                                               const Eigen::MatrixBase<QD>& qd,
                                               const Eigen::MatrixBase<QDD>& qdd) noexcept {
  return detail::rnea_impl<terms, false>(model, data, detail::base_acceleration(model), q, qd, qdd, nullptr);
}

/// As above, with external wrenches on the links.
/// \param fext  per link i: force (N) and moment (N m) about link i's origin, in link i's frame, applied
///              by the environment (wrench_from_world makes one from world quantities)
/// \return data.tau (N m), nj: the torques that produce qdd with those wrenches acting
template <Terms terms = Terms::Full, class Model, class Q, class QD, class QDD>
inline const typename Model::JointVector& rnea(const Model& model, Data<Model>& data, const Eigen::MatrixBase<Q>& q,
                                               const Eigen::MatrixBase<QD>& qd, const Eigen::MatrixBase<QDD>& qdd,
                                               const LinkWrenches<Model>& fext) noexcept {
  return detail::rnea_impl<terms, true>(model, data, detail::base_acceleration(model), q, qd, qdd, &fext);
}

/// Inverse dynamics on a moving base: the joint torques tau (N m, nj) that produce qdd (rad/s^2, nj) at q
/// (rad, nj) and qd (rad/s, nj) while the base frame moves as `base` says (world axes), under gravity;
/// written to data.tau and returned. A base at rest in the model's base pose (BaseMotion::at_rest) gives
/// the fixed-base rnea's results bit for bit. Terms::NoCoriolis drops the base's angular velocity with
/// the joints' velocity products; Terms::GravityOnly drops the base's accelerations too (only its pose
/// stays). Luh, Walker and Paul (1980): the base's motion enters the outward recursion as link 0's.
template <Terms terms = Terms::Full, class Model, class Q, class QD, class QDD>
inline const typename Model::JointVector& rnea(const Model& model, Data<Model>& data,
                                               const BaseMotion<typename Model::scalar_type>& base,
                                               const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                                               const Eigen::MatrixBase<QDD>& qdd) noexcept {
  return detail::rnea_impl<terms, false>(model, data, detail::base_acceleration<terms>(model, base), q, qd, qdd,
                                         nullptr);
}

/// As above, with external wrenches fext[i] acting on the links (each in its link's frame, as for rnea).
template <Terms terms = Terms::Full, class Model, class Q, class QD, class QDD>
inline const typename Model::JointVector& rnea(const Model& model, Data<Model>& data,
                                               const BaseMotion<typename Model::scalar_type>& base,
                                               const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                                               const Eigen::MatrixBase<QDD>& qdd,
                                               const LinkWrenches<Model>& fext) noexcept {
  return detail::rnea_impl<terms, true>(model, data, detail::base_acceleration<terms>(model, base), q, qd, qdd, &fext);
}

/// The static torques that hold the pose q against gravity: rnea<Terms::GravityOnly> (Featherstone
/// 2008, §5.3 with qd = qdd = 0).
/// \param q  joint angles (rad), nj
/// \return data.tau, the gravity torques g(q) (N m), nj
template <class Model, class Q>
inline const typename Model::JointVector& gravity_torques(const Model& model, Data<Model>& data,
                                                          const Eigen::MatrixBase<Q>& q) noexcept {
  return detail::rnea_impl<Terms::GravityOnly, false>(model, data, detail::base_acceleration(model), q, q, q, nullptr);
}

/// A wrench for rnea's fext from world quantities. Needs data.oMi from forward_kinematics.
/// \param data   workspace after forward_kinematics at the current q
/// \param link   index of the link the force acts on (0-based joint index), 0 <= link < nj
/// \param force  force (N), world frame
/// \param point  point of application (m), world frame
/// \return the force and its moment about link `link`'s origin (N, N m), in that link's frame
template <class Model>
inline Wrench<typename Model::scalar_type> wrench_from_world(const Data<Model>& data, int link,
                                                             const Vec3<typename Model::scalar_type>& force,
                                                             const Vec3<typename Model::scalar_type>& point) noexcept {
  const auto& X = data.oMi[std::size_t(link)];
  Wrench<typename Model::scalar_type> w;
  w.force = X.R.transpose() * force;
  w.moment = (X.R.transpose() * (point - X.p)).cross(w.force);
  return w;
}

}  // namespace humandyn
