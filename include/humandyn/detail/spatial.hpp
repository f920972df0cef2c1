// Spatial algebra in DH link frames (Featherstone, "Rigid Body Dynamics Algorithms", ch. 2), for the
// forward-dynamics algorithms. A spatial vector is (angular; linear), expressed in a link frame and
// taken about its origin. Between a parent link and link i the algorithms go through joint i's DH base
// frame b_i: the mount (if any) takes the parent frame to b_i, then E_i = Rz(theta_i + q_i) Rx(alpha_i)
// and the offset p_i, which in link i's coordinates is the constant p*_i = (a, d sin alpha, d cos alpha).
// Joint i turns about z of b_i: in link i's coordinates the axis is z_i = Rx(alpha)^T e_z and it passes
// through -p*_i, so its motion subspace is S_i = (z_i; z_i x p*_i).
#pragma once

#include "humandyn/data.hpp"
#include "humandyn/detail/dh.hpp"

namespace humandyn::detail {

// The spatial vector (top; bottom), assembled through fixed-size halves.
template <class S>
inline SpatialVector<S> spatial(const Vec3<S>& top, const Vec3<S>& bottom) noexcept {
  SpatialVector<S> out;
  out.template head<3>() = top;
  out.template tail<3>() = bottom;
  return out;
}

// The joint axis in link i's coordinates, z_i = Rx(alpha)^T e_z: (0, 0, 1) for alpha = 0, (0, 1, 0) for 90 degrees.
template <Twist T, class S>
inline Vec3<S> joint_axis(S ca, S sa) noexcept {
  return rot_x_t<T>(Vec3<S>(S(0), S(0), S(1)), ca, sa);
}

// Link i's motion subspace S_i = (z_i; z_i x p*_i) in its own frame.
template <Twist T, class S>
inline SpatialVector<S> motion_subspace(const JointConstants<S>& j) noexcept {
  const Vec3<S> z = joint_axis<T>(j.ca, j.sa);
  return spatial<S>(z, z.cross(j.pstar));
}

// A motion vector (velocity or spatial acceleration) of the parent link carried to link i's frame:
// i_X_parent m. Through the mount, then E_i^T, then the offset: lin_i = E^T lin_b + ang_i x p*.
template <Twist T, class S>
inline SpatialVector<S> motion_to_child(const JointConstants<S>& j, bool mounted, S c, S s,
                                        const SpatialVector<S>& m) noexcept {
  Vec3<S> ang = m.template head<3>(), lin = m.template tail<3>();
  if (mounted) {
    lin = j.mount_R.transpose() * (lin + ang.cross(j.mount_p));
    ang = j.mount_R.transpose() * ang;
  }
  const Vec3<S> ang_i = rot_x_t<T>(rot_z_t(ang, c, s), j.ca, j.sa);
  return spatial<S>(ang_i, rot_x_t<T>(rot_z_t(lin, c, s), j.ca, j.sa) + ang_i.cross(j.pstar));
}

// A force vector (moment; force) of link i carried to its parent's frame: parent_X_i^* f.
template <Twist T, class S>
inline SpatialVector<S> force_to_parent(const JointConstants<S>& j, bool mounted, S c, S s,
                                        const SpatialVector<S>& f) noexcept {
  const Vec3<S> force_i = f.template tail<3>();
  Vec3<S> force = rot_z(rot_x<T>(force_i, j.ca, j.sa), c, s);
  Vec3<S> moment = rot_z(rot_x<T>(Vec3<S>(f.template head<3>() + j.pstar.cross(force_i)), j.ca, j.sa), c, s);
  if (mounted) {
    force = j.mount_R * force;
    moment = j.mount_R * moment + j.mount_p.cross(force);
  }
  return spatial<S>(moment, force);
}

// R M R^T for R = Rz(theta) Rx(alpha). For the special twists Rx M Rx^T only permutes entries and
// flips signs (N(i, j) = sign_i sign_j M(perm_i, perm_j)); Rz then mixes rows 0, 1 and columns 0, 1.
template <Twist T, class S>
inline Mat3<S> rotate_dh(const Mat3<S>& M, S c, S s, S ca, S sa) noexcept {
  Mat3<S> N;
  if constexpr (T == Twist::Zero) {
    N = M;
  } else if constexpr (T == Twist::General) {
    Mat3<S> Rx;
    Rx << S(1), S(0), S(0), S(0), ca, -sa, S(0), sa, ca;
    N = Rx * M * Rx.transpose();
  } else {
    constexpr int perm[3] = {0, T == Twist::Pi ? 1 : 2, T == Twist::Pi ? 2 : 1};
    constexpr int sign[3] = {1, T == Twist::MinusHalfPi ? 1 : -1, T == Twist::HalfPi ? 1 : -1};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) N(i, k) = sign[i] * sign[k] == 1 ? M(perm[i], perm[k]) : -M(perm[i], perm[k]);
  }
  const Eigen::Matrix<S, 1, 3> r0 = N.row(0), r1 = N.row(1);
  N.row(0) = c * r0 - s * r1;
  N.row(1) = s * r0 + c * r1;
  const Vec3<S> c0 = N.col(0), c1 = N.col(1);
  N.col(0) = c * c0 - s * c1;
  N.col(1) = s * c0 + c * c1;
  return N;
}

// A spatial inertia [[A, B], [B^T, C]] (n = A w + B v, f = B^T w + C v) about a point O, moved to the
// point O' from which O is seen at r (same axes): A' = A - B[r] + [r]B^T - [r]C[r], B' = B + [r]C, C' = C.
// With K = [r]C: [r]B^T = -(B[r])^T and [r]C[r] = K[r]; the products with [r] are written out.
template <class S>
inline void shift_inertia(Mat3<S>& A, Mat3<S>& B, const Mat3<S>& C, const Vec3<S>& r) noexcept {
  const S x = r.x(), y = r.y(), z = r.z();
  Mat3<S> K;  // [r] C, row by row
  K.row(0) = y * C.row(2) - z * C.row(1);
  K.row(1) = z * C.row(0) - x * C.row(2);
  K.row(2) = x * C.row(1) - y * C.row(0);
  Mat3<S> Br, Kr;  // B [r] and K [r], column by column
  Br.col(0) = z * B.col(1) - y * B.col(2);
  Br.col(1) = x * B.col(2) - z * B.col(0);
  Br.col(2) = y * B.col(0) - x * B.col(1);
  Kr.col(0) = z * K.col(1) - y * K.col(2);
  Kr.col(1) = x * K.col(2) - z * K.col(0);
  Kr.col(2) = y * K.col(0) - x * K.col(1);
  A -= Br + Br.transpose() + Kr;
  B += K;
}

// Adds the spatial inertia I of link i (its frame, about its origin) to its parent's P, carried over
// the joint: parent_X_i^* I i_X_parent. Moved to b_i's origin, turned by E_i, then through the mount.
template <Twist T, class S>
inline void add_inertia_to_parent(const JointConstants<S>& j, bool mounted, S c, S s, const SpatialMatrix<S>& I,
                                  SpatialMatrix<S>& P) noexcept {
  Mat3<S> A = I.template topLeftCorner<3, 3>(), B = I.template topRightCorner<3, 3>();
  const Mat3<S> C0 = I.template bottomRightCorner<3, 3>();
  shift_inertia<S>(A, B, C0, j.pstar);
  A = rotate_dh<T>(A, c, s, j.ca, j.sa);
  B = rotate_dh<T>(B, c, s, j.ca, j.sa);
  Mat3<S> C = rotate_dh<T>(C0, c, s, j.ca, j.sa);
  if (mounted) {
    const Mat3<S>& R = j.mount_R;
    A = R * A * R.transpose();
    B = R * B * R.transpose();
    C = R * C * R.transpose();
    shift_inertia<S>(A, B, C, j.mount_p);
  }
  P.template topLeftCorner<3, 3>() += A;
  P.template topRightCorner<3, 3>() += B;
  P.template bottomLeftCorner<3, 3>() += B.transpose();
  P.template bottomRightCorner<3, 3>() += C;
}

// I S for a joint's motion subspace S = (z; zp), with the axis z = Rx(alpha)^T e_z picked as a signed
// column for the special twists.
template <Twist T, class S>
inline SpatialVector<S> inertia_times_subspace(const SpatialMatrix<S>& I, S ca, S sa, const Vec3<S>& zp) noexcept {
  SpatialVector<S> out = I.template rightCols<3>() * zp;
  if constexpr (T == Twist::Zero)
    out += I.col(2);
  else if constexpr (T == Twist::HalfPi)
    out += I.col(1);
  else if constexpr (T == Twist::MinusHalfPi)
    out -= I.col(1);
  else if constexpr (T == Twist::Pi)
    out -= I.col(2);
  else
    out += sa * I.col(1) + ca * I.col(2);
  return out;
}

// The rotation [x y z] Rx(alpha), given its columns before Rx: sign swaps for the special twists
// (the derivatives' link orientations, rnea_derivatives.hpp).
template <Twist T, class S>
inline Mat3<S> rotate_columns_x(const Vec3<S>& x, const Vec3<S>& y, const Vec3<S>& z, S ca, S sa) noexcept {
  Mat3<S> R;
  R.col(0) = x;
  if constexpr (T == Twist::Zero) {
    R.col(1) = y;
    R.col(2) = z;
  } else if constexpr (T == Twist::HalfPi) {
    R.col(1) = z;
    R.col(2) = -y;
  } else if constexpr (T == Twist::MinusHalfPi) {
    R.col(1) = -z;
    R.col(2) = y;
  } else if constexpr (T == Twist::Pi) {
    R.col(1) = -y;
    R.col(2) = -z;
  } else {
    R.col(1) = ca * y + sa * z;
    R.col(2) = ca * z - sa * y;
  }
  return R;
}

// A body's spatial inertia about a frame's origin from its mass m, first moment of mass h = m com and
// rotational inertia Io about the origin: [[Io, [h]], [[h]^T, m 1]] (Featherstone, RBDA eq. 2.63).
template <class S>
inline SpatialMatrix<S> spatial_inertia(S m, const Vec3<S>& h, const Mat3<S>& Io) noexcept {
  SpatialMatrix<S> I;
  I.template topLeftCorner<3, 3>() = Io;
  I.template topRightCorner<3, 3>() << S(0), -h.z(), h.y(),  //
      h.z(), S(0), -h.x(),                                   //
      -h.y(), h.x(), S(0);
  I.template bottomLeftCorner<3, 3>() = I.template topRightCorner<3, 3>().transpose();
  I.template bottomRightCorner<3, 3>() = m * Mat3<S>::Identity();
  return I;
}

// Link i's spatial inertia about its origin, from the model's constants (RigidBodyInertia::inertia_about).
template <class S>
inline SpatialMatrix<S> link_spatial_inertia(const JointConstants<S>& j) noexcept {
  return spatial_inertia(j.mass, j.h, j.inertia_origin);
}

// A rigid body's spatial inertia about its frame's origin.
template <class S>
inline SpatialMatrix<S> spatial_inertia(const RigidBodyInertia<S>& b) noexcept {
  return spatial_inertia(b.mass, Vec3<S>(b.mass * b.com), b.inertia_about(Vec3<S>::Zero()));
}

// Spatial cross products: m1 x m2 (motion) and m x* f (force).
template <class S>
HUMANDYN_ALWAYS_INLINE SpatialVector<S> cross_motion(const SpatialVector<S>& m1, const SpatialVector<S>& m2) noexcept {
  const Vec3<S> w = m1.template head<3>(), v = m1.template tail<3>();
  const Vec3<S> w2 = m2.template head<3>(), v2 = m2.template tail<3>();
  return spatial<S>(w.cross(w2), w.cross(v2) + v.cross(w2));
}

template <class S>
HUMANDYN_ALWAYS_INLINE SpatialVector<S> cross_force(const SpatialVector<S>& m, const SpatialVector<S>& f) noexcept {
  const Vec3<S> w = m.template head<3>(), v = m.template tail<3>();
  const Vec3<S> n = f.template head<3>(), force = f.template tail<3>();
  return spatial<S>(w.cross(n) + v.cross(force), w.cross(force));
}

}  // namespace humandyn::detail
