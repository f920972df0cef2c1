// The LTDL factorisation of the mass matrix (Featherstone, RBDA §6.5, Tables 6.3 and 6.4):
// M = L^T D L with L unit lower triangular. Eliminating the joints from the tips inwards, L(i, j) is
// non-zero only where j is an ancestor of i, like M itself: a tree produces no fill-in, and every loop
// below walks the parent array instead of whole rows (cost: the sum over joints of depth^2).
//   factorize_mass_matrix(model, data)         data.M                -> data.L, data.D
//   factorize_mass_matrix(model, data, extra)  data.M + diag(extra)  -> data.L, data.D (implicit integration)
//   solve_mass_matrix(model, data, x)          x <- (L^T D L)^-1 x, in place (a vector or a matrix of columns)
// data.M is left untouched.
#pragma once

#include "humandyn/data.hpp"
#include "humandyn/detail/joint_loop.hpp"
#include "humandyn/detail/tree.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace humandyn {
namespace detail {

// Copies M's diagonal and its entries M(i, a), a an ancestor of i, into data.L: all the factorisation
// reads (the rest of L's lower triangle stays zero from the start).
template <class Model>
inline void copy_tree_entries(const Model& model, Data<Model>& data) noexcept {
  for_each_joint(model, [&](auto i, auto, auto, auto) {
    data.L(int(i), int(i)) = data.M(int(i), int(i));
    for_each_ancestor_inline(model, i, [&](auto a) { data.L(int(i), int(a)) = data.M(int(i), int(a)); });
  });
}

// Featherstone's LTDL on the entries already copied into data.L.
template <class Model>
inline void ltdl_in_place(const Model& model, Data<Model>& data) noexcept {
  using S = typename Model::scalar_type;
  auto& H = data.L;
  // eliminate joint k (tips first) from its ancestors i: H(i, j) -= H(k, i) H(k, j) / H(k, k) for j = i
  // and i's ancestors; H(k, i) becomes L(k, i)
  for_each_joint_reverse(model, [&](auto k, auto, auto, auto) {
    const S inv_kk = S(1) / H(int(k), int(k));
    for_each_ancestor_inline(model, k, [&](auto i) {
      const S a = H(int(k), int(i)) * inv_kk;
      H(int(i), int(i)) -= a * H(int(k), int(i));
      for_each_ancestor_inline(model, i, [&](auto j) { H(int(i), int(j)) -= a * H(int(k), int(j)); });
      H(int(k), int(i)) = a;
    });
  });
  // D on the diagonal, L unit lower triangular
  data.D = H.diagonal();
  H.diagonal().setOnes();
}

// The three parts of a solve with L^T D L, in place on x (one column or several; Eigen's idiom for
// writable expressions). L^T y = b, tips inwards: joint i's value is final once its descendants are done.
template <class Model, class X>
inline void solve_lt(const Model& model, const Data<Model>& data, const Eigen::MatrixBase<X>& x_in) noexcept {
  auto& x = const_cast<Eigen::MatrixBase<X>&>(x_in);
  for_each_joint_reverse(model, [&](auto i, auto, auto, auto) {
    for_each_ancestor_inline(model, i, [&](auto j) { x.row(int(j)) -= data.L(int(i), int(j)) * x.row(int(i)); });
  });
}

// D z = y.
template <class Model, class X>
inline void solve_d(const Model& model, const Data<Model>& data, const Eigen::MatrixBase<X>& x_in) noexcept {
  auto& x = const_cast<Eigen::MatrixBase<X>&>(x_in);
  for (int i = 0; i < model.size(); ++i) x.row(i) /= data.D[i];
}

// L x = z, base outwards.
template <class Model, class X>
inline void solve_l(const Model& model, const Data<Model>& data, const Eigen::MatrixBase<X>& x_in) noexcept {
  auto& x = const_cast<Eigen::MatrixBase<X>&>(x_in);
  for_each_joint(model, [&](auto i, auto, auto, auto) {
    for_each_ancestor_inline(model, i, [&](auto j) { x.row(int(i)) -= data.L(int(i), int(j)) * x.row(int(j)); });
  });
}

}  // namespace detail

/// Factorises the mass matrix, data.M = L^T D L, exploiting the tree's sparsity (Featherstone 2008,
/// §6.5, Table 6.3). data.M is left untouched.
/// \param data  workspace holding M (crba); receives L (nj x nj, unit lower triangular, L(i, j) != 0
///              only for j an ancestor of i) and D (nj, the pivots, kg m^2)
template <class Model>
inline void factorize_mass_matrix(const Model& model, Data<Model>& data) noexcept {
  detail::copy_tree_entries(model, data);
  detail::ltdl_in_place(model, data);
}

/// Factorises data.M + diag(extra) = L^T D L, e.g. extra = h Kd + h^2 Kp for an implicit step.
/// \param extra  added to M's diagonal (kg m^2), nj; every entry >= 0 keeps the matrix positive definite
template <class Model, class Extra>
inline void factorize_mass_matrix(const Model& model, Data<Model>& data,
                                  const Eigen::MatrixBase<Extra>& extra) noexcept {
  eigen_assert(extra.size() == model.size());
  detail::copy_tree_entries(model, data);
  data.L.diagonal() += extra;
  detail::ltdl_in_place(model, data);
}

/// Where the mass matrix is singular, from the pivots of its elimination (D of M = L^T D L after
/// factorize_mass_matrix or mass-matrix forward dynamics; the articulated inertias about the joint axes,
/// 1 / data.D_inv, after the articulated-body method): looked at in the order the elimination meets them,
/// tips inwards, the first not above `relative` times the largest finite one (a zero pivot turns those
/// after it into NaN). The joint found turns, with the joints beyond it turning along, no mass.
/// \param n      the number of joints
/// \param pivot  pivot(i), joint i's pivot (kg m^2)
/// \return the joint's index, or -1 where every pivot is clearly positive. No allocation.
template <class Pivot>
inline int singular_pivot_joint(int n, const Pivot& pivot, double relative = 1e-10) noexcept {
  double largest = 0;
  for (int i = 0; i < n; ++i)
    if (const double p = double(pivot(i)); std::isfinite(p)) largest = std::max(largest, std::abs(p));
  for (int i = n - 1; i >= 0; --i)
    if (!(double(pivot(i)) > relative * largest)) return i;
  return -1;
}

/// Solves (L^T D L) x = b in place with the factors of the last factorisation (Featherstone 2008, §6.5,
/// Table 6.4).
/// \param data  workspace holding L and D
/// \param x     nj x k: b on entry (one column or several), the solution on exit (for b in N m, x in rad/s^2)
template <class Model, class X>
inline void solve_mass_matrix(const Model& model, const Data<Model>& data, const Eigen::MatrixBase<X>& x) noexcept {
  eigen_assert(x.rows() == model.size());
  detail::solve_lt(model, data, x);
  detail::solve_d(model, data, x);
  detail::solve_l(model, data, x);
}

}  // namespace humandyn
