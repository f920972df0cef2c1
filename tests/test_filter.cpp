// Zero-lag Butterworth filtering and differentiation: against the closed-form magnitude of the
// filter, against scipy.signal.filtfilt, and on motions whose derivatives are known.
#include "humandyn/motion/filter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

namespace test_filter {

using namespace humandyn;
using namespace humandyn::motion;
using std::numbers::pi;

namespace {

std::vector<double> sampled(int n, double rate, auto&& f) {
  std::vector<double> x(std::size_t(n), double{});
  for (int k = 0; k < n; ++k) x[std::size_t(k)] = f(k / rate);
  return x;
}

// The filtfilt gain at frequency f: the single pass's |H|^2 (Butterworth, bilinear, pre-warped).
double zero_lag_gain(double f, double cutoff, double rate) {
  return 1 / (1 + std::pow(std::tan(pi * f / rate) / std::tan(pi * cutoff / rate), 4));
}

}  // namespace

TEST(Butterworth, CoefficientsHaveTheClosedFormMagnitude) {
  const Biquad b = butterworth_lowpass(6, 120);
  // scipy.signal.butter(2, 6 / 60)
  EXPECT_NEAR(b.b0, 0.02008336556421123, 1e-15);
  EXPECT_NEAR(b.a1, -1.5610180758007182, 1e-15);
  EXPECT_NEAR(b.a2, 0.64135153805756318, 1e-15);
  for (double f : {0.0, 1.0, 6.0, 12.0, 30.0, 55.0}) {
    const std::complex<double> z = std::polar(1.0, -2 * pi * f / 120);  // z^-1
    const std::complex<double> H = (b.b0 + b.b1 * z + b.b2 * z * z) / (1.0 + b.a1 * z + b.a2 * z * z);
    EXPECT_NEAR(std::norm(H), zero_lag_gain(f, 6, 120), 1e-12) << f << " Hz";
  }
  EXPECT_THROW(butterworth_lowpass(60, 120), MotionError);
  EXPECT_THROW(butterworth_lowpass(0, 120), MotionError);
}

TEST(Filtfilt, ASinusoidIsScaledByTheMagnitudeWithNoPhase) {
  const double rate = 120, cutoff = 6;
  const Biquad b = butterworth_lowpass(cutoff, rate);
  for (double f : {0.5, 1.0, 2.0, 6.0, 9.0, 12.0, 20.0}) {
    const auto x = sampled(1200, rate, [&](double t) { return std::sin(2 * pi * f * t + 0.4); });
    const auto y = filtfilt(b, x);
    // in the middle 8 s (the ends' transients have died out), y = g sin(...) with g the closed form and
    // no cosine part: zero phase
    const double g = zero_lag_gain(f, cutoff, rate);
    double worst = 0;
    for (int k = 120; k < 1080; ++k) worst = std::max(worst, std::abs(y[std::size_t(k)] - g * x[std::size_t(k)]));
    EXPECT_LT(worst, 1e-9) << f << " Hz, gain " << g;
    if (f <= 1.0) {
      EXPECT_GT(g, 1 - 1e-3) << "well below the cut-off, it passes";
    }
  }
  EXPECT_NEAR(zero_lag_gain(cutoff, cutoff, rate), 0.5, 1e-15);  // -6 dB at the cut-off for both passes
}

TEST(Filtfilt, EqualsScipy) {
  // scipy 1.17: filtfilt(*butter(2, 6 / 60), x), x as below (t = k / 120)
  const auto x = sampled(60, 120.0, [](double t) {
    return std::sin(2 * pi * 1.3 * t) + 0.4 * std::sin(2 * pi * 9 * t + 0.3) + 0.2 * t * t +
           0.05 * std::cos(2 * pi * 17 * t) + 0.3;
  });
  const double scipy[60] = {
      0.439661862029884,    0.49471206635592002,   0.54662138797081261,   0.59193304481094922,  0.62944158446312459,
      0.66034446223646004,  0.68789510014058131,   0.71668496519350322,   0.75163552499355379,  0.79680128069243628,
      0.8541930826380244,   0.9229474619694582,    0.9991725545917538,    1.0766296487725433,   1.1481135179572166,
      1.2071210173105977,   1.2492940119020108,    1.2732412459783227,    1.280606521879446,    1.2755056749449249,
      1.2635794371453792,   1.2508860544983391,    1.2427711004373201,    1.2428114166906985,   1.251978352846514,
      1.268244464327932,    1.2868565626548936,    1.3013462086939236,    1.3050844685217289,   1.2929454496664354,
      1.262567350129091,    1.2148456346312784,    1.1535856016410921,    1.0845243550231507,   1.0140696219467071,
      0.94806501027555146,  0.89076022000446675,   0.84406186805563754,   0.80713148346262709,  0.776445243024112,
      0.74643295994521064,  0.71069424711817542,   0.66356874979277758,   0.60163362205817505,  0.52465319795704335,
      0.43567106722165427,  0.34024345218036556,   0.24510729847611173,   0.15671300203569674,  0.079990517753785975,
      0.017539215584679878, -0.030730404462629889, -0.067534054731631168, -0.09773322964751735, -0.12742031676368426,
      -0.16262711917953593, -0.20788218163016001,  -0.26500269215589756,  -0.33253012512846902, -0.40604422981341648};
  const auto y = filtfilt(butterworth_lowpass(6, 120), x);
  for (int k = 0; k < 60; ++k) EXPECT_NEAR(y[std::size_t(k)], scipy[k], 1e-13) << "sample " << k;
}

TEST(Filtfilt, AConstantPassesToTheEndsAndShortSignalsAreRefused) {
  const std::vector<double> c(30, 1.25);
  for (double v : filtfilt(butterworth_lowpass(6, 120), c)) EXPECT_NEAR(v, 1.25, 1e-14);
  try {
    (void)filtfilt(butterworth_lowpass(6, 120), std::vector<double>(9, 0.0), "q_r_knee_pitch");
    FAIL() << "no error";
  } catch (const MotionError& e) {
    EXPECT_STREQ(e.what(), "q_r_knee_pitch: 9 samples; the zero-lag filter needs more than 9");
  }
}

TEST(Unwrap, AnAngleRunningRoundComesBackContinuous) {
  auto x = sampled(200, 100.0, [](double t) { return std::remainder(3.0 * t * t + 2.0, 2 * pi); });
  unwrap(x);
  for (int k = 0; k < 200; ++k) EXPECT_NEAR(x[std::size_t(k)], 3.0 * (k / 100.0) * (k / 100.0) + 2.0, 1e-12);
}

TEST(Differentiate, ExactForAQuadraticSecondOrderForASine) {
  const double h = 0.01;
  const auto x = sampled(50, 1 / h, [](double t) { return 2 - 3 * t + 4 * t * t; });
  std::vector<double> xd(50), xdd(50);
  differentiate(x, h, xd, xdd);
  for (int k = 0; k < 50; ++k) {
    EXPECT_NEAR(xd[std::size_t(k)], -3 + 8 * k * h, 1e-9);
    EXPECT_NEAR(xdd[std::size_t(k)], 8, 1e-6);
  }
  const auto s = sampled(50, 1 / h, [](double t) { return std::sin(3 * t); });
  differentiate(s, h, xd, xdd);
  for (int k = 1; k < 49; ++k) {
    EXPECT_NEAR(xd[std::size_t(k)], 3 * std::cos(3 * k * h), 9 * h * h / 6 * 3 * 1.01);  // h^2 f''' / 6
    EXPECT_NEAR(xdd[std::size_t(k)], -9 * std::sin(3 * k * h), 81 * h * h / 12 * 1.01);  // h^2 f'''' / 12
  }
}

TEST(FilterFit, ASteadyTurnAndGlideKeepsItsVelocity) {
  // the base spinning at a constant rate about a tilted axis, gliding at constant speed; the joints
  // a slow quadratic: everything passes the low-pass and differentiates to the exact rates
  const double h = 1.0 / 120, w = 1.5;
  const Eigen::Vector3d axis = Eigen::Vector3d(0.2, -0.3, 1).normalized(), v(1.1, -0.2, 0.05);
  ClipFit fit;
  fit.frame_time = h;
  for (int k = 0; k < 600; ++k) {
    const double t = k * h;
    FrameFit f;
    f.base.R = Eigen::AngleAxisd(w * t, axis).toRotationMatrix() * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX());
    f.base.p = Eigen::Vector3d(0.1, 0.2, 0.9) + v * t;
    for (int j = 0; j < 16; ++j) f.q[j] = std::remainder(0.1 * j + 0.2 * t + 0.5 * j * t * t, 2 * pi);  // wrapped
    fit.frames.push_back(f);
  }
  const FloatingTrajectory m = filter_fit(fit, {.cutoff = 6});
  // the central difference of the quaternion (turning at w / 2) errs by h^2 (w / 2)^2 / 6 relative
  const double rate_error = 1.1 * w * h * h * w * w / 4 / 6;
  for (int k = 120; k < 480; ++k) {
    const auto& f = m.frames[std::size_t(k)];
    const double t = k * h;
    const Eigen::Vector3d w_body = f.base.R.transpose() * (w * axis);
    EXPECT_LT((f.v_b.head<3>() - w_body).norm(), rate_error) << k;
    EXPECT_LT((f.v_b.tail<3>() - f.base.R.transpose() * v).norm(), 1e-6) << k;
    EXPECT_LT(f.a_b.head<3>().norm(), 1e-5) << k;  // a steady turn: constant body-frame rate
    for (int j = 0; j < 16; ++j) {
      EXPECT_NEAR(f.q[j], 0.1 * j + 0.2 * t + 0.5 * j * t * t, 1e-6);
      EXPECT_NEAR(f.qd[j], 0.2 + j * t, 1e-6);
      EXPECT_NEAR(f.qdd[j], double(j), 1e-4);
    }
  }
}

TEST(FilterFit, ShortClipsGoUnfilteredAndACutOffTooLowIsRefused) {
  // a quadratic joint angle: its derivatives by the end formulas are exact with no filter
  const auto clip = [](int frames, double h) {
    ClipFit fit;
    fit.frame_time = h;
    for (int k = 0; k < frames; ++k) {
      FrameFit f;
      for (int j = 0; j < 16; ++j) f.q[j] = 0.5 * (k * h) * (k * h);
      fit.frames.push_back(f);
    }
    return fit;
  };
  const FloatingTrajectory m = filter_fit(clip(5, 0.01), {.cutoff = 0});
  ASSERT_EQ(m.frames.size(), 5u);
  for (const auto& f : m.frames) EXPECT_NEAR(f.qdd[3], 1.0, 1e-9);
  EXPECT_THROW(filter_fit(clip(3, 0.01), {.cutoff = 0}), MotionError);  // the end formulas need 4
  try {
    filter_fit(clip(9, 0.01), {.cutoff = 6});
    ADD_FAILURE() << "9 frames filtered";
  } catch (const MotionError& e) {
    EXPECT_STREQ(e.what(),
                 "filter: the clip has 9 frames; filtering needs more than 9 (--cutoff 0 leaves it unfiltered)");
  }
  // 6 Hz at a sampling rate of 1e16 Hz: K^2 = 3.6e-30, coefficients without precision
  try {
    filter_fit(clip(20, 1e-16), {.cutoff = 6});
    ADD_FAILURE() << "a frame time of 1e-16 s filtered";
  } catch (const MotionError& e) {
    EXPECT_NE(std::string(e.what()).find("below a millionth of the sampling rate"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(butterworth_lowpass(1.2e-4, 120));  // just above a millionth
  EXPECT_THROW(butterworth_lowpass(1.1e-4, 120), MotionError);
}

}  // namespace test_filter
