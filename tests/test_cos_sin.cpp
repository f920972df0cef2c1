// The joints' cosines and sines (detail/dh.hpp): every algorithm turns its vectors by them, so their
// accuracy bounds everything else. Double (sin_cos_reduced) against the x87's long double sinl and cosl;
// float (sin_cos_float) against the correctly rounded values (libm's double, rounded); a float batch
// equal to the scalar lane by lane; the quarter turns exact.
#include "humandyn/detail/batch.hpp"
#include "humandyn/detail/dh.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

namespace humandyn::detail {
namespace {

// |got - want| in units of the last place of want rounded to T
template <class T>
double ulps(T got, long double want) {
  const T w = T(want);
  const T ulp = std::nextafter(std::abs(w), std::numeric_limits<T>::infinity()) - std::abs(w);
  return double(fabsl((long double)got - want) / (long double)ulp);
}

TEST(CosSin, DoubleWithinOneAndAHalfUlpsToTwoHundredRadiansAndTwoAndAHalfToTheLimit) {
  std::mt19937_64 rng(7);
  for (const double range : {200.0, 1e5}) {
    std::uniform_real_distribution<double> draw(-range, range);
    double worst = 0;
    for (int i = 0; i < 1000000; ++i) {
      const double x = draw(rng);
      double s, c;
      sin_cos_reduced(x, s, c);
      worst = std::max({worst, ulps(s, sinl((long double)x)), ulps(c, cosl((long double)x))});
    }
    EXPECT_LE(worst, range == 200.0 ? 1.5 : 2.5) << "|x| <= " << range;
    EXPECT_GT(worst, 0.5) << "(the reference differs from the tested values)";
  }
}

// Four million floats spread over [-128, 128] rad, and every float on both sides of the fast path's end
// (128 rad).
TEST(CosSin, FloatWithinTwoUlpsOfTheCorrectlyRoundedValues) {
  double worst = 0, worst_near_zero = 0;
  long n = 0;
  const auto check = [&](float x) {
    float s, c;
    sin_cos_float(x, s, c);
    for (const auto& [got, want] : {std::pair{s, std::sin(double(x))}, std::pair{c, std::cos(double(x))}}) {
      if (std::abs(want) < 1e-6)
        worst_near_zero = std::max(worst_near_zero, std::abs(double(got) - want));
      else
        worst = std::max(worst, ulps(got, want));
    }
    ++n;
  };
  for (int i = -2000000; i <= 2000000; ++i) check(float(6.4e-5 * i));
  for (float x = 127; x < 129; x = std::nextafter(x, 130.0f)) check(x);
  EXPECT_GT(n, 4000000);
  EXPECT_LE(worst, 2.0);
  EXPECT_GT(worst, 0.5) << "(the reference differs from the tested values)";
  EXPECT_LE(worst_near_zero, 1e-12);
}

// A float batch, whatever the lanes hold (in range, beyond it, NaN, infinity), gives the scalar's bits.
TEST(CosSin, FloatLanesEqualTheScalarBitForBit) {
  using B = NativeBatch<float>;
  constexpr int W = int(B::size());
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> near(-10, 10), far(-300, 300);
  int compared = 0;
  for (int i = 0; i < 20000; ++i) {
    const B x([&](auto l) {
      const int k = (i * W + int(l)) % 97;
      return k == 0 ? inf : k == 1 ? -nan : k == 2 ? nan : k < 10 ? far(rng) : near(rng);
    });
    B s, c;
    cos_sin(x, c, s);
    for (int l = 0; l < W; ++l) {
      float s1, c1;
      cos_sin(float(x[std::size_t(l)]), c1, s1);
      const float sl = s[std::size_t(l)], cl = c[std::size_t(l)];
      EXPECT_EQ(std::memcmp(&s1, &sl, sizeof s1), 0) << "sin of " << x[std::size_t(l)];
      EXPECT_EQ(std::memcmp(&c1, &cl, sizeof c1), 0) << "cos of " << x[std::size_t(l)];
      ++compared;
    }
  }
  EXPECT_EQ(compared, 20000 * W);
}

// theta + q at a multiple of 90 degrees (as a float or double rounds it): a cosine or sine of exactly 0
// and the other exactly +-1.
template <class T>
void expect_quarter_turns_exact() {
  const long double half_pi = 1.5707963267948966192313216916397514L;
  for (int k = -8; k <= 8; ++k) {
    const T x = T(k * half_pi);
    T c, s;
    cos_sin(x, c, s);
    const int m = ((k % 4) + 4) % 4;
    EXPECT_EQ(c, m == 0 ? T(1) : m == 2 ? T(-1) : T(0)) << k << " quarter turns";
    EXPECT_EQ(s, m == 1 ? T(1) : m == 3 ? T(-1) : T(0)) << k << " quarter turns";
  }
}

TEST(CosSin, QuarterTurnsExact) {
  expect_quarter_turns_exact<double>();
  expect_quarter_turns_exact<float>();
}

}  // namespace
}  // namespace humandyn::detail
