// The stiff-and-extreme suite, a tool beside the engine (target humandyn_stability, not installed): the
// cases that make a character explode, run through the checked step and reported row by row. The
// GoogleTest suites (test_integrators, test_stability) assert each row's expectation; `humandyn
// stability` prints the same rows as a table, so the two cannot drift. The rows are compiled once, in
// stability_suite.cpp; what stays here is what callers instantiate for their own models.
//
// Not for the real-time path: it builds models, allocates rows and strings, and times itself.
//   stiff servos        kp 1e2..1e6 N m/rad, critically damped, h 1/1000..1/30 s, tracking a moving reference
//   light and heavy     hand-bearing forearms and foot at 1e-4 kg; a 50 kg load in the right hand
//   fast motion         |q̇| up to 100 rad/s, |q̈| up to 1e4 rad/s^2, |q| up to 1e3 rad, float and double
//   passive swing       hanging from the stance foot (gravity reversed), bent 0.3 rad, 60 s, no torque
//   flail               upright, released, falling around the stance foot (chaotic)
//                       (backward Euler: both at h 1/1000..1/30 s, no run-away, energy never above its start)
//   convergence         order of each integrator on a smooth 0.5 s swing
//   bad state           NaN or Inf in q, q̇ or tau
#pragma once

#include "humandyn/algorithm/crba.hpp"
#include "humandyn/algorithm/energy.hpp"
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/builders.hpp"
#include "humandyn/integrators.hpp"

#include <Eigen/Eigenvalues>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace humandyn::stability {

inline constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// Whether theory predicts that a case runs stably.
enum class Expect { Stable, Unstable, Unknown };

// One row of the suite's table.
struct Row {
  Row(std::string group_, std::string name_, std::string method_)
      : group(std::move(group_)), name(std::move(name_)), method(std::move(method_)) {}
  std::string group;   // "stiff servo", "light/heavy", "fast motion", "passive swing", ...
  std::string name;    // the case within the group, e.g. "kp=1e+04"
  std::string method;  // integrator (euler, rk4, implicit) or forward-dynamics method
  std::string scalar = "double";
  double dt = nan;            // time step (s); NaN when no stepping is involved
  bool stable = false;        // ran to the end with every step ok (and, for servos, converged)
  std::string status = "ok";  // "ok" or the step error, naming the joint
  double t_end = nan;         // simulated time reached (s)
  std::string error_name;     // what `error` measures
  double error = nan;
  double energy_drift = nan;  // max |E(t) - E(0)| / energy scale of the case (see each case)
  double energy_rise = nan;   // max (E(t) - E(0)) / the same scale: how far the energy ever rose (swing, flail)
  double dissipation = nan;   // (E(0) - E(end)) / t_end: the energy lost per simulated second (W; swing, flail)
  double run_time = 0;        // wall-clock seconds
  std::string note;           // ω h, condition number, ratios, ...
  Expect expect = Expect::Unknown;
};

// ------------------------------------------------------------------------------------------------
// Models and helpers

// The suite's body: the default seed human, whose pelvis (link 4) carries the lower trunk. The paper
// model keeps Table 1's massless pelvis: there the right hip pitch, waist pitch and left hip pitch
// (joints 4, 5, 13) turn about one line around a massless link, M (e4 - e5 - e13) = 0, forward dynamics
// is undefined in that direction and a spring on it has an infinite frequency. The "paper model" rows
// show that body.
template <class S>
using BodyT = HumanModel<S>;
using Body = BodyT<double>;
using Vec = Body::JointVector;

inline ModelDescription<double> body_description() { return human_description(default_parameters()); }

template <class S = double>
BodyT<S> body() {
  return BodyT<S>(body_description().template cast<S>());
}

// The default body with gravity along +z: hanging from the stance foot, the home pose is a stable
// equilibrium of the swing.
inline ModelDescription<double> hanging_description() {
  auto d = body_description();
  d.gravity = Eigen::Vector3d(0, 0, 9.81);
  return d;
}

// The index of the seed joint called `name` (a compile-time lookup in the body table).
consteval int joint_index(std::string_view name) { return seed_body.index(name); }

// A link's mass and inertia scaled to `mass` (the centre of mass stays).
inline void set_link_mass(ModelDescription<double>& d, int joint, double mass) {
  auto& b = d.joints[std::size_t(joint)].body;
  b.inertia *= mass / b.mass;
  b.mass = mass;
}

// A point mass added to a link at `point` (link frame).
inline void add_point_mass(ModelDescription<double>& d, int joint, double mass, const Eigen::Vector3d& point) {
  d.joints[std::size_t(joint)].body += RigidBodyInertia<double>::point_mass(mass, point);
}

// The bent pose of the swing: every joint by up to 0.3 rad, signs and sizes varied.
inline Vec bent_pose(double amplitude = 0.3) {
  Vec q;
  for (int i = 0; i < Body::nj; ++i) q[i] = amplitude * std::sin(1.7 * (i + 1) + 0.4);
  return q;
}

// Wall-clock seconds of f().
template <class F>
double timed(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Runs `integrator` (a run-time choice, dispatched to the compile-time step) once.
template <FdMethod method = FdMethod::MassMatrix, class M>
StepStatus step_with(Integrator integrator, const M& model, StepWorkspace<M>& ws, State<M>& x,
                     const typename M::JointVector& tau, const PdServo<std::type_identity_t<M>>* servo,
                     typename M::scalar_type h, const StepLimits<typename M::scalar_type>& limits) noexcept {
  switch (integrator) {
    case Integrator::SemiImplicitEuler:
      return step<Integrator::SemiImplicitEuler, method>(model, ws, x, tau, servo, h, limits);
    case Integrator::RungeKutta4:
      return step<Integrator::RungeKutta4, method>(model, ws, x, tau, servo, h, limits);
    case Integrator::ImplicitPD:
      return step<Integrator::ImplicitPD, method>(model, ws, x, tau, servo, h, limits);
    case Integrator::BackwardEuler:
      return step<Integrator::BackwardEuler>(model, ws, x, tau, servo, h, limits);
  }
  return {StepError::BadTimeStep, Quantity::None, -1};
}

inline constexpr std::array<Integrator, 4> integrators{Integrator::SemiImplicitEuler, Integrator::RungeKutta4,
                                                       Integrator::ImplicitPD, Integrator::BackwardEuler};

// Whether an integrator treats the servo implicitly (ImplicitPD, BackwardEuler).
inline constexpr bool implicit(Integrator m) { return m == Integrator::ImplicitPD || m == Integrator::BackwardEuler; }

inline std::string sci(double v, int digits = 1) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*e", digits, v);
  return buf;
}

// ------------------------------------------------------------------------------------------------
// Stiff servos

inline constexpr std::array<double, 5> servo_kp{1e2, 1e3, 1e4, 1e5, 1e6};
inline constexpr std::array<double, 4> servo_dt{1.0 / 1000, 1.0 / 240, 1.0 / 60, 1.0 / 30};
inline constexpr double servo_duration = 3.0;   // s
inline constexpr double servo_offset = 0.05;    // rad: the start's distance from the reference
inline constexpr double servo_amplitude = 0.2;  // rad: the reference's swing about the home pose
inline constexpr double servo_frequency = 0.5;  // Hz

// The reference motion q̄(t) = A sin(2 pi f t + phi_i) about the home pose, and its derivatives.
struct Reference {
  Vec q, qd, qdd;
  explicit Reference(double t) {
    const double w = 2 * 3.14159265358979323846 * servo_frequency;
    for (int i = 0; i < Body::nj; ++i) {
      const double phase = w * t + 0.9 * i;
      q[i] = servo_amplitude * std::sin(phase);
      qd[i] = servo_amplitude * w * std::cos(phase);
      qdd[i] = -servo_amplitude * w * w * std::sin(phase);
    }
  }
};

// Condition number of a symmetric positive semidefinite matrix; infinity when it is singular to
// rounding (smallest eigenvalue below 1e-13 of the largest).
double condition_number(const Eigen::MatrixXd& M);

// The linearised servo about a pose: M x'' = -K x - D x'. Its fastest mode has ω = sqrt(λ_max(M⁻¹K));
// one step of each integrator maps (x, x') by a matrix whose spectral radius ρ decides stability.
// A singular M (a massless mode) has an infinite ω: no explicit step is stable on it.
struct LinearServo {
  Eigen::MatrixXd M, K, D;
  bool singular() const { return !std::isfinite(condition_number(M)); }
  double omega_max() const {
    if (singular()) return std::numeric_limits<double>::infinity();
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, M, Eigen::EigenvaluesOnly);
    return std::sqrt(es.eigenvalues().maxCoeff());
  }
  // Spectral radius of the one-step map of `integrator` with step h.
  double spectral_radius(Integrator integrator, double h) const {
    if (!implicit(integrator) && singular()) return std::numeric_limits<double>::infinity();
    const int n = int(M.rows());
    const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
    const Eigen::Index n2 = 2 * Eigen::Index(n);
    Eigen::MatrixXd G(n2, n2);  // (x, v) -> (x', v')
    if (integrator == Integrator::RungeKutta4) {
      Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n2, n2);
      L.topRightCorner(n, n) = I;
      L.bottomLeftCorner(n, n) = -M.ldlt().solve(K);
      L.bottomRightCorner(n, n) = -M.ldlt().solve(D);
      const Eigen::MatrixXd A = h * L;
      const Eigen::MatrixXd I2 = Eigen::MatrixXd::Identity(n2, n2);
      G = I2 + A * (I2 + A / 2 * (I2 + A / 3 * (I2 + A / 4)));
    } else {
      // v' = v + h a, x' = x + h v'; a = Ax x + Av v
      Eigen::MatrixXd Ax, Av;
      if (integrator == Integrator::SemiImplicitEuler) {
        Ax = -M.ldlt().solve(K);
        Av = -M.ldlt().solve(D);
      } else {  // both implicit steps on the linear law: (M + h D + h^2 K) a = -K (x + h v) - D v
        const Eigen::MatrixXd S = M + h * D + h * h * K;
        Ax = -S.ldlt().solve(K);
        Av = -S.ldlt().solve(h * K + D);
      }
      G.topLeftCorner(n, n) = I + h * h * Ax;
      G.topRightCorner(n, n) = h * I + h * h * Av;
      G.bottomLeftCorner(n, n) = h * Ax;
      G.bottomRightCorner(n, n) = I + h * Av;
    }
    return G.eigenvalues().cwiseAbs().maxCoeff();
  }
};

// What the linearised servo predicts: the implicit steps always hold; an explicit one holds where ρ <= 1
// with ω h <= 1 (well inside the limits, 2 for Euler and 2.8 for RK4 without damping, so that the
// nonlinear terms cannot tip it), and must blow up where ρ^steps >= 1e6. In between: no prediction.
inline Expect predict(Integrator integrator, double rho, double omega_h, int steps) {
  if (implicit(integrator)) return Expect::Stable;
  if (rho <= 1 && omega_h <= 1) return Expect::Stable;
  if (rho > 1 && steps * std::log(rho) >= std::log(1e6)) return Expect::Unstable;
  return Expect::Unknown;
}

// A servo on every joint with stiffness kp and critical damping kd_i = 2 sqrt(kp / (M^-1)_ii) from the
// mass matrix at the reference's start (servo.hpp's effective_inertia), tracking Reference(t) with inverse-dynamics
// feed-forward, from a start 0.05 rad off the reference. The body hangs from the stance foot (gravity reversed), so
// that the motion it tracks is stable for every kp: standing, gravity's negative stiffness about the ankle (m g z_com,
// about 650 N m/rad) would beat kp = 1e2 however the servo were integrated. Stable: every step ok and the tracking
// error over the last third of the run below the starting offset.
Row stiff_servo(Integrator integrator, double kp, double h, double duration = servo_duration, Vec* final_q = nullptr);

// ------------------------------------------------------------------------------------------------
// Light and heavy bodies

enum class Load { Nominal, LightExtremities, HeavyHand, PaperModel };
inline const char* load_name(Load l) {
  switch (l) {
    case Load::Nominal:
      return "nominal";
    case Load::LightExtremities:
      return "forearms+hands and foot 1e-4 kg";
    case Load::HeavyHand:
      return "50 kg in the right hand";
    case Load::PaperModel:
      return "paper model (massless pelvis)";
  }
  return "?";
}

// The suite's body with the load, or the paper model; a runtime shape, as an imported model.
using AnyBody = AnyModel<double>;
AnyBody load_model(Load load);

// Uniform random state: |q| <= q_max, |q̇| <= qd_max, |q̈| <= qdd_max.
struct RandomState {
  Vec q, qd, qdd;
};
std::vector<RandomState> random_states(int count, double q_max, double qd_max, double qdd_max, unsigned seed = 7);

// Largest condition number of M over the home pose and `states`.
template <class M>
double max_condition(const M& model, const std::vector<RandomState>& states) {
  Data<M> data(model);
  double worst = 0;
  const auto cond = [&](const Vec& q) {
    const typename M::JointVector qm = q.cast<typename M::scalar_type>();
    crba(model, data, qm);
    worst = std::max(worst, condition_number(data.M.template cast<double>()));
  };
  cond(Vec::Zero());
  for (const auto& s : states) cond(s.q);
  return worst;
}

// Round trip q̈ -> tau = ID(q, q̇, q̈) -> FD(q, q̇, tau) in scalar S: the largest relative error
// |FD - q̈| / max(1, |q̈|) (infinity norms) over `states`.
template <FdMethod method, class M>
double round_trip_error(const M& model, const std::vector<RandomState>& states) {
  using S = typename M::scalar_type;
  Data<M> id(model), fd(model);
  double worst = 0;
  for (const auto& s : states) {
    const typename M::JointVector q = s.q.cast<S>(), qd = s.qd.cast<S>(), qdd = s.qdd.cast<S>();
    const auto tau = rnea(model, id, q, qd, qdd);
    const auto& back = forward_dynamics<method, Terms::Full>(model, fd, q, qd, tau);
    const double scale = std::max(1.0, double(qdd.cwiseAbs().maxCoeff()));
    const double err = double((back - qdd).cwiseAbs().maxCoeff()) / scale;
    worst = std::isfinite(err) ? std::max(worst, err) : std::numeric_limits<double>::infinity();
    if (!std::isfinite(worst)) break;
  }
  return worst;
}

inline const char* fd_name(FdMethod m) { return m == FdMethod::MassMatrix ? "fd ldlt" : "fd aba"; }

// Forward dynamics against inverse dynamics on 200 random states (|q| <= pi, |q̇| <= 10, |q̈| <= 100),
// both methods; the note gives the worst condition number of M.
Row light_heavy_round_trip(Load load, FdMethod method);

// Standing: holding the home pose with a servo (kp = 5e3, above the load's negative gravity stiffness;
// critical damping from the effective inertia) and the static torques as feed-forward, for 2 s at h = 1/1000, from
// 0.05 rad off. The light links' fast modes defeat explicit steps, and so does the
// paper model's massless mode; the implicit step must hold every body, the singular one included
// (M + h D + h^2 K is positive definite). Stable: every step ok and the final error below 0.05 rad.
Row light_heavy_hold(Load load, Integrator integrator);

// ------------------------------------------------------------------------------------------------
// Fast motion

inline constexpr double fast_q = 1e3, fast_qd = 100, fast_qdd = 1e4;

// Forward dynamics against inverse dynamics at |q| <= 1e3 rad, |q̇| <= 100 rad/s, |q̈| <= 1e4 rad/s^2,
// 200 random states, in S.
template <class S>
Row fast_round_trip(FdMethod method);
extern template Row fast_round_trip<float>(FdMethod);
extern template Row fast_round_trip<double>(FdMethod);

// Passive motion from |q| up to 1e3 rad and |q̇| up to 100 rad/s on every joint (gravity on, no
// torque) for `duration`, in S. The light distal links are whipped to thousands of rad/s within a
// tenth of a second. Energy drift relative to the initial kinetic energy.
template <class S>
Row fast_passive(Integrator integrator, double step, double duration = 0.1);
extern template Row fast_passive<float>(Integrator, double, double);
extern template Row fast_passive<double>(Integrator, double, double);

// ------------------------------------------------------------------------------------------------
// Long passive swing and the flail

struct SwingResult {
  StepStatus status;
  double t_end = 0;
  double drift = 0;        // max |E(t) - E(0)| / energy scale
  double rise = 0;         // max (E(t) - E(0)) / energy scale
  double dissipation = 0;  // (E(0) - E(end)) / t_end (W)
  double qd_max = 0;       // largest |q̇| reached
  State<Body> final_state;
  double run_time = 0;
  std::vector<Vec> samples;  // q every `sample_period` seconds (when asked for), t = 0 first
};

// Runs the passive body (no torque, no damping) from rest at q0 for `duration`, checking the energy
// every step. `scale` divides the drift. With sample_period > 0 (a whole number of steps), q is kept
// every sample_period seconds.
SwingResult passive_run(const Body& model, Integrator integrator, double h, double duration, const Vec& q0,
                        double scale, double sample_period = 0);

inline constexpr double swing_duration = 60;  // s

// The goal of backward Euler on the passive body: no run-away, and the energy never above its start by
// more than this, relative to the case's energy scale.
inline constexpr double energy_rise_bound = 1e-6;

// The columns a swing or flail row takes from its run; a backward-Euler row is stable only within the goal.
void fill_swing_row(Row& row, const Body& model, Integrator integrator, const SwingResult& r);

// The energy of the hanging swing above its rest: E(0) - V(home).
double swing_energy_scale(const Body& model);

// The body hanging from the stance foot, released from bent_pose() at rest, 60 s.
Row passive_swing(Integrator integrator, double h, double duration = swing_duration);

// The upright body released 0.01 rad off the home pose, falling around the stance foot for `duration`
// seconds. The drift is relative to m g z_com: total mass, g, and the height of the centre of mass.
Row flail(Integrator integrator, double h, double duration = 10);

// ------------------------------------------------------------------------------------------------
// Convergence order on a smooth motion: the hanging body released from bent_pose(0.1) for 0.5 s (later
// the light foot is whipped past 15 rad/s and the study leaves the asymptotic range), against
// RK4 at h = 1/8000; the error is the largest |q - q_ref| over samples every 0.01 s (a single instant
// can fall where the error changes sign). Halving h should cut it 2x (Euler, implicit) or 16x (RK4).

inline constexpr double convergence_duration = 0.5, convergence_sample = 0.01;

const std::vector<Vec>& convergence_reference();

// The trajectory error max_t |q(t) - q_ref(t)| at step h.
double convergence_error(Integrator integrator, double h);

// The step sizes of the convergence study, coarse to fine (each half the previous).
std::array<double, 3> convergence_steps(Integrator integrator);

// One row per step size; the note gives the error ratio to the previous (coarser) step.
std::vector<Row> convergence(Integrator integrator);

// ------------------------------------------------------------------------------------------------
// Bad state: a NaN or Inf in q, q̇ or tau must come back as an error naming the joint, the state untouched.

struct BadInput {
  const char* what;
  Quantity quantity;
  double value;
};
inline constexpr std::array<BadInput, 6> bad_inputs{
    {{"NaN in q", Quantity::Angle, std::numeric_limits<double>::quiet_NaN()},
     {"Inf in q", Quantity::Angle, std::numeric_limits<double>::infinity()},
     {"NaN in qd", Quantity::Velocity, std::numeric_limits<double>::quiet_NaN()},
     {"-Inf in qd", Quantity::Velocity, -std::numeric_limits<double>::infinity()},
     {"NaN in tau", Quantity::Torque, std::numeric_limits<double>::quiet_NaN()},
     {"Inf in tau", Quantity::Torque, std::numeric_limits<double>::infinity()}}};
inline constexpr int bad_joint = joint_index("r_shoulder_roll");

// Steps once with `bad` planted at the right shoulder roll; stable means: refused with the right status and joint,
// and nothing overwritten (NaN compared bit-for-bit).
Row bad_state(Integrator integrator, const BadInput& bad);

// ------------------------------------------------------------------------------------------------
// The whole suite. `full` adds the finer and coarser sweeps the tests leave out.

struct Options {
  bool full = true;
};

void run_suite(const Options& options, const std::function<void(const Row&)>& emit);

}  // namespace humandyn::stability
