// Forward dynamics: the joint accelerations qdd that torques tau produce at (q, qd), two ways, chosen
// at compile time:
//   FdMethod::MassMatrix   M(q) by composite rigid bodies, h(q, qd) by Newton-Euler, then
//                          M qdd = tau - h by the tree-sparse L^T D L factorisation;
//   FdMethod::Articulated  the articulated-body algorithm, O(n), no matrix.
// For the 16 joints of the seed body the mass-matrix method is the faster one (the default): the tree
// keeps M sparse and its factorisation cheap, while the articulated body pays a 6 x 6 inertia transform
// per joint.
// Both leave qdd in data.qdd; the mass-matrix method also leaves M, nle, L and D in data.
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
    if (fext)
      detail::crba_impl<true, terms, true>(model, data, q, qd, fext);
    else
      detail::crba_impl<true, terms, false>(model, data, q, qd, fext);
    factorize_mass_matrix(model, data);
    data.qdd = tau - data.nle;
    solve_mass_matrix(model, data, data.qdd);
    return data.qdd;
  }
}

}  // namespace detail

/// Forward dynamics: the joint accelerations that torques tau produce at (q, qd) under gravity,
/// M(q) qdd = tau - h(q, qd) (Featherstone 2008, eq. 6.1).
/// \tparam method  FdMethod::MassMatrix (crba + bias + tree-sparse LTDL, §6.2 and §6.5) or
///                 FdMethod::Articulated (aba, §7.3)
/// \tparam terms   Terms::Full or Terms::NoCoriolis (drops the velocity products, as if qd were zero)
/// \param q    joint angles (rad), nj
/// \param qd   joint velocities (rad/s), nj
/// \param tau  joint torques (N m), nj
/// \return data.qdd, joint accelerations (rad/s^2), nj; the mass-matrix method also leaves M, nle, L
///         and D in data. Meaningless where M is singular (see above). No allocation.
template <FdMethod method = FdMethod::MassMatrix, Terms terms = Terms::Full, class Model, class Q, class QD, class Tau>
inline const typename Model::JointVector& forward_dynamics(const Model& model, Data<Model>& data,
                                                           const Eigen::MatrixBase<Q>& q,
                                                           const Eigen::MatrixBase<QD>& qd,
                                                           const Eigen::MatrixBase<Tau>& tau) noexcept {
  return detail::forward_dynamics_impl<method, terms>(model, data, q, qd, tau, nullptr);
}

/// As above, with external wrenches on the links.
/// \param fext  per link: force (N) and moment (N m) about its origin, in its frame (as for rnea)
/// \return data.qdd (rad/s^2), nj
template <FdMethod method = FdMethod::MassMatrix, Terms terms = Terms::Full, class Model, class Q, class QD, class Tau>
inline const typename Model::JointVector& forward_dynamics(const Model& model, Data<Model>& data,
                                                           const Eigen::MatrixBase<Q>& q,
                                                           const Eigen::MatrixBase<QD>& qd,
                                                           const Eigen::MatrixBase<Tau>& tau,
                                                           const LinkWrenches<Model>& fext) noexcept {
  return detail::forward_dynamics_impl<method, terms>(model, data, q, qd, tau, &fext);
}

}  // namespace humandyn
