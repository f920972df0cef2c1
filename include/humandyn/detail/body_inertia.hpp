// The composite-rigid-body algorithm's working form of a RigidBodyInertia (model.hpp): the body about a
// frame's origin in that frame's axes, kept as its ten independent numbers, the mass m, the first moment
// of mass h = m c (c the centre of mass) and the six entries of the symmetric rotational inertia I about
// the origin. It starts as a link's inertia about its origin, which the model computes once
// (RigidBodyInertia::inertia_about), and is carried from link to link (Featherstone, RBDA §6.2) with the
// moves of a DH joint written out: a shift of the origin, Rx(alpha) (a permutation with signs for the
// special twists) and a planar Rz(theta + q).
#pragma once

#include "humandyn/detail/dh.hpp"
#include "humandyn/detail/inline.hpp"
#include "humandyn/model.hpp"

namespace humandyn::detail {

template <class S>
struct BodyInertia {
  S m = 0;
  Vec3<S> h = Vec3<S>::Zero();
  S xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;

  // I e_z, the moment of the unit rotation about z
  Vec3<S> col_z() const noexcept { return Vec3<S>(xz, yz, zz); }

  // the rotational inertia about the origin, as a symmetric matrix
  Mat3<S> rotational() const noexcept {
    Mat3<S> I;
    I << xx, xy, xz, xy, yy, yz, xz, yz, zz;
    return I;
  }

  HUMANDYN_ALWAYS_INLINE BodyInertia& operator+=(const BodyInertia& o) noexcept {
    m += o.m;
    h += o.h;
    xx += o.xx, yy += o.yy, zz += o.zz, xy += o.xy, xz += o.xz, yz += o.yz;
    return *this;
  }
};

// Link i's own inertia about its origin, from the model's constants (RigidBodyInertia::inertia_about).
template <class S>
HUMANDYN_ALWAYS_INLINE BodyInertia<S> link_inertia(const JointConstants<S>& j) noexcept {
  const Mat3<S>& I = j.inertia_origin;
  return {j.mass, j.h, I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)};
}

// A rigid body about its own frame's origin, in the ten-number form (a base body, which has no joint).
template <class S>
HUMANDYN_ALWAYS_INLINE BodyInertia<S> origin_form(const RigidBodyInertia<S>& b) noexcept {
  const Mat3<S> I = b.inertia_about(Vec3<S>::Zero());
  return {b.mass, Vec3<S>(b.mass * b.com), I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)};
}

// The same body about a new origin from which the old one is seen at p (same axes). With h' = h + m p
// and g = (h + h') / 2: I' = I + 2 (p . g) 1 - (g p^T + p g^T).
template <class S>
HUMANDYN_ALWAYS_INLINE BodyInertia<S> shifted(const BodyInertia<S>& B, const Vec3<S>& p) noexcept {
  BodyInertia<S> out;
  out.m = B.m;
  out.h = B.h + B.m * p;
  const Vec3<S> g = B.h + (constant<S>(0.5) * B.m) * p;
  out.xx = B.xx + S(2) * (p.y() * g.y() + p.z() * g.z());
  out.yy = B.yy + S(2) * (p.x() * g.x() + p.z() * g.z());
  out.zz = B.zz + S(2) * (p.x() * g.x() + p.y() * g.y());
  out.xy = B.xy - (g.x() * p.y() + p.x() * g.y());
  out.xz = B.xz - (g.x() * p.z() + p.x() * g.z());
  out.yz = B.yz - (g.y() * p.z() + p.y() * g.z());
  return out;
}

// The same body about a new origin from which the old one is seen at (a, 0, d): the DH offset of a link
// origin from its joint's base frame, in the base frame's axes once turned by Rx(alpha) (shifted above
// with p_y = 0 written out).
template <class S>
HUMANDYN_ALWAYS_INLINE BodyInertia<S> shifted_dh(const BodyInertia<S>& B, S a, S d) noexcept {
  BodyInertia<S> out;
  out.m = B.m;
  out.h = Vec3<S>(B.h.x() + B.m * a, B.h.y(), B.h.z() + B.m * d);
  const S gx = B.h.x() + constant<S>(0.5) * B.m * a, gy = B.h.y(), gz = B.h.z() + constant<S>(0.5) * B.m * d;
  out.xx = B.xx + S(2) * d * gz;
  out.yy = B.yy + S(2) * (a * gx + d * gz);
  out.zz = B.zz + S(2) * a * gx;
  out.xy = B.xy - a * gy;
  out.xz = B.xz - (d * gx + a * gz);
  out.yz = B.yz - d * gy;
  return out;
}

// Rx(alpha) applied to the body (I' = Rx I Rx^T, h' = Rx h): entries swap places and signs for the
// special twists.
template <Twist T, class S>
HUMANDYN_ALWAYS_INLINE BodyInertia<S> rotated_x(const BodyInertia<S>& B, S ca, S sa) noexcept {
  if constexpr (T == Twist::Zero) return B;
  BodyInertia<S> out;
  out.m = B.m;
  out.h = rot_x<T>(B.h, ca, sa);
  out.xx = B.xx;
  if constexpr (T == Twist::HalfPi) {  // y' = -z, z' = y
    out.yy = B.zz, out.zz = B.yy, out.yz = -B.yz, out.xy = -B.xz, out.xz = B.xy;
  } else if constexpr (T == Twist::MinusHalfPi) {  // y' = z, z' = -y
    out.yy = B.zz, out.zz = B.yy, out.yz = -B.yz, out.xy = B.xz, out.xz = -B.xy;
  } else if constexpr (T == Twist::Pi) {  // y' = -y, z' = -z
    out.yy = B.yy, out.zz = B.zz, out.yz = B.yz, out.xy = -B.xy, out.xz = -B.xz;
  } else {  // y' = ca y - sa z, z' = sa y + ca z
    const S cc = ca * ca, ss = sa * sa, cs = ca * sa;
    out.yy = cc * B.yy - S(2) * cs * B.yz + ss * B.zz;
    out.zz = ss * B.yy + S(2) * cs * B.yz + cc * B.zz;
    out.yz = cs * (B.yy - B.zz) + (cc - ss) * B.yz;
    out.xy = ca * B.xy - sa * B.xz;
    out.xz = sa * B.xy + ca * B.xz;
  }
  return out;
}

// Rz(theta) applied to the body, c = cos theta, s = sin theta: a planar rotation of the x-y block
// (through the double angle), of (xz, yz) and of (h_x, h_y); zz and h_z stay.
template <class S>
HUMANDYN_ALWAYS_INLINE BodyInertia<S> rotated_z(const BodyInertia<S>& B, S c, S s) noexcept {
  BodyInertia<S> out;
  out.m = B.m;
  out.h = rot_z(B.h, c, s);
  const S c2 = c * c - s * s, s2 = S(2) * c * s;
  const S u = constant<S>(0.5) * (B.xx + B.yy), v = constant<S>(0.5) * (B.xx - B.yy);
  const S v2 = c2 * v - s2 * B.xy;
  out.xx = u + v2;
  out.yy = u - v2;
  out.xy = s2 * v + c2 * B.xy;
  out.zz = B.zz;
  out.xz = c * B.xz - s * B.yz;
  out.yz = s * B.xz + c * B.yz;
  return out;
}

// A general rotation R applied to the body (a joint's mount): I' = R I R^T, h' = R h.
template <class S>
HUMANDYN_ALWAYS_INLINE BodyInertia<S> rotated(const BodyInertia<S>& B, const Mat3<S>& R) noexcept {
  Mat3<S> I;
  I << B.xx, B.xy, B.xz,  //
      B.xy, B.yy, B.yz,   //
      B.xz, B.yz, B.zz;
  const Mat3<S> J = R * I * R.transpose();
  BodyInertia<S> out;
  out.m = B.m;
  out.h = R * B.h;
  out.xx = J(0, 0), out.yy = J(1, 1), out.zz = J(2, 2), out.xy = J(0, 1), out.xz = J(0, 2), out.yz = J(1, 2);
  return out;
}

}  // namespace humandyn::detail
