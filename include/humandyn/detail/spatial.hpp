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

// R M R^T for R = Rz(theta) Rx(alpha), applied as sign swaps for the special twists.
template <Twist T, class S>
inline Mat3<S> rotate_dh(const Mat3<S>& M, S c, S s, S ca, S sa) noexcept {
  Mat3<S> RM, out;
  for (int k = 0; k < 3; ++k) RM.col(k) = rot_z(rot_x<T>(Vec3<S>(M.col(k)), ca, sa), c, s);
  for (int k = 0; k < 3; ++k) out.row(k) = rot_z(rot_x<T>(Vec3<S>(RM.row(k).transpose()), ca, sa), c, s).transpose();
  return out;
}

// The rotation [x y z] Rx(alpha), given its columns before Rx: sign swaps for the special twists.
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

// [r]x, the cross-product matrix.
template <class S>
inline Mat3<S> skew(const Vec3<S>& r) noexcept {
  Mat3<S> X;
  X << S(0), -r.z(), r.y(),  //
      r.z(), S(0), -r.x(),   //
      -r.y(), r.x(), S(0);
  return X;
}

// A spatial inertia [[A, B], [B^T, C]] (n = A w + B v, f = B^T w + C v) about a point O, moved to the
// point O' from which O is seen at r (same axes): A' = A - B[r] + [r]B^T - [r]C[r], B' = B + [r]C, C' = C.
template <class S>
inline void shift_inertia(SpatialMatrix<S>& I, const Vec3<S>& r) noexcept {
  const Mat3<S> rx = skew(r);
  const Mat3<S> B = I.template topRightCorner<3, 3>();
  const Mat3<S> C = I.template bottomRightCorner<3, 3>();
  const Mat3<S> rxC = rx * C;
  const Mat3<S> BrT = B * rx;  // B [r]; its transpose is -[r] B^T
  Mat3<S> A = I.template topLeftCorner<3, 3>();
  A += -BrT - BrT.transpose() - rxC * rx;  // -B[r] + [r]B^T - [r]C[r]
  I.template topLeftCorner<3, 3>() = S(0.5) * (A + A.transpose());
  const Mat3<S> Bn = B + rxC;
  I.template topRightCorner<3, 3>() = Bn;
  I.template bottomLeftCorner<3, 3>() = Bn.transpose();
}

// A spatial inertia of link i (its frame, about its origin) carried to its parent's frame:
// parent_X_i^* I i_X_parent. Moved to b_i's origin, turned by E_i, then through the mount.
template <Twist T, class S>
inline SpatialMatrix<S> inertia_to_parent(const JointConstants<S>& j, bool mounted, S c, S s,
                                          SpatialMatrix<S> I) noexcept {
  shift_inertia(I, j.pstar);
  SpatialMatrix<S> out;
  out.template topLeftCorner<3, 3>() = rotate_dh<T>(Mat3<S>(I.template topLeftCorner<3, 3>()), c, s, j.ca, j.sa);
  const Mat3<S> B = rotate_dh<T>(Mat3<S>(I.template topRightCorner<3, 3>()), c, s, j.ca, j.sa);
  out.template topRightCorner<3, 3>() = B;
  out.template bottomLeftCorner<3, 3>() = B.transpose();
  out.template bottomRightCorner<3, 3>() = rotate_dh<T>(Mat3<S>(I.template bottomRightCorner<3, 3>()), c, s, j.ca, j.sa);
  if (mounted) {
    const Mat3<S>& R = j.mount_R;
    out.template topLeftCorner<3, 3>() = R * out.template topLeftCorner<3, 3>() * R.transpose();
    const Mat3<S> Bm = R * out.template topRightCorner<3, 3>() * R.transpose();
    out.template topRightCorner<3, 3>() = Bm;
    out.template bottomLeftCorner<3, 3>() = Bm.transpose();
    out.template bottomRightCorner<3, 3>() = R * out.template bottomRightCorner<3, 3>() * R.transpose();
    shift_inertia(out, j.mount_p);
  }
  return out;
}

// The spatial inertia of a rigid body of mass m, centre of mass com and rotational inertia Ic about it,
// about the frame origin: A = Ic - m [com]^2, B = m [com], C = m 1.
template <class S>
inline SpatialMatrix<S> body_inertia(S m, const Vec3<S>& com, const Mat3<S>& Ic) noexcept {
  const Mat3<S> cx = skew(com);
  SpatialMatrix<S> I;
  I.template topLeftCorner<3, 3>() = Ic - m * cx * cx;
  I.template topRightCorner<3, 3>() = m * cx;
  I.template bottomLeftCorner<3, 3>() = -m * cx;
  I.template bottomRightCorner<3, 3>() = m * Mat3<S>::Identity();
  return I;
}

// Spatial cross products: m1 x m2 (motion) and m x* f (force).
template <class S>
inline SpatialVector<S> cross_motion(const SpatialVector<S>& m1, const SpatialVector<S>& m2) noexcept {
  const Vec3<S> w = m1.template head<3>(), v = m1.template tail<3>();
  const Vec3<S> w2 = m2.template head<3>(), v2 = m2.template tail<3>();
  return spatial<S>(w.cross(w2), w.cross(v2) + v.cross(w2));
}

template <class S>
inline SpatialVector<S> cross_force(const SpatialVector<S>& m, const SpatialVector<S>& f) noexcept {
  const Vec3<S> w = m.template head<3>(), v = m.template tail<3>();
  const Vec3<S> n = f.template head<3>(), force = f.template tail<3>();
  return spatial<S>(w.cross(n) + v.cross(force), w.cross(force));
}

}  // namespace humandyn::detail
