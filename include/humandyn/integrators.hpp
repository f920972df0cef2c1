// Time stepping with a fixed step h, checked: a step that would leave a non-finite or runaway state
// returns an error status naming the joint and leaves the caller's state as it was.
//
// Four integrators, chosen at compile time:
//   SemiImplicitEuler  q̈ = FD(q, q̇, tau + tau_s);  q̇' = q̇ + h q̈;  q' = q + h q̇'   (symplectic, order 1)
//   RungeKutta4        the classical four-stage method on (q, q̇)                          (order 4)
//   ImplicitPD         the servo, damping and limit springs of servo.hpp taken at the end of the step
//                      (backward Euler on the linear joint-space law, "stable PD" with the h^2 term):
//                        (M + h D + h^2 K) q̈ = tau + tau_s(q + h q̇, q̇; reference at t + h) - b(q, q̇)
//                      then q̇' = q̇ + h q̈, q' = q + h q̇'. Gravity and velocity products stay explicit.
//   BackwardEuler      backward Euler on the whole dynamics: q' = q + h q̇', q̇' = q̇ + h q̈ with
//                        ID(q', q̇', q̈) = tau(t + h) + tau_s(q', q̇'; reference at t + h)
//                      (gravity, velocity products, servo, damping, limit springs all at the end of the
//                      step), solved by Newton's method with the analytical Jacobian
//                        dr/dq̈ = M(q') + h (dtau/dq̇ + D) + h^2 (dtau/dq + K)
//                      (rnea_derivatives.hpp), kept from step to step while it serves (a chord
//                      iteration; a fresh step starts from ImplicitPD's q̈ and its matrix
//                      M + h D + h^2 K, and derives the Jacobian only when that one stops serving);
//                      the energy the step gains beyond the work of the joint
//                      forces is taken back from the velocity; a step that does not converge is retaken
//                      as 2, 4, ... substeps. Order 1. docs/stability.md derives all three implicit parts.
// The motor torques are a vector held over the step, or a schedule tau(s) evaluated at each stage's time
// s within the step (TorqueSchedule); the servo's reference moves on at q̄̇ within it.
// Forward dynamics (FD) is chosen by FdMethod (mass matrix + LDLᵀ, or articulated body) and Terms.
#pragma once

#include "humandyn/algorithm/crba.hpp"
#include "humandyn/algorithm/energy.hpp"
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/algorithm/ldlt.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/algorithm/rnea_derivatives.hpp"
#include "humandyn/data.hpp"
#include "humandyn/servo.hpp"

#include <Eigen/Core>
#include <Eigen/LU>

#include <concepts>
#include <limits>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>

namespace humandyn {

enum class Integrator : std::uint8_t {
  SemiImplicitEuler,  // explicit, symplectic, first order
  RungeKutta4,        // explicit, fourth order
  ImplicitPD,         // semi-implicit Euler with the joint-space springs and dampers implicit
  BackwardEuler,      // backward Euler on the whole dynamics, Newton's method with the analytical Jacobian
};

inline const char* integrator_name(Integrator m) noexcept {
  switch (m) {
    case Integrator::SemiImplicitEuler:
      return "euler";
    case Integrator::RungeKutta4:
      return "rk4";
    case Integrator::ImplicitPD:
      return "implicit";
    case Integrator::BackwardEuler:
      return "backward-euler";
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

/// Bounds beyond which a state counts as a runaway (a step that produces one fails). A NaN bound holds
/// nothing: every step fails as a runaway.
template <class S>
struct StepLimits {
  S max_abs_q = S(1e4);       // rad
  S max_abs_qd = S(1e4);      // rad/s
  S max_base_speed = S(1e3);  // m/s, a floating base's linear speed (floating_step)
};

// What went wrong in a step.
enum class StepError : std::uint8_t {
  None,
  BadTimeStep,         // h not finite or not positive
  BadInput,            // NaN or Inf in the input (see `quantity` and `joint`)
  BadServo,            // servo gains, reference or limits not usable at `joint`
  NonFinite,           // the step produced NaN or Inf at `joint`
  Runaway,             // the step produced |q| or |q̇| beyond StepLimits at `joint`
  NoSolution,          // backward Euler found no end state within its iterations, even in the finest substeps;
                       // `joint` (or -1) where its last iterate was not finite or farthest beyond StepLimits
  SingularMassMatrix,  // the step's accelerations were not finite (backward Euler: it found no end state)
                       // where the matrix it solves with is singular at `joint`: M (M + h D + h^2 K for the
                       // implicit steps with a servo), a turn of that joint, with the joints beyond it,
                       // moving no mass (a massless leaf)
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
      if (status.joint == -1 && status.quantity == Quantity::Angle)  // floating_step's base pose
        return "input pose of the floating base is not finite or its orientation is not a rotation";
      return std::string("input ") + what + " of " + joint() + " is not finite";
    case StepError::BadServo:
      return "servo gains, reference or limits of " + joint() + " are not usable";
    case StepError::NonFinite:
      return std::string("the step made the ") + what + " of " + joint() + " non-finite";
    case StepError::SingularMassMatrix:
      return "the mass matrix is singular at " + joint() +
             " (a turn of it, with the joints beyond it turning along, moves no mass): the step's accelerations "
             "are not finite";
    case StepError::Runaway:
      return std::string("the step made the ") + what + " of " + joint() + " run away";
    case StepError::NoSolution:
      return std::string(
                 "the backward-Euler step found no end state (Newton's method did not converge in the finest "
                 "substeps)") +
             (status.joint >= 0 ? std::string("; its last iterate had the ") + what + " of " + joint() +
                                      " not finite or farthest beyond the step's limits"
                                : std::string());
  }
  return "?";
}

/// What the last BackwardEuler step did (other integrators leave it alone).
template <class S>
struct BackwardEulerReport {
  int substeps = 0;   // 1, or more where Newton's method did not converge on a longer one (down to h / 256)
  int residuals = 0;  // residual evaluations (inverse dynamics) over all substeps and attempts
  int jacobians = 0;  // Jacobian evaluations (rnea_derivatives and an LU factorisation)
  S work = 0;         // work of the motor torques and joint-space forces over the step, h q̇'ᵀ tau (J)
  S dissipated = 0;   // energy the step removed beyond that work, E(start) + work - E(end) >= 0 (J)
  S energy = 0;       // the body's energy at the end (kinetic plus potential, energy.hpp; J)
};

/// Backward Euler's Jacobian, factorised by its tree sparsity (TreeLU, ldlt.hpp) where the elimination
/// without pivoting is accepted, else by a dense LU with partial pivoting. Made as the identity's.
template <class Model>
struct JacobianFactorisation {
  using Matrix = typename Data<Model>::MassMatrix;
  explicit JacobianFactorisation(const Model& model) : tree(model), dense(model.size()) {}
  /// factorises J (nj x nj)
  void compute(const Model& model, const Matrix& J) noexcept {
    sparse = tree.compute(model, J);
    if (!sparse) dense.compute(J);
  }
  /// x = J^-1 r (nj)
  template <class R, class X>
  void solve(const Model& model, const Eigen::MatrixBase<R>& r, Eigen::MatrixBase<X>& x) const noexcept {
    if (sparse) {
      x = r;
      tree.solve_in_place(model, x);
    } else {
      x = dense.solve(r);
    }
  }
  JacobianFactorisation(const JacobianFactorisation&) = default;
  /// copies the factors in use alone (a crowd character's memory is copied in and out every step)
  JacobianFactorisation& operator=(const JacobianFactorisation& other) noexcept {
    sparse = other.sparse;
    if (sparse)
      tree = other.tree;
    else
      dense = other.dense;
    return *this;
  }
  TreeLU<Model> tree;
  Eigen::PartialPivLU<Matrix> dense;
  bool sparse = true;  // which of the two holds J's factors
};

/// Every buffer a step writes, sized once from the model; owned by the caller.
template <class Model>
struct StepWorkspace {
  using S = typename Model::scalar_type;
  using JointVector = typename Model::JointVector;
  using JointMatrix = typename DerivativeData<Model>::JointMatrix;
  explicit StepWorkspace(const Model& model) : data(model), next(model), derivatives(model), lu(model), carried(model) {
    for (auto* v : {&tau_total, &tau_stage, &stiffness, &damping, &q_stage, &qd_stage, &qd_sum, &qdd_sum, &qdd_guess,
                    &correction, &carried_qdd, &carried_qdd_1, &carried_qdd_2})
      v->setZero(model.size());
    jacobian.setZero(model.size(), model.size());
  }
  Data<Model> data;                   // the dynamics' buffers
  State<Model> next;                  // the candidate end-of-step state, copied out only when it passes the checks
  JointVector tau_total;              // motor torques plus joint-space forces
  JointVector tau_stage;              // the motor torques a schedule gives at a stage
  JointVector stiffness;              // diagonal K of the implicit steps
  JointVector damping;                // diagonal D of the implicit steps
  JointVector q_stage, qd_stage;      // a Runge-Kutta stage's state; a backward-Euler substep's start
  JointVector qd_sum, qdd_sum;        // Runge-Kutta's weighted sums; backward Euler's residual and q̈
  JointVector correction;             // a Newton correction of backward Euler's q̈
  JointVector qdd_guess;              // the q̈ a backward-Euler substep starts from, kept for a retry
  DerivativeData<Model> derivatives;  // backward Euler's Jacobian: dtau/dq, dtau/dq̇, M
  JointMatrix jacobian;               // dr/dq̈ of backward Euler's residual
  JacobianFactorisation<Model> lu;    // its factorisation
  BackwardEulerReport<S> report;      // what the last backward-Euler step did
  // Backward Euler's last end state, its energy and the q̈ that reached it. A step of the same model that
  // starts exactly there takes that energy as its start's and begins Newton's method from that q̈
  // extrapolated along the steps before it of the same length (a parabola through the last three's q̈,
  // a line through two), with the Jacobian factorised last when its substep length and servo are the
  // step's (its result agrees with a fresh workspace's within Newton's tolerance when both take as many
  // substeps). forget() makes the next step start afresh.
  State<Model> carried;
  JointVector carried_qdd, carried_qdd_1, carried_qdd_2;  // the q̈ of the last step, of the one before, ...
  S carried_energy = S(0);
  S carried_h = S(0);     // the length of the step that reached carried_qdd (s)
  int carried_known = 0;  // how many of carried_qdd_1, _2 belong to steps of that length, each continuing
  const Model* carried_model = nullptr;  // the model of that step; nullptr: nothing carried
  void forget() noexcept { carried_model = nullptr; }
  // what `lu` factorises: the Jacobian of a substep of length jacobian_h (s; 0: none at hand) with this servo
  S jacobian_h = S(0);
  const PdServo<Model>* jacobian_servo = nullptr;
};

/// Motor torques as a function of time within a step: f(s, out) writes the torques (N m, nj) at s seconds
/// after the step's start into out. noexcept and without allocation, as the step itself.
template <class F, class Model>
concept TorqueSchedule = requires(const F& f, typename Model::scalar_type s, typename Model::JointVector& out) {
  { f(s, out) }
  noexcept;
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
    if (!(std::abs(v[i]) <= bound)) return int(i);  // (a NaN bound: every value beyond it, as in a crowd's lanes)
  return -1;
}

// The joint where |v| exceeds `bound` by the most, or -1 (v finite).
template <class V, class S>
inline int farthest_beyond(const Eigen::MatrixBase<V>& v, S bound) noexcept {
  int worst = -1;
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (!(std::abs(v[i]) <= bound) && (worst < 0 || std::abs(v[i]) > std::abs(v[worst]))) worst = int(i);
  return worst;
}

// The first check of every step (step, step_crowd, floating_step): ok, or BadTimeStep unless h (s) is
// finite and positive.
template <class S>
inline StepStatus check_time_step(S h) noexcept {
  if (std::isfinite(h) && h > 0) return {};
  return {StepError::BadTimeStep, Quantity::None, -1};
}

// The checks of a step's input, in order: ok, or the first fault (quantity and joint).
template <class Q, class QD, class Tau, class Servo, class S>
inline StepStatus check_step_input(const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<QD>& qd,
                                   const Eigen::MatrixBase<Tau>& tau, const Servo* servo, S h,
                                   const StepLimits<S>& limits) noexcept {
  if (const StepStatus st = check_time_step(h); !st.ok()) return st;
  if (int j = first_non_finite(q); j >= 0) return {StepError::BadInput, Quantity::Angle, j};
  if (int j = first_non_finite(qd); j >= 0) return {StepError::BadInput, Quantity::Velocity, j};
  if (int j = first_non_finite(tau); j >= 0) return {StepError::BadInput, Quantity::Torque, j};
  if (servo)
    if (int j = first_invalid_servo_joint(*servo, limits); j >= 0) return {StepError::BadServo, Quantity::None, j};
  return {};
}

// The matrix a step solves with, factorised anew at its start x into ws.data (L, D; ws.q_stage, ws.qd_sum,
// ws.stiffness and ws.damping are scratch): M for the explicit steps; M + h D + h^2 K for the implicit
// ones with a servo, its gains at the predicted end q + h q̇ as implicit_pd_accelerations takes them (a
// servo keeps that matrix regular whatever M is). Only on a failed step's path.
template <Integrator integrator, class Model>
inline void factorize_step_matrix(const Model& model, StepWorkspace<Model>& ws, const State<Model>& x,
                                  const PdServo<Model>* servo, typename Model::scalar_type h) noexcept {
  crba(model, ws.data, x.q);
  ws.qd_sum.setZero();
  if constexpr (integrator == Integrator::ImplicitPD || integrator == Integrator::BackwardEuler)
    if (servo) {
      ws.q_stage = x.q + h * x.qd;
      servo_gains(*servo, ws.q_stage, ws.stiffness, ws.damping);
      ws.qd_sum = h * ws.damping + (h * h) * ws.stiffness;
    }
  factorize_mass_matrix(model, ws.data, ws.qd_sum);
}

// Where that matrix is singular (singular_pivot_joint on its pivots), -1 where it is regular: a step whose
// end came out non-finite, or backward Euler's that found no end state, fails at that joint.
template <Integrator integrator, class Model>
inline int singular_joint_at_start(const Model& model, StepWorkspace<Model>& ws, const State<Model>& x,
                                   const PdServo<Model>* servo, typename Model::scalar_type h) noexcept {
  factorize_step_matrix<integrator>(model, ws, x, servo, h);
  return singular_pivot_joint(model.size(), [&](int i) { return ws.data.D[i]; });
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

// The motor torques of a step: a vector held over it, ...
template <class Model>
struct HeldTorque {
  const typename Model::JointVector& tau;
  int bad_joint = first_non_finite(tau);  // checked before the step
  const typename Model::JointVector& operator()(typename Model::scalar_type) noexcept { return tau; }
};

// ... or a schedule evaluated at each stage into ws.tau_stage, its first non-finite entry remembered.
template <class Model, class F>
struct ScheduledTorque {
  const F& schedule;
  typename Model::JointVector& out;
  int bad_joint = -1;
  const typename Model::JointVector& operator()(typename Model::scalar_type s) noexcept {
    schedule(s, out);
    if (bad_joint < 0) bad_joint = first_non_finite(out);
    return out;
  }
};

// ImplicitPD's q̈ for a step of length h from x: the joint-space law at the predicted end q + h q̇ (the
// reference and the motor torques at h), gravity and the velocity products at the start,
//   (M + h D + h^2 K) q̈ = tau + tau_s - b,
// into ws.tau_total. The factorisation of M + h D + h^2 K stays in ws.data; ws.q_stage and ws.qd_sum are
// scratch.
template <Terms terms, class Model, class Source>
inline void implicit_pd_accelerations(const Model& model, StepWorkspace<Model>& ws, const State<Model>& x, Source& tau,
                                      const PdServo<Model>* servo, typename Model::scalar_type h) noexcept {
  ws.q_stage = x.q + h * x.qd;
  ws.tau_total = tau(h);
  if (servo) {
    servo_gains(*servo, ws.q_stage, ws.stiffness, ws.damping);
    servo_torque(*servo, ws.q_stage, x.qd, h, ws.qd_sum);
    ws.tau_total += ws.qd_sum;
  } else {
    ws.stiffness.setZero();
    ws.damping.setZero();
  }
  // the mass matrix and the bias in one call (one sweep of the joints' cosines and sines, left in
  // ws.data), and a factorisation of the sum
  crba_impl<true, terms, false>(model, ws.data, x.q, x.qd, nullptr);
  ws.tau_total -= ws.data.nle;
  ws.qd_sum = h * ws.damping + (h * h) * ws.stiffness;
  factorize_mass_matrix(model, ws.data, ws.qd_sum);
  solve_mass_matrix(model, ws.data, ws.tau_total);  // now q̈
}

// Backward Euler's limits: Newton corrections per substep, and how often a substep may be halved.
inline constexpr int backward_euler_corrections = 8;
inline constexpr int backward_euler_halvings = 8;  // substeps down to h / 256

// One backward-Euler substep of length h from (ws.q_stage, ws.qd_stage), s0 seconds into the step, into
// ws.next, Newton's method starting from the q̈ in ws.qdd_sum. `energy` is the body's energy at the
// substep's start; on success, at its end. With mass_matrix_chord, the corrections start with the
// factorisation of M + h D + h^2 K that implicit_pd_accelerations left in ws.data. False when Newton's
// method did not converge or the end state holds more energy than the velocity can give back.
template <class Model, class Source>
inline bool backward_euler_substep(const Model& model, StepWorkspace<Model>& ws, Source& tau,
                                   const PdServo<Model>* servo, typename Model::scalar_type s0,
                                   typename Model::scalar_type h, typename Model::scalar_type& energy,
                                   bool mass_matrix_chord) noexcept {
  using S = typename Model::scalar_type;
  constexpr S eps = std::numeric_limits<S>::epsilon();
  const S tolerance = std::sqrt(eps);  // the residual's relative size: 1.5e-8 double, 3.5e-4 float
  // and its floor at the torques' rounding, which stays where they cancel: rnea sums terms of the order
  // of the body's weight at a metre's lever (a passive body falling from rest); the servo's terms are
  // kp |q_ref + s q̇_ref - q|, kd |q̇_ref - q̇|, B |q̇| and, where it pushes, a limit spring's
  // K |q_lim - q| (a body held at rest, or resting against a limit, without gravity too), each rounded
  // to its parts' size
  const S weight = S(16) * eps * model.total_mass() * model.gravity().norm() * S(1);
  S floor = weight;
  const S s = s0 + h;
  if (servo) {
    using std::abs, std::max;
    S largest = S(0);
    for (Eigen::Index i = 0; i < ws.q_stage.size(); ++i) {
      const S q = abs(ws.q_stage[i]), qd = abs(ws.qd_stage[i]);
      S parts = servo->kp[i] * (abs(servo->q_ref[i]) + s * abs(servo->qd_ref[i]) + q) +
                servo->kd[i] * (abs(servo->qd_ref[i]) + qd) + servo->damping[i] * qd;
      // a limit spring where it pushes, at the substep's start or at its end as the velocity carries it
      const S q_end = ws.q_stage[i] + h * ws.qd_stage[i];
      if (ws.q_stage[i] < servo->q_min[i] || q_end < servo->q_min[i])
        parts += servo->limit_stiffness[i] * (abs(servo->q_min[i]) + max(q, abs(q_end)));
      else if (ws.q_stage[i] > servo->q_max[i] || q_end > servo->q_max[i])
        parts += servo->limit_stiffness[i] * (abs(servo->q_max[i]) + max(q, abs(q_end)));
      largest = max(largest, parts);
    }
    floor += S(16) * eps * largest;
  }
  auto& x = ws.next;
  auto& a = ws.qdd_sum;  // q̈, the unknown
  auto& r = ws.qd_sum;   // the residual, ID(q', q̇', q̈) - tau - tau_s (N m)
  auto& dd = ws.derivatives;
  auto& report = ws.report;
  const auto& tau_end = tau(s);

  // Newton's method from the given q̈, a chord iteration (Hairer and Wanner, Solving ODEs II, §IV.8): the
  // implicit PD step's matrix M + h D + h^2 K when given, or the Jacobian at hand when it is for this
  // substep length and servo, else one at the first pass; and the Jacobian, new, whenever a correction
  // cut the residual less than tenfold
  const bool at_hand = mass_matrix_chord || (ws.jacobian_h == h && ws.jacobian_servo == servo);
  S r_previous = std::numeric_limits<S>::infinity(), r_start = 0;
  bool angles_in_data = false;  // whether ws.data holds the cosines and sines of the last x.q (rnea's)
  for (int k = 0;; ++k) {
    // the end state this q̈ gives, the torques inverse dynamics needs there and those the joints supply
    x.qd = ws.qd_stage + h * a;
    x.q = ws.q_stage + h * x.qd;
    const bool first = k == 0, derive = first && !at_hand;
    angles_in_data = !derive;
    const auto& id = derive ? (rnea_derivatives(model, dd, x.q, x.qd, a), dd.tau) : rnea(model, ws.data, x.q, x.qd, a);
    ++report.residuals;
    ws.tau_total = tau_end;
    if (servo) {
      servo_torque(*servo, x.q, x.qd, s, r);
      ws.tau_total += r;
    }
    r = id - ws.tau_total;
    const S r_norm = r.cwiseAbs().template maxCoeff<Eigen::PropagateNaN>();  // (the default passes over a NaN)
    if (!(r_norm <= std::numeric_limits<S>::max())) return false;            // NaN or Inf
    // converged: the residual small against the first one's and the torques', or at rounding
    if (first) r_start = r_norm;
    if (r_norm <=
        std::max(floor, tolerance * std::max({r_start, id.cwiseAbs().maxCoeff(), ws.tau_total.cwiseAbs().maxCoeff()})))
      break;
    if (k == backward_euler_corrections) return false;

    const bool slow = !first && !(r_norm <= r_previous / S(10));
    if (slow) rnea_derivatives(model, dd, x.q, x.qd, a);
    if (derive || slow) {
      // dr/dq̈ = M + h (dtau/dq̇ + D) + h^2 (dtau/dq + K), with q' and q̇' moving with q̈
      derivatives_mass_matrix(model, dd, ws.jacobian);
      ws.jacobian += h * dd.dtau_dqd + (h * h) * dd.dtau_dq;
      if (servo) {
        servo_gains(*servo, x.q, ws.stiffness, ws.damping);
        ws.jacobian.diagonal() += h * ws.damping + (h * h) * ws.stiffness;
      }
      ws.lu.compute(model, ws.jacobian);
      ws.jacobian_h = h;
      ws.jacobian_servo = servo;
      ++report.jacobians;
      mass_matrix_chord = false;
    }
    r_previous = r_norm;
    if (mass_matrix_chord) {
      ws.correction = r;
      solve_mass_matrix(model, ws.data, ws.correction);
    } else {
      ws.lu.solve(model, r, ws.correction);
    }
    a -= ws.correction;
  }

  // the energy: at most the start's plus the work of the joint forces; a gain beyond it (backward Euler
  // gains where gravity's stiffness is negative or the inertia changes fast) is taken from the velocity
  S kinetic, potential;
  if (angles_in_data)
    mechanical_energy_pass(model, ws.data, x.qd, kinetic, potential);
  else
    mechanical_energy(model, ws.data, x.q, x.qd, kinetic, potential);
  const S work = h * x.qd.dot(ws.tau_total);
  const S budget = energy + work;
  const S gain = kinetic + potential - budget;
  // the energies' rounding: 16 of the sums', the work's terms h |q̇'| . |tau| included
  const S rounding =
      S(16) * eps *
      (kinetic + std::abs(potential) + std::abs(energy) + h * x.qd.cwiseAbs().dot(ws.tau_total.cwiseAbs()));
  const S excess = gain + rounding;
  // what a gain may be and still be rounding: the energies', that of the potential's terms (the body's
  // weight at a metre's height, however closely they cancel: a body held where E is near 0 J), and the
  // work h |q̇'| . |r| of the residual Newton's method left
  const S slack = rounding + weight + h * x.qd.cwiseAbs().dot(r.cwiseAbs());
  // an end state that gains more than half its kinetic energy is not the step's: Newton's method found a
  // spurious root (a pendulum at a long step: a joint turned by hundreds of radians at thousands of rad/s,
  // which the velocity's scaling would hide), and a shorter substep finds the right one
  if (gain > kinetic / S(2) + slack) return false;
  // a gain within the energies' rounding is rounding, and stays: taken from every step with the margin, it
  // drained a body whose true change per step is below the rounding (a float body, one far from the world
  // origin, where the potential is large, or small steps), which then stood still
  if (gain > rounding) {
    // a body all but at rest keeps its velocity if its gain is within rounding
    if (kinetic > excess) {
      x.qd *= std::sqrt((kinetic - excess) / kinetic);
      kinetic -= excess;
    } else if (gain > slack) {
      return false;  // more than the velocity can give back
    }
  }
  energy = kinetic + potential;
  report.work += work;
  report.dissipated += budget - energy;
  return true;
}

// One step from `x` into ws.next, unchecked; false when backward Euler found no end state.
template <Integrator integrator, FdMethod method, Terms terms, class Model, class Source>
inline bool advance(const Model& model, StepWorkspace<Model>& ws, const State<Model>& x, Source& tau,
                    const PdServo<Model>* servo, typename Model::scalar_type h) noexcept {
  using S = typename Model::scalar_type;
  auto& next = ws.next;
  if constexpr (integrator == Integrator::SemiImplicitEuler) {
    // velocity first, then the position with the new velocity
    const auto& qdd = accelerations<method, terms>(model, ws, x.q, x.qd, tau(S(0)), servo, S(0));
    next.qd = x.qd + h * qdd;
    next.q = x.q + h * next.qd;
  } else if constexpr (integrator == Integrator::RungeKutta4) {
    // k1 at the start, k2 and k3 at the midpoint, k4 at the end; weights 1, 2, 2, 1 over 6
    const S half = h / 2;
    {
      const auto& a1 = accelerations<method, terms>(model, ws, x.q, x.qd, tau(S(0)), servo, S(0));
      ws.qd_sum = x.qd;
      ws.qdd_sum = a1;
      ws.q_stage = x.q + half * x.qd;
      ws.qd_stage = x.qd + half * a1;
    }
    const auto& tau_half = tau(half);
    {
      const auto& a2 = accelerations<method, terms>(model, ws, ws.q_stage, ws.qd_stage, tau_half, servo, half);
      ws.qd_sum += S(2) * ws.qd_stage;
      ws.qdd_sum += S(2) * a2;
      ws.q_stage = x.q + half * ws.qd_stage;
      ws.qd_stage = x.qd + half * a2;
    }
    {
      const auto& a3 = accelerations<method, terms>(model, ws, ws.q_stage, ws.qd_stage, tau_half, servo, half);
      ws.qd_sum += S(2) * ws.qd_stage;
      ws.qdd_sum += S(2) * a3;
      ws.q_stage = x.q + h * ws.qd_stage;
      ws.qd_stage = x.qd + h * a3;
    }
    {
      const auto& a4 = accelerations<method, terms>(model, ws, ws.q_stage, ws.qd_stage, tau(h), servo, h);
      ws.qd_sum += ws.qd_stage;
      ws.qdd_sum += a4;
    }
    next.q = x.q + (h / S(6)) * ws.qd_sum;
    next.qd = x.qd + (h / S(6)) * ws.qdd_sum;
  } else if constexpr (integrator == Integrator::ImplicitPD) {
    implicit_pd_accelerations<terms>(model, ws, x, tau, servo, h);
    next.qd = x.qd + h * ws.tau_total;
    next.q = x.q + h * next.qd;
  } else {
    static_assert(terms == Terms::Full, "backward Euler integrates the full dynamics (its Jacobian is rnea's)");
    // the whole step, else 2, 4, ... substeps, each from the previous one's end, its q̈ and its Jacobian.
    // A step that starts where the last one ended has its energy, a first q̈ and a Jacobian at hand; any
    // other starts from the implicit PD step's q̈ and matrix, and its substeps from q̈ = 0 and a Jacobian
    // of their own.
    auto& report = ws.report;
    report = {};
    const bool continuing = ws.carried_model == &model && (x.q.array() == ws.carried.q.array()).all() &&
                            (x.qd.array() == ws.carried.qd.array()).all();
    ws.carried_model = nullptr;
    S energy = ws.carried_energy;

    // the first guess of q̈: a continuing step's extrapolated along the last steps of this length (a
    // parabola through three, a line through two); any other step's from the implicit PD step, with its
    // matrix for the first corrections (where M + h D + h^2 K is singular, as on a massless link with no
    // servo, from q̈ = 0 instead)
    bool mass_matrix_chord = false;
    if (continuing) {
      const int known = ws.carried_h == h ? ws.carried_known : 0;
      if (known == 2)
        ws.qdd_sum = S(3) * (ws.carried_qdd - ws.carried_qdd_1) + ws.carried_qdd_2;
      else if (known == 1)
        ws.qdd_sum = S(2) * ws.carried_qdd - ws.carried_qdd_1;
      else
        ws.qdd_sum = ws.carried_qdd;
    } else {
      implicit_pd_accelerations<terms>(model, ws, x, tau, servo, h);
      S kinetic, potential;  // the start's energy, at the angles crba left in ws.data
      mechanical_energy_pass(model, ws.data, x.qd, kinetic, potential);
      energy = kinetic + potential;
      mass_matrix_chord = ws.tau_total.allFinite();
      if (mass_matrix_chord)
        ws.qdd_sum = ws.tau_total;
      else
        ws.qdd_sum.setZero();
      ws.jacobian_h = S(0);
    }

    // the step as substeps on a grid of h / 2^halvings, each a backward-Euler step from the last one's
    // end: the whole step first; a substep that fails is taken again from the same start and guess, once
    // with a fresh Jacobian if it began with a kept one, else at half its length, and the rest of the step
    // goes on at the shorter length
    constexpr int units = 1 << backward_euler_halvings;
    int done = 0, length = units;
    bool retried = false;
    ws.q_stage = x.q;
    ws.qd_stage = x.qd;
    ws.qdd_guess = ws.qdd_sum;
    while (done < units) {
      const S s0 = h * S(done) / S(units), hs = h * S(length) / S(units);
      const bool kept = !mass_matrix_chord && ws.jacobian_h == hs && ws.jacobian_servo == servo;
      if (backward_euler_substep(model, ws, tau, servo, s0, hs, energy, mass_matrix_chord)) {
        done += length;
        ++report.substeps;
        ws.q_stage = next.q;
        ws.qd_stage = next.qd;
        ws.qdd_guess = ws.qdd_sum;
        retried = false;
      } else if (kept && !retried) {
        retried = true;  // a kept Jacobian that led Newton's method astray (say, a limit spring came on)
        ws.jacobian_h = S(0);
        ws.qdd_sum = ws.qdd_guess;
      } else if (length > 1) {
        length /= 2;
        retried = false;
        ws.qdd_sum = ws.qdd_guess;
      } else {
        return false;
      }
      mass_matrix_chord = false;
    }
    report.energy = energy;
    ws.carried.q = next.q;
    ws.carried.qd = next.qd;
    ws.carried_known = continuing && ws.carried_h == h ? std::min(ws.carried_known + 1, 2) : 0;
    ws.carried_qdd_2 = ws.carried_qdd_1;
    ws.carried_qdd_1 = ws.carried_qdd;
    ws.carried_qdd = ws.qdd_sum;
    ws.carried_h = h;
    ws.carried_energy = energy;
    ws.carried_model = &model;
    return true;
  }
  return true;
}

}  // namespace detail

namespace detail {

// The checked step around advance: the candidate copied out only if it passes.
template <Integrator integrator, FdMethod method, Terms terms, class Model, class Source>
inline StepStatus checked_step(const Model& model, StepWorkspace<Model>& ws, State<Model>& state, Source& tau,
                               const PdServo<Model>* servo, typename Model::scalar_type h,
                               const StepLimits<typename Model::scalar_type>& limits) noexcept {
  // refuse bad input before touching anything
  if (const StepStatus st = check_time_step(h); !st.ok()) return st;
  if (int j = first_non_finite(state.q); j >= 0) return {StepError::BadInput, Quantity::Angle, j};
  if (int j = first_non_finite(state.qd); j >= 0) return {StepError::BadInput, Quantity::Velocity, j};
  if (tau.bad_joint >= 0) return {StepError::BadInput, Quantity::Torque, tau.bad_joint};
  if (servo)
    if (int j = first_invalid_servo_joint(*servo, limits); j >= 0) return {StepError::BadServo, Quantity::None, j};

  const bool solved = advance<integrator, method, terms>(model, ws, state, tau, servo, h);

  // check the torques a schedule gave, then the candidate; copy it out only if it passes
  if (tau.bad_joint >= 0) return {StepError::BadInput, Quantity::Torque, tau.bad_joint};
  if (!solved) {  // the step's matrix singular at the start (M + h D + h^2 K), else where backward Euler's
                  // last iterate went farthest beyond the limits (an input driving the body away), if it
                  // did: its first non-finite entry, else its largest rate, else angle
    if (const int j = singular_joint_at_start<integrator>(model, ws, state, servo, h); j >= 0)
      return {StepError::SingularMassMatrix, Quantity::None, j};
    const auto& q = ws.next.q;
    const auto& qd = ws.next.qd;
    if (int j = first_non_finite(qd); j >= 0) return {StepError::NoSolution, Quantity::Velocity, j};
    if (int j = first_non_finite(q); j >= 0) return {StepError::NoSolution, Quantity::Angle, j};
    if (int j = farthest_beyond(qd, limits.max_abs_qd); j >= 0) return {StepError::NoSolution, Quantity::Velocity, j};
    if (int j = farthest_beyond(q, limits.max_abs_q); j >= 0) return {StepError::NoSolution, Quantity::Angle, j};
    return {StepError::NoSolution, Quantity::None, -1};
  }
  const auto& next = ws.next;
  if (const StepStatus result = check_step_result(next.q, next.qd, limits); !result) {
    // a NaN where the step's matrix is singular: that joint, not the first NaN
    if (result.error == StepError::NonFinite)
      if (const int j = singular_joint_at_start<integrator>(model, ws, state, servo, h); j >= 0)
        return {StepError::SingularMassMatrix, Quantity::None, j};
    return result;
  }
  state.q = next.q;
  state.qd = next.qd;
  return {};
}

}  // namespace detail

/// Advances the state by one fixed time step, checked (the integrators above; ImplicitPD and
/// BackwardEuler as derived in docs/stability.md).
/// \tparam integrator  SemiImplicitEuler, RungeKutta4, ImplicitPD or BackwardEuler (Terms::Full only)
/// \tparam method      how forward dynamics is computed (forward_dynamics.hpp; BackwardEuler needs none)
/// \tparam terms       Terms::Full or Terms::NoCoriolis
/// \param ws      workspace made from `model`; after a BackwardEuler step ws.report says what it did, and
///                ws.carried remembers its end for the next step (StepWorkspace)
/// \param state   q (rad) and qd (rad/s), nj each: overwritten on success, left as it was on any error
/// \param tau     motor torques (N m), nj, held over the step
/// \param servo   joint-space forces (servo.hpp) added to tau, or nullptr for none
/// \param h       time step (s), finite and > 0
/// \param limits  bounds on |q| and |qd| beyond which the result counts as a runaway
/// \return ok, or the error (bad h, non-finite input, unusable servo, no backward-Euler solution,
///         non-finite or runaway result, a singular mass matrix) with the quantity and the joint at fault. No
///         allocation, no exception.
template <Integrator integrator, FdMethod method = FdMethod::MassMatrix, Terms terms = Terms::Full, class Model>
inline StepStatus step(const Model& model, StepWorkspace<Model>& ws, State<Model>& state,
                       const typename Model::JointVector& tau, const PdServo<std::type_identity_t<Model>>* servo,
                       typename Model::scalar_type h,
                       const StepLimits<typename Model::scalar_type>& limits = {}) noexcept {
  detail::HeldTorque<Model> held{tau};
  return detail::checked_step<integrator, method, terms>(model, ws, state, held, servo, h, limits);
}

/// As above, with the motor torques a function of time within the step, evaluated at each stage's time
/// (SemiImplicitEuler at 0; RungeKutta4 at 0, h/2, h; ImplicitPD and BackwardEuler at each (sub)step's end).
/// \param tau  the schedule: tau(s, out) writes the torques (N m, nj) at s in [0, h] seconds into the step;
///             a non-finite torque is refused as bad input, the state left as it was
template <Integrator integrator, FdMethod method = FdMethod::MassMatrix, Terms terms = Terms::Full, class Model,
          TorqueSchedule<Model> Schedule>
inline StepStatus step(const Model& model, StepWorkspace<Model>& ws, State<Model>& state, const Schedule& tau,
                       const PdServo<std::type_identity_t<Model>>* servo, typename Model::scalar_type h,
                       const StepLimits<typename Model::scalar_type>& limits = {}) noexcept {
  detail::ScheduledTorque<Model, Schedule> scheduled{tau, ws.tau_stage};
  return detail::checked_step<integrator, method, terms>(model, ws, state, scheduled, servo, h, limits);
}

/// As above, without joint-space forces.
template <Integrator integrator, FdMethod method = FdMethod::MassMatrix, Terms terms = Terms::Full, class Model>
inline StepStatus step(const Model& model, StepWorkspace<Model>& ws, State<Model>& state,
                       const typename Model::JointVector& tau, typename Model::scalar_type h,
                       const StepLimits<typename Model::scalar_type>& limits = {}) noexcept {
  return step<integrator, method, terms>(model, ws, state, tau, nullptr, h, limits);
}

}  // namespace humandyn
