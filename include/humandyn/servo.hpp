// Joint-space forces that act beside the motors' torques: a PD servo tracking a reference motion
// (q̄, q̄̇) with per-joint gains, viscous joint damping, and springs that push a joint back inside
// its limits. All are diagonal in joint space,
//   tau_s(q, q̇, s) = Kp (q̄ + s q̄̇ - q) + Kd (q̄̇ - q̇) - B q̇ + K_lim (clamp(q, lo, hi) - q),
// where s is the time since the reference was set (the reference moves on at q̄̇ within a step), so
// an integrator can treat the stiff part implicitly (integrators.hpp): stiffness Kp + K_lim (on the
// joints past a limit) and damping Kd + B.
#pragma once

#include "humandyn/detail/lanes.hpp"
#include "humandyn/model.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <type_traits>

namespace humandyn {

/// A PD servo with passive joint damping and joint-limit springs, all diagonal in joint space; every
/// vector has nj entries.
template <class Model>
struct PdServo {
  using S = typename Model::scalar_type;
  using JointVector = typename Model::JointVector;

  // A servo with zero gains, no damping and no limits: it adds no force until its fields are set.
  explicit PdServo(const Model& model) {
    const auto n = model.size();
    kp.setZero(n);
    kd.setZero(n);
    q_ref.setZero(n);
    qd_ref.setZero(n);
    damping.setZero(n);
    q_min.setConstant(n, -std::numeric_limits<S>::infinity());
    q_max.setConstant(n, std::numeric_limits<S>::infinity());
    limit_stiffness.setZero(n);
  }

  // the servo: tau = kp (q_ref - q) + kd (qd_ref - qd)
  JointVector kp;      // stiffness (N m / rad), one per joint, >= 0
  JointVector kd;      // damping gain (N m s / rad), >= 0
  JointVector q_ref;   // reference angles at the start of the step (rad); within StepLimits for a step
  JointVector qd_ref;  // reference velocities (rad/s), within StepLimits for a step; the reference moves on at
                       // this rate within the step
  // passive joint forces
  JointVector damping;          // viscous joint damping B (N m s / rad): tau = -B qd
  JointVector q_min, q_max;     // joint limits (rad); +-infinity for none
  JointVector limit_stiffness;  // K_lim (N m / rad): tau = K_lim (q_min - q) below, K_lim (q_max - q) above

  // Critically damped gains for a joint of effective inertia `inertia` (kg m^2): kd = 2 sqrt(kp I).
  static S critical_damping(S stiffness, S inertia) noexcept { return S(2) * std::sqrt(stiffness * inertia); }
};

/// The inertia each joint shows when every other joint moves freely, 1 / (M^-1)_ii: the inertia a servo
/// on that joint alone drives. It is below M_ii wherever the other joints can give way (a light link
/// between heavy ones), and is what critical damping should use: kd_i = 2 sqrt(kp_i / (M^-1)_ii).
/// \param M  the joint-space mass matrix (kg m^2), nj x nj, symmetric (crba)
/// \return the effective inertias (kg m^2), nj; M's diagonal when M is singular (an LDL^T pivot below
///         1e-12 of the largest). Allocates: not for the real-time path.
template <class Derived>
Eigen::Matrix<typename Derived::Scalar, Eigen::Dynamic, 1> effective_inertia(const Eigen::MatrixBase<Derived>& M) {
  using S = typename Derived::Scalar;
  using Dense = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  const Dense Md = M;
  const Eigen::LDLT<Dense> ldlt(Md);
  const auto d = ldlt.vectorD();
  const bool regular =
      ldlt.info() == Eigen::Success &&
      d.template minCoeff<Eigen::PropagateNaN>() > 1e-12 * d.cwiseAbs().template maxCoeff<Eigen::PropagateNaN>();
  if (!regular) return Md.diagonal();
  const Dense Minv = ldlt.solve(Dense::Identity(Md.rows(), Md.cols()));
  return Minv.diagonal().cwiseInverse();
}

/// The joint-space torque of the servo, damping and limit springs,
/// tau_s = Kp (q_ref + s qd_ref - q) + Kd (qd_ref - qd) - B qd + K_lim (clamp(q, q_min, q_max) - q).
/// \param q    joint angles (rad), nj
/// \param qd   joint velocities (rad/s), nj
/// \param s    time since the reference was set (s): the reference moves on at qd_ref
/// \param out  receives tau_s (N m), nj. No allocation.
template <class Model, class Q, class QD, class Out>
inline void servo_torque(const PdServo<Model>& servo, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                         typename Model::scalar_type s, Eigen::MatrixBase<Out>& out) noexcept {
  using S = typename Model::scalar_type;
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    // PD on the moving reference, then passive damping
    S t = servo.kp[i] * (servo.q_ref[i] + s * servo.qd_ref[i] - q[i]) + servo.kd[i] * (servo.qd_ref[i] - qd[i]) -
          servo.damping[i] * qd[i];
    // limit springs push back only from outside the limits (q_min <= q_max: at most one of the two)
    detail::lanes<S>::add_where(q[i] < servo.q_min[i], t, servo.limit_stiffness[i] * (servo.q_min[i] - q[i]));
    detail::lanes<S>::add_where(q[i] > servo.q_max[i], t, servo.limit_stiffness[i] * (servo.q_max[i] - q[i]));
    out[i] = t;
  }
}

/// The diagonal stiffness and damping of tau_s, for an implicit step (integrators.hpp).
/// \param q          joint angles (rad), nj: a limit spring counts on the joints past a limit
/// \param stiffness  receives K = Kp + K_lim (N m / rad), nj
/// \param damping    receives D = Kd + B (N m s / rad), nj
template <class Model, class Q, class K, class D>
inline void servo_gains(const PdServo<Model>& servo, const Eigen::MatrixBase<Q>& q, Eigen::MatrixBase<K>& stiffness,
                        Eigen::MatrixBase<D>& damping) noexcept {
  using S = typename Model::scalar_type;
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    const auto outside = q[i] < servo.q_min[i] || q[i] > servo.q_max[i];
    stiffness[i] = servo.kp[i] + detail::lanes<S>::select(outside, servo.limit_stiffness[i], S(0));
    damping[i] = servo.kd[i] + servo.damping[i];
  }
}

/// Whether every gain, reference and limit is usable: finite gains and references, non-negative gains,
/// limits not NaN and q_min <= q_max, not both at the same infinity; given a step's limits (StepLimits,
/// integrators.hpp), also references within them, |q_ref| <= max_abs_q and |qd_ref| <= max_abs_qd (the
/// step would call a joint driven beyond them a run-away).
/// \param servo   a PdServo, or anything with the same vector fields (one character of a crowd)
/// \param limits  a StepLimits, or anything with max_abs_q (rad) and max_abs_qd (rad/s)
/// \return the index of the first joint at fault, or -1 when all are usable
template <class Servo, class Limits>
inline int first_invalid_servo_joint(const Servo& servo, const Limits& limits) noexcept {
  using std::abs;
  using std::isfinite;
  for (Eigen::Index i = 0; i < servo.kp.size(); ++i) {
    const bool finite = isfinite(servo.kp[i]) && isfinite(servo.kd[i]) && isfinite(servo.q_ref[i]) &&
                        isfinite(servo.qd_ref[i]) && isfinite(servo.damping[i]) && isfinite(servo.limit_stiffness[i]);
    const bool signs = servo.kp[i] >= 0 && servo.kd[i] >= 0 && servo.damping[i] >= 0 && servo.limit_stiffness[i] >= 0;
    // (an infinite limit only as none, -inf below or +inf above: both at one infinity would give the
    // spring 0 * inf)
    const bool limits_usable =
        servo.q_min[i] <= servo.q_max[i] && (servo.q_min[i] < servo.q_max[i] || isfinite(servo.q_min[i]));
    // (a NaN limit holds nothing here: the step's result check reports it, as a run-away)
    const bool within = !(abs(servo.q_ref[i]) > limits.max_abs_q || abs(servo.qd_ref[i]) > limits.max_abs_qd);
    if (!(finite && signs && limits_usable && within)) return int(i);
  }
  return -1;
}

/// As above, with no limits on the references.
template <class Servo>
inline int first_invalid_servo_joint(const Servo& servo) noexcept {
  using S = std::decay_t<decltype(servo.kp[0])>;
  constexpr S inf = std::numeric_limits<S>::infinity();
  struct {
    S max_abs_q = inf, max_abs_qd = inf;
  } none;
  return first_invalid_servo_joint(servo, none);
}

}  // namespace humandyn
