// The joint-space equation of motion M(q) qdd + h(q, qd) = tau, in two parts:
//   crba               M(q) by the composite-rigid-body algorithm (Featherstone, RBDA §6.2);
//   nonlinear_effects  h(q, qd) = C(q, qd) qd + g(q) by Newton-Euler with qdd = 0, without M.
//
// The composite-rigid-body algorithm runs in the link frames, tips inwards (detail/body_inertia.hpp):
//   Ic_i, the inertia of the subtree joint i carries, is link i's own inertia plus its children's
//     composites, about link i's origin;
//   moved to joint i's DH base frame b_i (a shift by p*_i, Rx(alpha_i), a planar Rz(theta_i + q_i)),
//     where the joint turns about z through the origin, S_i = (e_z; 0): M_ii = (Ic_i)_zz, and
//     F_i = Ic_i S_i = (Ic_i e_z; e_z x h_i) with h_i the first moment of mass;
//   b_i is the parent link's frame (after the mount, if any): Ic_i joins the parent's composite there,
//     and F_i walks down the ancestors k, carried over each joint like a force (parent_X_k^*):
//     M_ki = M_ik = S_k . F_i, the z moment in b_k.
// Joints on different branches never meet in that last walk: their entries of M stay exactly zero.
// Forward dynamics asks for h in the same call: Newton-Euler's link forces then cross each joint the
// way F_i does, and the cosines and sines of the joint angles serve both.
#pragma once

#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/data.hpp"
#include "humandyn/detail/body_inertia.hpp"
#include "humandyn/detail/joint_loop.hpp"
#include "humandyn/detail/tree.hpp"

#include <Eigen/Core>

namespace humandyn {

namespace detail {

// A force (moment n about the origin; force f) in link k's frame carried to joint k's DH base frame
// b_k: turned by Rx(alpha_k), where the link origin sits at (a, 0, d) from b_k's origin, moved there,
// then turned by Rz(theta_k + q_k). Returns the z moment about b_k's origin, S_k . F.
template <Twist T, class S>
HUMANDYN_ALWAYS_INLINE S force_to_joint_frame(const JointConstants<S>& j, S c, S s, Vec3<S>& n, Vec3<S>& f) noexcept {
  const Vec3<S> fx = rot_x<T>(f, j.ca, j.sa), nx = rot_x<T>(n, j.ca, j.sa);
  const S nz = nx.z() + j.a * fx.y();
  n = Vec3<S>(c * (nx.x() - j.d * fx.y()) - s * (nx.y() + j.d * fx.x() - j.a * fx.z()),
              s * (nx.x() - j.d * fx.y()) + c * (nx.y() + j.d * fx.x() - j.a * fx.z()), nz);
  f = rot_z(fx, c, s);
  return nz;
}

// A force (moment n about the origin; force f) in joint k's DH base frame b_k, carried to the frame
// of k's parent link through the mount.
template <class S>
HUMANDYN_ALWAYS_INLINE void force_through_mount(const JointConstants<S>& j, Vec3<S>& n, Vec3<S>& f) noexcept {
  f = j.mount_R * f;
  n = j.mount_R * n + j.mount_p.cross(f);
}

// Newton-Euler's forward step of joint i for the bias (qdd = 0), out of line and flattened like rnea's
// (rnea.hpp): inlined into the unrolled pass, its small vector operations are left out of line or not
// as the compiler's budget for the whole translation unit goes (GCC left a float cross product out of
// line once the float sweep of sines joined the benchmarks' unit: forward dynamics took 1.5x its time;
// in the command line's crowd unit a double character's Euler step took 1.4x the benchmarks').
template <bool velocity, Twist T, class Model, class Mounted, class Massless>
HUMANDYN_NOINLINE HUMANDYN_FLATTEN inline void bias_forward_step(
    const Model& model, Data<Model>& data, int i, typename Model::scalar_type c, typename Model::scalar_type s,
    typename Model::scalar_type qd, const BaseAcceleration<typename Model::scalar_type>& base, Mounted mounted,
    Massless massless) noexcept {
  newton_euler_forward_step<velocity, false, T>(model, data, i, c, s, qd, typename Model::scalar_type(0), base, mounted,
                                                massless);
}

// A floating base's rows of the mass matrix (floating.hpp), in the base frame about its origin: the
// whole body's composite inertia (it starts as the base body's) and Mbj, column i the momentum of
// subtree i turning at unit rate, F_i carried on past the root of i's chain.
template <class Model>
struct BaseRows {
  BodyInertia<typename Model::scalar_type>& body;
  Eigen::Matrix<typename Model::scalar_type, 6, Model::nj>& Mbj;
};

// The composite-rigid-body algorithm; with with_bias also the bias h(q, qd) by Newton-Euler with qdd = 0
// (and external wrenches *fext when with_external), whose forces cross each joint as F_i does; with
// *rows also a floating base's rows. Each sweep is a loop of its own: one loop doing everything would be
// one very long function for a static shape, and slower.
template <bool with_bias, Terms terms, bool with_external, bool with_base = false, class Model, class Q, class QD>
inline void crba_impl(const Model& model, Data<Model>& data, const Eigen::MatrixBase<Q>& q,
                      const Eigen::MatrixBase<QD>& qd, const LinkWrenches<Model>* fext,
                      const BaseRows<Model>* rows = nullptr) noexcept {
  using S = typename Model::scalar_type;
  eigen_assert(q.size() == model.size());

  // the joints' cosines and sines (a float body's in a sweep of their own, a register's lanes at a time);
  // each composite starts as its own link's inertia, about the link origin
  constexpr bool float_sweep = std::is_same_v<S, float>;
  if constexpr (float_sweep) joint_cos_sin(model, q, data.cos_q, data.sin_q);
  const auto first_sweep = [&] {
    for_each_joint(model, [&](auto i, auto, auto, auto massless) {
      const auto k = std::size_t(i);
      const auto& j = model.joint(int(i));
      if constexpr (!float_sweep) cos_sin(S(j.theta + S(q[int(i)])), data.cos_q[k], data.sin_q[k]);
      if (massless)
        data.Ic[k] = BodyInertia<S>{};
      else
        data.Ic[k] = link_inertia(j);
    });
  };
  if constexpr (lanes<S>::is_batch)
    call_flattened(first_sweep);  // (a batch's sines and cosines inlined, their results kept in registers)
  else
    first_sweep();

  if constexpr (with_bias) {
    // the bias, base outwards: link motions and the forces they demand
    const auto base = base_acceleration(model);
    for_each_joint(model, [&](auto i, auto T, auto mounted, auto massless) {
      const auto k = std::size_t(i);
      S qdi = 0;
      if constexpr (terms == Terms::Full) qdi = S(qd[int(i)]);
      constexpr bool velocity = terms == Terms::Full;
      bias_forward_step<velocity, decltype(T)::value>(model, data, int(i), data.cos_q[k], data.sin_q[k], qdi, base,
                                                      mounted, massless);
      if constexpr (with_external) {
        data.f[k] -= (*fext)[k].force;
        data.n_o[k] -= (*fext)[k].moment;
      }
    });
    // tips inwards: the forces link i and its subtree need, in b_i, where h_i is their z moment
    for_each_joint_reverse(model, [&](auto i, auto T, auto mounted, auto) {
      const auto k = std::size_t(i);
      const auto& j = model.joint(int(i));
      Vec3<S> n = data.n_o[k], f = data.f[k];
      data.nle[int(i)] = force_to_joint_frame<decltype(T)::value>(j, data.cos_q[k], data.sin_q[k], n, f);
      const int parent = parent_of(model, i);
      if (parent < 0) return;
      if (mounted) force_through_mount(j, n, f);
      data.n_o[std::size_t(parent)] += n;
      data.f[std::size_t(parent)] += f;
    });
  } else {
    (void)qd, (void)fext;
  }

  // the composites, tips inwards: each is complete once its children have joined it
  for_each_joint_reverse(model, [&](auto i, auto T, auto mounted, auto) {
    const auto k = std::size_t(i);
    const auto& j = model.joint(int(i));

    // Ic_i in b_i, about its origin: turned by Rx(alpha_i), moved to b_i's origin, from which the link
    // origin is seen at (a_i, 0, d_i), turned by Rz(theta_i + q_i)
    const BodyInertia<S> Ic = rotated_z(shifted_dh(rotated_x<decltype(T)::value>(data.Ic[k], j.ca, j.sa), j.a, j.d),
                                        data.cos_q[k], data.sin_q[k]);
    data.M(int(i), int(i)) = Ic.zz;
    Vec3<S> n = Ic.col_z(), f(-Ic.h.y(), Ic.h.x(), S(0));  // F_i = Ic_i (e_z; 0)

    // Ic_i joins its parent's composite (or the base's), in the parent link's frame
    const int parent = parent_of(model, i);
    if (parent < 0 && !with_base) return;
    BodyInertia<S>& into = parent >= 0 ? data.Ic[std::size_t(parent)] : rows->body;
    if (mounted) {
      into += shifted(rotated(Ic, j.mount_R), j.mount_p);
      force_through_mount(j, n, f);
    } else {
      into += Ic;
    }

    // F_i down the ancestors a, each time into b_a, where M_ai is its z moment; for a floating base, on
    // through the mount of the chain's root into the base frame, where it is Mbj's column i
    [[maybe_unused]] int root = int(i);
    for_each_ancestor_inline(model, i, [&](auto a) {
      const auto& ja = model.joint(int(a));
      with_joint(model, a, [&](auto Ta, auto mounted_a) {
        const auto b = std::size_t(a);
        const S m = force_to_joint_frame<decltype(Ta)::value>(ja, data.cos_q[b], data.sin_q[b], n, f);
        data.M(int(i), int(a)) = m;
        data.M(int(a), int(i)) = m;
        if (mounted_a && ja.parent >= 0) force_through_mount(ja, n, f);
      });
      if constexpr (with_base) root = int(a);
    });
    if constexpr (with_base) {
      if (root != int(i) && model.joint(root).mounted) force_through_mount(model.joint(root), n, f);
      rows->Mbj.col(int(i)) << n, f;
    }
  });
}

}  // namespace detail

/// The joint-space mass matrix by the composite-rigid-body algorithm (Featherstone 2008, §6.2, Table 6.2),
/// in link frames.
/// \param model  the model
/// \param data   workspace made from `model`; receives M (and the composites Ic, cos_q, sin_q)
/// \param q      joint angles (rad), nj
/// \return data.M, nj x nj (kg m^2): symmetric positive semidefinite (definite when every joint moves
///         some inertia), exactly zero between joints on different branches. No allocation.
template <class Model, class Q>
inline const typename Data<Model>::MassMatrix& crba(const Model& model, Data<Model>& data,
                                                    const Eigen::MatrixBase<Q>& q) noexcept {
  detail::crba_impl<false, Terms::Full, false>(model, data, q, q, nullptr);
  return data.M;
}

/// The bias torques h = C(q, qd) qd + g(q), the torques that give qdd = 0: rnea(q, qd, 0)
/// (Featherstone 2008, §5.3, eq. 5.12 with qdd = 0).
/// \tparam terms  Terms::Full; Terms::NoCoriolis and Terms::GravityOnly drop the velocity products: h = g(q)
/// \param q   joint angles (rad), nj
/// \param qd  joint velocities (rad/s), nj
/// \return data.nle, the bias torques (N m), nj; bitwise equal to rnea(q, qd, 0)
template <Terms terms = Terms::Full, class Model, class Q, class QD>
inline const typename Model::JointVector& nonlinear_effects(const Model& model, Data<Model>& data,
                                                            const Eigen::MatrixBase<Q>& q,
                                                            const Eigen::MatrixBase<QD>& qd) noexcept {
  using JointVector = typename Model::JointVector;
  if constexpr (terms == Terms::Full)
    data.nle = rnea<Terms::Full>(model, data, q, qd, JointVector::Zero(model.size()));
  else
    data.nle = gravity_torques(model, data, q);
  return data.nle;
}

/// As above, with external wrenches on the links: h = C qd + g - J^T fext.
/// \param fext  per link: force (N) and moment (N m) about its origin, in its frame (as for rnea)
/// \return data.nle (N m), nj
template <Terms terms = Terms::Full, class Model, class Q, class QD>
inline const typename Model::JointVector& nonlinear_effects(const Model& model, Data<Model>& data,
                                                            const Eigen::MatrixBase<Q>& q,
                                                            const Eigen::MatrixBase<QD>& qd,
                                                            const LinkWrenches<Model>& fext) noexcept {
  using JointVector = typename Model::JointVector;
  constexpr Terms used = terms == Terms::Full ? Terms::Full : Terms::GravityOnly;
  data.nle = rnea<used>(model, data, q, qd, JointVector::Zero(model.size()), fext);
  return data.nle;
}

}  // namespace humandyn
