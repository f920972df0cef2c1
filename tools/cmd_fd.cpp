// humandyn fd: forward dynamics of every state in a CSV file, one row of joint accelerations per state;
// rows that switch the stance foot; in the floating form, the base's acceleration too.
#include "cli/base_columns.hpp"
#include "cli/commands.hpp"
#include "cli/csv.hpp"
#include "cli/joint_table.hpp"
#include "cli/model_source.hpp"
#include "cli/stance_switching.hpp"
#include "cli/states_command.hpp"
#include "cli/wrench_option.hpp"
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/data.hpp"
#include "humandyn/floating.hpp"
#include "humandyn/model.hpp"
#include "humandyn/stance.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace humandyn::cli {

namespace {

struct FdOptions {
  StatesOptions io;
  FdMethod method = FdMethod::MassMatrix;
  bool full = true;  // --terms full, else no-coriolis
};

// Fixed-base forward dynamics with the method and terms chosen at run time, with or without wrenches.
const Eigen::VectorXd& accelerations(FdMethod method, bool full, const AnyModel<double>& model,
                                     Data<AnyModel<double>>& data, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                     const Eigen::VectorXd& tau, const LinkWrenches<AnyModel<double>>* fext) {
  const auto run = [&]<FdMethod m, Terms t>() -> const Eigen::VectorXd& {
    return fext ? forward_dynamics<m, t>(model, data, q, qd, tau, *fext)
                : forward_dynamics<m, t>(model, data, q, qd, tau);
  };
  return method == FdMethod::Articulated ? (full ? run.template operator()<FdMethod::Articulated, Terms::Full>()
                                                 : run.template operator()<FdMethod::Articulated, Terms::NoCoriolis>())
                                         : (full ? run.template operator()<FdMethod::MassMatrix, Terms::Full>()
                                                 : run.template operator()<FdMethod::MassMatrix, Terms::NoCoriolis>());
}

// The pivots the last forward dynamics on `data` met: the articulated inertia about each joint axis, or
// D of M = L^T D L.
Eigen::VectorXd pivots_of(const Data<AnyModel<double>>& data, FdMethod method) {
  return method == FdMethod::Articulated ? Eigen::VectorXd(data.D_inv.cwiseInverse()) : Eigen::VectorXd(data.D);
}

// Floating-base forward dynamics with the method and terms chosen at run time: the joints' accelerations,
// and the base's in fd.a_b.
const Eigen::VectorXd& floating_accelerations(FdMethod method, bool full, const AnyModel<double>& model,
                                              FloatingData<AnyModel<double>>& fd, const BaseState& b,
                                              const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                              const Eigen::VectorXd& tau) {
  const SpatialVector<double> v_b = b.twist();
  return method == FdMethod::Articulated
             ? (full ? floating_forward_dynamics<FdMethod::Articulated, Terms::Full>(model, fd, b.pose, v_b, q, qd, tau)
                     : floating_forward_dynamics<FdMethod::Articulated, Terms::NoCoriolis>(model, fd, b.pose, v_b, q,
                                                                                           qd, tau))
             : (full ? floating_forward_dynamics<FdMethod::MassMatrix, Terms::Full>(model, fd, b.pose, v_b, q, qd, tau)
                     : floating_forward_dynamics<FdMethod::MassMatrix, Terms::NoCoriolis>(model, fd, b.pose, v_b, q, qd,
                                                                                          tau));
}

int run_fd(const FdOptions& o) {
  const bool full = o.io.scene.scene.empty() ? o.full : scene_terms(o.io.scene.scene) == Terms::Full;
  const bool floating = o.io.model.floating;
  const ModelDescription<double> description = load_model(o.io.model);

  const AnyModel<double> model(description);
  Data<AnyModel<double>> data(model);
  FloatingData<AnyModel<double>> fd(model);
  ExternalWrenches wrenches(o.io.wrenches, model);
  const std::vector<std::string> names = joint_names(description);

  // the columns: q always, tau, and qd where the terms read them (a scene's locked joints: none of these but
  // the angle --lock does not give); the floating base's pose and velocity; a stance foot; others passed
  // through
  std::vector<ColumnGroup> groups;
  const JointColumns state_columns(o.io, description, full ? ColumnGroup::Required : ColumnGroup::Ignored, "tau_",
                                   ColumnGroup::Required, groups);
  const BaseColumns base(groups);
  // the columns fd writes, refused in its input as such: the accelerations (a scene's moving joints' alone, but
  // a qdd_ column is a result under any scene), and the floating base's
  std::vector<std::string> outputs = joint_columns(names, "qdd_");
  if (floating)
    for (const BaseGroup g : {BaseGroup::AngularAcceleration, BaseGroup::Acceleration})
      for (const auto& c : base_columns(g)) outputs.push_back(c);
  const JointTable states(o.io.in, groups, {"q_", "qd_", "qdd_", "tau_", "base_"}, {"stance"},
                          floating ? StateForm::Floating : StateForm::StanceRooted, outputs);
  if (!floating && base.any(states))
    throw UsageError("the base_ columns of " + states.csv().source +
                     " go with --floating (the pelvis's motion): fd's stance-rooted base stands still in the "
                     "model's base pose (a moving stance foot, as motion import writes it, is read by id only)");
  std::optional<StanceSwitching> stances;
  if (floating && states.csv().column("stance") >= 0)
    throw UsageError("the stance column of " + states.csv().source +
                     " goes with the stance-rooted form, not --floating");
  if (StanceSwitching::any_left_row(states)) {  // (rows all on the right foot need no switch)
    if (!o.io.scene.scene.empty() || !wrenches.empty())
      throw UsageError("the stance column's left rows of " + states.csv().source + " do not go with " +
                       (o.io.scene.scene.empty() ? "--wrench" : "--scene") +
                       " (a scene or a wrench is for a body standing on its right foot in the model's base pose)");
    stances.emplace(description, o.io.in, o.io.model.model);
  }

  // a scene: its locked joints held at the first row's angles, or where --lock says
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.size()), qd = q, tau = q;
  if (states.rows() > 0) state_columns.read_angles(states, 0, q);
  wrenches.attach(model, data, q);
  std::optional<SceneRunner> scene = make_scene(o.io.scene, description, q);
  if (scene) warn_locked_motion(*scene, states.csv(), names, "fd");
  std::vector<std::size_t> written;  // the joints whose accelerations are written
  for (int i = 0; i < model.size(); ++i)
    if (!scene || !scene->locked(i)) written.push_back(std::size_t(i));

  ResultColumns results;
  const auto qdd_names = joint_columns(names, "qdd_");
  for (const std::size_t i : written) results.add(qdd_names[i], "acceleration of joint '" + names[i] + "'");
  if (floating)
    for (const BaseGroup g : {BaseGroup::AngularAcceleration, BaseGroup::Acceleration})
      for (const auto& c : base_columns(g)) results.add(c, "base acceleration " + c);

  Eigen::VectorXd lq(model.size()), lqd(model.size());
  write_results(states, o.io.out, results, [&](std::size_t r, std::vector<std::optional<double>>& cells) {
    state_columns.read(states, r, q, qd, tau);
    if (stances && StanceSwitching::left_row(states, r)) {
      // a left row: the left-stance model standing where its foot is, on the mapped state and torques; its
      // accelerations carried back to the right model's joints
      const AnyModel<double> left = rebase(stances->left(), stances->to_left(q, qd, lq, lqd));
      Data<AnyModel<double>>& ld = stances->left_data();
      const Eigen::VectorXd lqdd = accelerations(o.method, full, left, ld, lq, lqd, stances->to_left(tau), nullptr);
      check_pivots(pivots_of(ld, o.method), left, states.where(r));
      const Eigen::VectorXd qdd = stances->to_right(lqdd);
      for (const std::size_t i : written) cells.push_back(qdd[Eigen::Index(i)]);
      return;
    }
    const LinkWrenches<AnyModel<double>>* fext = wrenches.empty() ? nullptr : &wrenches.at(model, data, q);
    const Eigen::VectorXd scene_qdd = scene ? scene->forward_dynamics(q, qd, tau, o.method) : Eigen::VectorXd();
    const BaseState b = floating ? base.read(states, r, model.base_pose()) : BaseState{};
    if (floating)
      if (const std::string motion = floating_null_motion(model, q); !motion.empty())
        throw InputError(states.where(r) + "the floating body's mass matrix is singular: " + motion +
                         " moves no mass; forward dynamics is undefined");
    const Eigen::VectorXd& qdd = floating ? floating_accelerations(o.method, full, model, fd, b, q, qd, tau)
                                 : scene  ? scene_qdd
                                          : accelerations(o.method, full, model, data, q, qd, tau, fext);
    const Eigen::VectorXd pivots = scene ? scene->pivots(o.method) : pivots_of(floating ? fd.data : data, o.method);
    check_pivots(pivots, model, states.where(r));
    for (const std::size_t i : written) cells.push_back(qdd[Eigen::Index(i)]);
    if (floating) {
      // the base's angular acceleration and its origin's, world axes: R a_b and R (dv_b/dt + w_b x v_b)
      const SpatialVector<double> v_b = b.twist();
      const Vec3<double> wd = b.pose.R * fd.a_b.head<3>();
      const Vec3<double> a = b.pose.R * (fd.a_b.tail<3>() + (full ? Vec3<double>(v_b.head<3>().cross(v_b.tail<3>()))
                                                                  : Vec3<double>::Zero()));
      cells.insert(cells.end(), {wd.x(), wd.y(), wd.z(), a.x(), a.y(), a.z()});
    }
  });
  return 0;
}

}  // namespace

Command add_fd(CLI::App& humandyn) {
  const auto o = std::make_shared<FdOptions>();
  CLI::App* c = humandyn.add_subcommand(
      "fd",
      "forward dynamics: joint accelerations for every state and torque of a CSV file\n\n"
      "Forward dynamics of every row of STATES.csv: the joint accelerations that the joint torques produce\n"
      "at each state under gravity (the inverse of `humandyn id`).");
  add_model_options(*c, o->io.model);
  add_choice(*c, "--method", o->method, {{"mass-matrix", FdMethod::MassMatrix}, {"articulated", FdMethod::Articulated}},
             "mass-matrix: the mass matrix by composite rigid bodies and its\n"
             "tree-sparse L^T D L factorisation (default); articulated: the\n"
             "articulated-body algorithm")
      ->option_text("M");
  CLI::Option* terms = add_choice(*c, "--terms", o->full, {{"full", true}, {"no-coriolis", false}},
                                  "full: every term (default); no-coriolis: without the velocity\n"
                                  "products, as the seed paper does (the qd_ columns are then not needed)")
                           ->option_text("T");
  CLI::Option* scene = add_states_options(
      *c, o->io,
      {.floating = "The states then give the base's pose and velocity\n"
                   "(base_ columns, as `humandyn id` reads them; left out: at rest in the\n"
                   "home pose) and the output adds the base's accelerations base_wdx..\n"
                   "(rad/s^2) and base_ax.. (m/s^2, without gravity), world axes",
       .scene = "a named scene of the seed body instead of --terms: its terms\n"
                "(static_pose steps without the velocity products), its locked joints\n"
                "held at the first row's angles (their qd_ and tau_ columns are not\n"
                "read and may be left out, and so may a q_ column when --lock gives\n"
                "its angle),\n"
                "accelerations written for its moving joints only:",
       .lock = "with --scene: hold these locked joints at these angles (rad) instead\nof the first row's",
       .wrench = "The accelerations then include the wrenches' push",
       .in = "the states, '-' for standard input. Header: q_<joint> (rad),\n"
             "qd_<joint> (rad/s) and tau_<joint> (N m) for every joint; with\n"
             "--floating the base_ columns. A column stance (right, left, r or l):\n"
             "the stance foot of each row, as `humandyn id` reads it: its left rows\n"
             "go through the exact state map to the left-stance model, standing\n"
             "where its foot is, and their accelerations come back in the right\n"
             "model's joints. Any other column (t, phase, ...) is copied to the\n"
             "output; the output's own columns (qdd_, and with --floating base_wd..\n"
             "and base_a..) and a misspelt q_, qd_, tau_ or base_ column are errors",
       .out = "the accelerations, qdd_<joint> (rad/s^2), one row per input row\n"
              "(default: standard output), after t and the copied columns; written\n"
              "only when every row is valid"});
  terms->excludes(scene);
  c->footer(
      "The mass matrix must be regular. The paper's model is not: Table 1's pelvis link is massless and the\n"
      "right hip pitch, the waist pitch and the left hip pitch turn about one line, so no torque fixes the\n"
      "pelvis's turn about that line. Such a state is reported as an error, naming the joint.");
  return {c, [o] { return run_fd(*o); }};
}

}  // namespace humandyn::cli
