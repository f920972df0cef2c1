// The rotations of one standard DH link, R = Rz(theta + q) * Rx(alpha), applied to 3-vectors without
// forming a matrix. Rx is specialised on the twist class, so alpha = 0, ±90°, 180° cost sign swaps.
#pragma once

#include "humandyn/detail/lanes.hpp"
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
  if constexpr (T == Twist::Zero)
    return v;
  else if constexpr (T == Twist::HalfPi)
    return Vec3<S>(v.x(), -v.z(), v.y());
  else if constexpr (T == Twist::MinusHalfPi)
    return Vec3<S>(v.x(), v.z(), -v.y());
  else if constexpr (T == Twist::Pi)
    return Vec3<S>(v.x(), -v.y(), -v.z());
  else
    return Vec3<S>(v.x(), ca * v.y() - sa * v.z(), sa * v.y() + ca * v.z());
}

// v' = Rx(alpha)^T * v
template <Twist T, class S>
inline Vec3<S> rot_x_t(const Vec3<S>& v, S ca, S sa) noexcept {
  if constexpr (T == Twist::Zero)
    return v;
  else if constexpr (T == Twist::HalfPi)
    return Vec3<S>(v.x(), v.z(), -v.y());
  else if constexpr (T == Twist::MinusHalfPi)
    return Vec3<S>(v.x(), -v.z(), v.y());
  else if constexpr (T == Twist::Pi)
    return Vec3<S>(v.x(), -v.y(), -v.z());
  else
    return Vec3<S>(v.x(), ca * v.y() + sa * v.z(), -sa * v.y() + ca * v.z());
}

// sin x and cos x from those of r, where x = k pi/2 + r: quadrant k mod 4 swaps and negates them,
// 0: (sin r, cos r); 1: (cos r, -sin r); 2: (-sin r, -cos r); 3: (-cos r, sin r).
template <class S>
inline void by_quadrant(const S& k, const S& sin_r, const S& cos_r, S& s, S& c) noexcept {
  using L = lanes<S>;
  const auto quadrant = L::quadrant(k);
  const auto swap = quadrant == 1 || quadrant == 3;
  const auto negate_s = quadrant >= 2, negate_c = quadrant == 1 || quadrant == 2;
  s = L::select(swap, cos_r, sin_r);
  c = L::select(swap, sin_r, cos_r);
  s = L::select(negate_s, S(-s), s);
  c = L::select(negate_c, S(-c), c);
}

// cos and sin of x in double, together and inline, within 1.5 ulps of the correctly rounded values for
// |x| <= 200 rad and 2.5 up to 1e5 rad (libm's beyond; test_cos_sin.cpp). Two steps:
//   x = k pi/2 + r with |r| <= pi/4: k by rounding x 2/pi; r by subtracting k pi/2 in three pieces
//     (Cody and Waite): the first two pieces have 33 significant bits, so k times each is exact for
//     |k| < 2^20, and the third carries pi/2's next 53 bits;
//   sin r and cos r by their Taylor series to r^17 and r^18 (the next terms are below 1e-19 on
//     |r| <= pi/4), then the quadrant k mod 4 swaps and negates them.
// For a float result (for_float: a float beyond sin_cos_float's range), the series stop at r^9 and r^10:
// the next terms are below 2e-9 and 1.2e-10, under a float's half ulp (3e-8 relative).
// S is double or a batch of doubles in SIMD lanes (detail/batch.hpp): every lane takes the same steps, and
// the lanes beyond 1e5 rad are given libm's values one by one.
template <class S, bool for_float = false>
inline void sin_cos_reduced(S x, S& s, S& c) noexcept {
#if defined(__clang__)
#pragma clang fp contract(off)  // (no fused multiply-adds: a lane gives the scalar's bits, as with GCC)
#endif
  using L = lanes<S>;
  const auto in_range = L::abs(x) <= S(1e5);  // (false for NaN and Inf)
  if constexpr (!L::is_batch) {
    if (!in_range) {
      s = std::sin(x);
      c = std::cos(x);
      return;
    }
  }
  constexpr double two_over_pi = 0x1.45f306dc9c883p-1;
  constexpr double pio2_1 = 0x1.921fb544p+0, pio2_2 = 0x1.0b4611a6p-34, pio2_3 = 0x1.3198a2e037073p-69;
  constexpr double round_magic = 0x1.8p52;  // adding and subtracting it rounds to an integer
  const S k = (x * two_over_pi + round_magic) - round_magic;
  const S r = ((x - k * pio2_1) - k * pio2_2) - k * pio2_3;
  const S r2 = r * r;
  S sin_r, cos_r;
  if constexpr (for_float) {
    sin_r = r + r * r2 * (-1.0 / 6 + r2 * (1.0 / 120 + r2 * (-1.0 / 5040 + r2 * (1.0 / 362880))));
    cos_r = 1.0 + r2 * (-0.5 + r2 * (1.0 / 24 + r2 * (-1.0 / 720 + r2 * (1.0 / 40320 + r2 * (-1.0 / 3628800)))));
  } else {
    sin_r =
        r + r * r2 *
                (-1.0 / 6 +
                 r2 * (1.0 / 120 + r2 * (-1.0 / 5040 +
                                         r2 * (1.0 / 362880 +
                                               r2 * (-1.0 / 39916800 +
                                                     r2 * (1.0 / 6227020800 + r2 * (-1.0 / 1307674368000 +
                                                                                    r2 * (1.0 / 355687428096000))))))));
    cos_r =
        1.0 +
        r2 * (-0.5 + r2 * (1.0 / 24 +
                           r2 * (-1.0 / 720 +
                                 r2 * (1.0 / 40320 +
                                       r2 * (-1.0 / 3628800 +
                                             r2 * (1.0 / 479001600 + r2 * (-1.0 / 87178291200 +
                                                                           r2 * (1.0 / 20922789888000 +
                                                                                 r2 * (-1.0 / 6402373705728000)))))))));
  }
  by_quadrant(k, sin_r, cos_r, s, c);
  if constexpr (L::is_batch) L::libm_sin_cos_where(!in_range, x, s, c);
}

// cos and sin of x in float arithmetic, for a float or a batch of floats, within 2 ulps of the correctly
// rounded values (about 1 % of them an ulp off; within 1e-12 absolute where the value is below 1e-6)
// for |x| <= 128 rad; beyond, sin_cos_reduced's float form in double, rounded (test_cos_sin.cpp). The
// same two steps in float:
//   x = k pi/2 + r: k by rounding x 2/pi; r by subtracting k pi/2 in three pieces of 8, 12 and 24
//     significant bits (k times each of the first two is exact, and x - k P1 is exact; the third piece
//     leaves pi/2's error at 1.7e-15, k times that within the bound for |k| <= 82);
//   sin r and cos r by polynomials to r^7 and r^8 (cos r = 1 - r^2/2 + ...) whose coefficients, rounded
//     to float, keep the error on |r| <= pi/4 at 8.3e-9 relative and 5.1e-10 (below a float's half
//     ulp), then the quadrant as above.
// A float register holds twice the doubles' lanes, so a sweep over the joints in lanes
// (joint_loop.hpp) computes four to sixteen of them at once, each with the same bits as alone.
template <class S>
inline void sin_cos_float(S x, S& s, S& c) noexcept {
#if defined(__clang__)
#pragma clang fp contract(off)  // (no fused multiply-adds: a lane gives the scalar's bits, as with GCC)
#endif
  using L = lanes<S>;
  const auto in_range = L::abs(x) <= S(128.0f);  // (false for NaN and Inf)
  if constexpr (!L::is_batch) {
    if (!in_range) {
      double sd, cd;
      sin_cos_reduced<double, true>(double(x), sd, cd);
      s = float(sd);
      c = float(cd);
      return;
    }
  }
  constexpr float two_over_pi = 0x1.45f306p-1f, round_magic = 0x1.8p23f;
  constexpr float pio2_1 = 0x1.92p+0f, pio2_2 = 0x1.fb6p-12f, pio2_3 = -0x1.777a5cp-25f;
  const S k = (x * two_over_pi + round_magic) - round_magic;
  const S r = ((x - k * pio2_1) - k * pio2_2) - k * pio2_3;
  const S r2 = r * r;
  const S sin_r = r + r * r2 * (-0x1.555546p-3f + r2 * (0x1.11073ap-7f + r2 * -0x1.9943ccp-13f));
  const S cos_r = 1.0f + r2 * (-0.5f + r2 * (0x1.55554ap-5f + r2 * (-0x1.6c0c8cp-10f + r2 * 0x1.9a024cp-16f)));
  by_quadrant(k, sin_r, cos_r, s, c);
  if constexpr (L::is_batch) {
    if (L::any(!in_range))
      for (int l = 0; l < L::width; ++l)
        if (!in_range[std::size_t(l)]) {
          double sd, cd;
          sin_cos_reduced<double, true>(double(L::get(x, l)), sd, cd);
          L::set(s, l, float(sd));
          L::set(c, l, float(cd));
        }
  }
}

// cos and sin of a joint angle theta + q, exact at the quarter turns: a value within rounding of 0
// (a few ulps, i.e. an angle within ~1e-15 rad of a multiple of 90 degrees in double) is taken as 0;
// the other one is then +-1 to the last bit already. So a straight pose such as theta + q = -pi/2
// turns vectors by exact sign swaps, and a torque that physics makes zero (gravity about a vertical
// axis, a straight arm about its own axis) comes out as exactly 0, not 1e-31. Double uses
// sin_cos_reduced (one call instead of libm's, which the per-joint passes pay sixteen times); float
// sin_cos_float (so float lanes, which cannot call libm's sinf and cosf, give the same bits as one float
// character); other types take libm's.
template <class S>
inline void cos_sin(S angle, S& c, S& s) noexcept {
  using L = lanes<S>;
  using T = typename L::value_type;
  const S tiny = L::constant(4 * double(std::numeric_limits<T>::epsilon()));
  if constexpr (std::is_same_v<T, double>) {
    sin_cos_reduced(angle, s, c);
  } else if constexpr (std::is_same_v<T, float>) {
    sin_cos_float(angle, s, c);
  } else {
    using std::cos, std::sin;  // (or the scalar's own, found by its namespace)
    c = cos(angle);
    s = sin(angle);
  }
  c = L::select(L::abs(c) < tiny, S(0), c);
  s = L::select(L::abs(s) < tiny, S(0), s);
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
  [&]<int... I>(std::integer_sequence<int, I...>) { (f(std::integral_constant<int, I>{}), ...); }
  (std::make_integer_sequence<int, N>{});
}

// Calls f(std::integral_constant<int, i>) for i = N-1 .. 0, unrolled at compile time.
template <int N, class F>
inline void static_for_reverse(F&& f) {
  [&]<int... I>(std::integer_sequence<int, I...>) { (f(std::integral_constant<int, N - 1 - I>{}), ...); }
  (std::make_integer_sequence<int, N>{});
}

// Calls f(std::integral_constant<Twist, t>) for the runtime twist t: one instantiation per class.
template <class F>
inline void with_twist(Twist t, F&& f) {
  switch (t) {
    case Twist::Zero:
      f(std::integral_constant<Twist, Twist::Zero>{});
      break;
    case Twist::HalfPi:
      f(std::integral_constant<Twist, Twist::HalfPi>{});
      break;
    case Twist::MinusHalfPi:
      f(std::integral_constant<Twist, Twist::MinusHalfPi>{});
      break;
    case Twist::Pi:
      f(std::integral_constant<Twist, Twist::Pi>{});
      break;
    default:
      f(std::integral_constant<Twist, Twist::General>{});
      break;
  }
}

}  // namespace humandyn::detail
