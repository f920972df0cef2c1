// The integrators, the servo and the checked step: each step checked against the equation it claims
// to solve, written with inverse dynamics (RNEA) only; Runge-Kutta against an independent RK4 on a
// dense solve of RNEA's columns; the step's refusals; no allocation. (The order of convergence is asserted
// with the stiff-and-extreme suite, test_stability.cpp.)
#include "humandyn/algorithm/energy.hpp"
#include "humandyn/builders.hpp"
#include "humandyn/integrators.hpp"
#include "stability_suite.hpp"
#include "support/long_runs.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <tuple>

namespace test_integrators {

namespace {

using namespace humandyn;
using Vec = stability::Body::JointVector;

// A servo with every kind of force active: gains, a moving reference, damping, and limits that the
// state below crosses on some joints. Soft enough for explicit steps of 1/240 s on the light foot
// (M_ii about 0.008 kg m^2).
template <class M>
PdServo<M> busy_servo(const M& model) {
  using S = typename M::scalar_type;
  PdServo<M> servo(model);
  for (int i = 0; i < model.size(); ++i) {
    servo.kp[i] = S(20 + 4 * i);
    servo.kd[i] = S(0.5 + 0.1 * i);
    servo.q_ref[i] = S(0.2 * std::cos(0.7 * i));
    servo.qd_ref[i] = S(0.5 * std::sin(1.1 * i));
    servo.damping[i] = S(0.01 * i);
    servo.q_min[i] = S(-0.25);
    servo.q_max[i] = S(0.25);
    servo.limit_stiffness[i] = S(100);
  }
  return servo;
}

template <class M>
State<M> some_state(const M& model) {
  using S = typename M::scalar_type;
  State<M> x(model);
  for (int i = 0; i < model.size(); ++i) {
    x.q[i] = S(0.4 * std::sin(1.3 * i + 0.2));
    x.qd[i] = S(1.5 * std::cos(0.9 * i));
  }
  return x;
}

template <class M>
typename M::JointVector some_torque(const M& model) {
  typename M::JointVector tau(model.size());
  for (int i = 0; i < model.size(); ++i) tau[i] = typename M::scalar_type(3 * std::sin(2.1 * i));
  return tau;
}

// The servo's torque by hand, joint by joint.
TEST(Servo, TorqueIsPdPlusDampingPlusLimitSprings) {
  const auto model = stability::body<double>();
  const auto servo = busy_servo(model);
  const auto x = some_state(model);
  const double s = 0.01;
  Vec out;
  servo_torque(servo, x.q, x.qd, s, out);
  int above = 0, below = 0;
  for (int i = 0; i < 16; ++i) {
    double expected = servo.kp[i] * (servo.q_ref[i] + s * servo.qd_ref[i] - x.q[i]) +
                      servo.kd[i] * (servo.qd_ref[i] - x.qd[i]) - servo.damping[i] * x.qd[i];
    if (x.q[i] > 0.25) expected += 100 * (0.25 - x.q[i]), ++above;
    if (x.q[i] < -0.25) expected += 100 * (-0.25 - x.q[i]), ++below;
    EXPECT_NEAR(out[i], expected, 1e-12 * std::max(1.0, std::abs(expected))) << i;
  }
  EXPECT_GT(above, 0);  // the state does cross both limits somewhere
  EXPECT_GT(below, 0);

  Vec K, D;
  servo_gains(servo, x.q, K, D);
  for (int i = 0; i < 16; ++i) {
    EXPECT_EQ(K[i], servo.kp[i] + (std::abs(x.q[i]) > 0.25 ? 100.0 : 0.0));
    EXPECT_EQ(D[i], servo.kd[i] + servo.damping[i]);
  }
}

TEST(Servo, InvalidSettingsAreFound) {
  const auto model = stability::body<double>();
  auto servo = busy_servo(model);
  EXPECT_EQ(first_invalid_servo_joint(servo), -1);
  servo.kd[6] = -1;
  EXPECT_EQ(first_invalid_servo_joint(servo), 6);
  servo.kd[6] = 1;
  servo.q_ref[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(first_invalid_servo_joint(servo), 3);
  servo.q_ref[3] = 0;
  servo.q_min[9] = 1;
  servo.q_max[9] = 0;
  EXPECT_EQ(first_invalid_servo_joint(servo), 9);
  // limits at infinity: none (-inf below, +inf above) is usable; both at one infinity is not (its spring
  // would be 0 * inf); equal finite limits are
  constexpr double inf = std::numeric_limits<double>::infinity();
  for (const auto& [lo, hi, ok] : {std::tuple{-inf, inf, true},
                                   {-inf, 0.5, true},
                                   {0.5, inf, true},
                                   {0.5, 0.5, true},
                                   {inf, inf, false},
                                   {-inf, -inf, false}}) {
    servo.q_min[9] = lo;
    servo.q_max[9] = hi;
    EXPECT_EQ(first_invalid_servo_joint(servo), ok ? -1 : 9) << lo << " " << hi;
  }
  servo.q_min[9] = -inf;
  servo.q_max[9] = inf;
  // references within a step's limits: at them is within, past them (or infinite) is not
  const StepLimits<double> limits;
  EXPECT_EQ(first_invalid_servo_joint(servo, limits), -1);
  for (const auto& [angle, rate, ok] : {std::tuple{1e4, 1e4, true},
                                        {-1e4, -1e4, true},
                                        {std::nextafter(1e4, inf), 0.0, false},
                                        {0.0, -std::nextafter(1e4, inf), false},
                                        {1e300, 0.0, false}}) {
    servo.q_ref[5] = angle;
    servo.qd_ref[5] = rate;
    EXPECT_EQ(first_invalid_servo_joint(servo, limits), ok ? -1 : 5) << angle << " " << rate;
    EXPECT_EQ(first_invalid_servo_joint(servo), -1) << angle << " " << rate;  // no limits: any finite reference
  }
}

// M(q) q̈ + b(q, q̇) by inverse dynamics.
Vec id(const stability::Body& model, const Vec& q, const Vec& qd, const Vec& qdd) {
  Data<stability::Body> data(model);
  return rnea(model, data, q, qd, qdd);
}

// Semi-implicit Euler: M q̈ + b = tau + tau_s at the start, velocity first, then position.
TEST(Step, SemiImplicitEulerSolvesItsEquation) {
  const auto model = stability::body<double>();
  const auto servo = busy_servo(model);
  const auto x0 = some_state(model);
  const Vec tau = some_torque(model);
  const double h = 1e-3;
  for (int method = 0; method < 2; ++method) {
    auto x = x0;
    StepWorkspace<stability::Body> ws(model);
    const StepStatus s = method == 0
                             ? step<Integrator::SemiImplicitEuler, FdMethod::MassMatrix>(model, ws, x, tau, &servo, h)
                             : step<Integrator::SemiImplicitEuler, FdMethod::Articulated>(model, ws, x, tau, &servo, h);
    ASSERT_TRUE(s.ok()) << describe(s, model);
    const Vec qdd = (x.qd - x0.qd) / h;
    Vec ts;
    servo_torque(servo, x0.q, x0.qd, 0.0, ts);
    const Vec lhs = id(model, x0.q, x0.qd, qdd), rhs = tau + ts;
    EXPECT_LT((lhs - rhs).cwiseAbs().maxCoeff(), 1e-8 * rhs.cwiseAbs().maxCoeff()) << method;
    EXPECT_LT((x.q - (x0.q + h * x.qd)).cwiseAbs().maxCoeff(), 1e-15);
  }
}

// The implicit step is backward Euler on the joint-space law: with M and b frozen at the start,
//   M q̈ + b = tau + tau_s(q', q̇', reference at t + h),  q̇' = q̇ + h q̈,  q' = q + h q̇',
// the limit springs counted where the predicted q + h q̇ is past a limit.
TEST(Step, ImplicitStepIsBackwardEulerOnTheServo) {
  const auto model = stability::body<double>();
  auto servo = busy_servo(model);
  for (int i = 0; i < 16; ++i) servo.kp[i] *= 1e4;  // stiff: an explicit step would explode at this h
  const auto x0 = some_state(model);
  const Vec tau = some_torque(model);
  const double h = 1.0 / 60;
  auto x = x0;
  StepWorkspace<stability::Body> ws(model);
  const StepStatus s = step<Integrator::ImplicitPD>(model, ws, x, tau, &servo, h);
  ASSERT_TRUE(s.ok()) << describe(s, model);
  const Vec qdd = (x.qd - x0.qd) / h;
  EXPECT_LT((x.q - (x0.q + h * x.qd)).cwiseAbs().maxCoeff(), 1e-14);

  // tau_s at the end state, the limit springs on the set chosen at the predicted position
  const Vec q_pred = x0.q + h * x0.qd;
  Vec ts;
  for (int i = 0; i < 16; ++i) {
    ts[i] = servo.kp[i] * (servo.q_ref[i] + h * servo.qd_ref[i] - x.q[i]) + servo.kd[i] * (servo.qd_ref[i] - x.qd[i]) -
            servo.damping[i] * x.qd[i];
    if (q_pred[i] > servo.q_max[i]) ts[i] += servo.limit_stiffness[i] * (servo.q_max[i] - x.q[i]);
    if (q_pred[i] < servo.q_min[i]) ts[i] += servo.limit_stiffness[i] * (servo.q_min[i] - x.q[i]);
  }
  const Vec lhs = id(model, x0.q, x0.qd, qdd), rhs = tau + ts;
  EXPECT_LT((lhs - rhs).cwiseAbs().maxCoeff(), 1e-9 * rhs.cwiseAbs().maxCoeff());

  // the paper model (Table 1's massless pelvis) has a singular M, yet M + h D + h^2 K is regular: the
  // implicit step still solves its equation
  {
    const auto seed = human_model<double>(paper_parameters());
    auto y = some_state(seed);
    const auto y0 = y;
    const auto seed_servo = busy_servo(seed);
    StepWorkspace<HumanModel<double>> seed_ws(seed);
    ASSERT_TRUE(step<Integrator::ImplicitPD>(seed, seed_ws, y, tau, &seed_servo, h).ok());
    const Vec a = (y.qd - y0.qd) / h, q_pred0 = y0.q + h * y0.qd;
    Vec ts2;
    for (int i = 0; i < 16; ++i) {
      ts2[i] = seed_servo.kp[i] * (seed_servo.q_ref[i] + h * seed_servo.qd_ref[i] - y.q[i]) +
               seed_servo.kd[i] * (seed_servo.qd_ref[i] - y.qd[i]) - seed_servo.damping[i] * y.qd[i];
      if (q_pred0[i] > seed_servo.q_max[i]) ts2[i] += seed_servo.limit_stiffness[i] * (seed_servo.q_max[i] - y.q[i]);
      if (q_pred0[i] < seed_servo.q_min[i]) ts2[i] += seed_servo.limit_stiffness[i] * (seed_servo.q_min[i] - y.q[i]);
    }
    Data<HumanModel<double>> d(seed);
    const Vec l2 = rnea(seed, d, y0.q, y0.qd, a), r2 = tau + ts2;
    EXPECT_LT((l2 - r2).cwiseAbs().maxCoeff(), 1e-9 * r2.cwiseAbs().maxCoeff());
  }

  // without a servo it is semi-implicit Euler
  auto a = x0, b = x0;
  ASSERT_TRUE(step<Integrator::ImplicitPD>(model, ws, a, tau, h).ok());
  ASSERT_TRUE(step<Integrator::SemiImplicitEuler>(model, ws, b, tau, h).ok());
  EXPECT_LT((a.q - b.q).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((a.qd - b.qd).cwiseAbs().maxCoeff(), 1e-10);
}

// Backward Euler solves its equation with everything at the end of the step:
//   ID(q', q̇', q̈) = tau + tau_s(q', q̇', reference at t + h),  q̇' = q̇ + h q̈,  q' = q + h q̇',
// the limit springs counted where q' is past a limit; on a stiff servo at 1/60 s.
TEST(Step, BackwardEulerSolvesItsEquation) {
  const auto model = stability::body<double>();
  auto servo = busy_servo(model);
  for (int i = 0; i < 16; ++i) servo.kp[i] *= 1e4;
  const auto x0 = some_state(model);
  const Vec tau = some_torque(model);
  for (double h : {1.0 / 1000, 1.0 / 60}) {
    auto x = x0;
    StepWorkspace<stability::Body> ws(model);
    const StepStatus s = step<Integrator::BackwardEuler>(model, ws, x, tau, &servo, h);
    ASSERT_TRUE(s.ok()) << describe(s, model);
    // under this servo's pull a correction with the implicit PD step's matrix cuts the residual less
    // than tenfold, and Newton's method calls in the Jacobian
    EXPECT_GE(ws.report.jacobians, 1);
    EXPECT_GE(ws.report.dissipated, 0);
    const Vec qdd = (x.qd - x0.qd) / h;
    EXPECT_LT((x.q - (x0.q + h * x.qd)).cwiseAbs().maxCoeff(), 1e-14);
    Vec ts;
    servo_torque(servo, x.q, x.qd, h, ts);
    const Vec lhs = id(model, x.q, x.qd, qdd), rhs = tau + ts;
    EXPECT_LT((lhs - rhs).cwiseAbs().maxCoeff(), 1e-8 * rhs.cwiseAbs().maxCoeff()) << "h " << h;
    // and the semi-implicit steps, which take gravity and the velocity products at the start, do not
    auto y = x0;
    ASSERT_TRUE(step<Integrator::ImplicitPD>(model, ws, y, tau, &servo, h).ok());
    servo_torque(servo, y.q, y.qd, h, ts);
    const Vec l2 = id(model, y.q, y.qd, (y.qd - x0.qd) / h), r2 = tau + ts;
    EXPECT_GT((l2 - r2).cwiseAbs().maxCoeff(), 1e-6 * r2.cwiseAbs().maxCoeff()) << "h " << h;
  }
}

// For a passive body (no torque, no servo) each step's energy only falls, and the report says by how much.
TEST(Step, BackwardEulerPassiveEnergyOnlyFalls) {
  for (const bool hanging : {true, false}) {
    const stability::Body model(hanging ? stability::hanging_description() : stability::body_description());
    StepWorkspace<stability::Body> ws(model);
    Data<stability::Body> aux(model);
    auto x = some_state(model);
    const Vec tau = Vec::Zero();
    for (int k = 0; k < humandyn::testing::long_run(200, 30); ++k) {  // support/long_runs.hpp
      const double e0 = total_energy(model, aux, x.q, x.qd);
      ASSERT_TRUE(step<Integrator::BackwardEuler>(model, ws, x, tau, 1.0 / 30).ok()) << k;
      const double e1 = total_energy(model, aux, x.q, x.qd);
      EXPECT_LE(e1, e0) << k;
      EXPECT_EQ(ws.report.work, 0.0);
      EXPECT_NEAR(ws.report.dissipated, e0 - e1, 1e-9 * std::abs(e0)) << k;
      EXPECT_NEAR(ws.report.energy, e1, 1e-9 * std::abs(e0)) << k;
    }
  }
}

// Backward Euler takes the end state's energy at the cosines and sines its last residual left, except
// where that residual came from rnea_derivatives (a continuing step without a Jacobian at hand, solved
// by its first q̈): there it takes its own sweep. The motion here is uniform: each step's torque is what
// inverse dynamics needs at its end with q̈ = 0, so continuing steps start right and stop at their first
// residual. The reported and carried energies are the end state's, which a stale sweep (the start's
// angles) would miss by the potential of a step's travel.
TEST(Step, BackwardEulerEnergyAfterADerivativeResidualIsTheEndState) {
  const auto model = stability::body<double>();
  StepWorkspace<stability::Body> ws(model);
  Data<stability::Body> aux(model);
  auto x = some_state(model);
  constexpr double h = 1e-3;
  int derivative_residuals = 0;
  for (int k = 0; k < 10; ++k) {
    const Vec tau = rnea(model, aux, Vec(x.q + h * x.qd), x.qd, Vec::Zero());
    const Vec q0 = x.q;
    ASSERT_TRUE(step<Integrator::BackwardEuler>(model, ws, x, tau, h).ok()) << k;
    ASSERT_GT((x.q - q0).cwiseAbs().maxCoeff(), 1e-4) << k;
    const double e = total_energy(model, aux, x.q, x.qd);
    EXPECT_NEAR(ws.report.energy, e, 1e-12 * std::abs(e)) << k;
    EXPECT_NEAR(ws.carried_energy, e, 1e-12 * std::abs(e)) << k;
    if (k > 0 && ws.report.residuals == 1 && ws.report.jacobians == 0 && ws.jacobian_h == 0.0) ++derivative_residuals;
  }
  EXPECT_EQ(derivative_residuals, 9);  // every continuing step
}

// Steps that continue from the last one's end reuse its energy, start Newton's method from its q̈ and
// keep its Jacobian while it serves (a chord iteration): the states agree with those of fresh workspaces
// within Newton's tolerance, with few Jacobians; a step from any other state (or after forget(), or of
// another model) starts afresh, from the implicit PD step's q̈ and matrix, which serve it here without a
// Jacobian; one with another step length or servo factorises its own Jacobian.
TEST(Step, BackwardEulerContinuingStepsAgreeWithFreshOnes) {
  const auto model = stability::body<double>();
  const auto servo = busy_servo(model);
  const Vec tau = some_torque(model);
  StepWorkspace<stability::Body> ws(model);
  Data<stability::Body> aux(model);
  auto x = some_state(model), y = x;
  constexpr int steps = 100;
  int continuing_residuals = 0, fresh_residuals = 0, continuing_jacobians = 0, fresh_jacobians = 0;
  double worst_q = 0, worst_qd = 0;
  for (int k = 0; k < steps; ++k) {
    ASSERT_TRUE(step<Integrator::BackwardEuler>(model, ws, x, tau, &servo, 1e-3).ok()) << k;
    ASSERT_EQ(ws.carried_model, &model);
    ASSERT_EQ(ws.report.substeps, 1) << k;
    if (k > 0) continuing_residuals += ws.report.residuals, continuing_jacobians += ws.report.jacobians;
    // the carried energy is the end state's
    EXPECT_NEAR(ws.carried_energy, total_energy(model, aux, x.q, x.qd), 1e-12 * std::abs(ws.carried_energy)) << k;
    StepWorkspace<stability::Body> fresh(model);
    ASSERT_TRUE(step<Integrator::BackwardEuler>(model, fresh, y, tau, &servo, 1e-3).ok()) << k;
    if (k > 0) fresh_residuals += fresh.report.residuals, fresh_jacobians += fresh.report.jacobians;
    worst_q = std::max(worst_q, (x.q - y.q).cwiseAbs().maxCoeff());
    worst_qd = std::max(worst_qd, (x.qd - y.qd).cwiseAbs().maxCoeff());
    y = x;  // each fresh step from the continuing one's state
  }
  EXPECT_LT(worst_q, 1e-10) << "rad";
  EXPECT_LT(worst_qd, 1e-7) << "rad/s";
  EXPECT_EQ(fresh_jacobians, 0);  // M + h D + h^2 K cut every residual at least tenfold
  EXPECT_LE(continuing_jacobians, steps / 4);
  RecordProperty("residuals_continuing_fresh",
                 std::to_string(continuing_residuals) + "/" + std::to_string(fresh_residuals));
  RecordProperty("jacobians_continuing_fresh",
                 std::to_string(continuing_jacobians) + "/" + std::to_string(fresh_jacobians));
  // from another state, or from the carried one after forget() or with another model: the same step as a
  // fresh workspace's, bit for bit, with as many residuals
  const auto other = stability::body<double>();
  for (const int start : {0, 1, 2}) {
    State<stability::Body> a = start == 0 ? some_state(model) : ws.carried, b = a;
    if (start == 1) ws.forget();
    const auto& m = start == 2 ? other : model;
    StepWorkspace<stability::Body> fresh(m);
    ASSERT_TRUE(step<Integrator::BackwardEuler>(m, ws, a, tau, &servo, 1e-3).ok());
    ASSERT_TRUE(step<Integrator::BackwardEuler>(m, fresh, b, tau, &servo, 1e-3).ok());
    EXPECT_TRUE(a.q == b.q && a.qd == b.qd) << "start " << start;
    EXPECT_EQ(ws.report.residuals, fresh.report.residuals) << "start " << start;
  }
  // continuing a 1-ms step with a 2-ms one, then with that length but without the servo: a Jacobian of
  // its own each time
  State<stability::Body> a = some_state(model);
  ASSERT_TRUE(step<Integrator::BackwardEuler>(model, ws, a, tau, &servo, 1e-3).ok());
  for (const PdServo<stability::Body>* s : {&servo, static_cast<const PdServo<stability::Body>*>(nullptr)}) {
    ASSERT_EQ(ws.carried_model, &model);
    ASSERT_TRUE(step<Integrator::BackwardEuler>(model, ws, a, tau, s, 2e-3).ok());
    ASSERT_EQ(ws.report.substeps, 1);
    EXPECT_GE(ws.report.jacobians, 1) << (s ? "another step length" : "no servo");
  }
}

// A passive body falling from rest: its torques, and so the residual's scale, are near zero while the
// inertial and gravity torques that cancel in them are not. Newton's method stops at rnea's rounding
// (before, a continuing step whose extrapolated start was already that close could never meet a
// tolerance relative to those near-zero torques, and was retaken in halves: its fourth step here).
// With steps of 1e-8 s the energy a step moves is below the rounding of the body's 718 J: such a step keeps
// its velocity (before, every step after the second was refused).
TEST(Step, BackwardEulerFromRestStopsAtRounding) {
  const auto model = stability::body<double>();
  const Vec tau = Vec::Zero();
  for (const double h : {1e-3, 1e-8}) {
    StepWorkspace<stability::Body> ws(model);
    State<stability::Body> x(model);  // standing, at rest
    for (int k = 0; k < 50; ++k) {
      ASSERT_TRUE(step<Integrator::BackwardEuler>(model, ws, x, tau, h).ok()) << k << ", h " << h;
      EXPECT_EQ(ws.report.substeps, 1) << k;
      EXPECT_LE(ws.report.residuals, 6) << k;
      EXPECT_LE(ws.report.jacobians, 1) << k;
    }
    EXPECT_GT(x.qd.cwiseAbs().maxCoeff(), h) << "the body has begun to fall";
  }
}

// The energy check takes from the velocity only a gain beyond the energies' rounding. Taking every step's
// rounding margin drained a body whose true change per step is below it: in float, the hanging body's swing
// stood still (at most 0.003 J of kinetic energy, where double reaches 162 J), and so it did in double with
// the world origin 1e6 m away (the potential, and with it the rounding, a million times larger). The swing
// reaches the same kinetic energy in float, and wherever the world origin is.
template <class S>
double backward_euler_swing_peak(double height, double h, int steps) {
  using M = HumanModel<S>;
  ModelDescription<double> d = human_description(default_parameters());
  d.base_pose.p.z() += height;
  d.gravity = -d.gravity;  // hanging from the stance foot
  const M model(d.cast<S>());
  StepWorkspace<M> ws(model);
  Data<M> data(model);
  State<M> x(model);
  for (int i = 0; i < M::nj; ++i) x.q[i] = S(0.3 * ((i % 3) - 1) + 0.05);
  const typename M::JointVector tau = M::JointVector::Zero();
  double peak = 0;
  for (int k = 0; k < steps; ++k) {
    EXPECT_TRUE(step<Integrator::BackwardEuler>(model, ws, x, tau, S(h)).ok()) << k;
    S T, V;
    mechanical_energy(model, data, x.q, x.qd, T, V);
    peak = std::max(peak, double(T));
  }
  return peak;
}

TEST(Step, BackwardEulerKeepsASwingWhoseStepsChangeItsEnergyByLessThanRounding) {
  const double h = 1e-4;
  const int steps = humandyn::testing::long_run(2000, 300);
  const double reference = backward_euler_swing_peak<double>(0, h, steps);
  EXPECT_GT(reference, humandyn::testing::long_run(10.0, 0.1));  // (the swing is under way)
  EXPECT_NEAR(backward_euler_swing_peak<float>(0, h, steps), reference, 1e-3 * reference);
  EXPECT_NEAR(backward_euler_swing_peak<double>(1e6, h, steps), reference, 1e-5 * reference);
}

// A massless leaf joint (a sensor frame on the right wrist) makes the mass matrix singular at every pose:
// each explicit step and the implicit one without a servo fail, naming that joint, not the first joint
// the NaN reached (joint 1, as before), and leave the state as it was
TEST(Step, ASingularMassMatrixIsNamedAtItsJoint) {
  ModelDescription<double> d = human_description(default_parameters());
  JointDescription<double> tip;
  tip.name = "r_wrist_sensor";
  tip.link_name = "sensor";
  tip.parent = 11;
  tip.dh = {0.05, 0.0, 0.0, 0.0};
  d.joints.push_back(tip);
  using A = AnyModel<double>;
  const A model(d);
  StepWorkspace<A> ws(model);
  const Eigen::VectorXd tau = Eigen::VectorXd::Zero(model.size());
  const auto check = [&](StepStatus s, const State<A>& x, const char* which) {
    EXPECT_EQ(s.error, StepError::SingularMassMatrix) << which << ": " << describe(s, model);
    EXPECT_EQ(s.joint, 16) << which;
    EXPECT_EQ(describe(s, model).rfind("the mass matrix is singular at joint 17 'r_wrist_sensor'", 0), 0u) << which;
    EXPECT_TRUE(x.q.isZero(0) && x.qd.isZero(0)) << which;
  };
  State<A> x(model);
  check(step<Integrator::SemiImplicitEuler>(model, ws, x, tau, 1e-3), x, "euler");
  check(step<Integrator::SemiImplicitEuler, FdMethod::Articulated>(model, ws, x, tau, 1e-3), x, "euler, aba");
  check(step<Integrator::RungeKutta4>(model, ws, x, tau, 1e-3), x, "rk4");
  check(step<Integrator::ImplicitPD>(model, ws, x, tau, 1e-3), x, "implicit");
  // backward Euler steps such a body at rest, but a torque on the massless joint leaves no end state:
  // named at that joint too, not where the NaN spread to (joint 1)
  EXPECT_TRUE(step<Integrator::BackwardEuler>(model, ws, x, tau, 1e-3).ok());
  x.q.setZero();
  x.qd.setZero();
  Eigen::VectorXd pushed = tau;
  pushed[16] = 1;
  check(step<Integrator::BackwardEuler>(model, ws, x, pushed, 1e-3), x, "backward euler, a torque on it");
  // a torque that overflows a regular body is still its own fault
  const auto regular = default_model<double>();
  StepWorkspace<HumanModel<double>> rws(regular);
  State<HumanModel<double>> rx(regular);
  HumanModel<double>::JointVector big = HumanModel<double>::JointVector::Zero();
  big[12] = 1e308;
  EXPECT_EQ(step<Integrator::RungeKutta4>(regular, rws, rx, big, 1e-3).error, StepError::NonFinite);
  // and so is a step so long that h^2 overflows (0 times inf in the implicit step's h^2 K, without a servo)
  const HumanModel<double>::JointVector zero = HumanModel<double>::JointVector::Zero();
  EXPECT_EQ(step<Integrator::ImplicitPD>(regular, rws, rx, zero, 1e200).error, StepError::NonFinite);
  // and so is one on a body whose M is singular (the paper model's massless pelvis) where a servo makes the
  // implicit steps' M + h D + h^2 K regular: their own failure, not the mass matrix's
  const auto paper = HumanModel<double>(human_description(paper_parameters()));
  StepWorkspace<HumanModel<double>> pws(paper);
  State<HumanModel<double>> px(paper);
  PdServo<HumanModel<double>> servo(paper);
  servo.kp.setConstant(200);
  servo.kd.setConstant(20);
  const HumanModel<double>::JointVector huge = HumanModel<double>::JointVector::Constant(1e308);
  const StepStatus implicit = step<Integrator::ImplicitPD>(paper, pws, px, huge, &servo, 1e-3);
  EXPECT_EQ(implicit.error, StepError::NonFinite) << describe(implicit, paper);
  const StepStatus be = step<Integrator::BackwardEuler>(paper, pws, px, huge, &servo, 1e-3);
  EXPECT_EQ(be.error, StepError::NoSolution) << describe(be, paper);
  // without the servo, the explicit step's failure there is the mass matrix's, at joint 4 (r_hip_pitch)
  const StepStatus euler = step<Integrator::SemiImplicitEuler>(paper, pws, px, big, 1e-3);
  EXPECT_EQ(euler.error, StepError::SingularMassMatrix) << describe(euler, paper);
  EXPECT_EQ(euler.joint, 3);
}

// A residual that is not finite ends a Newton iteration at once: from velocities of 1e200 rad/s (finite,
// but their products in rnea overflow) the whole step and each of its 8 halvings stops at its first
// residual, 9 in all (where it corrected on, each would take 9), and the step finds no end state, naming
// the first joint whose velocity came out not finite; the state stays as it was.
TEST(Step, BackwardEulerStopsAtAResidualThatIsNotFinite) {
  using M = HumanModel<double>;
  const M model = default_model<double>();
  State<M> x(model);
  x.qd.setConstant(1e200);
  StepWorkspace<M> ws(model);
  const StepStatus st = step<Integrator::BackwardEuler>(model, ws, x, M::JointVector::Zero(), 1e-3);
  EXPECT_EQ(st.error, StepError::NoSolution);
  EXPECT_EQ(st.quantity, Quantity::Velocity);
  EXPECT_EQ(st.joint, 0);
  EXPECT_EQ(ws.report.residuals, 9);
  EXPECT_EQ(ws.report.substeps, 0);
  EXPECT_TRUE((x.q.array() == 0).all() && (x.qd.array() == 1e200).all());
}

// A limit of backward Euler (docs/stability.md, "NoSolution"): every joint started 0.05 rad past a stop of
// 1e9 N m/rad, at h = 1/60 s, finds no end state even in substeps of h / 256 and leaves the state as it was,
// where the implicit PD step, its limit springs linear in the step, takes the step.
TEST(Step, BackwardEulerFindsNoEndStateDeepInAVeryStiffStop) {
  using M = HumanModel<double>;
  const M model = default_model<double>();
  PdServo<M> servo(model);
  servo.q_min.setConstant(-0.1);
  servo.q_max.setConstant(0.1);
  servo.limit_stiffness.setConstant(1e9);
  const M::JointVector zero = M::JointVector::Zero();
  State<M> pd(model), be(model);
  pd.q.setConstant(0.15);
  be.q = pd.q;
  StepWorkspace<M> ws(model);
  EXPECT_TRUE(step<Integrator::ImplicitPD>(model, ws, pd, zero, &servo, 1.0 / 60).ok());
  const StepStatus st = step<Integrator::BackwardEuler>(model, ws, be, zero, &servo, 1.0 / 60);
  EXPECT_EQ(st.error, StepError::NoSolution);
  EXPECT_TRUE((be.q.array() == 0.15).all() && (be.qd.array() == 0).all());
}

// Steps far longer than the body's motions allow Newton's method from the step's start (the upright body
// falling around its foot, passive, at 0.1 to 1 s): a substep that fails is halved where it failed, the
// rest of the step going on at that length, down to h / 256. Every step is accepted, in more than one
// substep where the whip of the light links needs it, and the energy never rises. (Before, the whole step
// was retaken as 2, 4, 8 and 16 equal substeps, each from q̈ = 0, and these runs stopped at their first
// step at 0.5 and 1 s, and part-way at 0.1 s.) Over 10 s; 3 s in the sanitizer build.
TEST(Step, BackwardEulerTakesLongStepsInSubsteps) {
  const auto model = stability::body<double>();
  Data<stability::Body> aux(model);
  const Vec tau = Vec::Zero();
  for (const double h : {0.1, 0.5, 1.0}) {
    StepWorkspace<stability::Body> ws(model);
    State<stability::Body> x(model);  // standing, at rest
    x.q[0] = 0.05;                    // leaning on the stance ankle
    double e = total_energy(model, aux, x.q, x.qd);
    int most = 0;
    for (int k = 0; k * h < humandyn::testing::long_run(10.0, 3.0); ++k) {
      ASSERT_TRUE(step<Integrator::BackwardEuler>(model, ws, x, tau, h).ok()) << "h " << h << ", step " << k;
      const double e1 = total_energy(model, aux, x.q, x.qd);
      EXPECT_LE(e1, e + 1e-12 * std::abs(e)) << "h " << h << ", step " << k;
      EXPECT_NEAR(ws.report.dissipated, e - e1, 1e-9 * std::abs(e)) << "h " << h << ", step " << k;
      EXPECT_GE(ws.report.substeps, 1);
      EXPECT_LE(ws.report.substeps, 256);
      most = std::max(most, ws.report.substeps);
      e = e1;
    }
    EXPECT_GT(most, 1) << "h " << h << ": the fallback was not needed";
    EXPECT_LT(x.q.cwiseAbs().maxCoeff(), 1e3) << "h " << h;
  }
}

// A stiff servo holding the body at rest, every joint at 1 rad, its feed-forward the gravity torques there:
// without gravity (E near 0 J), and with it, the world's origin at the centre of mass's height (E of a few J,
// while the potential's terms are hundreds of J). What is left to cancel there is rounding: of the servo's
// kp |q| (the residual's floor) and of the potential's terms (the energy check's). Every step is accepted.
// (Before, the floors scaled with the torques and the energy themselves, and these runs stopped with no
// end state within 1.1 s at kp = 1e6.)
TEST(Step, BackwardEulerHoldsABodyAtRestWhereItsEnergyIsNearZero) {
  for (const bool gravity : {false, true}) {
    auto d = stability::body_description();
    const Vec held = Vec::Constant(1.0);
    if (!gravity) {
      d.gravity.setZero();
    } else {
      const stability::Body m0(d);
      Data<stability::Body> data(m0);
      forward_kinematics(m0, data, held);
      const Eigen::Vector3d up = -d.gravity.normalized();
      d.base_pose.p -= up * up.dot(data.com);
    }
    const stability::Body model(d);
    Data<stability::Body> aux(model);
    PdServo<stability::Body> servo(model);
    servo.kp.setConstant(1e6);
    servo.kd.setConstant(5e4);
    servo.q_ref = held;
    const Vec tau = gravity_torques(model, aux, held);
    for (const double h : {1e-3, 1.0 / 30}) {
      StepWorkspace<stability::Body> ws(model);
      State<stability::Body> x(model);
      x.q = held;
      x.q[0] += 0.01;
      for (int k = 0; k * h < 3; ++k) {
        ASSERT_TRUE(step<Integrator::BackwardEuler>(model, ws, x, tau, &servo, h).ok())
            << (gravity ? "gravity" : "no gravity") << ", h " << h << ", step " << k << ", E "
            << total_energy(model, aux, x.q, x.qd) << " J";
      }
      EXPECT_LT((x.q - held).cwiseAbs().maxCoeff(), 1e-6) << "rad";
      if (gravity) {
        EXPECT_LT(std::abs(total_energy(model, aux, x.q, x.qd)), 10.0) << "J: near 0 J as meant";
      }
    }
  }
}

// Without gravity, a body whose only joint forces are limit springs (stiff: 1e4 to 1e6 N m/rad), or only
// passive damping, settles against its limits, backward Euler's damping taking its energy: nearly at
// rest, a spring's K (q_lim - q) cancels to rounding of K |q_lim| while the torques are tiny, and that
// rounding is the residual's floor. Every step is accepted, and the joints stay near their limits (0.1
// rad). (Before, the floor knew only the servo's kp and kd: from the first such state on, at step 1351
// of 3000, every step failed with no end state, whatever its length, and the body froze. The sanitizer
// build runs 300 steps of each, the same code: the other builds pass that step.)
TEST(Step, BackwardEulerStepsOnAgainstLimitSpringsWithoutGravity) {
  auto d = stability::body_description();
  d.gravity.setZero();
  const stability::Body model(d);
  const Vec tau = Vec::Zero();
  for (const auto& [stiffness, damping, h] :
       {std::tuple{1e5, 0.0, 1.0 / 60}, {1e4, 0.0, 1.0 / 30}, {1e6, 0.0, 1.0 / 60}, {0.0, 2.0, 1.0 / 60}}) {
    PdServo<stability::Body> servo(model);
    if (stiffness > 0) {
      servo.q_min.setConstant(-0.1);
      servo.q_max.setConstant(0.1);
      servo.limit_stiffness.setConstant(stiffness);
    }
    servo.damping.setConstant(damping);
    StepWorkspace<stability::Body> ws(model);
    State<stability::Body> x(model);
    for (int i = 0; i < model.size(); ++i) {
      x.q[i] = 0.05 * std::sin(1.3 * i + 0.2);
      x.qd[i] = 1.5 * std::cos(0.9 * i);
    }
    for (int k = 0; k < humandyn::testing::long_run(3000, 300); ++k)
      ASSERT_TRUE(step<Integrator::BackwardEuler>(model, ws, x, tau, &servo, h).ok())
          << "K " << stiffness << ", B " << damping << ", h " << h << ", step " << k;
    if (stiffness > 0) {
      EXPECT_LT(x.q.cwiseAbs().maxCoeff(), 0.1 + 0.01) << "K " << stiffness << ", h " << h;
    }
  }
}

// A passive triple pendulum (three 1 kg, 0.5 m links on horizontal axes) let go at 0.5, 0.8, 1.1 rad, for
// 20 s at long steps. Newton's method can meet a spurious root there, an end state turning a joint by
// hundreds of radians at thousands of rad/s (at h = 0.1 s, thousands of radians in one step, then a
// run-away), which the energy check's scaling of the velocity would hide. Such a root is refused and the
// step taken in substeps: every step is accepted and no joint turns by more than a radian in one.
TEST(Step, BackwardEulerRefusesSpuriousRootsOfLongSteps) {
  ModelDescription<double> d;
  d.name = "triple pendulum";
  for (int i = 0; i < 3; ++i) {
    JointDescription<double> j;
    j.name = "j" + std::to_string(i);
    j.link_name = "link" + std::to_string(i);
    j.parent = i - 1;
    j.dh = {0.5, 0.0, 0.0, 0.0};
    j.body = {1.0, Eigen::Vector3d(-0.25, 0, 0), 0.01 * Eigen::Matrix3d::Identity()};
    d.joints.push_back(j);
  }
  d.base_pose.R = Eigen::AngleAxisd(1.5707963267948966, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const AnyModel<double> model(d);
  Data<AnyModel<double>> aux(model);
  const Eigen::VectorXd tau = Eigen::VectorXd::Zero(3);
  for (const double h : {0.05, 0.1}) {
    StepWorkspace<AnyModel<double>> ws(model);
    State<AnyModel<double>> x(model);
    x.q << 0.5, 0.8, 1.1;
    double e = total_energy(model, aux, x.q, x.qd), largest = 0;
    for (int k = 0; k * h < 20; ++k) {
      const Eigen::VectorXd q = x.q;
      ASSERT_TRUE(step<Integrator::BackwardEuler>(model, ws, x, tau, h).ok()) << "h " << h << ", step " << k;
      largest = std::max(largest, (x.q - q).cwiseAbs().maxCoeff());
      const double e1 = total_energy(model, aux, x.q, x.qd);
      EXPECT_LE(e1, e + 1e-12 * std::abs(e)) << "h " << h << ", step " << k;
      e = e1;
    }
    EXPECT_LT(largest, 1.0) << "h " << h;
  }
}

// A step that fails from a kept Jacobian (here its factorisation is poisoned with NaN, as a Jacobian that
// throws Newton's method off would) is taken again once with a fresh Jacobian before it is halved: one
// substep, a Jacobian of its own, and the end state of a fresh workspace's step within Newton's tolerance.
TEST(Step, BackwardEulerRetriesAStepThatFailsFromAKeptJacobian) {
  const auto model = stability::body<double>();
  const auto servo = busy_servo(model);
  const Vec tau = some_torque(model);
  StepWorkspace<stability::Body> ws(model), fresh(model);
  auto a = some_state(model);
  for (int k = 0; k < 3; ++k) ASSERT_TRUE(step<Integrator::BackwardEuler>(model, ws, a, tau, &servo, 1e-3).ok());
  auto b = a;
  ASSERT_EQ(ws.jacobian_h, 1e-3);  // kept for the next step
  ws.lu.compute(model, decltype(ws.jacobian)::Constant(model.size(), model.size(), std::nan("")));
  ASSERT_TRUE(step<Integrator::BackwardEuler>(model, ws, a, tau, &servo, 1e-3).ok());
  EXPECT_EQ(ws.report.substeps, 1) << "retried with a fresh Jacobian, not halved";
  EXPECT_GE(ws.report.jacobians, 1);
  ASSERT_TRUE(step<Integrator::BackwardEuler>(model, fresh, b, tau, &servo, 1e-3).ok());
  EXPECT_LT((a.q - b.q).cwiseAbs().maxCoeff(), 1e-10) << "rad";
  EXPECT_LT((a.qd - b.qd).cwiseAbs().maxCoeff(), 1e-7) << "rad/s";
}

// A torque schedule that returns a constant gives what the held vector gives, for every integrator; a
// non-finite torque from a schedule is refused, naming the joint, the state kept.
TEST(Step, TorqueScheduleAtTheStages) {
  const auto model = stability::body<double>();
  const auto servo = busy_servo(model);
  const auto x0 = some_state(model);
  const Vec tau = some_torque(model);
  const auto constant = [&](double, Vec& out) noexcept { out = tau; };
  StepWorkspace<stability::Body> ws(model);
  for (Integrator m : stability::integrators) {
    auto a = x0, b = x0;
    ASSERT_TRUE(stability::step_with(m, model, ws, a, tau, &servo, 1e-3, {}).ok());
    const StepStatus s =
        m == Integrator::SemiImplicitEuler ? step<Integrator::SemiImplicitEuler>(model, ws, b, constant, &servo, 1e-3)
        : m == Integrator::RungeKutta4     ? step<Integrator::RungeKutta4>(model, ws, b, constant, &servo, 1e-3)
        : m == Integrator::ImplicitPD      ? step<Integrator::ImplicitPD>(model, ws, b, constant, &servo, 1e-3)
                                           : step<Integrator::BackwardEuler>(model, ws, b, constant, &servo, 1e-3);
    ASSERT_TRUE(s.ok()) << integrator_name(m);
    EXPECT_EQ(a.q, b.q) << integrator_name(m);
    EXPECT_EQ(a.qd, b.qd) << integrator_name(m);
  }
  // RK4 asks for the torques at 0, h/2 and h
  std::vector<double> times;
  auto x = x0;
  const auto recording = [&](double s, Vec& out) noexcept {
    times.push_back(s);
    out = tau;
  };
  times.reserve(8);
  ASSERT_TRUE(step<Integrator::RungeKutta4>(model, ws, x, recording, &servo, 1e-3).ok());
  EXPECT_EQ(times, (std::vector<double>{0, 5e-4, 1e-3}));
  // a NaN at the midpoint
  const auto bad = [&](double s, Vec& out) noexcept {
    out = tau;
    if (s > 0 && s < 1e-3) out[5] = std::numeric_limits<double>::quiet_NaN();
  };
  x = x0;
  const StepStatus s = step<Integrator::RungeKutta4>(model, ws, x, bad, &servo, 1e-3);
  EXPECT_EQ(s.error, StepError::BadInput);
  EXPECT_EQ(s.quantity, Quantity::Torque);
  EXPECT_EQ(s.joint, 5);
  EXPECT_EQ(x.q, x0.q);
  EXPECT_EQ(x.qd, x0.qd);
}

// RK4 against a separate RK4 whose forward dynamics is a dense solve of RNEA's columns.
TEST(Step, RungeKutta4MatchesAnIndependentRk4) {
  const auto model = stability::body<double>();
  const auto servo = busy_servo(model);
  const auto x0 = some_state(model);
  const Vec tau = some_torque(model);
  const double h = 1.0 / 240;

  const auto fd = [&](const Vec& q, const Vec& qd, double s) -> Vec {
    Eigen::Matrix<double, 16, 16> M;
    const Vec b = id(model, q, qd, Vec::Zero());
    for (int j = 0; j < 16; ++j) M.col(j) = id(model, q, qd, Vec::Unit(j)) - b;
    Vec ts;
    for (int i = 0; i < 16; ++i) {
      ts[i] = servo.kp[i] * (servo.q_ref[i] + s * servo.qd_ref[i] - q[i]) + servo.kd[i] * (servo.qd_ref[i] - qd[i]) -
              servo.damping[i] * qd[i];
      if (q[i] > servo.q_max[i]) ts[i] += servo.limit_stiffness[i] * (servo.q_max[i] - q[i]);
      if (q[i] < servo.q_min[i]) ts[i] += servo.limit_stiffness[i] * (servo.q_min[i] - q[i]);
    }
    return M.ldlt().solve(tau + ts - b);
  };
  const Vec k1v = x0.qd, k1a = fd(x0.q, x0.qd, 0);
  const Vec k2v = x0.qd + h / 2 * k1a, k2a = fd(x0.q + h / 2 * k1v, k2v, h / 2);
  const Vec k3v = x0.qd + h / 2 * k2a, k3a = fd(x0.q + h / 2 * k2v, k3v, h / 2);
  const Vec k4v = x0.qd + h * k3a, k4a = fd(x0.q + h * k3v, k4v, h);
  const Vec q1 = x0.q + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
  const Vec qd1 = x0.qd + h / 6 * (k1a + 2 * k2a + 2 * k3a + k4a);

  for (int method = 0; method < 2; ++method) {
    auto x = x0;
    StepWorkspace<stability::Body> ws(model);
    const StepStatus s = method == 0
                             ? step<Integrator::RungeKutta4, FdMethod::MassMatrix>(model, ws, x, tau, &servo, h)
                             : step<Integrator::RungeKutta4, FdMethod::Articulated>(model, ws, x, tau, &servo, h);
    ASSERT_TRUE(s.ok()) << describe(s, model);
    EXPECT_LT((x.q - q1).cwiseAbs().maxCoeff(), 1e-12) << method;
    EXPECT_LT((x.qd - qd1).cwiseAbs().maxCoeff(), 1e-10 * qd1.cwiseAbs().maxCoeff()) << method;
  }
}

// A model of runtime shape steps exactly as the compiled seed shape does.
TEST(Step, DynamicShapeMatchesStaticShape) {
  const auto model = stability::body<double>();
  const AnyModel<double> any(model.description());
  const auto servo = busy_servo(model);
  const auto any_servo = busy_servo(any);
  const Vec tau = some_torque(model);
  const Eigen::VectorXd any_tau = tau;
  auto x = some_state(model);
  auto y = some_state(any);
  StepWorkspace<stability::Body> ws(model);
  StepWorkspace<AnyModel<double>> any_ws(any);
  for (int k = 0; k < 10; ++k) {
    ASSERT_TRUE((step<Integrator::RungeKutta4>(model, ws, x, tau, &servo, 1e-3).ok()));
    ASSERT_TRUE((step<Integrator::RungeKutta4>(any, any_ws, y, any_tau, &any_servo, 1e-3).ok()));
    ASSERT_TRUE((step<Integrator::ImplicitPD>(model, ws, x, tau, &servo, 1e-3).ok()));
    ASSERT_TRUE((step<Integrator::ImplicitPD>(any, any_ws, y, any_tau, &any_servo, 1e-3).ok()));
  }
  EXPECT_LT((x.q - y.q).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((x.qd - y.qd).cwiseAbs().maxCoeff(), 1e-10);
}

// Every bad input is refused, names the joint and the quantity, and leaves the state as it was.
template <Integrator I>
void check_refusals() {
  const auto model = stability::body<double>();
  StepWorkspace<stability::Body> ws(model);
  const auto x0 = some_state(model);
  const Vec tau0 = some_torque(model);
  const auto same = [](const State<stability::Body>& a, const State<stability::Body>& b) {
    return std::memcmp(a.q.data(), b.q.data(), sizeof(double) * 16) == 0 &&
           std::memcmp(a.qd.data(), b.qd.data(), sizeof(double) * 16) == 0;
  };
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity()})
    for (int j : {0, 7, 15}) {
      for (Quantity what : {Quantity::Angle, Quantity::Velocity, Quantity::Torque}) {
        auto x = x0;
        Vec tau = tau0;
        if (what == Quantity::Angle) x.q[j] = bad;
        if (what == Quantity::Velocity) x.qd[j] = bad;
        if (what == Quantity::Torque) tau[j] = bad;
        const auto before = x;
        const StepStatus s = step<I>(model, ws, x, tau, 1e-3);
        EXPECT_EQ(s.error, StepError::BadInput);
        EXPECT_EQ(s.quantity, what);
        EXPECT_EQ(s.joint, j);
        EXPECT_TRUE(same(x, before));
        EXPECT_NE(describe(s, model).find(model.joint_name(j)), std::string::npos) << describe(s, model);
      }
    }
  // bad time steps
  for (double h : {0.0, -1e-3, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    auto x = x0;
    EXPECT_EQ(step<I>(model, ws, x, tau0, h).error, StepError::BadTimeStep);
    EXPECT_TRUE(same(x, x0));
  }
  // a bad servo
  {
    auto servo = busy_servo(model);
    servo.kp[4] = std::numeric_limits<double>::infinity();
    auto x = x0;
    const StepStatus s = step<I>(model, ws, x, tau0, &servo, 1e-3);
    EXPECT_EQ(s.error, StepError::BadServo);
    EXPECT_EQ(s.joint, 4);
    EXPECT_TRUE(same(x, x0));
  }
  // a reference beyond the step's limits (the run would stop as a run-away of some joint): refused by its joint
  for (const auto& [angle, rate] : {std::pair{2e4, 0.0}, {-2e4, 0.0}, {0.0, 2e4}, {1.5, -1e5}}) {
    auto servo = busy_servo(model);
    servo.q_ref[7] = angle;
    servo.qd_ref[7] = rate;
    auto x = x0;
    const StepStatus s = step<I>(model, ws, x, tau0, &servo, 1e-3);
    EXPECT_EQ(s.error, StepError::BadServo) << angle << " " << rate;
    EXPECT_EQ(s.joint, 7);
    EXPECT_TRUE(same(x, x0));
  }
  // a result past the runaway bounds: refused, the state kept, the first joint past it named
  {
    auto x = x0;
    StepLimits<double> tight;
    tight.max_abs_qd = 1.0;  // some_state already has |qd| up to 1.5
    const StepStatus s = step<I>(model, ws, x, tau0, 1e-3, tight);
    EXPECT_EQ(s.error, StepError::Runaway);
    EXPECT_EQ(s.quantity, Quantity::Velocity);
    int first = -1;
    for (int i = 0; i < 16 && first < 0; ++i)
      if (std::abs(x0.qd[i]) > 1.0) first = i;
    // the first joint past the bound after the step: near the start's (the step is tiny) but checked on the result
    EXPECT_GE(s.joint, 0);
    EXPECT_EQ(s.joint, first);
    EXPECT_TRUE(same(x, x0));
    tight = {};
    tight.max_abs_q = 0.1;
    const StepStatus sq = step<I>(model, ws, x, tau0, 1e-3, tight);
    EXPECT_EQ(sq.error, StepError::Runaway);
    EXPECT_EQ(sq.quantity, Quantity::Angle);
    EXPECT_TRUE(same(x, x0));
    // a NaN bound holds nothing: a runaway at the first joint
    tight = {};
    tight.max_abs_q = std::numeric_limits<double>::quiet_NaN();
    const StepStatus sn = step<I>(model, ws, x, tau0, 1e-3, tight);
    EXPECT_EQ(sn.error, StepError::Runaway);
    EXPECT_EQ(sn.quantity, Quantity::Angle);
    EXPECT_EQ(sn.joint, 0);
    EXPECT_TRUE(same(x, x0));
  }
  // a finite torque so large that the result overflows: non-finite (backward Euler: no solution), reported,
  // the state kept
  {
    auto x = x0;
    Vec tau = tau0;
    tau[12] = 1e308;
    const StepStatus s = step<I>(model, ws, x, tau, 1e-3);
    if (I == Integrator::BackwardEuler) {
      // Newton's method meets the overflow first, and names where its last iterate left the limits
      EXPECT_EQ(s.error, StepError::NoSolution) << describe(s, model);
      EXPECT_GE(s.joint, 0) << describe(s, model);
      EXPECT_NE(describe(s, model).find("; its last iterate had the "), std::string::npos) << describe(s, model);
      // a finite torque that drives one joint away: that joint named, not the first one dragged along
      tau[12] = 0;
      tau[11] = 1e30;
      const StepStatus driven = step<I>(model, ws, x, tau, 1e-3);
      EXPECT_EQ(driven.error, StepError::NoSolution) << describe(driven, model);
      EXPECT_EQ(driven.joint, 11) << describe(driven, model);
      EXPECT_TRUE(same(x, x0));
    } else {
      EXPECT_EQ(s.error, StepError::NonFinite) << describe(s, model);
      EXPECT_GE(s.joint, 0);
    }
    EXPECT_TRUE(same(x, x0));
  }
}

TEST(CheckedStep, RefusesBadInputEuler) { check_refusals<Integrator::SemiImplicitEuler>(); }
TEST(CheckedStep, RefusesBadInputRk4) { check_refusals<Integrator::RungeKutta4>(); }
TEST(CheckedStep, RefusesBadInputImplicit) { check_refusals<Integrator::ImplicitPD>(); }
TEST(CheckedStep, RefusesBadInputBackwardEuler) { check_refusals<Integrator::BackwardEuler>(); }

// No heap allocation in any step, for both scalars, both forward-dynamics methods and both shapes.
template <class M, Integrator I, FdMethod F>
void check_no_allocation(const M& model) {
  const auto servo = busy_servo(model);
  StepWorkspace<M> ws(model);
  auto x = some_state(model);
  const auto tau = some_torque(model);
  using S = typename M::scalar_type;
  Eigen::internal::set_is_malloc_allowed(false);
  const StepStatus a = step<I, F>(model, ws, x, tau, &servo, S(1e-3));
  const StepStatus b = step<I, F>(model, ws, x, tau, S(1e-3));
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(a.ok());
  EXPECT_TRUE(b.ok());
}

template <class M>
void check_no_allocation_all(const M& model) {
  check_no_allocation<M, Integrator::SemiImplicitEuler, FdMethod::MassMatrix>(model);
  check_no_allocation<M, Integrator::SemiImplicitEuler, FdMethod::Articulated>(model);
  check_no_allocation<M, Integrator::RungeKutta4, FdMethod::MassMatrix>(model);
  check_no_allocation<M, Integrator::RungeKutta4, FdMethod::Articulated>(model);
  check_no_allocation<M, Integrator::ImplicitPD, FdMethod::MassMatrix>(model);
  check_no_allocation<M, Integrator::BackwardEuler, FdMethod::MassMatrix>(model);
}

TEST(Step, NoAllocation) {
  check_no_allocation_all(stability::body<double>());
  check_no_allocation_all(stability::body<float>());
  check_no_allocation_all(AnyModel<double>(stability::body<double>().description()));
}

// Float runs the same steps, to float's precision.
TEST(Step, FloatAgreesWithDouble) {
  const auto md = stability::body<double>();
  const auto mf = stability::body<float>();
  const auto sd = busy_servo(md);
  const auto sf = busy_servo(mf);
  auto xd = some_state(md);
  auto xf = some_state(mf);
  const auto td = some_torque(md);
  const auto tf = some_torque(mf);
  StepWorkspace<stability::Body> wd(md);
  StepWorkspace<stability::BodyT<float>> wf(mf);
  for (int k = 0; k < 100; ++k) {
    ASSERT_TRUE(step<Integrator::RungeKutta4>(md, wd, xd, td, &sd, 1e-3).ok());
    ASSERT_TRUE(step<Integrator::RungeKutta4>(mf, wf, xf, tf, &sf, 1e-3f).ok());
  }
  EXPECT_LT((xd.q - xf.q.cast<double>()).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_LT((xd.qd - xf.qd.cast<double>()).cwiseAbs().maxCoeff(), 1e-2);
  // backward Euler too, its fresh first step and the continuing ones
  xd = some_state(md);
  xf = some_state(mf);
  for (int k = 0; k < 100; ++k) {
    ASSERT_TRUE(step<Integrator::BackwardEuler>(md, wd, xd, td, &sd, 1e-3).ok());
    ASSERT_TRUE(step<Integrator::BackwardEuler>(mf, wf, xf, tf, &sf, 1e-3f).ok());
    if (k == 0) {
      EXPECT_LT((xd.q - xf.q.cast<double>()).cwiseAbs().maxCoeff(), 1e-6) << "the fresh step";
      EXPECT_LT((xd.qd - xf.qd.cast<double>()).cwiseAbs().maxCoeff(), 1e-3) << "the fresh step";
    }
  }
  EXPECT_LT((xd.q - xf.q.cast<double>()).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_LT((xd.qd - xf.qd.cast<double>()).cwiseAbs().maxCoeff(), 1e-2);
}

}  // namespace

}  // namespace test_integrators
