// The stiff-and-extreme suite, a tool beside the engine (target humandyn_stability, not installed): the
// cases that make a character explode, run through the checked step and reported row by row. The
// GoogleTest suites (test_integrators, test_stability) assert each row's expectation; `humandyn
// stability` prints the same rows as a table, so the two cannot drift.
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
#include <cstring>
#include <functional>
#include <limits>
#include <random>
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
  auto& b = d.joints[std::size_t(joint)].body;
  const double m = b.mass + mass;
  const Eigen::Vector3d c = (b.mass * b.com + mass * point) / m;
  const auto shift = [](double mm, const Eigen::Vector3d& r) -> Eigen::Matrix3d {
    return mm * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
  };
  b.inertia = b.inertia + shift(b.mass, b.com - c) + shift(mass, point - c);
  b.com = c;
  b.mass = m;
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
inline double condition_number(const Eigen::MatrixXd& M) {
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M, Eigen::EigenvaluesOnly).eigenvalues();
  if (ev.minCoeff() <= 1e-13 * ev.maxCoeff()) return std::numeric_limits<double>::infinity();
  return ev.maxCoeff() / ev.minCoeff();
}

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
inline Row stiff_servo(Integrator integrator, double kp, double h, double duration = servo_duration,
                       Vec* final_q = nullptr) {
  Row row{"stiff servo", "kp=" + sci(kp, 0), integrator_name(integrator)};
  row.dt = h;
  row.error_name = "max |q - q_ref| over the last third (rad)";
  const Body model(hanging_description());
  StepWorkspace<Body> ws(model);
  Data<Body> aux(model);
  PdServo<Body> servo(model);

  // gains and the linear prediction at the reference's start
  const Reference r0(0);
  crba(model, aux, r0.q);
  const Eigen::MatrixXd M = aux.M;
  servo.kp.setConstant(kp);
  const Eigen::VectorXd inertia = effective_inertia(M);
  for (int i = 0; i < model.size(); ++i) servo.kd[i] = PdServo<Body>::critical_damping(kp, inertia[i]);
  const LinearServo lin{M, Eigen::MatrixXd(servo.kp.asDiagonal()), Eigen::MatrixXd(servo.kd.asDiagonal())};
  const double omega = lin.omega_max();
  const double rho = lin.spectral_radius(integrator, h);
  const int steps = int(std::lround(duration / h));
  row.note = "w*h=" + sci(omega * h) + " rho=" + sci(rho, 3);
  row.expect = predict(integrator, rho, omega * h, steps);

  State<Body> x(model);
  x.q = r0.q;
  for (int i = 0; i < model.size(); ++i) x.q[i] += (i % 2 ? -servo_offset : servo_offset);
  x.qd = r0.qd;
  StepLimits<double> limits;
  limits.max_abs_qd = 1e3;
  double worst_late = 0;
  Vec tau;
  row.run_time = timed([&] {
    for (int k = 0; k < steps; ++k) {
      // the reference at the step's start and inverse-dynamics feed-forward along it
      const Reference ref(k * h);
      servo.q_ref = ref.q;
      servo.qd_ref = ref.qd;
      tau = rnea(model, aux, ref.q, ref.qd, ref.qdd);
      const StepStatus s = step_with(integrator, model, ws, x, tau, &servo, h, limits);
      if (!s) {
        row.status = describe(s, model);
        row.t_end = k * h;
        return;
      }
      if (3 * (k + 1) >= 2 * steps)
        worst_late = std::max(worst_late, (x.q - Reference((k + 1) * h).q).cwiseAbs().maxCoeff());
    }
    row.t_end = steps * h;
  });
  row.error = row.status == "ok" ? worst_late : nan;
  row.stable = row.status == "ok" && worst_late < servo_offset;
  if (final_q) *final_q = x.q;
  return row;
}

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
inline AnyBody load_model(Load load) {
  auto d = load == Load::PaperModel ? human_description(paper_parameters()) : body_description();
  if (load == Load::LightExtremities)
    for (int j : {joint_index("l_elbow_pitch"), joint_index("r_elbow_pitch"), joint_index("l_ankle_pitch")})
      set_link_mass(d, j, 1e-4);  // left and right forearm with hand, left foot
  if (load == Load::HeavyHand)    // at the right wrist, the origin of the forearm's frame
    add_point_mass(d, joint_index("r_elbow_pitch"), 50.0, Eigen::Vector3d::Zero());
  return AnyBody(d);
}

// Uniform random state: |q| <= q_max, |q̇| <= qd_max, |q̈| <= qdd_max.
struct RandomState {
  Vec q, qd, qdd;
};
inline std::vector<RandomState> random_states(int count, double q_max, double qd_max, double qdd_max,
                                              unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<RandomState> out(static_cast<std::size_t>(count));
  for (auto& s : out)
    for (int i = 0; i < Body::nj; ++i) {
      s.q[i] = q_max * u(rng);
      s.qd[i] = qd_max * u(rng);
      s.qdd[i] = qdd_max * u(rng);
    }
  return out;
}

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
inline Row light_heavy_round_trip(Load load, FdMethod method) {
  Row row{"light/heavy", load_name(load), fd_name(method)};
  row.error_name = "FD(ID(qdd)) rel. error";
  const AnyBody model = load_model(load);
  const auto states = random_states(200, 3.14159265358979, 10, 100);
  row.note = "cond(M)<=" + sci(max_condition(model, states));
  if (load == Load::PaperModel) row.note += " (M e4-e5-e13 = 0)";
  row.run_time = timed([&] {
    row.error = method == FdMethod::MassMatrix ? round_trip_error<FdMethod::MassMatrix>(model, states)
                                               : round_trip_error<FdMethod::Articulated>(model, states);
  });
  // the paper model has no forward dynamics along its null direction: no promise there
  row.stable = std::isfinite(row.error) && row.error < 1e-6;
  row.status = std::isfinite(row.error) ? "ok" : "non-finite";
  row.expect = load == Load::PaperModel ? Expect::Unknown : Expect::Stable;
  return row;
}

// Standing: holding the home pose with a servo (kp = 5e3, above the load's negative gravity stiffness;
// critical damping from the effective inertia) and the static torques as feed-forward, for 2 s at h = 1/1000, from
// 0.05 rad off. The light links' fast modes defeat explicit steps, and so does the
// paper model's massless mode; the implicit step must hold every body, the singular one included
// (M + h D + h^2 K is positive definite). Stable: every step ok and the final error below 0.05 rad.
inline Row light_heavy_hold(Load load, Integrator integrator) {
  Row row{"light/heavy", load_name(load), integrator_name(integrator)};
  const double h = 1.0 / 1000, kp = 5e3, duration = 2;
  row.dt = h;
  row.error_name = "final max |q - q_ref| (rad)";
  const AnyBody model = load_model(load);
  StepWorkspace<AnyBody> ws(model);
  Data<AnyBody> aux(model);
  PdServo<AnyBody> servo(model);
  const Eigen::VectorXd home = Eigen::VectorXd::Zero(model.size());
  crba(model, aux, home);
  const Eigen::MatrixXd M = aux.M;
  servo.kp.setConstant(kp);
  const Eigen::VectorXd inertia = effective_inertia(M);
  for (int i = 0; i < model.size(); ++i) servo.kd[i] = PdServo<AnyBody>::critical_damping(kp, inertia[i]);
  const LinearServo lin{M, Eigen::MatrixXd(servo.kp.asDiagonal()), Eigen::MatrixXd(servo.kd.asDiagonal())};
  const double omega = lin.omega_max(), rho = lin.spectral_radius(integrator, h);
  row.note = "w*h=" + sci(omega * h) + " rho=" + sci(rho, 3);
  const int steps = int(std::lround(duration / h));
  row.expect = predict(integrator, rho, omega * h, steps);  // a singular M: ω = ρ = infinity, unstable

  State<AnyBody> x(model);
  for (int i = 0; i < model.size(); ++i) x.q[i] = (i % 2 ? -servo_offset : servo_offset);
  const Eigen::VectorXd tau = gravity_torques(model, aux, home);  // feed-forward: the static torques
  StepLimits<double> limits;
  limits.max_abs_qd = 1e3;
  row.run_time = timed([&] {
    for (int k = 0; k < steps; ++k) {
      const StepStatus s = step_with(integrator, model, ws, x, tau, &servo, h, limits);
      if (!s) {
        row.status = describe(s, model);
        row.t_end = k * h;
        return;
      }
    }
    row.t_end = duration;
  });
  row.error = row.status == "ok" ? x.q.cwiseAbs().maxCoeff() : nan;
  row.stable = row.status == "ok" && row.error < servo_offset;
  return row;
}

// ------------------------------------------------------------------------------------------------
// Fast motion

inline constexpr double fast_q = 1e3, fast_qd = 100, fast_qdd = 1e4;

// Forward dynamics against inverse dynamics at |q| <= 1e3 rad, |q̇| <= 100 rad/s, |q̈| <= 1e4 rad/s^2,
// 200 random states, in S.
template <class S>
Row fast_round_trip(FdMethod method) {
  Row row{"fast motion", "round trip |q|<=1e3 |qd|<=100 |qdd|<=1e4", fd_name(method)};
  row.scalar = std::is_same_v<S, float> ? "float" : "double";
  row.error_name = "FD(ID(qdd)) rel. error";
  const auto model = body<S>();
  const auto states = random_states(200, fast_q, fast_qd, fast_qdd, 11);
  row.run_time = timed([&] {
    row.error = method == FdMethod::MassMatrix ? round_trip_error<FdMethod::MassMatrix>(model, states)
                                               : round_trip_error<FdMethod::Articulated>(model, states);
  });
  row.stable = std::isfinite(row.error);
  row.status = row.stable ? "ok" : "non-finite";
  row.expect = Expect::Stable;
  return row;
}

// Passive motion from |q| up to 1e3 rad and |q̇| up to 100 rad/s on every joint (gravity on, no
// torque) for `duration`, in S. The light distal links are whipped to thousands of rad/s within a
// tenth of a second. Energy drift relative to the initial kinetic energy.
template <class S>
Row fast_passive(Integrator integrator, double step, double duration = 0.1) {
  Row row{"fast motion", "passive " + sci(duration, 0) + " s from |qd|<=100", integrator_name(integrator)};
  row.scalar = std::is_same_v<S, float> ? "float" : "double";
  using M = BodyT<S>;
  const M model = body<S>();
  const S h = S(step);
  row.dt = double(h);
  row.error_name = "max |qd| reached (rad/s)";
  StepWorkspace<M> ws(model);
  Data<M> aux(model);
  const auto start = random_states(1, fast_q, fast_qd, 0, 13)[0];
  State<M> x(model);
  x.q = start.q.cast<S>();
  x.qd = start.qd.cast<S>();
  const typename M::JointVector tau = M::JointVector::Zero(model.size());
  const double e0 = double(total_energy(model, aux, x.q, x.qd));
  const double scale = double(kinetic_energy(model, aux, x.q, x.qd));
  double drift = 0, qd_max = 0;
  const int steps = int(std::lround(duration / step));
  row.run_time = timed([&] {
    for (int k = 0; k < steps; ++k) {
      const StepStatus s = step_with(integrator, model, ws, x, tau, nullptr, h, StepLimits<S>{});
      if (!s) {
        row.status = describe(s, model);
        row.t_end = k * double(h);
        return;
      }
      drift = std::max(drift, std::abs(double(total_energy(model, aux, x.q, x.qd)) - e0) / scale);
      qd_max = std::max(qd_max, double(x.qd.cwiseAbs().maxCoeff()));
    }
    row.t_end = steps * double(h);
  });
  row.stable = row.status == "ok";
  row.error = qd_max;
  row.energy_drift = drift;
  if (integrator == Integrator::RungeKutta4 && step <= 1e-4) row.expect = Expect::Stable;
  return row;
}

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
inline SwingResult passive_run(const Body& model, Integrator integrator, double h, double duration, const Vec& q0,
                               double scale, double sample_period = 0) {
  StepWorkspace<Body> ws(model);
  Data<Body> aux(model);
  SwingResult r{{}, 0, 0, 0, 0, 0, State<Body>(model), 0, {}};
  auto& x = r.final_state;
  x.q = q0;
  const Vec tau = Vec::Zero();
  const double e0 = total_energy(model, aux, x.q, x.qd);
  const long steps = std::lround(duration / h);
  const long every = sample_period > 0 ? std::lround(sample_period / h) : 0;
  if (every > 0) r.samples.push_back(x.q);
  r.run_time = timed([&] {
    for (long k = 0; k < steps; ++k) {
      r.status = step_with(integrator, model, ws, x, tau, nullptr, h, StepLimits<double>{});
      if (!r.status) {
        r.t_end = double(k) * h;
        return;
      }
      if (every > 0 && (k + 1) % every == 0) r.samples.push_back(x.q);
      const double e = total_energy(model, aux, x.q, x.qd);
      r.drift = std::max(r.drift, std::abs(e - e0) / scale);
      r.rise = std::max(r.rise, (e - e0) / scale);
      r.qd_max = std::max(r.qd_max, x.qd.cwiseAbs().maxCoeff());
    }
    r.t_end = double(steps) * h;
  });
  if (r.t_end > 0) r.dissipation = (e0 - total_energy(model, aux, x.q, x.qd)) / r.t_end;
  return r;
}

inline constexpr double swing_duration = 60;  // s

// The goal of backward Euler on the passive body: no run-away, and the energy never above its start by
// more than this, relative to the case's energy scale.
inline constexpr double energy_rise_bound = 1e-6;

// The columns a swing or flail row takes from its run; a backward-Euler row is stable only within the goal.
inline void fill_swing_row(Row& row, const Body& model, Integrator integrator, const SwingResult& r) {
  row.status = r.status ? "ok" : describe(r.status, model);
  row.stable = bool(r.status);
  row.t_end = r.t_end;
  row.error = r.qd_max;
  row.energy_drift = r.drift;
  row.energy_rise = r.rise;
  row.dissipation = r.dissipation;
  row.run_time = r.run_time;
  row.note = "rise=" + sci(r.rise) + " dissipation=" + sci(r.dissipation, 2) + " W";
  if (integrator == Integrator::BackwardEuler) {
    row.stable = row.stable && r.rise <= energy_rise_bound;
    row.expect = Expect::Stable;
  }
}

// The energy of the hanging swing above its rest: E(0) - V(home).
inline double swing_energy_scale(const Body& model) {
  Data<Body> aux(model);
  return potential_energy(model, aux, bent_pose()) - potential_energy(model, aux, Vec::Zero());
}

// The body hanging from the stance foot, released from bent_pose() at rest, 60 s.
inline Row passive_swing(Integrator integrator, double h, double duration = swing_duration) {
  Row row{"passive swing", "hanging, bent 0.3 rad, " + std::to_string(int(duration)) + " s",
          integrator_name(integrator)};
  row.dt = h;
  row.error_name = "max |qd| reached (rad/s)";
  const Body model(hanging_description());
  const SwingResult r = passive_run(model, integrator, h, duration, bent_pose(), swing_energy_scale(model));
  fill_swing_row(row, model, integrator, r);
  if (integrator == Integrator::RungeKutta4 && h <= 1.0 / 1000) row.expect = Expect::Stable;
  return row;
}

// The upright body released 0.01 rad off the home pose, falling around the stance foot for `duration`
// seconds. The drift is relative to m g z_com: total mass, g, and the height of the centre of mass.
inline Row flail(Integrator integrator, double h, double duration = 10) {
  Row row{"flail", "upright, released, " + std::to_string(int(duration)) + " s", integrator_name(integrator)};
  row.dt = h;
  row.error_name = "max |qd| reached (rad/s)";
  const Body model = body<double>();
  Data<Body> aux(model);
  forward_kinematics(model, aux, Vec::Zero());
  const double scale = model.total_mass() * 9.81 * aux.com.z();
  const SwingResult r = passive_run(model, integrator, h, duration, bent_pose(0.01), scale);
  fill_swing_row(row, model, integrator, r);
  return row;
}

// ------------------------------------------------------------------------------------------------
// Convergence order on a smooth motion: the hanging body released from bent_pose(0.1) for 0.5 s (later
// the light foot is whipped past 15 rad/s and the study leaves the asymptotic range), against
// RK4 at h = 1/8000; the error is the largest |q - q_ref| over samples every 0.01 s (a single instant
// can fall where the error changes sign). Halving h should cut it 2x (Euler, implicit) or 16x (RK4).

inline constexpr double convergence_duration = 0.5, convergence_sample = 0.01;

inline const std::vector<Vec>& convergence_reference() {
  static const std::vector<Vec> ref = [] {
    const Body model(hanging_description());
    return passive_run(model, Integrator::RungeKutta4, 1.0 / 8000, convergence_duration, bent_pose(0.1), 1,
                       convergence_sample)
        .samples;
  }();
  return ref;
}

// The trajectory error max_t |q(t) - q_ref(t)| at step h.
inline double convergence_error(Integrator integrator, double h) {
  const Body model(hanging_description());
  const auto r = passive_run(model, integrator, h, convergence_duration, bent_pose(0.1), 1, convergence_sample);
  const auto& ref = convergence_reference();
  if (!r.status || r.samples.size() != ref.size()) return std::numeric_limits<double>::infinity();
  double worst = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) worst = std::max(worst, (r.samples[k] - ref[k]).cwiseAbs().maxCoeff());
  return worst;
}

// The step sizes of the convergence study, coarse to fine (each half the previous).
inline std::array<double, 3> convergence_steps(Integrator integrator) {
  if (integrator == Integrator::RungeKutta4) return {1.0 / 100, 1.0 / 200, 1.0 / 400};
  return {1.0 / 500, 1.0 / 1000, 1.0 / 2000};
}

// One row per step size; the note gives the error ratio to the previous (coarser) step.
inline std::vector<Row> convergence(Integrator integrator) {
  std::vector<Row> rows;
  double previous = nan;
  for (double h : convergence_steps(integrator)) {
    Row row{"convergence", "hanging, bent 0.1 rad, 0.5 s", integrator_name(integrator)};
    row.dt = h;
    row.error_name = "max over 0.5 s of |q - q_ref| (rad)";
    row.run_time = timed([&] { row.error = convergence_error(integrator, h); });
    row.stable = std::isfinite(row.error);
    row.status = row.stable ? "ok" : "diverged";
    row.t_end = convergence_duration;
    if (std::isfinite(previous)) row.note = "ratio=" + sci(previous / row.error, 2);
    row.expect = Expect::Stable;
    previous = row.error;
    rows.push_back(row);
  }
  return rows;
}

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
inline Row bad_state(Integrator integrator, const BadInput& bad) {
  Row row{"bad state", bad.what, integrator_name(integrator)};
  row.dt = 1.0 / 240;
  const Body model = body<double>();
  StepWorkspace<Body> ws(model);
  State<Body> x(model);
  x.q = bent_pose();
  x.qd.setConstant(0.5);
  Vec tau = Vec::Constant(1.0);
  if (bad.quantity == Quantity::Angle) x.q[bad_joint] = bad.value;
  if (bad.quantity == Quantity::Velocity) x.qd[bad_joint] = bad.value;
  if (bad.quantity == Quantity::Torque) tau[bad_joint] = bad.value;
  const State<Body> before = x;
  StepStatus s;
  row.run_time = timed([&] { s = step_with(integrator, model, ws, x, tau, nullptr, row.dt, StepLimits<double>{}); });
  const std::size_t bytes = sizeof(double) * std::size_t(model.size());
  const bool untouched =
      std::memcmp(before.q.data(), x.q.data(), bytes) == 0 && std::memcmp(before.qd.data(), x.qd.data(), bytes) == 0;
  row.status = describe(s, model);
  row.stable = s.error == StepError::BadInput && s.quantity == bad.quantity && s.joint == bad_joint && untouched;
  row.error_name = "state untouched";
  row.error = untouched ? 0 : 1;
  row.expect = Expect::Stable;
  return row;
}

// ------------------------------------------------------------------------------------------------
// The whole suite. `full` adds the finer and coarser sweeps the tests leave out.

struct Options {
  bool full = true;
};

inline void run_suite(const Options& options, const std::function<void(const Row&)>& emit) {
  for (double kp : servo_kp)
    for (double h : servo_dt)
      for (Integrator m : integrators) emit(stiff_servo(m, kp, h));

  for (Load load : {Load::Nominal, Load::LightExtremities, Load::HeavyHand, Load::PaperModel}) {
    for (FdMethod f : {FdMethod::MassMatrix, FdMethod::Articulated}) emit(light_heavy_round_trip(load, f));
    for (Integrator m : integrators) emit(light_heavy_hold(load, m));
  }

  for (FdMethod f : {FdMethod::MassMatrix, FdMethod::Articulated}) {
    emit(fast_round_trip<double>(f));
    emit(fast_round_trip<float>(f));
  }
  for (double h : {1e-3, 1e-4})
    for (Integrator m : integrators) {
      emit(fast_passive<double>(m, h));
      emit(fast_passive<float>(m, h));
    }

  const std::vector<double> rk4_dt = options.full
                                         ? std::vector<double>{1.0 / 125, 1.0 / 250, 1.0 / 500, 1.0 / 1000, 1.0 / 2000}
                                         : std::vector<double>{1.0 / 500, 1.0 / 1000};
  const std::vector<double> euler_dt = options.full ? std::vector<double>{1.0 / 30, 1.0 / 60, 1.0 / 240, 1.0 / 1000}
                                                    : std::vector<double>{1.0 / 60, 1.0 / 1000};
  for (double h : rk4_dt) emit(passive_swing(Integrator::RungeKutta4, h));
  for (double h : euler_dt) {
    emit(passive_swing(Integrator::SemiImplicitEuler, h));
    emit(passive_swing(Integrator::ImplicitPD, h));
  }

  for (double h : {1.0 / 1000, 1.0 / 240})
    for (Integrator m : integrators)
      if (m != Integrator::BackwardEuler) emit(flail(m, h));
  // backward Euler's goal: the 60-s hang and the 10-s flail at every step a game uses
  for (double h : servo_dt) {
    emit(passive_swing(Integrator::BackwardEuler, h));
    emit(flail(Integrator::BackwardEuler, h));
  }

  for (Integrator m : integrators)
    for (const Row& r : convergence(m)) emit(r);

  for (const BadInput& bad : bad_inputs)
    for (Integrator m : integrators) emit(bad_state(m, bad));
}

}  // namespace humandyn::stability
