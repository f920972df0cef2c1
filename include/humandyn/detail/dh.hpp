// The rotations of one standard DH link, R = Rz(theta + q) * Rx(alpha), applied to 3-vectors without
// forming a matrix. Rx is specialised on the twist class, so alpha = 0, ±90°, 180° cost sign swaps.
#pragma once

#include "humandyn/shape.hpp"

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>

namespace humandyn::detail {

template <class S>
using Vec3 = Eigen::Matrix<S, 3, 1>;

// v' = Rx(alpha) * v
template <Twist T, class S>
inline Vec3<S> rot_x(const Vec3<S>& v, S ca, S sa) noexcept {
  if constexpr (T == Twist::Zero) return v;
  else if constexpr (T == Twist::HalfPi) return Vec3<S>(v.x(), -v.z(), v.y());
  else if constexpr (T == Twist::MinusHalfPi) return Vec3<S>(v.x(), v.z(), -v.y());
  else if constexpr (T == Twist::Pi) return Vec3<S>(v.x(), -v.y(), -v.z());
  else return Vec3<S>(v.x(), ca * v.y() - sa * v.z(), sa * v.y() + ca * v.z());
}

// v' = Rx(alpha)^T * v
template <Twist T, class S>
inline Vec3<S> rot_x_t(const Vec3<S>& v, S ca, S sa) noexcept {
  if constexpr (T == Twist::Zero) return v;
  else if constexpr (T == Twist::HalfPi) return Vec3<S>(v.x(), v.z(), -v.y());
  else if constexpr (T == Twist::MinusHalfPi) return Vec3<S>(v.x(), -v.z(), v.y());
  else if constexpr (T == Twist::Pi) return Vec3<S>(v.x(), -v.y(), -v.z());
  else return Vec3<S>(v.x(), ca * v.y() + sa * v.z(), -sa * v.y() + ca * v.z());
}

// cos and sin of a joint angle theta + q, exact at the quarter turns: a value within rounding of 0
// (a few ulps, i.e. an angle within ~1e-15 rad of a multiple of 90 degrees in double) is taken as 0;
// the other one is then +-1 to the last bit already. So a straight pose such as theta + q = -pi/2
// turns vectors by exact sign swaps, and a torque that physics makes zero (gravity about a vertical
// axis, a straight arm about its own axis) comes out as exactly 0, not 1e-31.
template <class S>
inline void cos_sin(S angle, S& c, S& s) noexcept {
  constexpr S tiny = S(4) * std::numeric_limits<S>::epsilon();
  c = std::cos(angle);
  s = std::sin(angle);
  if (std::abs(c) < tiny) c = S(0);
  if (std::abs(s) < tiny) s = S(0);
}

// v' = Rz(theta) * v
template <class S>
inline Vec3<S> rot_z(const Vec3<S>& v, S c, S s) noexcept {
  return Vec3<S>(c * v.x() - s * v.y(), s * v.x() + c * v.y(), v.z());
}

// v' = Rz(theta)^T * v
template <class S>
inline Vec3<S> rot_z_t(const Vec3<S>& v, S c, S s) noexcept {
  return Vec3<S>(c * v.x() + s * v.y(), -s * v.x() + c * v.y(), v.z());
}

// Calls f(std::integral_constant<int, i>) for i = 0 .. N-1, unrolled at compile time.
template <int N, class F>
inline void static_for(F&& f) {
  [&]<int... I>(std::integer_sequence<int, I...>) {
    (f(std::integral_constant<int, I>{}), ...);
  }(std::make_integer_sequence<int, N>{});
}

// Calls f(std::integral_constant<int, i>) for i = N-1 .. 0, unrolled at compile time.
template <int N, class F>
inline void static_for_reverse(F&& f) {
  [&]<int... I>(std::integer_sequence<int, I...>) {
    (f(std::integral_constant<int, N - 1 - I>{}), ...);
  }(std::make_integer_sequence<int, N>{});
}

// Calls f(std::integral_constant<Twist, t>) for the runtime twist t: one instantiation per class.
template <class F>
inline void with_twist(Twist t, F&& f) {
  switch (t) {
    case Twist::Zero: f(std::integral_constant<Twist, Twist::Zero>{}); break;
    case Twist::HalfPi: f(std::integral_constant<Twist, Twist::HalfPi>{}); break;
    case Twist::MinusHalfPi: f(std::integral_constant<Twist, Twist::MinusHalfPi>{}); break;
    case Twist::Pi: f(std::integral_constant<Twist, Twist::Pi>{}); break;
    default: f(std::integral_constant<Twist, Twist::General>{}); break;
  }
}

}  // namespace humandyn::detail
