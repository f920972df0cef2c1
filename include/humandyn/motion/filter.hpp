// Zero-lag low-pass filtering and differentiation of a fitted clip, the biomechanics default (Winter,
// "Biomechanics and Motor Control of Human Movement", 4th ed. 2009, sec. 2.2): a second-order
// Butterworth low-pass run forward and then backward (a fourth-order response with no phase lag),
// after unwrapping the angles; rates and accelerations by central differences of the filtered signal.
//
//   const FloatingTrajectory motion = filter_fit(fit, {.cutoff = 6.0});  // per frame X, v_b, a_b, q, qd, qdd
//
// The filter and its end padding are scipy's `filtfilt(*butter(2, cutoff / (rate / 2)), x)`: odd
// extension by 3 x 3 = 9 samples at each end (the signal reflected through its end point), each pass
// started in the steady state of its first sample (lfilter_zi). The cut-off is each pass's -3 dB point;
// the two passes together are -6 dB there (Winter's correction of the cut-off by 0.802 is not applied).
#pragma once

#include "humandyn/motion/fit.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <span>
#include <string>
#include <vector>

namespace humandyn::motion {

/// A second-order IIR section: y[n] = b0 x[n] + b1 x[n-1] + b2 x[n-2] - a1 y[n-1] - a2 y[n-2].
struct Biquad {
  double b0 = 1, b1 = 0, b2 = 0, a1 = 0, a2 = 0;
};

/// The second-order Butterworth low-pass of cut-off `cutoff` (Hz) at sampling rate `rate` (Hz), by the
/// bilinear transform with the cut-off pre-warped (K = tan(pi cutoff / rate)): its magnitude is
/// |H(f)|^2 = 1 / (1 + (tan(pi f / rate) / K)^4).
/// \throws MotionError unless 0 < cutoff < rate / 2, or for a cut-off below a millionth of the rate (where
/// K^2 < 1e-11 and the coefficients would lose their precision in double).
inline Biquad butterworth_lowpass(double cutoff, double rate) {
  if (!(cutoff > 0) || !(cutoff < rate / 2))
    throw MotionError("low-pass: cut-off " + exact_number(cutoff) +
                      " Hz must lie between 0 and half the sampling rate (" + exact_number(rate / 2) + " Hz)");
  if (!(cutoff >= rate * 1e-6))
    throw MotionError("low-pass: cut-off " + exact_number(cutoff) + " Hz is below a millionth of the sampling rate (" +
                      exact_number(rate) + " Hz): the filter's coefficients would lose their precision");
  const double K = std::tan(3.14159265358979323846 * cutoff / rate), r2 = std::sqrt(2.0);
  const double norm = 1 / (1 + r2 * K + K * K);
  Biquad f;
  f.b0 = K * K * norm;
  f.b1 = 2 * f.b0;
  f.b2 = f.b0;
  f.a1 = 2 * (K * K - 1) * norm;
  f.a2 = (1 - r2 * K + K * K) * norm;
  return f;
}

/// Makes a sequence of angles continuous (rad), in place: where one sample jumps from the last by more
/// than pi, it and all that follow are moved by the multiple of 2 pi that undoes the jump (numpy.unwrap).
inline void unwrap(std::span<double> x) noexcept {
  constexpr double two_pi = 6.283185307179586476925;
  double offset = 0;
  for (std::size_t k = 1; k < x.size(); ++k) {
    const double raw = x[k] - (x[k - 1] - offset);  // the step as sampled
    if (std::abs(raw) > two_pi / 2) offset -= two_pi * std::round(raw / two_pi);
    x[k] += offset;
  }
}

/// How many samples filtfilt pads each end with: 3 x (the filter's order + 1), scipy's default.
inline constexpr int filtfilt_padding = 9;

/// The signal filtered forward and backward by `f` (zero phase, the magnitude squared), its ends padded
/// by odd extension (2 x[0] - x[k], 2 x[n-1] - x[n-1-k], k = 1..9) and each pass started in the steady
/// state of its first sample. Equal to scipy.signal.filtfilt(b, a, x) to rounding.
/// \throws MotionError when x has 9 samples or fewer (`what` names the signal).
inline std::vector<double> filtfilt(const Biquad& f, std::span<const double> x, const std::string& what = "signal") {
  const int n = int(x.size()), pad = filtfilt_padding;
  if (n <= pad)
    throw MotionError(what + ": " + std::to_string(n) + " samples; the zero-lag filter needs more than " +
                      std::to_string(pad));
  std::vector<double> e(std::size_t(n + 2 * pad));
  for (int k = 0; k < pad; ++k) {
    e[std::size_t(k)] = 2 * x[0] - x[std::size_t(pad - k)];
    e[std::size_t(n + pad + k)] = 2 * x[std::size_t(n - 1)] - x[std::size_t(n - 2 - k)];
  }
  for (int k = 0; k < n; ++k) e[std::size_t(pad + k)] = x[std::size_t(k)];
  // the steady state of a unit step in transposed direct form II (scipy.signal.lfilter_zi)
  const double det = (1 + f.a1) + f.a2, r0 = f.b1 - f.a1 * f.b0, r1 = f.b2 - f.a2 * f.b0;
  const double zi0 = (r0 + r1) / det, zi1 = r1 - f.a2 * zi0;
  const auto pass = [&](std::vector<double>& s) {
    double z0 = zi0 * s[0], z1 = zi1 * s[0];
    for (double& v : s) {
      const double in = v, out = f.b0 * in + z0;
      z0 = f.b1 * in - f.a1 * out + z1;
      z1 = f.b2 * in - f.a2 * out;
      v = out;
    }
  };
  pass(e);
  std::reverse(e.begin(), e.end());
  pass(e);
  std::reverse(e.begin(), e.end());
  return {e.begin() + pad, e.begin() + pad + n};
}

/// First and second derivatives of a sampled signal (step h, s): central differences inside,
/// (x[k+1] - x[k-1]) / 2h and (x[k+1] - 2 x[k] + x[k-1]) / h^2, and second-order one-sided differences at
/// the ends; all exact for a quadratic. Needs 4 samples or more.
inline void differentiate(std::span<const double> x, double h, std::span<double> xd, std::span<double> xdd) noexcept {
  const std::size_t n = x.size();
  for (std::size_t k = 1; k + 1 < n; ++k) {
    xd[k] = (x[k + 1] - x[k - 1]) / (2 * h);
    xdd[k] = (x[k + 1] - 2 * x[k] + x[k - 1]) / (h * h);
  }
  xd[0] = (-3 * x[0] + 4 * x[1] - x[2]) / (2 * h);
  xd[n - 1] = (3 * x[n - 1] - 4 * x[n - 2] + x[n - 3]) / (2 * h);
  xdd[0] = (2 * x[0] - 5 * x[1] + 4 * x[2] - x[3]) / (h * h);
  xdd[n - 1] = (2 * x[n - 1] - 5 * x[n - 2] + 4 * x[n - 3] - x[n - 4]) / (h * h);
}

/// What the filter needs: the cut-off (Hz; 6 Hz, the common choice for walking, by default).
struct FilterOptions {
  double cutoff = 6.0;
};

/// A floating-form motion, per frame: what floating_rnea takes.
struct FloatingFrame {
  Pose<double> base;                                          ///< pelvis frame in the world
  SpatialVector<double> v_b = SpatialVector<double>::Zero();  ///< base velocity (angular; linear), base frame
  SpatialVector<double> a_b = SpatialVector<double>::Zero();  ///< its time derivative (same coordinates)
  JointAngles q = JointAngles::Zero(), qd = JointAngles::Zero(), qdd = JointAngles::Zero();
};

struct FloatingTrajectory {
  double frame_time = 0;
  std::vector<FloatingFrame> frames;
};

/// A fitted clip filtered and differentiated. Each joint angle is unwrapped, filtered (filtfilt) and
/// differentiated (differentiate). The base position is filtered coordinate by coordinate; the base
/// orientation as its unit quaternion (each one turned to the hemisphere of the one before, the four
/// components filtered, the result normalised). The base velocity is v_b = (omega_b, R^T p'), with
/// omega_b = 2 vec(conj(r) r') from the differentiated quaternion r; a_b is v_b differentiated.
/// With `cutoff` = 0 nothing is filtered (the derivatives of the fit as it is).
/// \throws MotionError for fewer than 10 frames (4 unfiltered) or a cut-off butterworth_lowpass refuses.
inline FloatingTrajectory filter_fit(const ClipFit& fit, const FilterOptions& options = {}) {
  const int n = int(fit.frames.size());
  const double h = fit.frame_time;
  const bool filtered = options.cutoff != 0;
  if (filtered && n <= filtfilt_padding)
    throw MotionError("filter: the clip has " + std::to_string(n) + " frames; filtering needs more than " +
                      std::to_string(filtfilt_padding) + " (--cutoff 0 leaves it unfiltered)");
  if (n < 4) throw MotionError("filter: the clip has " + std::to_string(n) + " frames; the derivatives need 4 or more");
  const Biquad f = filtered ? butterworth_lowpass(options.cutoff, 1 / h) : Biquad{};
  constexpr int nj = FloatingModel::nj, channels = nj + 3 + 4;
  // the channels: q, base position, base quaternion
  std::vector<std::vector<double>> c(channels, std::vector<double>(std::size_t(n)));
  Eigen::Quaterniond prev = Eigen::Quaterniond::Identity();
  for (int k = 0; k < n; ++k) {
    const FrameFit& fr = fit.frames[std::size_t(k)];
    for (int j = 0; j < nj; ++j) c[std::size_t(j)][std::size_t(k)] = fr.q[j];
    for (int i = 0; i < 3; ++i) c[std::size_t(nj + i)][std::size_t(k)] = fr.base.p[i];
    Eigen::Quaterniond r(fr.base.R);
    if (k > 0 && r.coeffs().dot(prev.coeffs()) < 0) r.coeffs() = -r.coeffs();
    prev = r;
    for (int i = 0; i < 4; ++i) c[std::size_t(nj + 3 + i)][std::size_t(k)] = r.coeffs()[i];
  }
  for (int j = 0; j < nj; ++j) unwrap(c[std::size_t(j)]);
  if (filtered)
    for (auto& ch : c) ch = filtfilt(f, ch, "filter");
  // normalise the quaternions, then differentiate everything
  for (int k = 0; k < n; ++k) {
    double norm = 0;
    for (int i = 0; i < 4; ++i)
      norm += c[std::size_t(nj + 3 + i)][std::size_t(k)] * c[std::size_t(nj + 3 + i)][std::size_t(k)];
    for (int i = 0; i < 4; ++i) c[std::size_t(nj + 3 + i)][std::size_t(k)] /= std::sqrt(norm);
  }
  std::vector<std::vector<double>> d(channels, std::vector<double>(std::size_t(n))), dd = d;
  for (int i = 0; i < channels; ++i) differentiate(c[std::size_t(i)], h, d[std::size_t(i)], dd[std::size_t(i)]);

  FloatingTrajectory out;
  out.frame_time = h;
  out.frames.resize(std::size_t(n));
  std::vector<SpatialVector<double>> v(out.frames.size());
  for (int k = 0; k < n; ++k) {
    FloatingFrame& o = out.frames[std::size_t(k)];
    const auto at = [&](const std::vector<std::vector<double>>& s, int i) { return s[std::size_t(i)][std::size_t(k)]; };
    for (int j = 0; j < nj; ++j) o.q[j] = at(c, j), o.qd[j] = at(d, j), o.qdd[j] = at(dd, j);
    const Eigen::Quaterniond r(at(c, nj + 6), at(c, nj + 3), at(c, nj + 4), at(c, nj + 5));  // (w, x, y, z)
    const Eigen::Quaterniond rd(at(d, nj + 6), at(d, nj + 3), at(d, nj + 4), at(d, nj + 5));
    o.base.R = r.toRotationMatrix();
    o.base.p = Eigen::Vector3d(at(c, nj), at(c, nj + 1), at(c, nj + 2));
    const Eigen::Vector3d pd(at(d, nj), at(d, nj + 1), at(d, nj + 2));
    o.v_b << 2 * (r.conjugate() * rd).vec(), o.base.R.transpose() * pd;
    v[std::size_t(k)] = o.v_b;
  }
  // a_b: the base velocity's coordinates differentiated
  const auto size = std::size_t(n);
  std::vector<double> s(size, 0.0), sd(size, 0.0), sdd(size, 0.0);
  for (int i = 0; i < 6; ++i) {
    for (int k = 0; k < n; ++k) s[std::size_t(k)] = v[std::size_t(k)][i];
    differentiate(s, h, sd, sdd);
    for (int k = 0; k < n; ++k) out.frames[std::size_t(k)].a_b[i] = sd[std::size_t(k)];
  }
  return out;
}

}  // namespace humandyn::motion
