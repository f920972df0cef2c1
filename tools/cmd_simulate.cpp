// humandyn simulate: the body stepped through time under gravity, passive or tracking a motion with
// PD servos, or in the floating form through the air; writes the trajectory and reports the energy drift.
#include "cli/base_columns.hpp"
#include "cli/commands.hpp"
#include "cli/csv.hpp"
#include "cli/joint_table.hpp"
#include "cli/model_source.hpp"
#include "cli/print.hpp"
#include "cli/scene_option.hpp"
#include "cli/stance_switching.hpp"
#include "cli/states_command.hpp"
#include "cli/wrench_option.hpp"
#include "humandyn/algorithm/energy.hpp"
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/floating.hpp"
#include "humandyn/integrators.hpp"
#include "humandyn/poses.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace humandyn::cli {

namespace {

using SimModel = AnyModel<double>;

// A time step: seconds as a number or a fraction such as 1/240.
double parse_step(const std::string& text) {
  const std::size_t slash = text.find('/');
  std::string why;
  const auto x = read_number(text.substr(0, slash), &why);
  const auto d =
      !x || slash == std::string::npos ? std::optional<double>(1.0) : read_number(text.substr(slash + 1), &why);
  if (!x || !d || !(*d > 0) || !std::isfinite(*x / *d) || !(*x / *d > 0))
    throw UsageError("option --dt needs a positive number of seconds or 1/N, got '" + shown(text) + "'" +
                     (why.empty() ? "" : ": " + why));
  return *x / *d;
}

struct SimulateOptions {
  ModelOptions model;
  Integrator integrator = Integrator::RungeKutta4;
  bool aba = false;       // --fd aba, else ldlt
  bool fd_given = false;  // --fd given (it is the explicit integrators')
  double h = 1e-3, duration = 1.0;
  std::string track;  // "" for none
  double kp = 1000.0;
  std::optional<double> kd;  // default: critical damping
  SceneOptions scene;
  std::vector<std::string> wrenches;
  std::string start;  // --floating: the starting state ("" for rest in the home pose)
  std::string out;    // "" for none
};

// A reference motion read from CSV: times, angles and velocities per row.
struct Motion {
  std::vector<double> t;
  std::vector<Eigen::VectorXd> q, qd;

  // The reference at time `time`: linear between rows (the rows' own values at their times), held at rest
  // outside them: the first row's pose before it, the last row's after it, each with no velocity.
  void at(double time, Eigen::VectorXd& q_out, Eigen::VectorXd& qd_out) const {
    if (time < t.front() || time > t.back()) {
      q_out = time < t.front() ? q.front() : q.back();
      qd_out.setZero(q_out.size());
      return;
    }
    const auto k = std::min(std::size_t(std::upper_bound(t.begin(), t.end(), time) - t.begin()), t.size() - 1);
    if (k == 0 || time == t[k]) {  // at the last row, or at a track's only one (a pose: at rest)
      q_out = q[k];
      qd_out = t.size() > 1 ? qd[k] : Eigen::VectorXd::Zero(q_out.size());
      return;
    }
    const double u = (time - t[k - 1]) / (t[k] - t[k - 1]);
    q_out = (1 - u) * q[k - 1] + u * q[k];
    qd_out = (1 - u) * qd[k - 1] + u * qd[k];
  }
};

// The reference motion of --track, read as id reads states: q_ for every joint, qd_ all or none, qdd_
// and tau_ of the model's joints allowed and unread, other columns (a phase, a label) passed over; a
// misspelt q_, qd_, qdd_, tau_ or base_ column is an error. With a scene, a locked joint's columns may be
// left out (its reference is where the scene holds it, at rest); given, they are read, and a value other
// than that is said to go unused (warn_locked_motion). Angles and velocities, given or from the slopes,
// beyond what a step allows (StepLimits) are refused, naming the cell. The body stands on its foot in the model's base
// pose: a row on the other foot is refused, and base_ columns (a moving stance foot) are said to go unused.
Motion read_motion(const std::string& path, const SimModel& model, const SceneRunner* scene) {
  const std::vector<std::string> names = joint_names(model.description());
  const auto locked = [&](std::size_t i) { return scene && scene->locked(int(i)); };
  // groups 0 and 1: the free joints' q_ and qd_; 2 and 3: qdd_ and tau_, unread; then the locked joints'
  // q_ and qd_ one by one; then the base's
  std::vector<std::size_t> free_joints, locked_joints;
  for (std::size_t i = 0; i < names.size(); ++i) (locked(i) ? locked_joints : free_joints).push_back(i);
  const auto columns = [&](const std::vector<std::size_t>& joints, const std::string& prefix) {
    std::vector<std::string> out;
    for (const std::size_t i : joints) out.push_back(prefix + names[i]);
    return out;
  };
  std::vector<ColumnGroup> groups{{columns(free_joints, "q_"), ColumnGroup::Required},
                                  {columns(free_joints, "qd_"), ColumnGroup::Optional},
                                  {joint_columns(names, "qdd_"), ColumnGroup::Ignored},
                                  {joint_columns(names, "tau_"), ColumnGroup::Ignored}};
  for (const std::size_t i : locked_joints)
    for (const char* prefix : {"q_", "qd_"}) groups.push_back({{prefix + names[i]}, ColumnGroup::Optional});
  const BaseColumns base(groups);
  const JointTable table(path, groups, {"q_", "qd_", "qdd_", "tau_", "base_"}, {"stance"}, StateForm::StanceRooted);
  const std::string& source = table.csv().source;
  if (!table.has_time()) throw InputError(source + ": missing column 't' (the reference's time, s)");
  if (table.rows() == 0) throw InputError(source + ": no rows: the motion needs at least one");
  if (scene) warn_locked_motion(*scene, table.csv(), names, "simulate");
  if (base.any(table))
    cli::print(stderr,
               "humandyn simulate: warning: {}: the base_ columns are not used: the body stands on its foot in "
               "the model's base pose, and the servos track the joint angles alone\n",
               source);
  const bool given_qd = table.has(1);

  Motion m;
  const int n = model.size();
  const StepLimits<double> limits;
  for (std::size_t r = 0; r < table.rows(); ++r) {
    if (StanceSwitching::left_row(table, r))  // (which refuses a word that names no foot)
      table.fail_at(r, "stance",
                    "the simulated body stands on its right foot throughout: a row on the left foot is not a "
                    "reference for it (id and view read such a file)");
    const double t = table.time(r);
    if (r > 0 && !(t > m.t.back()))
      table.fail_at(
          r, "t",
          "time must increase from row to row (" + format_number(t) + " after " + format_number(m.t.back()) + ")");
    m.t.push_back(t);
    Eigen::VectorXd q(n), qd = Eigen::VectorXd::Zero(n);
    table.read(r, 0, free_joints, q);
    table.read(r, 1, free_joints, qd);
    for (const std::size_t i : locked_joints) q[Eigen::Index(i)] = scene->lock_angles()[Eigen::Index(i)];
    // a reference beyond the bounds of a step (StepLimits) would drive the body into a runaway that names
    // some joint, not the cell
    for (const std::size_t i : free_joints)
      for (const auto& [value, column, bound, unit] : {std::tuple{q[Eigen::Index(i)], "q_", limits.max_abs_q, "rad"},
                                                       {qd[Eigen::Index(i)], "qd_", limits.max_abs_qd, "rad/s"}})
        if (std::abs(value) > bound)
          table.fail_at(
              r, column + names[i],
              fmt::format("{} {} is beyond the {:g} {} a step allows", format_number(value), unit, bound, unit));
    m.q.push_back(q);
    m.qd.push_back(qd);
  }
  // velocities from the slopes between rows where the file gives none (central inside, one-sided at the
  // ends); a slope a double cannot hold (rows too close in time, or angles too far apart) is refused,
  // naming the row and joint
  if (!given_qd && m.t.size() > 1) {
    const std::size_t last = m.t.size() - 1;
    for (std::size_t r = 0; r <= last; ++r) {
      const std::size_t a = r == 0 ? 0 : r - 1, b = r == last ? last : r + 1;
      m.qd[r] = (m.q[b] - m.q[a]) / (m.t[b] - m.t[a]);
      for (const std::size_t i : free_joints)
        if (const double slope = m.qd[r][Eigen::Index(i)]; !(std::abs(slope) <= limits.max_abs_qd))
          table.fail_at(b, "q_" + names[i],
                        fmt::format("the velocity from the slope between the rows at t = {} and {} s ({} rad over "
                                    "{} s) is {}: give qd_ columns, or check those rows",
                                    format_number(m.t[a]), format_number(m.t[b]),
                                    format_number(m.q[b][Eigen::Index(i)] - m.q[a][Eigen::Index(i)]),
                                    format_number(m.t[b] - m.t[a]),
                                    std::isfinite(slope) ? fmt::format("{} rad/s, beyond the {:g} rad/s a step allows",
                                                                       format_number(slope), limits.max_abs_qd)
                                                         : std::string("not finite")));
    }
  }
  return m;
}

// The trajectory file: t, the state's columns, energy and stopped. Each row waits for the next to say
// whether it is the last; no file for an empty path.
class TrajectoryFile {
 public:
  // `floating`: the states are the floating form's, which a last column `form` says on every row
  TrajectoryFile(const std::string& path, std::vector<std::string> state, bool floating = false) {
    if (path.empty()) return;
    state.insert(state.begin(), "t");
    state.insert(state.end(), {"energy", "stopped"});
    if (floating) {
      state.emplace_back("form");
      form_ = {"floating"};
    }
    out_ = std::make_unique<CsvWriter>(path, state);
  }
  explicit operator bool() const { return bool(out_); }
  // The row of time t, started: the caller appends the state and the energy.
  std::vector<double>& next(double t) {
    flush(false);
    row_.assign(1, t);
    return row_;
  }
  // The last row, and the file committed: the trajectory up to the last good step, even after a failure.
  void finish(bool stopped) {
    flush(stopped);
    if (out_) out_->commit();
  }

 private:
  void flush(bool stopped) {
    if (!out_ || row_.empty()) return;
    row_.push_back(stopped ? 1 : 0);
    out_->row(row_, form_);
    row_.clear();
  }
  std::unique_ptr<CsvWriter> out_;
  std::vector<double> row_;
  std::vector<std::string> form_;  // the text cells ending every row
};

// ---- the floating form: a free body through the air ------------------------------------------------

// The energy of a floating state: (1/2) nu^T M nu with nu = (v_b, qd) from the mass matrix's blocks, and
// -m g . c with the centre of mass (first moment over mass, base frame) placed by the base pose X.
double floating_energy(const SimModel& model, FloatingData<SimModel>& fd, const FloatingState<SimModel>& x) {
  floating_crba(model, fd, x.q);
  const double kinetic = 0.5 * (x.v_b.dot(fd.Mbb * x.v_b) + 2 * x.v_b.dot(fd.Mbj * x.qd) + x.qd.dot(fd.data.M * x.qd));
  const Vec3<double> c = x.base * Vec3<double>(fd.body.h / fd.body.m);
  return kinetic - fd.body.m * model.gravity().dot(c);
}

// The starting state of --start: the first row of a file with the base_ position, orientation,
// angular velocity and velocity columns and the q_ and qd_ columns, each group all or none (left out:
// at rest in the home pose).
void read_start(const std::string& path, const SimModel& model, FloatingState<SimModel>& x) {
  const std::vector<std::string> names = joint_names(model.description());
  std::vector<ColumnGroup> groups{{joint_columns(names, "q_"), ColumnGroup::Optional},
                                  {joint_columns(names, "qd_"), ColumnGroup::Optional}};
  const BaseColumns base(groups);
  // (accelerations and torques are taken in, to be refused below with the reason)
  groups.push_back({joint_columns(names, "qdd_"), ColumnGroup::Ignored});
  groups.push_back({joint_columns(names, "tau_"), ColumnGroup::Ignored});
  const JointTable start(path, groups, {"q_", "qd_", "qdd_", "tau_", "base_"}, {}, StateForm::Floating);
  if (start.rows() == 0) throw InputError(start.csv().source + ": no rows: the starting state needs one");
  // (a trajectory given as the start: its first row is the state; the rest is checked, not used, and its time
  // is not read: said)
  if (start.rows() > 1)
    cli::print(stderr,
               "humandyn simulate: warning: {}the flight starts from this row's state; the {} row(s) after it are "
               "checked, not used\n",
               start.where(0), start.rows() - 1);
  if (start.has_time() && start.time(0) != 0)
    cli::print(stderr, "humandyn simulate: warning: {}t = {} is not read: the flight starts at t = 0\n", start.where(0),
               format_number(start.time(0)));
  for (const std::string& name : names) {
    if (start.csv().column("qdd_" + name) >= 0)
      start.fail_at(0, "qdd_" + name, "a starting state has no acceleration: forward dynamics gives it");
    if (start.csv().column("tau_" + name) >= 0)
      start.fail_at(0, "tau_" + name, "the floating body flies with no joint torque: a start has none");
  }
  if (start.csv().column("stance") >= 0)
    start.fail_at(0, "stance",
                  "the floating body has no stance foot (its base_ columns are the pelvis's, docs/base.md): "
                  "a stance-rooted state is not its starting state");
  const BaseState b = base.read(start, 0, model.base_pose());
  if (b.wd.squaredNorm() + b.a.squaredNorm() > 0)
    start.fail_at(0, b.wd.squaredNorm() > 0 ? "base_wdx" : "base_ax",
                  "a starting state has no acceleration: forward dynamics gives it");
  x.base = b.pose;
  x.v_b = b.twist();
  Eigen::VectorXd v(model.size());
  start.read(0, 0, v);
  x.q = v;
  start.read(0, 1, v);
  x.qd = v;
  // within the bounds of a step (StepLimits), which would stop the run at its first step naming no cell
  const StepLimits<double> limits;
  for (int i = 0; i < model.size(); ++i)
    for (const auto& [value, column, bound, unit] :
         {std::tuple{x.q[i], "q_", limits.max_abs_q, "rad"}, {x.qd[i], "qd_", limits.max_abs_qd, "rad/s"}})
      if (std::abs(value) > bound)
        start.fail_at(
            0, column + names[std::size_t(i)],
            fmt::format("{} {} is beyond the {:g} {} a step allows", format_number(value), unit, bound, unit));
  // the base's speeds are bounded as vectors (their length, the same in the world's axes and the base's):
  // the message names the file's largest of the three cells
  const auto check_speed = [&](const Vec3<double>& u, BaseGroup group, const char* what, double bound,
                               const char* unit) {
    if (!(u.norm() > bound)) return;
    Eigen::Index largest = 0;
    u.cwiseAbs().maxCoeff(&largest);
    start.fail_at(
        0, base_columns(group)[std::size_t(largest)],
        fmt::format("{} of {:.6g} {} is beyond the {:g} {} a step allows", what, u.stableNorm(), unit, bound, unit));
  };
  check_speed(b.w, BaseGroup::AngularVelocity, "an angular speed", limits.max_abs_qd, "rad/s");
  check_speed(b.v, BaseGroup::Velocity, "a speed", limits.max_base_speed, "m/s");
}

// Where the summary lines go: standard output, unless the trajectory goes there (`--out -`, or
// `--out /dev/stdout`: the CSV alone, for whatever reads it) or it is closed (>&-: the run, its file
// written, is not failed for a report).
std::FILE* summary_stream(const SimulateOptions& o) {
  return names_standard_output(o.out) || standard_output_closed ? stderr : stdout;
}

// What a runaway angle means: past the step's bound on |q|, which a joint that keeps turning reaches too.
std::string limit_note(const StepStatus& status) {
  if (status.error != StepError::Runaway || status.quantity != Quantity::Angle) return {};
  return fmt::format(
      " (|q| > {:g} rad, the step's bound, which a joint that keeps turning, as in a steady spin, "
      "reaches too)",
      StepLimits<double>{}.max_abs_q);
}

// Why a run stopped at time t, on stderr; said before the trajectory file is committed, which may fail.
template <class Model>
void say_stopped(double t, const StepStatus& status, const Model& model, const std::string& note = {}) {
  cli::print(stderr, "humandyn simulate: stopped at t = {:g} s: {}{}{}\n", t, describe(status, model),
             limit_note(status), note);
}

// Where the mass matrix at q is singular, the joint at which its factorisation meets the zero pivot (as
// check_pivots finds it): " at joint 5 'waist_pitch'", or "" where it is regular.
std::string singular_at(const SimModel& model, Data<SimModel>& data, const Eigen::VectorXd& q) {
  crba(model, data, q);
  factorize_mass_matrix(model, data);
  const Eigen::Index i = singular_joint(data.D);
  return i < 0 ? "" : fmt::format(" at joint {} '{}'", i + 1, model.joint_name(int(i)));
}

// After a run stopped at a divergence, where its partial trajectory went (the one deliberate partial result).
void say_partial(const SimulateOptions& o, double t) {
  cli::print(stderr,
             "humandyn simulate: {} holds the partial trajectory up to t = {:g} s (its last row has stopped = 1)\n",
             o.out == "-" ? std::string("standard output") : shown(o.out), t);
}

int run_floating(const SimulateOptions& o, const ModelDescription<double>& description) {
  if (!o.track.empty() || !o.scene.scene.empty() || !o.wrenches.empty())
    throw UsageError("--floating simulates a free body: not with --track, --scene or --wrench");
  if (o.integrator == Integrator::ImplicitPD || o.integrator == Integrator::BackwardEuler)
    throw UsageError("--floating steps with euler or rk4 (the implicit steps are the stance-rooted body's)");
  const SimModel model(description);
  const int n = model.size();
  FloatingData<SimModel> fd(model), aux(model);
  FloatingState<SimModel> x(model);
  if (!o.start.empty()) read_start(o.start, model, x);
  const Eigen::VectorXd tau = Eigen::VectorXd::Zero(n);

  // the trajectory: t, the base's pose and velocity (world), q, qd, energy, stopped
  TrajectoryFile out(
      o.out,
      state_columns({BaseGroup::Position, BaseGroup::Orientation, BaseGroup::AngularVelocity, BaseGroup::Velocity},
                    joint_names(description), {"q_", "qd_"}),
      true);
  Eigen::Quaterniond previous = Eigen::Quaterniond::Identity();
  const auto write = [&](double t, double energy) {
    if (!out) return;
    // the quaternion's sign kept from row to row, so that its columns are continuous
    Eigen::Quaterniond r(x.base.R);
    if (r.coeffs().dot(previous.coeffs()) < 0) r.coeffs() *= -1;
    previous = r;
    const Vec3<double> w = x.base.R * x.v_b.head<3>(), v = x.base.R * x.v_b.tail<3>();
    std::vector<double>& row = out.next(t);
    row.insert(row.end(), {x.base.p.x(), x.base.p.y(), x.base.p.z(), r.w(), r.x(), r.y(), r.z(), w.x(), w.y(), w.z(),
                           v.x(), v.y(), v.z()});
    row.insert(row.end(), x.q.data(), x.q.data() + n);
    row.insert(row.end(), x.qd.data(), x.qd.data() + n);
    row.push_back(energy);
  };

  if (const std::string motion = floating_null_motion(model, x.q); !motion.empty())
    cli::print(stderr,
               "humandyn simulate: warning: the floating body's mass matrix is singular at the start: {} moves no "
               "mass (a massless link, such as the paper model's pelvis); forward dynamics is undefined there and "
               "the steps will drift along that motion or fail\n",
               motion);
  const double e0 = floating_energy(model, aux, x);
  if (!std::isfinite(e0))
    throw InputError(
        fmt::format("{}: the energy is not finite (E(0) = {} J): a value too large for the dynamics in "
                    "double",
                    o.start.empty() ? "model '" + shown(description.name) + "' at rest in the home pose"
                                    : shown(o.start) + ": the starting state",
                    format_number(e0)));
  const double scale = model.total_mass() * model.gravity().norm() * 1.0;  // m g times one metre
  double drift = 0;
  write(0, e0);
  const long steps = std::lround(o.duration / o.h);
  const bool aba = o.aba;
  StepStatus status;
  long k = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (; k < steps; ++k) {
    status = o.integrator == Integrator::SemiImplicitEuler
                 ? (aba ? floating_step<Integrator::SemiImplicitEuler, FdMethod::Articulated>(model, fd, x, tau, o.h)
                        : floating_step<Integrator::SemiImplicitEuler, FdMethod::MassMatrix>(model, fd, x, tau, o.h))
                 : (aba ? floating_step<Integrator::RungeKutta4, FdMethod::Articulated>(model, fd, x, tau, o.h)
                        : floating_step<Integrator::RungeKutta4, FdMethod::MassMatrix>(model, fd, x, tau, o.h));
    if (!status) break;
    const double e = floating_energy(model, aux, x);
    drift = std::max(drift, std::abs(e - e0));
    write(double(k + 1) * o.h, e);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!status) say_stopped(double(k) * o.h, status, model);
  out.finish(!status);

  std::FILE* summary = summary_stream(o);
  cli::print(summary, "floating, {}, {}, dt = {:g} s, {} of {} steps in {:.3f} s ({:.2f} us per step)\n",
             integrator_name(o.integrator), aba ? "aba" : "ldlt", o.h, k, steps, seconds,
             k > 0 ? 1e6 * seconds / double(k) : 0.0);
  cli::print(summary, "energy: E(0) = {:.6g} J, max |E(t) - E(0)| = {:.3g} J{}\n", e0, drift,
             scale > 0 ? fmt::format(" = {:.3g} of m g * 1 m = {:.6g} J", drift / scale, scale)
                       : std::string(" (no scale for a relative drift: no gravity)"));
  if (!status) {
    if (out) say_partial(o, double(k) * o.h);
    return 3;
  }
  return 0;
}

// ---- the stance-rooted form --------------------------------------------------------------------------

int run_simulate(const SimulateOptions& o) {
  const Integrator integrator = o.integrator;
  const double h = o.h, duration = o.duration, kp = o.kp;
  if (!(duration >= 0)) throw UsageError("--duration must not be negative");
  if (o.fd_given && (integrator == Integrator::ImplicitPD || integrator == Integrator::BackwardEuler))
    throw UsageError("--fd chooses the forward dynamics of euler and rk4: --integrator " +
                     std::string(integrator_name(integrator)) + " solves its own equation");
  if (integrator == Integrator::BackwardEuler && !o.scene.scene.empty())
    throw UsageError("--integrator backward-euler steps the whole body: not with --scene");
  if (duration / h > 1e9) throw UsageError("--duration / --dt is more than 1e9 steps");
  if (const double steps = duration / h; duration > 0 && steps < 1 - 1e-9)
    throw UsageError(fmt::format("--duration {} s is shorter than one --dt {} s step", duration, h));
  if (const double steps = duration / h; std::abs(steps - std::round(steps)) > 1e-9 * std::max(1.0, steps))
    throw UsageError(
        fmt::format("--duration {} s is not a whole number of --dt {} s steps ({:.6g})", duration, h, steps));
  // (gains beyond 1e12 hold no joint of a body better, and their servo energies swamp the body's in rounding:
  // a step's energy balance then reads as noise of their size)
  constexpr double max_gain = 1e12;
  if (!(kp >= 0 && kp <= max_gain)) throw UsageError("--kp must be from 0 to 1e12 N m/rad, got " + format_number(kp));
  if (o.kd && !(*o.kd >= 0 && *o.kd <= max_gain))
    throw UsageError("--kd must be from 0 to 1e12 N m s/rad, got " + format_number(*o.kd));
  const ModelDescription<double> description = load_model(o.model);
  if (o.model.floating) return run_floating(o, description);

  const SimModel model(description);
  const int n = model.size();
  StepWorkspace<SimModel> ws(model);
  Data<SimModel> aux(model);
  State<SimModel> x(model);  // standing, at rest
  ExternalWrenches wrenches(o.wrenches, model);
  wrenches.attach(model, aux, x.q);

  // a scene: its locked joints held in the starting pose, or where --lock says
  std::optional<SceneRunner> scene = make_scene(o.scene, description, x.q);
  if (scene)
    for (int i = 0; i < n; ++i)
      if (scene->locked(i)) x.q[i] = scene->lock_angles()[i];

  // the servo, if tracking: gains, and critical damping from the mass matrix at the reference's start
  std::optional<Motion> motion;
  std::unique_ptr<PdServo<SimModel>> servo;
  Eigen::VectorXd tau = Eigen::VectorXd::Zero(n), q_ref(n), qd_ref(n);
  if (!o.track.empty()) {
    motion = read_motion(o.track, model, scene ? &*scene : nullptr);
    servo = std::make_unique<PdServo<SimModel>>(model);
    servo->kp.setConstant(kp);
    crba(model, aux, motion->q.front());
    const Eigen::VectorXd inertia = effective_inertia(aux.M);
    for (int i = 0; i < n; ++i) servo->kd[i] = o.kd ? *o.kd : PdServo<SimModel>::critical_damping(kp, inertia[i]);
  }

  // the trajectory file: t, q, qd, energy, stopped
  TrajectoryFile out(o.out, state_columns({}, joint_names(description), {"q_", "qd_"}));
  const auto write = [&](double t, double energy) {
    if (!out) return;
    std::vector<double>& row = out.next(t);
    row.insert(row.end(), x.q.data(), x.q.data() + n);
    row.insert(row.end(), x.qd.data(), x.qd.data() + n);
    row.push_back(energy);
  };

  // energy scale: m g z of the centre of mass at the start (the work gravity could do down to the base)
  forward_kinematics(model, aux, x.q);
  const double scale = std::abs(model.total_mass() * model.gravity().norm() *
                                (aux.com - model.base_pose().p).dot(-model.gravity().normalized()));
  const double e0 = total_energy(model, aux, x.q, x.qd);
  if (!std::isfinite(e0))
    throw InputError(
        fmt::format("model '{}' at rest in the starting pose: the energy is not finite (E(0) = {} J): "
                    "its masses, lengths or gravity are too large for the dynamics in double",
                    shown(description.name), format_number(e0)));
  if (!scene) {  // (a scene's locks may remove the singular direction)
    if (const std::string joint = singular_at(model, aux, x.q); !joint.empty())
      cli::print(stderr,
                 "humandyn simulate: warning: the mass matrix is singular at the start{} (its pivot there is "
                 "below 1e-10 of the largest): a turn of this joint, with the joints beyond it turning along, "
                 "moves no mass or next to none, so forward dynamics there is undefined or rounding noise: euler "
                 "and rk4 fail or follow that noise, as may implicit without a servo (--track); implicit with "
                 "one steps on, and so does backward-euler, where without a servo the motion nothing fixes may "
                 "run away (docs/stability.md)\n",
                 joint);
  }
  double drift = 0, dissipated = 0;  // (dissipated: backward Euler's own damping, J)
  write(0, e0);

  const long steps = std::lround(duration / h);
  StepStatus status;
  long k = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (; k < steps; ++k) {
    const double t = double(k) * h;
    if (servo) {
      // reference at the step's start; gravity feed-forward at the reference pose
      motion->at(t, q_ref, qd_ref);
      servo->q_ref = q_ref;
      servo->qd_ref = qd_ref;
      tau = gravity_torques(model, aux, q_ref);
    }
    if (!wrenches.empty()) {
      if (!servo) tau.setZero();
      tau += wrenches.joint_torques(model, aux, x.q);
    }
    const bool aba = o.aba;
    if (scene) {
      status =
          scene->step(integrator, aba ? FdMethod::Articulated : FdMethod::MassMatrix, x.q, x.qd, tau, servo.get(), h);
    } else {
      switch (integrator) {
        case Integrator::SemiImplicitEuler:
          status = aba ? step<Integrator::SemiImplicitEuler, FdMethod::Articulated>(model, ws, x, tau, servo.get(), h)
                       : step<Integrator::SemiImplicitEuler, FdMethod::MassMatrix>(model, ws, x, tau, servo.get(), h);
          break;
        case Integrator::RungeKutta4:
          status = aba ? step<Integrator::RungeKutta4, FdMethod::Articulated>(model, ws, x, tau, servo.get(), h)
                       : step<Integrator::RungeKutta4, FdMethod::MassMatrix>(model, ws, x, tau, servo.get(), h);
          break;
        case Integrator::ImplicitPD:
          status = step<Integrator::ImplicitPD>(model, ws, x, tau, servo.get(), h);
          break;
        case Integrator::BackwardEuler:
          status = step<Integrator::BackwardEuler>(model, ws, x, tau, servo.get(), h);
          if (status) dissipated += ws.report.dissipated;
          break;
      }
    }
    if (!status) break;
    const double e = total_energy(model, aux, x.q, x.qd);
    drift = std::max(drift, std::abs(e - e0));
    write(double(k + 1) * h, e);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!status) say_stopped(double(k) * h, status, model);  // (a singular mass matrix: step names its joint)
  out.finish(!status);

  std::FILE* summary = summary_stream(o);
  cli::print(summary, "{}, {}, dt = {:g} s, {} of {} steps in {:.3f} s ({:.2f} us per step)\n",
             integrator_name(integrator),
             integrator == Integrator::BackwardEuler          ? "Newton (LU of its Jacobian)"
             : integrator == Integrator::ImplicitPD || !o.aba ? "ldlt"
                                                              : "aba",
             h, k, steps, seconds, k > 0 ? 1e6 * seconds / double(k) : 0.0);
  // what changes the energy besides the integrator's error
  std::vector<std::string> working;
  if (servo) working.emplace_back("the servo does work");
  if (wrenches.any_force()) working.emplace_back("the external forces do work");
  if (scene && scene_terms(o.scene.scene) != Terms::Full) working.emplace_back("the scene drops the velocity products");
  // (relative to m g z_com only where that is not 0: no gravity, or a centre of mass at the base's
  // height, gives no scale)
  cli::print(
      summary, "energy: E(0) = {:.6g} J, max |E(t) - E(0)| = {:.3g} J{}{}\n", e0, drift,
      scale > 0 ? fmt::format(" = {:.3g} of m g z_com = {:.6g} J", drift / scale, scale)
                : fmt::format(" (no scale for a relative drift: m g z_com = {:.6g} J)", scale),
      working.empty() ? std::string() : fmt::format(" ({}: drift is not an error here)", fmt::join(working, " and ")));
  if (integrator == Integrator::BackwardEuler && k > 0)
    cli::print(summary, "backward Euler dissipated {:.3g} J in {:g} s ({:.3g} W), its numerical damping\n", dissipated,
               double(k) * h, dissipated / (double(k) * h));
  if (!status) {
    if (out) say_partial(o, double(k) * h);
    return 3;
  }
  return 0;
}

}  // namespace

Command add_simulate(CLI::App& humandyn) {
  const auto o = std::make_shared<SimulateOptions>();
  CLI::App* c = humandyn.add_subcommand(
      "simulate",
      "step the body through time (euler, rk4, implicit, backward-euler), passive or tracking with servos\n\n"
      "Steps the body from rest in the standing (home) pose under gravity, rooted at the stance foot. Without\n"
      "--track it falls passively; with --track, a PD servo on every joint follows the motion, with the\n"
      "gravity torques of the reference pose as feed-forward. Prints the energy drift, what besides the\n"
      "integrator changes the energy (the servo, --wrench, a scene's dropped velocity products), and for "
      "backward-euler the energy its damping\n"
      "removed; a step that would give a non-finite or runaway state stops the run with an error naming\n"
      "the joint (exit code 3); the trajectory up to the last good step is then still written, on\n"
      "purpose, and its last row says so.");
  add_model_options(*c, o->model);
  CLI::Option* floating = add_floating_option(*c, o->model,
                                              "It flies free, with no contact and no joint torque,\n"
                                              "from rest in the home pose or from --start: a body tossed into a\n"
                                              "somersault, a ragdoll's fall. The trajectory then adds the base's pose\n"
                                              "and velocity (base_ columns, as `humandyn id --floating` reads\n"
                                              "them) and a last column form = floating");
  c->add_option("--start", o->start,
                "with --floating: the starting state, the first row of a CSV file with\n"
                "the base_ position, orientation, angular velocity and velocity (world)\n"
                "and q_, qd_, each group all or none (left out: at rest in the home pose)")
      ->option_text("FILE")
      ->needs(floating);
  add_choice(*c, "--integrator", o->integrator,
             {{"euler", Integrator::SemiImplicitEuler},
              {"rk4", Integrator::RungeKutta4},
              {"implicit", Integrator::ImplicitPD},
              {"backward-euler", Integrator::BackwardEuler}},
             "euler: semi-implicit (symplectic) Euler; rk4: classical Runge-Kutta\n"
             "(default); implicit: semi-implicit Euler with the servo taken\n"
             "implicitly (stable PD); backward-euler: the whole dynamics at the\n"
             "step's end, by Newton's method (never gains energy; not with --scene)")
      ->option_text("I");
  add_choice(*c, "--fd", o->aba, {{"ldlt", false}, {"aba", true}},
             "forward dynamics of the explicit integrators: ldlt (mass matrix,\n"
             "default) or aba (articulated body); the implicit step always\n"
             "factorises M + h Kd + h^2 Kp, backward-euler its own Jacobian")
      ->option_text("F")
      ->each([o](const std::string&) { o->fd_given = true; });
  c->add_option_function<std::string>(
       "--dt", [o](const std::string& text) { o->h = parse_step(text); },
       "time step in seconds, a number or 1/N (default 0.001)")
      ->option_text("H");
  add_number(*c, "--duration", o->duration, "simulated seconds, a whole number of steps (default 1)")->option_text("T");
  CLI::Option* track = c->add_option("--track", o->track,
                                     "reference motion: a column t (s, increasing) and q_<joint> (rad) for\n"
                                     "every joint, optionally qd_<joint> (rad/s; otherwise from the slope\n"
                                     "between rows). The reference is linear between rows and held at rest\n"
                                     "outside them: the first row's pose before its t, the last row's after.\n"
                                     "With --scene, a locked joint's columns may be left out (unused).\n"
                                     "qdd_ and tau_ columns and others (a phase) are passed over; rows on\n"
                                     "the left foot (stance) are refused, and so are angles beyond 1e4 rad\n"
                                     "and velocities (given or from the slopes) beyond 1e4 rad/s, which no\n"
                                     "step allows; base_ columns go unused")
                           ->option_text("FILE");
  add_number(*c, "--kp", o->kp, "servo stiffness for every joint, N m/rad, 0 to 1e12 (default 1000)")
      ->option_text("KP")
      ->needs(track);
  add_number(*c, "--kd", o->kd,
             "servo damping for every joint, N m s/rad, 0 to 1e12 (default: critical,\n"
             "2 sqrt(KP I_i) with I_i = 1 / (M^-1)_ii, the joint's effective inertia\n"
             "at the reference's first pose)")
      ->option_text("KD")
      ->needs(track);
  CLI::Option* scene =
      add_scene_options(*c, o->scene,
                        "a named scene of the seed body: its terms (static_pose steps without\n"
                        "the velocity products), its locked joints held in the starting pose:",
                        std::string("with --scene: hold these locked joints at these angles (rad) instead,\n"
                                    "e.g. seated, with --scene upper_body:\n--lock ") +
                            poses::lock_text(poses::seated));
  add_wrench_option(*c, o->wrenches,
                    "Their joint torques are taken at each step's start and held over the\n"
                    "step (as the feed-forward is). Not with --scene")
      ->excludes(scene);
  c->add_option("--out", o->out,
                "the trajectory: t, q_<joint>, qd_<joint>, energy (J), stopped, one row\n"
                "per step ('-' for standard output, the summary then on stderr;\n"
                "default: none). stopped is 0, except on the last row of a run that\n"
                "stopped early (the next step failed): 1. Written all or nothing\n"
                "otherwise: an error or a kill leaves a previous FILE as it was")
      ->option_text("FILE");
  return {c, [o] { return run_simulate(*o); }};
}

}  // namespace humandyn::cli
