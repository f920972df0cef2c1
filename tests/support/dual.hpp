// A forward-mode dual number, x = v + d ε with ε² = 0: run through the algorithms (templated on the
// scalar) with d seeded to 1 on one input, every output's d is its exact derivative along that input,
// with no step to choose and no truncation. The tests use it as a check of the analytical derivatives
// independent of both the recursions and finite differences. Comparisons and conversions see the value
// alone.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <limits>

namespace humandyn::testing {

struct Dual {
  double v = 0, d = 0;

  constexpr Dual() = default;
  constexpr Dual(double value) : v(value) {}  // NOLINT(google-explicit-constructor): constants mix in freely
  constexpr Dual(double value, double derivative) : v(value), d(derivative) {}
  constexpr explicit operator double() const { return v; }

  Dual& operator+=(const Dual& b) { return *this = *this + b; }
  Dual& operator-=(const Dual& b) { return *this = *this - b; }
  Dual& operator*=(const Dual& b) { return *this = *this * b; }
  Dual& operator/=(const Dual& b) { return *this = *this / b; }

  friend constexpr Dual operator+(const Dual& a) { return a; }
  friend constexpr Dual operator-(const Dual& a) { return {-a.v, -a.d}; }
  friend constexpr Dual operator+(const Dual& a, const Dual& b) { return {a.v + b.v, a.d + b.d}; }
  friend constexpr Dual operator-(const Dual& a, const Dual& b) { return {a.v - b.v, a.d - b.d}; }
  friend constexpr Dual operator*(const Dual& a, const Dual& b) { return {a.v * b.v, a.d * b.v + a.v * b.d}; }
  friend constexpr Dual operator/(const Dual& a, const Dual& b) {
    return {a.v / b.v, (a.d * b.v - a.v * b.d) / (b.v * b.v)};
  }
  friend constexpr bool operator<(const Dual& a, const Dual& b) { return a.v < b.v; }
  friend constexpr bool operator>(const Dual& a, const Dual& b) { return a.v > b.v; }
  friend constexpr bool operator<=(const Dual& a, const Dual& b) { return a.v <= b.v; }
  friend constexpr bool operator>=(const Dual& a, const Dual& b) { return a.v >= b.v; }
  friend constexpr bool operator==(const Dual& a, const Dual& b) { return a.v == b.v; }
  friend constexpr bool operator!=(const Dual& a, const Dual& b) { return a.v != b.v; }

  // the functions the algorithms call, found by argument-dependent lookup
  friend Dual sin(const Dual& a) { return {std::sin(a.v), a.d * std::cos(a.v)}; }
  friend Dual cos(const Dual& a) { return {std::cos(a.v), -a.d * std::sin(a.v)}; }
  friend Dual sqrt(const Dual& a) {
    const double r = std::sqrt(a.v);
    return {r, a.d / (2 * r)};
  }
  friend Dual abs(const Dual& a) { return a.v < 0 ? -a : a; }
  friend bool isfinite(const Dual& a) { return std::isfinite(a.v) && std::isfinite(a.d); }
};

}  // namespace humandyn::testing

template <>
struct std::numeric_limits<humandyn::testing::Dual> : std::numeric_limits<double> {};

// Eigen's facts about it: double's, but a class type that needs construction
template <>
struct Eigen::NumTraits<humandyn::testing::Dual> : Eigen::NumTraits<double> {
  using Real = humandyn::testing::Dual;
  using NonInteger = humandyn::testing::Dual;
  using Nested = humandyn::testing::Dual;
  using Literal = double;
  enum { RequireInitialization = 1 };
};
