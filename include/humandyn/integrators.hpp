// Time stepping with a fixed step h, checked: a step that would leave a non-finite or runaway state
// returns an error status naming the joint and leaves the caller's state as it was.
//
// Three integrators, chosen at compile time:
//   SemiImplicitEuler  q̈ = FD(q, q̇, tau + tau_s);  q̇' = q̇ + h q̈;  q' = q + h q̇'   (symplectic, order 1)
//   RungeKutta4        the classical four-stage method on (q, q̇)                          (order 4)
//   ImplicitPD         the servo, damping and limit springs of servo.hpp taken at the end of the step
//                      (backward Euler on the linear joint-space law, "stable PD" with the h^2 term):
//                        (M + h D + h^2 K) q̈ = tau + tau_s(q + h q̇, q̇; reference at t + h) - b(q, q̇)
//                      then q̇' = q̇ + h q̈, q' = q + h q̇'. Gravity and velocity products stay explicit.
//                      docs/stability.md derives it.
// The motor torques tau are held over the step; the servo's reference moves on at q̄̇ within it.
// Forward dynamics (FD) is chosen by FdMethod (mass matrix + LDLᵀ, or articulated body) and Terms.
#pragma once

#include "humandyn/algorithm/crba.hpp"
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/algorithm/ldlt.hpp"
#include "humandyn/data.hpp"
#include "humandyn/servo.hpp"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>

namespace humandyn {

enum class Integrator : std::uint8_t {
  SemiImplicitEuler,  // explicit, symplectic, first order
  RungeKutta4,        // explicit, fourth order
  ImplicitPD,         // semi-implicit Euler with the joint-space springs and dampers implicit
};

inline const char* integrator_name(Integrator m) noexcept {
  switch (m) {
    case Integrator::SemiImplicitEuler:
      return "euler";
    case Integrator::RungeKutta4:
      return "rk4";
    case Integrator::ImplicitPD:
      return "implicit";
  }
  return "?";
}

/// The state of the body: joint angles q (rad) and velocities qd (rad/s), nj each.
template <class Model>
struct State {
  using JointVector = typename Model::JointVector;
  explicit State(const Model& model) {
    q.setZero(model.size());
    qd.setZero(model.size());
  }
  JointVector q;   // rad
  JointVector qd;  // rad/s
};

/// Bounds beyond which a state counts as a runaway (a step that produces one fails).
template <class S>
struct StepLimits {
  S max_abs_q = S(1e4);       // rad
  S max_abs_qd = S(1e4);      // rad/s
  S max_base_speed = S(1e3);  // m/s, a floating base's linear speed (floating_step)
};

// What went wrong in a step.
enum class StepError : std::uint8_t {
  None,
  BadTimeStep,  // h not finite or not positive
  BadInput,     // NaN or Inf in the input (see `quantity` and `joint`)
  BadServo,     // servo gains, reference or limits not usable at `joint`
  NonFinite,    // the step produced NaN or Inf at `joint`
  Runaway,      // the step produced |q| or |q̇| beyond StepLimits at `joint`
};

// Which input or state entry is at fault.
enum class Quantity : std::uint8_t { None, Angle, Velocity, Torque };

struct StepStatus {
  StepError error = StepError::None;
  Quantity quantity = Quantity::None;
  int joint = -1;  // index of the joint at fault; model.joint_name(joint) names it
  bool ok() const noexcept { return error == StepError::None; }
  explicit operator bool() const noexcept { return ok(); }
};

/// A sentence describing a step's status, naming the joint at fault by number and name.
/// \return e.g. "input torque of joint 3 'r_hip_roll' is not finite". Allocates: not for the real-time path.
template <class Model>
std::string describe(const StepStatus& status, const Model& model) {
  const auto joint = [&] {
    if (status.joint == -1) return std::string("the floating base");  // floating_step's base
    if (status.joint < 0 || status.joint >= model.size()) return std::string("?");
    return "joint " + std::to_string(status.joint + 1) + " '" + model.joint_name(status.joint) + "'";
  };
  const char* what = status.quantity == Quantity::Angle      ? "angle"
                     : status.quantity == Quantity::Velocity ? "velocity"
                     : status.quantity == Quantity::Torque   ? "torque"
                                                             : "value";
  switch (status.error) {
    case StepError::None:
      return "ok";
    case StepError::BadTimeStep:
      return "time step is not a positive finite number";
    case StepError::BadInput:
      return std::string("input ") + what + " of " + joint() + " is not finite";
    case StepError::BadServo:
      return "servo gains, reference or limits of " + joint() + " are not usable";
    case StepError::NonFinite:
      return std::string("the step made the ") + what + " of " + joint() + " non-finite";
    case StepError::Runaway:
      return std::string("the step made the ") + what + " of " + joint() + " run away";
  }
  return "?";
}

/// Every buffer a step writes, sized once from the model; owned by the caller.
template <class Model>
struct StepWorkspace {
  using JointVector = typename Model::JointVector;
  explicit StepWorkspace(const Model& model) : data(model), next(model) {
    for (auto* v : {&tau_total, &stiffness, &damping, &q_stage, &qd_stage, &qd_sum, &qdd_sum}) v->setZero(model.size());
  }
  Data<Model> data;               // the dynamics' buffers
  State<Model> next;              // the candidate end-of-step state, copied out only when it passes the checks
  JointVector tau_total;          // motor torques plus joint-space forces
  JointVector stiffness;          // diagonal K of the implicit step
  JointVector damping;            // diagonal D of the implicit step
  JointVector q_stage, qd_stage;  // a Runge-Kutta stage's state
  JointVector qd_sum, qdd_sum;    // Runge-Kutta's weighted sums of the stage derivatives
};

namespace detail {

// The first joint where v is not finite, or -1. (The common case in one vectorised test: x - x is 0 for
// every finite x and NaN for NaN and Inf.)
template <class V>
inline int first_non_finite(const Eigen::MatrixBase<V>& v) noexcept {
  if (((v.array() - v.array()) == 0).all()) return -1;
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i])) return int(i);
  return -1;
}

// The first joint where |v| exceeds `bound`, or -1.
template <class V, class S>
inline int first_beyond(const Eigen::MatrixBase<V>& v, S bound) noexcept {
  if ((v.array().abs() <= bound).all()) return -1;
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (std::abs(v[i]) > bound) return int(i);
  return -1;
}

// The checks of a step's input, in order: ok, or the first fault (quantity and joint).
template <class Q, class QD, class Tau, class Servo, class S>
inline StepStatus check_step_input(const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                                   const Eigen::MatrixBase<Tau>& tau, const Servo* servo, S h) noexcept {
  if (!(std::isfinite(h) && h > 0)) return {StepError::BadTimeStep, Quantity::None, -1};
  if (int j = first_non_finite(q); j >= 0) return {StepError::BadInput, Quantity::Angle, j};
  if (int j = first_non_finite(qd); j >= 0) return {StepError::BadInput, Quantity::Velocity, j};
  if (int j = first_non_finite(tau); j >= 0) return {StepError::BadInput, Quantity::Torque, j};
  if (servo)
    if (int j = first_invalid_servo_joint(*servo); j >= 0) return {StepError::BadServo, Quantity::None, j};
  return {};
}

// The checks of a step's candidate end state, in order: ok, or the first fault.
template <class Q, class QD, class S>
inline StepStatus check_step_result(const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                                    const StepLimits<S>& limits) noexcept {
  if (int j = first_non_finite(q); j >= 0) return {StepError::NonFinite, Quantity::Angle, j};
  if (int j = first_non_finite(qd); j >= 0) return {StepError::NonFinite, Quantity::Velocity, j};
  if (int j = first_beyond(qd, limits.max_abs_qd); j >= 0) return {StepError::Runaway, Quantity::Velocity, j};
  if (int j = first_beyond(q, limits.max_abs_q); j >= 0) return {StepError::Runaway, Quantity::Angle, j};
  return {};
}

// q̈ of the explicit integrators: motor torques plus joint-space forces at (q, q̇, s), through FD.
template <FdMethod method, Terms terms, class Model, class Q, class QD>
inline const typename Model::JointVector& accelerations(const Model& model, StepWorkspace<Model>& ws,
                                                        const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                                                        const typename Model::JointVector& tau,
                                                        const PdServo<Model>* servo,
                                                        typename Model::scalar_type s) noexcept {
  if (servo) {
    servo_torque(*servo, q, qd, s, ws.tau_total);
    ws.tau_total += tau;
    return forward_dynamics<method, terms>(model, ws.data, q, qd, ws.tau_total);
  }
  return forward_dynamics<method, terms>(model, ws.data, q, qd, tau);
}

// One step from `x` into ws.next, unchecked.
template <Integrator integrator, FdMethod method, Terms terms, class Model>
inline void advance(const Model& model, StepWorkspace<Model>& ws, const State<Model>& x,
                    const typename Model::JointVector& tau, const PdServo<Model>* servo,
                    typename Model::scalar_type h) noexcept {
  using S = typename Model::scalar_type;
  auto& next = ws.next;
  if constexpr (integrator == Integrator::SemiImplicitEuler) {
    // velocity first, then the position with the new velocity
    const auto& qdd = accelerations<method, terms>(model, ws, x.q, x.qd, tau, servo, S(0));
    next.qd = x.qd + h * qdd;
    next.q = x.q + h * next.qd;
  } else if constexpr (integrator == Integrator::RungeKutta4) {
    // k1 at the start, k2 and k3 at the midpoint, k4 at the end; weights 1, 2, 2, 1 over 6
    const S half = h / 2;
    {
      const auto& a1 = accelerations<method, terms>(model, ws, x.q, x.qd, tau, servo, S(0));
      ws.qd_sum = x.qd;
      ws.qdd_sum = a1;
      ws.q_stage = x.q + half * x.qd;
      ws.qd_stage = x.qd + half * a1;
    }
    {
      const auto& a2 = accelerations<method, terms>(model, ws, ws.q_stage, ws.qd_stage, tau, servo, half);
      ws.qd_sum += S(2) * ws.qd_stage;
      ws.qdd_sum += S(2) * a2;
      ws.q_stage = x.q + half * ws.qd_stage;
      ws.qd_stage = x.qd + half * a2;
    }
    {
      const auto& a3 = accelerations<method, terms>(model, ws, ws.q_stage, ws.qd_stage, tau, servo, half);
      ws.qd_sum += S(2) * ws.qd_stage;
      ws.qdd_sum += S(2) * a3;
      ws.q_stage = x.q + h * ws.qd_stage;
      ws.qd_stage = x.qd + h * a3;
    }
    {
      const auto& a4 = accelerations<method, terms>(model, ws, ws.q_stage, ws.qd_stage, tau, servo, h);
      ws.qd_sum += ws.qd_stage;
      ws.qdd_sum += a4;
    }
    next.q = x.q + (h / S(6)) * ws.qd_sum;
    next.qd = x.qd + (h / S(6)) * ws.qdd_sum;
  } else {
    // the joint-space law at the predicted end of the step, q + h q̇, with the reference at t + h
    ws.q_stage = x.q + h * x.qd;
    ws.tau_total = tau;
    if (servo) {
      servo_gains(*servo, ws.q_stage, ws.stiffness, ws.damping);
      servo_torque(*servo, ws.q_stage, x.qd, h, ws.qd_stage);
      ws.tau_total += ws.qd_stage;
    } else {
      ws.stiffness.setZero();
      ws.damping.setZero();
    }
    // (M + h D + h^2 K) q̈ = tau + tau_s - b: the mass matrix, the bias, and a factorisation of the sum
    crba(model, ws.data, x.q);
    ws.tau_total -= nonlinear_effects<terms>(model, ws.data, x.q, x.qd);
    ws.qdd_sum = h * ws.damping + (h * h) * ws.stiffness;
    factorize_mass_matrix(model, ws.data, ws.qdd_sum);
    solve_mass_matrix(model, ws.data, ws.tau_total);  // now q̈
    next.qd = x.qd + h * ws.tau_total;
    next.q = x.q + h * next.qd;
  }
}

}  // namespace detail

/// Advances the state by one fixed time step, checked (the integrators above; ImplicitPD as derived
/// in docs/stability.md).
/// \tparam integrator  SemiImplicitEuler, RungeKutta4 or ImplicitPD
/// \tparam method      how forward dynamics is computed (forward_dynamics.hpp)
/// \tparam terms       Terms::Full or Terms::NoCoriolis
/// \param ws      workspace made from `model`
/// \param state   q (rad) and qd (rad/s), nj each: overwritten on success, left as it was on any error
/// \param tau     motor torques (N m), nj, held over the step
/// \param servo   joint-space forces (servo.hpp) added to tau, or nullptr for none
/// \param h       time step (s), finite and > 0
/// \param limits  bounds on |q| and |qd| beyond which the result counts as a runaway
/// \return ok, or the error (bad h, non-finite input, unusable servo, non-finite or runaway result)
///         with the quantity and the joint at fault. No allocation, no exception.
template <Integrator integrator, FdMethod method = FdMethod::MassMatrix, Terms terms = Terms::Full, class Model>
inline StepStatus step(const Model& model, StepWorkspace<Model>& ws, State<Model>& state,
                       const typename Model::JointVector& tau, const PdServo<std::type_identity_t<Model>>* servo,
                       typename Model::scalar_type h,
                       const StepLimits<typename Model::scalar_type>& limits = {}) noexcept {
  // refuse bad input before touching anything
  if (const StepStatus input = detail::check_step_input(state.q, state.qd, tau, servo, h); !input) return input;

  detail::advance<integrator, method, terms>(model, ws, state, tau, servo, h);

  // check the candidate; copy it out only if it passes
  const auto& next = ws.next;
  if (const StepStatus result = detail::check_step_result(next.q, next.qd, limits); !result) return result;
  state.q = next.q;
  state.qd = next.qd;
  return {};
}

/// As above, without joint-space forces.
template <Integrator integrator, FdMethod method = FdMethod::MassMatrix, Terms terms = Terms::Full, class Model>
inline StepStatus step(const Model& model, StepWorkspace<Model>& ws, State<Model>& state,
                       const typename Model::JointVector& tau, typename Model::scalar_type h,
                       const StepLimits<typename Model::scalar_type>& limits = {}) noexcept {
  return step<integrator, method, terms>(model, ws, state, tau, nullptr, h, limits);
}

}  // namespace humandyn
