// Characters in SIMD lanes: std::experimental::simd<T, Abi> (GCC's libstdc++, C++ Parallelism TS 2) as
// the scalar of every algorithm, lane i being character i. Two pieces make the templated algorithms run
// on it unchanged:
//   - Eigen's NumTraits for the batch type, so Eigen's fixed-size vectors and matrices hold batches
//     (no Eigen packet is used: each batch is already a SIMD register, or several);
//   - detail::lanes<simd>, the lane-wise forms of the few operations that depend on values (a choice
//     becomes a blend, a test over the lanes a mask reduction, libm's fallback a loop over the lanes
//     that need it).
// docs/architecture.md says why this type and how the lanes are proven equal to the scalar code.
#pragma once

#include "humandyn/detail/dh.hpp"
#include "humandyn/detail/lanes.hpp"

#include <Eigen/Core>

#include <cmath>
#include <experimental/simd>
#include <limits>

namespace humandyn {

namespace stdx = std::experimental;

/// A batch of characters in SIMD lanes: the native width of the instruction set compiled for (double:
/// 2 with SSE2, 4 with AVX2, 8 with AVX-512; float twice as many).
template <class T>
using NativeBatch = stdx::native_simd<T>;

/// A batch of W characters whatever the instruction set (several registers when W is wider). With clang,
/// a batch wider than the registers compiled for needs Eigen's static alignment to match its own
/// (EIGEN_MAX_STATIC_ALIGN_BYTES, or the instruction set's flags); GCC aligns it as it needs.
template <class T, int W>
using FixedBatch = stdx::fixed_size_simd<T, W>;

namespace detail {

template <class T, class Abi>
struct lanes<stdx::simd<T, Abi>> {
  using S = stdx::simd<T, Abi>;
  static constexpr bool is_batch = true;
  static constexpr int width = int(S::size());
  using value_type = T;
  using mask = typename S::mask_type;

  // Under clang, libstdc++ 12's masked assignment with AVX-512's bitmasks is a choice of one whole
  // vector, not a blend (its _S_blend_avx512 has a FIXME there): such builds blend lane by lane.
#if defined(__clang__) && defined(__AVX512F__)
  static constexpr bool where_blends = false;
#else
  static constexpr bool where_blends = true;
#endif

  static S constant(double v) noexcept { return S(T(v)); }
  static S select(const mask& m, const S& a, const S& b) noexcept {
    if constexpr (where_blends) {
      S out = b;
      stdx::where(m, out) = a;
      return out;
    } else {
      return S([&](auto l) { return m[l] ? a[l] : b[l]; });
    }
  }
  static S abs(const S& x) noexcept { return stdx::abs(x); }
  static void add_where(const mask& m, S& x, const S& v) noexcept {
    if constexpr (where_blends)
      stdx::where(m, x) += v;
    else
      x = select(m, S(x + v), x);
  }
  static bool all(const mask& m) noexcept { return stdx::all_of(m); }
  static bool any(const mask& m) noexcept { return stdx::any_of(m); }
  // k mod 4 for integral k, exactly, in the lanes: k - 4 floor(k / 4)
  static S quadrant(const S& k) noexcept { return k - T(4) * stdx::floor(k * T(0.25)); }
  // libm's sine and cosine for the lanes in m (those sin_cos_reduced does not cover)
  static void libm_sin_cos_where(const mask& m, const S& x, S& s, S& c) noexcept {
    if (!stdx::any_of(m)) return;
    for (std::size_t i = 0; i < std::size_t(width); ++i)
      if (m[i]) {
        s[i] = std::sin(T(x[i]));
        c[i] = std::cos(T(x[i]));
      }
  }
  static T get(const S& x, int i) noexcept { return x[std::size_t(i)]; }
  static void set(S& x, int i, T v) noexcept { x[std::size_t(i)] = v; }
};

}  // namespace detail
}  // namespace humandyn

namespace Eigen {

// Eigen's facts about a batch: a real, signed, non-integer number that needs construction, costing one
// operation per arithmetic step; precision and range are the lanes' (the algorithms ask Eigen for none).
template <class T, class Abi>
struct NumTraits<std::experimental::simd<T, Abi>> {
  using Self = std::experimental::simd<T, Abi>;
  using Real = Self;
  using NonInteger = Self;
  using Literal = Self;
  using Nested = Self;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 1,
    AddCost = 1,
    MulCost = 1,
  };
  static Self epsilon() { return Self(std::numeric_limits<T>::epsilon()); }
  static Self dummy_precision() { return Self(NumTraits<T>::dummy_precision()); }
  static Self highest() { return Self(std::numeric_limits<T>::max()); }
  static Self lowest() { return Self(std::numeric_limits<T>::lowest()); }
  static Self infinity() { return Self(std::numeric_limits<T>::infinity()); }
  static Self quiet_NaN() { return Self(std::numeric_limits<T>::quiet_NaN()); }
  static int digits10() { return std::numeric_limits<T>::digits10; }
};

}  // namespace Eigen
