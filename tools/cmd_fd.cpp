// humandyn fd: forward dynamics of every state in a CSV file, one row of joint accelerations per state.
#include "cli/commands.hpp"
#include "cli/csv.hpp"
#include "cli/joint_table.hpp"
#include "cli/model_source.hpp"
#include "cli/scene_option.hpp"
#include "cli/wrench_option.hpp"
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/data.hpp"
#include "humandyn/model.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace humandyn::cli {

namespace {

struct FdOptions {
  ModelOptions model;
  FdMethod method = FdMethod::MassMatrix;
  bool full = true;  // --terms full, else no-coriolis
  SceneOptions scene;
  std::vector<std::string> wrenches;
  std::string in, out = "-";
};

// The smallest pivot below this fraction of the largest marks a singular mass matrix: round-off of a
// zero pivot sits near 1e-16 of the largest, a light hand's real pivot near 1e-7.
constexpr double singular_pivot = 1e-10;

template <FdMethod method, Terms terms>
const Eigen::VectorXd& accelerations(const AnyModel<double>& model, Data<AnyModel<double>>& data,
                                     const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& tau,
                                     const LinkWrenches<AnyModel<double>>* fext) {
  return fext ? forward_dynamics<method, terms>(model, data, q, qd, tau, *fext)
              : forward_dynamics<method, terms>(model, data, q, qd, tau);
}

int run_fd(const FdOptions& o) {
  const bool articulated = o.method == FdMethod::Articulated;
  const bool full = o.scene.scene.empty() ? o.full : scene_terms(o.scene.scene) == Terms::Full;
  if (o.in != "-" && o.in == o.out) throw UsageError("--in and --out name the same file");
  const ModelDescription<double> description = load_model(o.model);

  const AnyModel<double> model(description);
  Data<AnyModel<double>> data(model);
  ExternalWrenches wrenches(o.wrenches, model);
  std::vector<std::string> names;
  for (int i = 0; i < model.size(); ++i) names.push_back(model.joint_name(i));

  // the columns: q and tau always, qd where the terms read it, an optional time t
  const JointTable states(o.in, names, {{"q_", true}, {"qd_", full}, {"tau_", true}});

  // a scene: its locked joints held at the first row's angles, or where --lock says
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.size()), qd(model.size()), tau(model.size());
  if (states.rows() > 0) states.read(0, 0, q);
  wrenches.attach(model, data, q);
  std::optional<SceneRunner> scene = make_scene(o.scene, description, q);
  std::vector<std::size_t> written;  // the joints whose accelerations are written
  for (int i = 0; i < model.size(); ++i)
    if (!scene || !scene->locked(i)) written.push_back(std::size_t(i));

  std::vector<std::string> header;
  if (states.has_time()) header.push_back("t");
  const auto qdd_names = joint_columns(names, "qdd_");
  for (const std::size_t i : written) header.push_back(qdd_names[i]);
  CsvWriter out(o.out, header);

  for (std::size_t r = 0; r < states.rows(); ++r) {
    states.read(r, 0, q);
    states.read(r, 1, qd);
    states.read(r, 2, tau);
    const LinkWrenches<AnyModel<double>>* fext = wrenches.empty() ? nullptr : &wrenches.at(model, data, q);
    const Eigen::VectorXd scene_qdd = scene ? scene->forward_dynamics(q, qd, tau, o.method) : Eigen::VectorXd();
    const Eigen::VectorXd& qdd =
        scene         ? scene_qdd
        : articulated ? (full ? accelerations<FdMethod::Articulated, Terms::Full>(model, data, q, qd, tau, fext)
                              : accelerations<FdMethod::Articulated, Terms::NoCoriolis>(model, data, q, qd, tau, fext))
                      : (full ? accelerations<FdMethod::MassMatrix, Terms::Full>(model, data, q, qd, tau, fext)
                              : accelerations<FdMethod::MassMatrix, Terms::NoCoriolis>(model, data, q, qd, tau, fext));

    // the pivots: the articulated inertia about each joint axis, or D of M = L^T D L
    const Eigen::VectorXd pivots = scene         ? scene->pivots(o.method)
                                   : articulated ? Eigen::VectorXd(data.D_inv.cwiseInverse())
                                                 : Eigen::VectorXd(data.D);
    // looked at in the order the elimination meets them, tips inwards: the first that is not clearly
    // positive is where M is singular (a zero pivot turns those after it into NaN)
    double largest = 0;
    for (Eigen::Index i = 0; i < pivots.size(); ++i)
      if (std::isfinite(pivots[i])) largest = std::max(largest, std::abs(pivots[i]));
    const std::string where = states.where(r);
    for (Eigen::Index i = pivots.size() - 1; i >= 0; --i)
      if (!(pivots[i] > singular_pivot * largest))
        throw InputError(where + "the mass matrix is singular at joint '" + names[std::size_t(i)] + "' (pivot " +
                         (std::isfinite(pivots[i]) ? format_number(pivots[i]) : std::string("not finite")) +
                         " kg m^2, largest " + format_number(largest) +
                         "): the motion this joint adds moves no mass; forward dynamics is undefined");
    states.write(out, r, written, names, qdd, "acceleration");
  }
  out.commit();
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
  add_model_options(*c, o->model);
  add_choice(*c, "--method", o->method, {{"mass-matrix", FdMethod::MassMatrix}, {"articulated", FdMethod::Articulated}},
             "mass-matrix: the mass matrix by composite rigid bodies and its\n"
             "tree-sparse L^T D L factorisation (default); articulated: the\n"
             "articulated-body algorithm")
      ->option_text("M");
  CLI::Option* terms = add_choice(*c, "--terms", o->full, {{"full", true}, {"no-coriolis", false}},
                                  "full: every term (default); no-coriolis: without the velocity\n"
                                  "products, as the seed paper does (the qd_ columns are then not needed)")
                           ->option_text("T");
  CLI::Option* scene =
      add_scene_options(*c, o->scene,
                        "a named scene of the seed body instead of --terms: its terms\n"
                        "(static_pose steps without the velocity products), its locked joints\n"
                        "held at the first row's angles (their tau_ columns are not read),\n"
                        "accelerations written for its moving joints only:",
                        "with --scene: hold these locked joints at these angles (rad) instead\nof the first row's");
  terms->excludes(scene);
  add_wrench_option(*c, o->wrenches, "The accelerations then include the wrenches' push. Not with --scene")
      ->excludes(scene);
  c->add_option("--in", o->in,
                "the states, '-' for standard input. Header: q_<joint> (rad),\n"
                "qd_<joint> (rad/s) and tau_<joint> (N m) for every joint; an optional\n"
                "time column t is copied")
      ->option_text("FILE")
      ->required();
  c->add_option("--out", o->out,
                "the accelerations, qdd_<joint> (rad/s^2), one row per input row\n"
                "(default: standard output); written only when every row is valid")
      ->option_text("FILE");
  c->footer(
      "The mass matrix must be regular. The paper's model is not: Table 1's pelvis link is massless and the\n"
      "right hip pitch, the waist pitch and the left hip pitch turn about one line, so no torque fixes the\n"
      "pelvis's turn about that line. Such a state is reported as an error, naming the joint.");
  return {c, [o] { return run_fd(*o); }};
}

}  // namespace humandyn::cli
