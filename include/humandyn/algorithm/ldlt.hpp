// The LTDL factorisation of the mass matrix (Featherstone, RBDA §6.5, Tables 6.3 and 6.4):
// M = L^T D L with L unit lower triangular. Eliminating the joints from the tips inwards, L(i, j) is
// non-zero only where j is an ancestor of i, like M itself: a tree produces no fill-in, and every loop
// below walks the parent array instead of whole rows (cost: the sum over joints of depth^2).
//   factorize_mass_matrix(model, data)         data.M                -> data.L, data.D
//   factorize_mass_matrix(model, data, extra)  data.M + diag(extra)  -> data.L, data.D (implicit integration)
//   solve_mass_matrix(model, data, x)          x <- (L^T D L)^-1 x, in place (a vector or a matrix of columns)
// data.M is left untouched. TreeLU factorises a matrix of M's sparsity that is not symmetric (backward
// Euler's Jacobian) the same way, as U D L.
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

/// A square matrix with the mass matrix's sparsity but not symmetric, A(i, j) zero unless i = j or one
/// of them is an ancestor of the other (as M + h dtau/dqd + h^2 dtau/dq, backward Euler's Jacobian:
/// rnea_derivatives.hpp), factorised as A = U D L: joints eliminated tips inwards as in LTDL, U unit
/// upper and L unit lower triangular, both of A's sparsity (no fill-in; cost the sum over joints of
/// depth^2, against a dense LU's n^3 / 3). Without pivoting: compute() refuses a matrix whose elimination
/// meets a non-finite pivot or one within rounding of zero (at most max(1e-10, 64 epsilon) times the
/// largest diagonal entry), or a multiplier larger than max_multiplier (the growth that pivoting would
/// prevent), and the caller then factorises it densely. No allocation.
template <class Model>
struct TreeLU {
  using S = typename Model::scalar_type;
  using Matrix = typename Data<Model>::MassMatrix;  // nj x nj
  static constexpr double max_multiplier = 1e3;

  explicit TreeLU(const Model& model) : F(Matrix::Identity(model.size(), model.size())) {}

  /// Factorises A (nj x nj, of the tree's sparsity: entries off it are not read).
  /// \return false, F then unusable, where the elimination without pivoting is refused (see above)
  template <class A>
  bool compute(const Model& model, const Eigen::MatrixBase<A>& a) noexcept {
    eigen_assert(a.rows() == model.size() && a.cols() == model.size());
    F = a;
    // a pivot that is rounding against the diagonal's largest is taken as zero, as singular_pivot_joint takes it
    using std::abs, std::max;
    const S floor = S(max(1e-10, 64 * double(Eigen::NumTraits<S>::epsilon()))) * F.diagonal().cwiseAbs().maxCoeff();
    bool ok = true;
    // eliminate joint k (tips first) from its ancestors i and j: A(i, j) -= A(i, k) A(k, j) / A(k, k);
    // A(i, k) becomes U(i, k), A(k, i) becomes L(k, i)
    detail::for_each_joint_reverse(model, [&](auto k, auto, auto, auto) {
      const S d = F(int(k), int(k));
      ok = ok && std::isfinite(d) && abs(d) > floor;
      const S inv = S(1) / d;
      detail::for_each_ancestor_inline(model, k, [&](auto i) {
        const S u = F(int(i), int(k)) * inv, l = F(int(k), int(i)) * inv;
        ok = ok && abs(u) <= S(max_multiplier) && abs(l) <= S(max_multiplier);
        F(int(i), int(i)) -= u * F(int(k), int(i));
        detail::for_each_ancestor_inline(model, i, [&](auto j) {
          F(int(i), int(j)) -= u * F(int(k), int(j));
          F(int(j), int(i)) -= F(int(j), int(k)) * l;
        });
        F(int(i), int(k)) = u;
        F(int(k), int(i)) = l;
      });
    });
    return ok;
  }

  /// x <- A^-1 x in place (nj, or nj x k columns) with the last factorisation compute() accepted.
  template <class X>
  void solve_in_place(const Model& model, const Eigen::MatrixBase<X>& x_in) const noexcept {
    auto& x = const_cast<Eigen::MatrixBase<X>&>(x_in);
    eigen_assert(x.rows() == model.size());
    // U y = b, tips inwards; D z = y; L x = z, base outwards
    detail::for_each_joint_reverse(model, [&](auto k, auto, auto, auto) {
      detail::for_each_ancestor_inline(model, k, [&](auto i) { x.row(int(i)) -= F(int(i), int(k)) * x.row(int(k)); });
    });
    for (int k = 0; k < model.size(); ++k) x.row(k) /= F(k, k);
    detail::for_each_joint(model, [&](auto k, auto, auto, auto) {
      detail::for_each_ancestor_inline(model, k, [&](auto i) { x.row(int(k)) -= F(int(k), int(i)) * x.row(int(i)); });
    });
  }

  Matrix F;  ///< D on the diagonal, U(i, k) above it and L(k, i) below it, i an ancestor of k
};

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
