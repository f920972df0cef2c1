// Forward dynamics: the joint accelerations qdd that torques tau produce at (q, qd), two ways, chosen
// at compile time:
//   FdMethod::MassMatrix   M(q) by composite rigid bodies, h(q, qd) by Newton-Euler, then
//                          M qdd = tau - h by the tree-sparse L^T D L factorisation;
//   FdMethod::Articulated  the articulated-body algorithm, O(n), no matrix.
// Both leave qdd in data.qdd; the mass-matrix method also leaves M, h, L and D in data.
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
    crba(model, data, q);
    if (fext) nonlinear_effects<terms>(model, data, q, qd, *fext);
    else nonlinear_effects<terms>(model, data, q, qd);
    factorize(model, data);
    data.qdd = tau - data.h;
    solve(model, data, data.qdd);
    return data.qdd;
  }
}

}  // namespace detail

// Joint accelerations qdd (rad/s^2) at angles q, velocities qd and joint torques tau under gravity,
// into data.qdd. Terms::NoCoriolis drops the velocity products (as if qd were zero).
template <FdMethod method = FdMethod::Articulated, Terms terms = Terms::Full, class Model, class Q, class QD, class Tau>
inline const typename Model::JointVector& forward_dynamics(const Model& model, Data<Model>& data,
                                                           const Eigen::MatrixBase<Q>& q,
                                                           const Eigen::MatrixBase<QD>& qd,
                                                           const Eigen::MatrixBase<Tau>& tau) noexcept {
  return detail::forward_dynamics_impl<method, terms>(model, data, q, qd, tau, nullptr);
}

// As above, with external wrenches fext[i] on the links (each in its link's frame, about its origin,
// as for rnea).
template <FdMethod method = FdMethod::Articulated, Terms terms = Terms::Full, class Model, class Q, class QD, class Tau>
inline const typename Model::JointVector& forward_dynamics(const Model& model, Data<Model>& data,
                                                           const Eigen::MatrixBase<Q>& q,
                                                           const Eigen::MatrixBase<QD>& qd,
                                                           const Eigen::MatrixBase<Tau>& tau,
                                                           const LinkWrenches<Model>& fext) noexcept {
  return detail::forward_dynamics_impl<method, terms>(model, data, q, qd, tau, &fext);
}

}  // namespace humandyn
