// What an algorithm needs to know about its scalar to run the same code on one character or on a batch
// of characters in SIMD lanes (detail/batch.hpp): the few operations that depend on values (a choice,
// a magnitude, a test over every lane) written once for both. `lanes<S>` describes a plain scalar, one
// lane; detail/batch.hpp specialises it for std::experimental::simd.
#pragma once

#include <cmath>

namespace humandyn::detail {

template <class S>
struct lanes {
  static constexpr bool is_batch = false;
  static constexpr int width = 1;
  using value_type = S;
  using mask = bool;

  static S constant(double v) noexcept { return S(v); }
  static S select(bool m, const S& a, const S& b) noexcept { return m ? a : b; }
  static S abs(const S& x) noexcept {
    using std::abs;  // (or the scalar's own, found by its namespace)
    return abs(x);
  }
  // x += v where m holds
  static void add_where(bool m, S& x, const S& v) noexcept {
    if (m) x += v;
  }
  // k mod 4 of an integral k (sin_cos_reduced's quadrant)
  static long long quadrant(const S& k) noexcept { return static_cast<long long>(k) & 3; }
  static bool all(bool m) noexcept { return m; }
  static bool any(bool m) noexcept { return m; }
};

// A constant of the scalar type (for float lanes, which take no double directly).
template <class S>
inline S constant(double v) noexcept {
  return lanes<S>::constant(v);
}

}  // namespace humandyn::detail
