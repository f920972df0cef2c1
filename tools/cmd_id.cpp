// humandyn id: inverse dynamics of every state in a CSV file, one row of joint torques per state; on a
// moving base, with the ground reaction and its checks on request; rows that switch the stance foot; the
// floating form with its base wrench.
#include "cli/base_columns.hpp"
#include "cli/commands.hpp"
#include "cli/csv.hpp"
#include "cli/joint_table.hpp"
#include "cli/print.hpp"
#include "cli/stance_switching.hpp"
#include "cli/states_command.hpp"
#include "cli/wrench_option.hpp"
#include "humandyn/algorithm/ground_reaction.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/data.hpp"
#include "humandyn/floating.hpp"
#include "humandyn/model.hpp"
#include "humandyn/poses.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace humandyn::cli {

namespace {

using M = AnyModel<double>;

struct IdOptions {
  StatesOptions io;
  Terms terms = Terms::Full;
  bool ground_reaction = false;
  double mu = 0.8;
  std::string about;  // --moment-about X,Y,Z ("" for none)
  std::string sole;   // --sole LENGTH,WIDTH,HEEL,ANKLE ("" for de Leva's)
};

// rnea with the terms chosen at run time, on a moving base, with or without external wrenches.
const Eigen::VectorXd& inverse_dynamics(Terms terms, const M& model, Data<M>& data, const BaseMotion<double>& base,
                                        const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                        const LinkWrenches<M>* fext) {
  const auto run = [&]<Terms t>() -> const Eigen::VectorXd& {
    return fext ? rnea<t>(model, data, base, q, qd, qdd, *fext) : rnea<t>(model, data, base, q, qd, qdd);
  };
  return terms == Terms::Full         ? run.template operator()<Terms::Full>()
         : terms == Terms::NoCoriolis ? run.template operator()<Terms::NoCoriolis>()
                                      : run.template operator()<Terms::GravityOnly>();
}

GroundReaction<double> reaction(Terms terms, const M& model, const Data<M>& data, const BaseMotion<double>& base) {
  return terms == Terms::Full         ? ground_reaction<Terms::Full>(model, data, base)
         : terms == Terms::NoCoriolis ? ground_reaction<Terms::NoCoriolis>(model, data, base)
                                      : ground_reaction<Terms::GravityOnly>(model, data, base);
}

// The sole of --sole, or de Leva's foot scaled to the stature that the ankle's height above the ground
// implies (0.039 of stature, Drillis and Contini): the reference female's for the built-in female body, the
// male's for any other (a model file says nothing of sex).
SoleDimensions sole_of(const IdOptions& o, const ModelDescription<double>& d) {
  if (!o.sole.empty()) {
    double x[4];
    std::string why;
    const bool numbers = read_numbers(o.sole, x, 4, &why);
    if (!numbers || !(x[0] > 0 && x[1] > 0 && x[2] >= 0 && x[3] >= 0))
      throw UsageError(
          "option --sole needs LENGTH,WIDTH,HEEL_TO_ANKLE,ANKLE_HEIGHT in m (positive length and width), got '" +
          shown(o.sole) + "'" + (numbers ? "" : ": " + why));
    // a foot's sizes: a sole of 1 mm to 10 m, an ankle at most 10 m above it (beyond, the checks lose meaning)
    if (!(x[0] >= 1e-3 && x[1] >= 1e-3 && x[0] <= 10 && x[1] <= 10 && x[3] <= 10))
      throw UsageError("option --sole: " + shown(o.sole) +
                       " m is not a foot's: the sole's length and width from 0.001 to 10 m, the ankle at most 10 m "
                       "above it");
    if (x[2] > x[0])
      throw UsageError("option --sole: the ankle stands " + format_number(x[2]) + " m ahead of the heel, beyond the " +
                       format_number(x[0]) + " m sole: HEEL_TO_ANKLE must be at most LENGTH");
    return {x[0], x[1], x[2], x[3]};
  }
  const double ankle = d.base_pose.p.z();
  if (!(ankle > 0))
    throw UsageError("the base of model '" + shown(d.name) +
                     "' is not above the ground, so its stature is unknown: give the sole with --sole");
  return de_leva_sole(ankle / anthropometry::ankle_height,
                      o.io.model.model == "female" ? anthropometry::Sex::Female : anthropometry::Sex::Male);
}

// The ground reaction's columns and its checks (foot_contact), and their count over the file.
struct ReactionColumns {
  std::optional<Vec3<double>> about;  // --moment-about
  SoleDimensions sole;
  double mu = 0.8;
  std::array<std::size_t, 3> flagged{};  // rows with each flag: pulls, CoP outside, slips
  std::size_t any_flag = 0;              // rows with one flag or more

  std::vector<std::string> names() const {
    std::vector<std::string> n{"grf_fx", "grf_fy", "grf_fz", "grf_mx", "grf_my", "grf_mz"};
    if (about) n.insert(n.end(), {"grf_px", "grf_py", "grf_pz"});
    n.insert(n.end(), {"cop_x", "cop_y", "cop_z", "grf_normal", "friction_ratio", "free_moment", "foot_pulls",
                       "cop_outside_sole", "foot_slips"});
    return n;
  }

  // Appends the row's cells (none where the normal force is not positive: no centre of pressure, no friction ratio
  // where it is infinite) and counts its flags.
  void append(const GroundReaction<double>& r, const Pose<double>& base_pose,
              const Eigen::Matrix<double, 3, 4>& corners, std::vector<std::optional<double>>& cells) {
    for (const auto& v : {r.force, r.moment}) cells.insert(cells.end(), {v.x(), v.y(), v.z()});
    if (about) {
      const Vec3<double> m = r.moment_about(*about);
      cells.insert(cells.end(), {m.x(), m.y(), m.z()});
    }
    const FootContact<double> c = foot_contact(r, base_pose, corners, mu);
    const auto if_finite = [&](double x) { return std::isfinite(x) ? std::optional<double>(x) : std::nullopt; };
    const auto if_pushed = [&](double x) { return c.normal > 0 ? std::optional<double>(x) : std::nullopt; };
    cells.insert(cells.end(), {if_pushed(c.cop.x()), if_pushed(c.cop.y()), if_pushed(c.cop.z()), c.normal,
                               if_finite(c.friction_ratio), if_pushed(c.free_moment)});
    const int bits[] = {FootPulls, CopOutsideSole, FootSlips};
    for (std::size_t k = 0; k < 3; ++k) {
      const bool set = (c.flags & bits[k]) != 0;
      cells.push_back(set ? 1.0 : 0.0);
      flagged[k] += set;
    }
    any_flag += c.flags != ContactOk;
  }

  // The summary on stderr: how many rows one foot on the ground cannot produce, and why.
  void report(std::size_t rows) const {
    cli::print(stderr,
               "humandyn id: ground reaction: {} of {} rows with a flag: the foot would have to pull on the ground in "
               "{}, the centre of pressure lies outside the sole in {}, the friction exceeds mu = {:g} in {}{}\n",
               any_flag, rows, flagged[0], flagged[1], mu, flagged[2],
               any_flag == 0 ? "" : " (one foot on the ground cannot produce those rows)");
  }
};

// The columns id writes, refused in its input as such: the torques (a scene writes its moving joints' alone,
// but a tau_ column is a result under any scene, not a misspelling) and the floating base's wrench.
std::vector<std::string> id_outputs(const IdOptions& o, const std::vector<std::string>& names) {
  std::vector<std::string> out = joint_columns(names, "tau_");
  if (o.io.model.floating) out.insert(out.end(), {"base_fx", "base_fy", "base_fz", "base_mx", "base_my", "base_mz"});
  return out;
}

int run_id(const IdOptions& o) {
  if (o.mu < 0) throw UsageError(fmt::format("option --mu needs a friction coefficient >= 0, got {:g}", o.mu));
  const Terms terms = o.io.scene.scene.empty() ? o.terms : scene_terms(o.io.scene.scene);
  const bool floating = o.io.model.floating;
  if (floating && o.ground_reaction)
    throw UsageError("--ground-reaction goes with the stance-rooted form: the floating form writes its base wrench");
  const ModelDescription<double> description = load_model(o.io.model);

  const SoleDimensions sole = o.ground_reaction ? sole_of(o, description) : SoleDimensions{};

  const M model(description);
  Data<M> data(model);
  ExternalWrenches wrenches(o.io.wrenches, model);
  const std::vector<std::string> names = joint_names(description);

  // the columns: q always, qd and qdd where the chosen terms read them (a scene's locked joints: none of
  // these but the angle --lock does not give), the base's, a stance foot, others passed through
  std::vector<ColumnGroup> groups;
  const JointColumns state_columns(o.io, description,
                                   terms == Terms::Full ? ColumnGroup::Required : ColumnGroup::Ignored, "qdd_",
                                   terms != Terms::GravityOnly ? ColumnGroup::Required : ColumnGroup::Ignored, groups);
  const BaseColumns base_columns(groups);
  const JointTable states(o.io.in, groups, {"q_", "qd_", "qdd_", "tau_", "base_"}, {"stance"},
                          floating ? StateForm::Floating : StateForm::StanceRooted, id_outputs(o, names));
  if (floating && states.csv().column("stance") >= 0)
    throw UsageError("the stance column of " + states.csv().source +
                     " goes with the stance-rooted form, not --floating");
  const bool moving = base_columns.any(states), switching = StanceSwitching::any_left_row(states);
  if ((moving || switching) && (!o.io.scene.scene.empty() || !wrenches.empty()))
    throw UsageError(std::string("the ") + (moving ? "base_ columns" : "stance column's left rows") + " of " +
                     states.csv().source + " do not go with " + (o.io.scene.scene.empty() ? "--wrench" : "--scene") +
                     " (a scene or a wrench is for a body standing on its right foot in the model's base pose)");
  std::optional<StanceSwitching> stances;
  if (switching) stances.emplace(description, o.io.in, o.io.model.model);

  // a scene: its locked joints held at the first row's angles, or where --lock says
  const Eigen::Index n = model.size();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(n), qd = q, qdd = q, lq(n), lqd(n), lqdd(n);
  if (states.rows() > 0) state_columns.read_angles(states, 0, q);
  wrenches.attach(model, data, q);
  std::optional<SceneRunner> scene = make_scene(o.io.scene, description, q);
  if (scene) warn_locked_motion(*scene, states.csv(), names, "id");
  std::vector<std::size_t> written;  // the joints whose torques are written
  for (int i = 0; i < model.size(); ++i)
    if (!scene || scene->output(i)) written.push_back(std::size_t(i));

  // the results' columns: the torques, the floating base's wrench or the ground reaction
  ResultColumns results;
  const auto tau_names = joint_columns(names, "tau_");
  for (const std::size_t i : written) results.add(tau_names[i], "torque of joint '" + names[i] + "'");
  ReactionColumns grf;
  if (o.ground_reaction) {
    if (!o.about.empty()) {
      grf.about.emplace();
      if (std::string why; !read_numbers(o.about, grf.about->data(), 3, &why))
        throw UsageError("option --moment-about needs X,Y,Z in m, got '" + shown(o.about) + "': " + why);
    }
    grf.sole = sole;
    grf.mu = o.mu;
  }
  const std::vector<std::string> extra =
      floating            ? std::vector<std::string>{"base_fx", "base_fy", "base_fz", "base_mx", "base_my", "base_mz"}
      : o.ground_reaction ? grf.names()
                          : std::vector<std::string>{};
  for (const auto& e : extra) results.add(e, e);
  const auto right_corners = sole_corners(model, grf.sole);
  const auto left_corners = stances ? sole_corners(stances->left(), grf.sole) : right_corners;
  FloatingData<M> fd(model);

  // every row is valid now (the reader checked each cell): compute and write, all or nothing
  write_results(states, o.io.out, results, [&](std::size_t r, std::vector<std::optional<double>>& cells) {
    state_columns.read(states, r, q, qd, qdd);
    const bool left = stances && StanceSwitching::left_row(states, r);

    if (floating) {
      // the base's pose and motion in the world, as floating_rnea takes them (base-frame coordinates)
      const BaseState b = base_columns.read(states, r, model.base_pose());
      const SpatialVector<double> v_b = b.twist(), a_b = b.twist_rate(terms == Terms::Full);
      const auto& tau = terms == Terms::Full ? floating_rnea<Terms::Full>(model, fd, b.pose, v_b, a_b, q, qd, qdd)
                        : terms == Terms::NoCoriolis
                            ? floating_rnea<Terms::NoCoriolis>(model, fd, b.pose, v_b, a_b, q, qd, qdd)
                            : floating_rnea<Terms::GravityOnly>(model, fd, b.pose, v_b, a_b, q, qd, qdd);
      for (const std::size_t i : written) cells.push_back(tau[Eigen::Index(i)]);
      const Vec3<double> f = b.pose.R * fd.base_wrench.tail<3>(), m = b.pose.R * fd.base_wrench.head<3>();
      cells.insert(cells.end(), {f.x(), f.y(), f.z(), m.x(), m.y(), m.z()});
    } else if (scene) {
      const Eigen::VectorXd& tau = scene->inverse_dynamics(q, qd, qdd);
      for (const std::size_t i : written) cells.push_back(tau[Eigen::Index(i)]);
    } else {
      // the stance foot's model, state and base: the left foot's through the exact state map
      const M& stance_model = left ? stances->left() : model;
      Data<M>& d = left ? stances->left_data() : data;
      Pose<double> home = model.base_pose();
      if (left) {
        home = stances->to_left(q, qd, lq, lqd);
        lqdd = stances->to_left(qdd);
      }
      const BaseMotion<double> base = moving ? base_columns.read(states, r, home).motion() : [&] {
        BaseMotion<double> at_rest = BaseMotion<double>::at_rest(stance_model);
        at_rest.pose = home;
        return at_rest;
      }();
      const LinkWrenches<M>* fext = wrenches.empty() ? nullptr : &wrenches.at(model, data, q);
      const Eigen::VectorXd& tau_stance =
          inverse_dynamics(terms, stance_model, d, base, left ? lq : q, left ? lqd : qd, left ? lqdd : qdd, fext);
      const Eigen::VectorXd tau = left ? stances->to_right(tau_stance) : tau_stance;
      for (const std::size_t i : written) cells.push_back(tau[Eigen::Index(i)]);
      if (o.ground_reaction)
        grf.append(reaction(terms, stance_model, d, base), base.pose, left ? left_corners : right_corners, cells);
    }
  });
  if (o.ground_reaction) grf.report(states.rows());
  return 0;
}

}  // namespace

Command add_id(CLI::App& humandyn) {
  const auto o = std::make_shared<IdOptions>();
  CLI::App* c = humandyn.add_subcommand(
      "id",
      "inverse dynamics: joint torques for every state of a CSV file\n\n"
      "Inverse dynamics (recursive Newton-Euler) of every row of STATES.csv: the joint torques that hold or\n"
      "move the body through each state under gravity. The base (the stance foot) stands still in the\n"
      "model's base pose unless the file gives its motion (base_ columns); --ground-reaction adds what the\n"
      "ground must then give the foot, and flags the rows one foot on the ground cannot produce. A stance\n"
      "column switches the stance foot row by row. --floating: the body with a free base at the pelvis,\n"
      "its joint torques and the wrench its base needs (zero for a motion a free body can make).");
  add_model_options(*c, o->io.model);
  CLI::Option* terms =
      add_choice(*c, "--terms", o->terms,
                 {{"full", Terms::Full}, {"no-coriolis", Terms::NoCoriolis}, {"gravity", Terms::GravityOnly}},
                 "full: every term (default); no-coriolis: without the velocity\n"
                 "products (of the base's rotation too), as the seed paper does;\n"
                 "gravity: the static torques only (in the base's pose)")
          ->option_text("T");
  CLI::Option* scene =
      add_states_options(*c, o->io,
                         {.floating = "The base_ columns are then the pelvis's,\n"
                                      "the q_ of the re-hung stance leg its own DH angles (docs/base.md); the\n"
                                      "output adds base_fx..base_mz",
                          .scene = "a named scene of the seed body instead of --terms (its terms, its\n"
                                   "locked joints held at the first row's angles, only its output\n"
                                   "torques written). A locked joint's qd_ and qdd_ columns are not\n"
                                   "read and may be left out, and so may its q_ column when --lock\n"
                                   "gives its angle:",
                          .lock = "with --scene: hold these locked joints at these angles (rad) instead,\n"
                                  "e.g. seated, with --scene upper_body:\n--lock " +
                                  poses::lock_text(poses::seated),
                          .wrench = "The torques then also hold the wrenches (a load in the hand raises the\n"
                                    "arm's)",
                          .in = "the states, '-' for standard input. Header: q_<joint> (rad) for every\n"
                                "joint, and qd_<joint> (rad/s) and qdd_<joint> (rad/s^2) for every joint\n"
                                "where the terms use them (full: both; no-coriolis: qdd; gravity:\n"
                                "neither). Optional, each group all or none, in the world frame: the\n"
                                "base's position base_x,base_y,base_z (m), orientation base_qw,base_qx,\n"
                                "base_qy,base_qz (unit quaternion), angular velocity base_wx.. (rad/s),\n"
                                "velocity base_vx.. (m/s; the floating form's), angular acceleration\n"
                                "base_wdx.. (rad/s^2), acceleration base_ax.. (m/s^2, without gravity);\n"
                                "left out: at rest in the model's base pose. A column stance (right,\n"
                                "left, r or l): the stance foot of each row, whose q_ stay the right-\n"
                                "stance model's; its left rows go through the exact state map and\n"
                                "their torques come back in the right model's joints. Any other column\n"
                                "(t, phase, ...) is copied to the output; a tau_ column (the\n"
                                "output's) and a misspelt q_, qd_, qdd_ or base_ column are errors",
                          .out = "the torques, tau_<joint> (N m), one row per input row (default:\n"
                                 "standard output), after t and the copied columns; written only when\n"
                                 "every row is valid"});
  terms->excludes(scene);
  CLI::Option* grf = c->add_flag("--ground-reaction", o->ground_reaction,
                                 "also write the wrench the stance foot needs from the ground, world\n"
                                 "axes: grf_fx,grf_fy,grf_fz (N), grf_mx,grf_my,grf_mz (N m about the\n"
                                 "base origin); the centre of pressure on the ground z = 0 cop_x,cop_y,\n"
                                 "cop_z (m), the normal force grf_normal (N), friction_ratio\n"
                                 "(tangential / normal), free_moment (N m about the vertical through\n"
                                 "the centre of pressure) - the centre of pressure and free_moment\n"
                                 "empty where the normal force is not positive, friction_ratio where\n"
                                 "it is infinite - and the flags foot_pulls (normal <= 0 under a load),\n"
                                 "cop_outside_sole, foot_slips (ratio > mu), 0 or 1, none on a foot that\n"
                                 "carries nothing; a count of the flagged rows on stderr");
  grf->group("the ground reaction")->excludes(scene);
  add_number(*c, "--mu", o->mu, "friction coefficient of the foot_slips flag, >= 0 (default 0.8)")
      ->needs(grf)
      ->group("the ground reaction");
  c->add_option("--moment-about", o->about, "also the moment about this point P (world, m): grf_px,grf_py,grf_pz")
      ->option_text("X,Y,Z")
      ->needs(grf)
      ->group("the ground reaction");
  c->add_option("--sole", o->sole,
                "the sole (m): length heel to toe, width, the ankle's distance ahead of\n"
                "the heel and height above the sole (default: de Leva's foot, the\n"
                "reference female's with --model female and the male's with any other\n"
                "body, scaled to the stature the ankle's height implies, 0.039 of it)")
      ->option_text("L,W,H,A")
      ->needs(grf)
      ->group("the ground reaction");
  return {c, [o] { return run_id(*o); }};
}

}  // namespace humandyn::cli
