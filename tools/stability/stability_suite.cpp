// The stiff-and-extreme suite's rows (stability_suite.hpp), compiled once for the command line and the
// test suites that assert them.
#include "stability_suite.hpp"

#include <cstring>
#include <random>

namespace humandyn::stability {

double condition_number(const Eigen::MatrixXd& M) {
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M, Eigen::EigenvaluesOnly).eigenvalues();
  if (ev.minCoeff() <= 1e-13 * ev.maxCoeff()) return std::numeric_limits<double>::infinity();
  return ev.maxCoeff() / ev.minCoeff();
}

Row stiff_servo(Integrator integrator, double kp, double h, double duration, Vec* final_q) {
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

AnyBody load_model(Load load) {
  auto d = load == Load::PaperModel ? human_description(paper_parameters()) : body_description();
  if (load == Load::LightExtremities)
    for (int j : {joint_index("l_elbow_pitch"), joint_index("r_elbow_pitch"), joint_index("l_ankle_pitch")})
      set_link_mass(d, j, 1e-4);  // left and right forearm with hand, left foot
  if (load == Load::HeavyHand)    // at the right wrist, the origin of the forearm's frame
    add_point_mass(d, joint_index("r_elbow_pitch"), 50.0, Eigen::Vector3d::Zero());
  return AnyBody(d);
}

std::vector<RandomState> random_states(int count, double q_max, double qd_max, double qdd_max, unsigned seed) {
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

Row light_heavy_round_trip(Load load, FdMethod method) {
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

Row light_heavy_hold(Load load, Integrator integrator) {
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

SwingResult passive_run(const Body& model, Integrator integrator, double h, double duration, const Vec& q0,
                        double scale, double sample_period) {
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

void fill_swing_row(Row& row, const Body& model, Integrator integrator, const SwingResult& r) {
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

double swing_energy_scale(const Body& model) {
  Data<Body> aux(model);
  return potential_energy(model, aux, bent_pose()) - potential_energy(model, aux, Vec::Zero());
}

Row passive_swing(Integrator integrator, double h, double duration) {
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

Row flail(Integrator integrator, double h, double duration) {
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

const std::vector<Vec>& convergence_reference() {
  static const std::vector<Vec> ref = [] {
    const Body model(hanging_description());
    return passive_run(model, Integrator::RungeKutta4, 1.0 / 8000, convergence_duration, bent_pose(0.1), 1,
                       convergence_sample)
        .samples;
  }();
  return ref;
}

double convergence_error(Integrator integrator, double h) {
  const Body model(hanging_description());
  const auto r = passive_run(model, integrator, h, convergence_duration, bent_pose(0.1), 1, convergence_sample);
  const auto& ref = convergence_reference();
  if (!r.status || r.samples.size() != ref.size()) return std::numeric_limits<double>::infinity();
  double worst = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) worst = std::max(worst, (r.samples[k] - ref[k]).cwiseAbs().maxCoeff());
  return worst;
}

std::array<double, 3> convergence_steps(Integrator integrator) {
  if (integrator == Integrator::RungeKutta4) return {1.0 / 100, 1.0 / 200, 1.0 / 400};
  return {1.0 / 500, 1.0 / 1000, 1.0 / 2000};
}

std::vector<Row> convergence(Integrator integrator) {
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

Row bad_state(Integrator integrator, const BadInput& bad) {
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

void run_suite(const Options& options, const std::function<void(const Row&)>& emit) {
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

template Row fast_round_trip<float>(FdMethod);
template Row fast_round_trip<double>(FdMethod);

template <class S>
Row fast_passive(Integrator integrator, double step, double duration) {
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

template Row fast_passive<float>(Integrator, double, double);
template Row fast_passive<double>(Integrator, double, double);

}  // namespace humandyn::stability
