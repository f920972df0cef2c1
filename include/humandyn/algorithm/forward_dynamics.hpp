// Forward dynamics: the joint accelerations qdd that torques tau produce at (q, qd), two ways, chosen
// at compile time:
//   FdMethod::MassMatrix   M(q) by composite rigid bodies, h(q, qd) by Newton-Euler, then
//                          M qdd = tau - h by the tree-sparse L^T D L factorisation;
//   FdMethod::Articulated  the articulated-body algorithm, O(n), no matrix.
// For the 16 joints of the seed body the mass-matrix method is the faster one (the default): the tree
// keeps M sparse and its factorisation cheap, while the articulated body pays a 6 x 6 inertia transform
// per joint.
// Both leave qdd in data.qdd; the mass-matrix method also leaves M, h, L and D in data.
// M must be regular: every joint must move some inertia that no other joint can move instead. Table 1's
// body is not (a massless pelvis between three coaxial joints): there the pivots D (data.D, or
// 1 / data.D_inv for the articulated body) fall to round-off and the accelerations are meaningless.
#pragma once

#include "humandyn/algorithm/aba.hpp"
#include "humandyn/algorithm/crba.hpp"
#include "humandyn/algorithm/ldlt.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/data.hpp"

#include <Eigen/Core>

namespace humandyn {

enum class FdMethod {
  MassMatrix,   // M(q) and h(q, qd), then the tree-sparse L^T D L solve
  Articulated,  // the articulated-body algorithm
};

namespace detail {

template <FdMethod method, Terms terms, class Model, class Q, class QD, class Tau>
inline const typename Model::JointVector& forward_dynamics_impl(const Model& model, Data<Model>& data,
                                                                const Eigen::MatrixBase<Q>& q,
                                                                const Eigen::MatrixBase<QD>& qd,
                                                                const Eigen::MatrixBase<Tau>& tau,
                                                                const LinkWrenches<Model>* fext) noexcept {
  static_assert(terms != Terms::GravityOnly, "forward dynamics needs the inertial terms: use Full or NoCoriolis");
  if constexpr (method == FdMethod::Articulated) {
    return fext ? aba<terms>(model, data, q, qd, tau, *fext) : aba<terms>(model, data, q, qd, tau);
  } else {
    // M and h in the same two sweeps over the tree
    if (fext) detail::crba_impl<true, terms, true>(model, data, q, qd, fext);
    else detail::crba_impl<true, terms, false>(model, data, q, qd, fext);
    factorize(model, data);
    data.qdd = tau - data.h;
    solve(model, data, data.qdd);
    return data.qdd;
  }
}

}  // namespace detail

// Joint accelerations qdd (rad/s^2) at angles q, velocities qd and joint torques tau under gravity,
// into data.qdd. Terms::NoCoriolis drops the velocity products (as if qd were zero).
template <FdMethod method = FdMethod::MassMatrix, Terms terms = Terms::Full, class Model, class Q, class QD, class Tau>
inline const typename Model::JointVector& forward_dynamics(const Model& model, Data<Model>& data,
                                                           const Eigen::MatrixBase<Q>& q,
                                                           const Eigen::MatrixBase<QD>& qd,
                                                           const Eigen::MatrixBase<Tau>& tau) noexcept {
  return detail::forward_dynamics_impl<method, terms>(model, data, q, qd, tau, nullptr);
}

// As above, with external wrenches fext[i] on the links (each in its link's frame, about its origin,
// as for rnea).
template <FdMethod method = FdMethod::MassMatrix, Terms terms = Terms::Full, class Model, class Q, class QD, class Tau>
inline const typename Model::JointVector& forward_dynamics(const Model& model, Data<Model>& data,
                                                           const Eigen::MatrixBase<Q>& q,
                                                           const Eigen::MatrixBase<QD>& qd,
                                                           const Eigen::MatrixBase<Tau>& tau,
                                                           const LinkWrenches<Model>& fext) noexcept {
  return detail::forward_dynamics_impl<method, terms>(model, data, q, qd, tau, &fext);
}

}  // namespace humandyn
