// The rotations of one standard DH link, R = Rz(theta + q) * Rx(alpha), applied to 3-vectors without
// forming a matrix. Rx is specialised on the twist class, so alpha = 0, ±90°, 180° cost sign swaps.
#pragma once

#include "humandyn/shape.hpp"

#include <Eigen/Core>

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
